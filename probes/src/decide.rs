//! "Which basis, at what cost": per signal (irradiance; specular per α),
//! the Pareto front of error against each cost axis, and the best mode within a budget of
//! storage and CPU reconstruction cost. Computed from [`MapResults`] alone, so anyone can
//! recompute it from `results.json` (a test does).
//!
//! Candidates are the modes with a runtime (coefficients stored; the Monte Carlo mode is a
//! reference, not a candidate) and a finite error. A mode is on a front when no other
//! candidate has a cost ≤ and an error ≤ with one of them strictly smaller.

use crate::results::MapResults;
use serde::{Deserialize, Serialize};

/// Every signal's decision for one map.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Decision {
    pub signals: Vec<SignalDecision>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SignalDecision {
    /// `irradiance`, or `specular α=<α>`.
    pub signal: String,
    /// One front per cost axis.
    pub fronts: Vec<Front>,
    pub budget: Budget,
}

/// The cost axes; `gpu_ns` only where the run measured GPU costs (`--gpu-cost`), over
/// the modes that have a WGSL runtime.
pub const AXES: [&str; 4] = ["storage_bytes", "eval_ns", "encode_total_s", "gpu_ns"];

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Front {
    /// One of [`AXES`].
    pub axis: String,
    /// The front, by increasing cost (and so decreasing error).
    pub points: Vec<Point>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Point {
    pub id: String,
    pub cost: f64,
    pub error: f64,
}

/// Best mode (lowest RMS) within each (storage, CPU cost) budget.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Budget {
    /// Storage budgets (rows): the distinct storage sizes of the candidates, bytes.
    pub bytes: Vec<usize>,
    /// CPU cost budgets (columns), ns per evaluation; `None` = no limit.
    pub ns: Vec<Option<f64>>,
    /// `best[row][column]`: the winning mode and its error, if any mode fits.
    pub best: Vec<Vec<Option<Point>>>,
}

/// CPU budgets tried (ns per evaluation); those below the cheapest candidate are dropped.
pub const NS_LADDER: [f64; 8] = [5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0];

/// A candidate: id, error, storage, CPU ns, encode s, GPU ns (NaN: not measured).
struct Candidate {
    id: String,
    error: f64,
    costs: [f64; 4],
}

/// The decision for one map's results.
pub fn decide(r: &MapResults) -> Decision {
    let runtime: Vec<_> = r.modes.iter().filter(|m| m.coefficient_count > 0).collect();
    let mut signals = Vec::new();
    let irr: Vec<Candidate> = runtime
        .iter()
        .map(|m| Candidate {
            id: m.id.clone(),
            error: m.metrics.irradiance.rms,
            costs: [
                m.cost.storage_bytes as f64,
                m.cost.eval.median_ns,
                m.cost.encode_total_s,
                m.cost.gpu.as_ref().map_or(f64::NAN, |g| g.ns),
            ],
        })
        .collect();
    signals.push(signal("irradiance".into(), irr));
    let alphas: Vec<String> = r.reference.specular_error.keys().cloned().collect();
    for a in alphas {
        let c: Vec<Candidate> = runtime
            .iter()
            .filter_map(|m| {
                let e = m.metrics.specular.get(&a)?;
                let ns = m.cost.specular_eval?.median_ns;
                let gpu = m.cost.gpu.as_ref().and_then(|g| g.specular_ns).unwrap_or(f64::NAN);
                Some(Candidate {
                    id: m.id.clone(),
                    error: e.metrics.rms,
                    costs: [m.cost.storage_bytes as f64, ns, m.cost.encode_total_s, gpu],
                })
            })
            .collect();
        if !c.is_empty() {
            signals.push(signal(format!("specular α={a}"), c));
        }
    }
    Decision { signals }
}

fn signal(name: String, mut c: Vec<Candidate>) -> SignalDecision {
    c.retain(|x| x.error.is_finite() && x.costs[..3].iter().all(|v| v.is_finite()));
    let fronts = AXES
        .iter()
        .enumerate()
        .filter_map(|(k, axis)| {
            // Only candidates measured on this axis; an axis nobody was measured on is left out.
            let on: Vec<&Candidate> = c.iter().filter(|x| x.costs[k].is_finite()).collect();
            (!on.is_empty()).then(|| Front { axis: axis.to_string(), points: front(&on, k) })
        })
        .collect();
    SignalDecision { signal: name, fronts, budget: budget(&c) }
}

/// The Pareto front of error against cost axis `k`.
fn front(c: &[&Candidate], k: usize) -> Vec<Point> {
    let mut idx: Vec<usize> = (0..c.len()).collect();
    idx.sort_by(|a, b| c[*a].costs[k].total_cmp(&c[*b].costs[k]).then(c[*a].error.total_cmp(&c[*b].error)).then(c[*a].id.cmp(&c[*b].id)));
    let mut out: Vec<Point> = Vec::new();
    for i in idx {
        if out.last().is_none_or(|p| c[i].error < p.error) {
            out.push(Point { id: c[i].id.clone(), cost: c[i].costs[k], error: c[i].error });
        }
    }
    out
}

/// The lowest-error candidate within each budget (ties: the cheaper, then by id).
fn budget(c: &[Candidate]) -> Budget {
    let mut bytes: Vec<usize> = c.iter().map(|x| x.costs[0] as usize).collect();
    bytes.sort_unstable();
    bytes.dedup();
    let cheapest = c.iter().map(|x| x.costs[1]).fold(f64::INFINITY, f64::min);
    let dearest = c.iter().map(|x| x.costs[1]).fold(0.0, f64::max);
    let mut ns: Vec<Option<f64>> = NS_LADDER.iter().copied().filter(|b| *b >= cheapest && *b < dearest).map(Some).collect();
    ns.push(None);
    let best = bytes
        .iter()
        .map(|b| {
            ns.iter()
                .map(|t| {
                    c.iter()
                        .filter(|x| x.costs[0] as usize <= *b && t.is_none_or(|t| x.costs[1] <= t))
                        .min_by(|p, q| p.error.total_cmp(&q.error).then(p.costs[0].total_cmp(&q.costs[0])).then(p.id.cmp(&q.id)))
                        .map(|x| Point { id: x.id.clone(), cost: x.costs[0], error: x.error })
                })
                .collect()
        })
        .collect();
    Budget { bytes, ns, best }
}
