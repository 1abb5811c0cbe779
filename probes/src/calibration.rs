//! Calibrated CPU costs: every mode's runtime evaluation (irradiance, and specular where it
//! has one, per runtime variant) measured once on a reference machine with many
//! side-by-side rounds and committed (`probes/data/cpu_costs.json`), so that the decisions
//! ([`crate::decide`]) — which compare cost tiers — come out the same on every run and
//! every machine. Each run still measures and reports its own costs ([`crate::cost`]);
//! `probes calibrate` regenerates the file on the machine it runs on.
//!
//! Why not decide from the run's own measurement: a run's costs move from run to run (on a
//! shared 2-core VM the same evaluator measured 17 ns and 29 ns seconds apart, and the
//! slowdown differs between evaluators), and any grouping of measured values into tiers
//! has boundaries that some mode lies near: repeated runs then disagree.

use crate::cost::{measure_side_by_side, CostJob, CostStat};
use crate::modes::{self, Context, SgIrradiance, SpecularRuntime};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The committed calibration.
static COMMITTED: &str = include_str!("../data/cpu_costs.json");

/// A calibration: where and how it was measured, and each evaluator's cost by key
/// ([`irradiance_key`], [`specular_key`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    pub machine: String,
    pub date: String,
    pub command: String,
    /// Side-by-side measurements (each of [`crate::cost::REPEATS`] rounds) combined per key.
    pub batches: usize,
    /// The map the evaluators ran on (costs depend on the output grid, not on the map's
    /// content).
    pub map: String,
    pub costs: BTreeMap<String, CostStat>,
}

/// The committed calibration (parsed once).
pub fn committed() -> &'static Calibration {
    static C: OnceLock<Calibration> = OnceLock::new();
    C.get_or_init(|| serde_json::from_str(COMMITTED).expect("probes/data/cpu_costs.json parses (a test checks it)"))
}

/// Key of a mode's irradiance evaluator: `irradiance/<id>[/<variant>]`.
pub fn irradiance_key(id: &str, variant: &str) -> String {
    if variant.is_empty() {
        format!("irradiance/{id}")
    } else {
        format!("irradiance/{id}/{variant}")
    }
}

/// Key of a mode's specular evaluator: `specular/<id>` for SH and the prefiltered maps (one
/// path), otherwise
/// `specular/<id>/<table|fit>`; `None` without a specular path.
pub fn specular_key(id: &str, runtime: SpecularRuntime) -> Option<String> {
    if !crate::specular::supported(id) {
        None
    } else if crate::specular::is_sh(id) || crate::specular::is_pf(id) {
        Some(format!("specular/{id}"))
    } else {
        Some(format!("specular/{id}/{}", runtime.name()))
    }
}

/// Every evaluator key a run can produce (each mode of [`modes::MODES`] with a runtime, each
/// SG reconstruction, each specular runtime).
pub fn variants() -> Vec<(SgIrradiance, SpecularRuntime)> {
    let mut v = Vec::new();
    for s in [SgIrradiance::Hill, SgIrradiance::Peer, SgIrradiance::Prior] {
        for r in [SpecularRuntime::Table, SpecularRuntime::Fit] {
            v.push((s, r));
        }
    }
    v
}

/// Measures every evaluator on the built-in sky (256×128): `batches` side-by-side
/// measurements of all of them; per key the median of the batch medians, `low`/`high` the
/// lowest and highest batch median (how far the cost moves between measurements: the
/// spread the decisions use) and `min`/`max` the extreme passes.
pub fn calibrate(batches: usize, progress: &dyn Fn(&str)) -> Result<Calibration, String> {
    let sky = sbf::envmap::ProceduralSky::default();
    let map = sbf::envmap::LatLongImage::from_fn(256, 128, |d| sky.radiance(d)).map_err(|e| e.to_string())?;
    let contexts: Vec<(SgIrradiance, SpecularRuntime, Context)> = variants()
        .into_iter()
        .map(|(s, r)| {
            let mut ctx = Context::new(map.clone());
            ctx.sg_irradiance = s;
            ctx.specular_runtime = r;
            (s, r, ctx)
        })
        .collect();
    let mut results = Vec::new();
    for (_, r, ctx) in &contexts {
        for modes::Mode { id, .. } in modes::MODES {
            progress(&format!("{id} ({})", r.name()));
            let p = modes::prepare(id, ctx, 1)?;
            results.push((p, *r, ctx));
        }
    }
    // One job per distinct key, in a fixed order; reused by every batch.
    let mut keys: Vec<String> = Vec::new();
    let mut jobs: Vec<CostJob> = Vec::new();
    for (p, r, ctx) in &mut results {
        let ik = irradiance_key(p.result.id, p.result.irradiance_variant);
        if !keys.contains(&ik) {
            if let Some(job) = p.eval.take() {
                keys.push(ik);
                jobs.push(job);
            }
        }
        if let Some(sk) = specular_key(p.result.id, *r) {
            if !keys.contains(&sk) {
                if let Some(job) = crate::specular::cost_job(&p.result, ctx, crate::profile::DEFAULT_ALPHAS[0]) {
                    keys.push(sk);
                    jobs.push(job);
                }
            }
        }
    }
    let mut per_key: Vec<Vec<CostStat>> = vec![Vec::new(); keys.len()];
    for b in 0..batches {
        progress(&format!("measuring {} evaluators side by side, batch {}/{batches}", keys.len(), b + 1));
        for (k, s) in measure_side_by_side(&mut jobs).into_iter().enumerate() {
            per_key[k].push(s);
        }
    }
    let costs = keys
        .into_iter()
        .zip(per_key)
        .map(|(k, v)| {
            let mut med: Vec<f64> = v.iter().map(|s| s.median_ns).collect();
            med.sort_by(f64::total_cmp);
            let s = CostStat {
                median_ns: med[med.len() / 2],
                min_ns: v.iter().map(|s| s.min_ns).fold(f64::INFINITY, f64::min),
                max_ns: v.iter().map(|s| s.max_ns).fold(0.0, f64::max),
                low_ns: med[0],
                high_ns: med[med.len() - 1],
                repeats: v.iter().map(|s| s.repeats).sum(),
                batch: v[0].batch,
            };
            (k, s)
        })
        .collect();
    Ok(Calibration {
        machine: String::new(),
        date: String::new(),
        command: format!("probes calibrate --batches {batches}"),
        batches,
        map: "built-in procedural sky, 256×128".into(),
        costs,
    })
}

/// Today's date (UTC), `YYYY-MM-DD` (days since 1970 to the civil calendar: Hinnant,
/// "chrono-Compatible Low-Level Date Algorithms", `civil_from_days`).
pub fn today() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let z = (secs / 86_400) as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}")
}
