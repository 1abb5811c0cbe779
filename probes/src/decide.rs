//! "Which basis, at what cost": per signal (irradiance; specular per α), the CPU cost tiers,
//! the Pareto front of error against storage, CPU cost and (with `--gpu-cost`) GPU cost, the
//! best mode within each budget of storage and CPU cost, and one recommendation. Computed
//! from [`MapResults`] alone, so anyone can recompute it from `results.json` (a test does).
//!
//! Candidates are the modes with a runtime (coefficients stored; the Monte Carlo mode is a
//! reference, not a candidate) and a finite error.
//!
//! **CPU costs** come from the committed calibration ([`crate::calibration`]) by each mode's
//! evaluator key, so the same inputs give the same decision on every run and machine; where
//! the calibration lacks one of a signal's candidates, that signal falls back to this run's
//! measurement (and says so in `cpu_costs`). Storage is exact; GPU costs are this run's.
//!
//! **Ties.** A cost is an interval: the calibration's range of batch medians (a run's own
//! measurement: the 2nd fastest to the 2nd slowest pass; GPU: the one figure), widened to at
//! least ±[`NOISE_FLOOR`] about its geometric middle. Sorted by lower end, the first
//! candidate and every candidate whose interval starts inside the first's form one
//! **tier**, and so on (anchored: a chain of overlaps cannot stretch a tier). Decisions
//! compare tiers, never medians — within a tier the lower error wins, then the smaller
//! storage, then the id — and the decision records hold no measured time.
//!
//! **Recommendation** ([`RECOMMEND_WITHIN`]): the cheapest point of the CPU front (lowest
//! tier) whose error is within 25 % of the best error any candidate reaches — and within the
//! usability threshold ([`MapResults::usable_error_percent`], [`USABLE_ERROR_PERCENT`] by
//! default) where the best is; with it, the front point just cheaper (what one step down in
//! cost gives up). Where even the best candidate's error exceeds the threshold, the
//! recommendation is that best candidate, marked unusable (`usable: false`), and the text
//! says no mode fits.

use crate::results::{Budget, Decision, Front, MapResults, ModeRecord, Point, Recommendation, SignalDecision, Tiers, AXES};

/// Smallest relative half-width of a cost interval. The side-by-side medians of two copies
/// of one evaluator agreed within 1.10× in 99 % of 540 pairs on a 2-core VM with a busy
/// neighbour (worst 1.29×, `probes/tests/cost.rs`); ±10 % about each makes such a pair one
/// tier.
pub const NOISE_FLOOR: f64 = 0.10;
/// A recommendation's error may exceed the best candidate's by this factor.
pub const RECOMMEND_WITHIN: f64 = 1.25;
pub use crate::results::USABLE_ERROR_PERCENT;

/// A candidate: its decision point, and per timed axis (CPU, GPU) its cost interval (None:
/// not measured on that axis).
struct Candidate {
    point: Point,
    intervals: [Option<(f64, f64)>; 2],
}

/// `[lo, hi]` widened to at least ±`floor` about its geometric middle.
fn widen(lo: f64, hi: f64, floor: f64) -> Option<(f64, f64)> {
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo) {
        return None;
    }
    let mid = (lo * hi).sqrt();
    Some((lo.min(mid / (1.0 + floor)), hi.max(mid * (1.0 + floor))))
}

/// One signal's candidates: (mode, error RMS, error relative to the reference RMS, this
/// run's CPU cost, calibration key, GPU ns).
type Raw<'a> = (&'a ModeRecord, f64, f64, crate::cost::CostStat, Option<String>, Option<f64>);

/// The decision for one map's results.
pub fn decide(r: &MapResults) -> Decision {
    let runtime: Vec<&ModeRecord> = r.modes.iter().filter(|m| m.coefficient_count > 0).collect();
    let mut signals = Vec::new();
    let irr: Vec<Raw> = runtime
        .iter()
        .map(|m| {
            let e = &m.metrics.irradiance;
            (*m, e.rms, e.rel_rms, m.cost.eval, Some(m.cost_keys.irradiance.clone()), m.cost.gpu.as_ref().map(|g| g.ns))
        })
        .collect();
    let usable = r.usable_error_percent;
    signals.push(signal("irradiance".into(), &irr, usable));
    for a in r.reference.specular_error.keys() {
        let c: Vec<Raw> = runtime
            .iter()
            .filter_map(|m| {
                let e = &m.metrics.specular.get(a)?.metrics;
                let gpu = m.cost.gpu.as_ref().and_then(|g| g.specular_ns);
                Some((*m, e.rms, e.rel_rms, m.cost.specular_eval?, m.cost_keys.specular.clone(), gpu))
            })
            .collect();
        if !c.is_empty() {
            signals.push(signal(format!("specular α={a}"), &c, usable));
        }
    }
    Decision { signals }
}

/// The candidates of one signal with their CPU intervals from the calibration (or, where it
/// lacks any of them, from this run), and where those came from.
fn candidates(raw: &[Raw]) -> (Vec<Candidate>, String) {
    let cal = crate::calibration::committed();
    let calibrated: Option<Vec<(f64, f64)>> =
        raw.iter().map(|x| x.4.as_ref().and_then(|k| cal.costs.get(k)).map(|s| (s.low_ns, s.high_ns))).collect();
    let missing: Vec<&str> =
        raw.iter().filter(|x| x.4.as_ref().and_then(|k| cal.costs.get(k)).is_none()).map(|x| x.0.id.as_str()).collect();
    let source = match &calibrated {
        Some(_) => format!("calibrated ({}, {}; probes/data/cpu_costs.json)", cal.machine, cal.date),
        None => format!("measured in this run (the calibration lacks {})", missing.join(", ")),
    };
    let c = raw
        .iter()
        .enumerate()
        .map(|(i, (m, error, rel, run, _, gpu))| Candidate {
            point: Point { id: m.id.clone(), error: *error, error_percent: 100.0 * rel, bytes: m.cost.storage_bytes, cpu_tier: 0 },
            intervals: [
                match &calibrated {
                    Some(v) => widen(v[i].0, v[i].1, NOISE_FLOOR),
                    None => widen(run.low_ns, run.high_ns, NOISE_FLOOR),
                },
                gpu.and_then(|x| widen(x, x, NOISE_FLOOR)),
            ],
        })
        .collect();
    (c, source)
}

/// Tier (1-based) of every candidate on timed axis `k` (0 where not measured), cheapest
/// first (see the module docs).
fn tiers(c: &[Candidate], k: usize) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..c.len()).filter(|i| c[*i].intervals[k].is_some()).collect();
    let iv = |i: usize| c[i].intervals[k].expect("filtered");
    idx.sort_by(|a, b| iv(*a).0.total_cmp(&iv(*b).0).then(c[*a].point.id.cmp(&c[*b].point.id)));
    let mut tier = vec![0; c.len()];
    let (mut t, mut reach) = (0, f64::NEG_INFINITY);
    for i in idx {
        let (lo, hi) = iv(i);
        if lo > reach {
            t += 1;
            reach = hi;
        }
        tier[i] = t;
    }
    tier
}

fn signal(name: String, raw: &[Raw], usable_percent: f64) -> SignalDecision {
    let (mut c, cpu_costs) = candidates(raw);
    c.retain(|x| x.point.error.is_finite() && x.intervals[0].is_some());
    let tier_of: [Vec<usize>; 2] = [tiers(&c, 0), tiers(&c, 1)];
    for (x, t) in c.iter_mut().zip(&tier_of[0]) {
        x.point.cpu_tier = *t;
    }
    let tiers = (0..2)
        .filter(|k| c.iter().any(|x| x.intervals[*k].is_some()))
        .map(|k| {
            let n = tier_of[k].iter().copied().max().unwrap_or(0);
            let mut groups: Vec<Vec<String>> =
                (1..=n).map(|t| c.iter().zip(&tier_of[k]).filter(|(_, x)| **x == t).map(|(m, _)| m.point.id.clone()).collect()).collect();
            groups.iter_mut().for_each(|g| g.sort());
            Tiers { axis: AXES[k + 1].to_string(), tiers: groups }
        })
        .collect();
    // Cost rank per axis: storage exactly, the timed axes by tier.
    let rank = |i: usize, axis: usize| -> Option<f64> {
        match axis {
            0 => Some(c[i].point.bytes),
            k => (tier_of[k - 1][i] > 0).then(|| tier_of[k - 1][i] as f64),
        }
    };
    let fronts: Vec<Front> = (0..AXES.len())
        .filter_map(|axis| {
            let on: Vec<usize> = (0..c.len()).filter(|i| rank(*i, axis).is_some()).collect();
            (!on.is_empty()).then(|| Front { axis: AXES[axis].to_string(), points: front(&c, &on, |i| rank(i, axis).expect("filtered")) })
        })
        .collect();
    let recommended = fronts.iter().find(|f| f.axis == "eval_ns").and_then(|f| recommend(&f.points, usable_percent));
    let usable = recommended.as_ref().is_some_and(|r| r.mode.error_percent <= usable_percent);
    SignalDecision { signal: name, recommended, usable, cpu_costs, tiers, fronts, budget: budget(&c) }
}

/// The Pareto front of error against a cost rank: by increasing rank, each point strictly
/// better in error than every cheaper one (within a rank, the lower error, then the smaller
/// storage, then the id).
fn front(c: &[Candidate], on: &[usize], rank: impl Fn(usize) -> f64) -> Vec<Point> {
    let mut idx = on.to_vec();
    idx.sort_by(|a, b| rank(*a).total_cmp(&rank(*b)).then(better(&c[*a].point, &c[*b].point)));
    let mut out: Vec<Point> = Vec::new();
    for i in idx {
        if out.last().is_none_or(|p| rounded(c[i].point.error) < rounded(p.error)) {
            out.push(c[i].point.clone());
        }
    }
    out
}

/// An error as decisions compare it: rounded to 9 significant digits, so that two modes
/// computing the same image by different roundings (a 32² and a 64² prefiltered map read
/// at the same mips, whose trilinear weights differ in the last bit) tie, and the smaller
/// storage wins; a monotone function of the error, so orders stay total.
fn rounded(error: f64) -> f64 {
    if error.is_finite() && error != 0.0 {
        format!("{error:.8e}").parse().unwrap_or(error)
    } else {
        error
    }
}

/// Order of preference between two points of equal cost: lower error ([`rounded`]), smaller
/// storage, id.
fn better(a: &Point, b: &Point) -> std::cmp::Ordering {
    rounded(a.error).total_cmp(&rounded(b.error)).then(a.bytes.total_cmp(&b.bytes)).then(a.id.cmp(&b.id))
}

/// The recommendation on a CPU front (see the module docs): within 25 % of the best error
/// and within the usability threshold (a percentage); the best itself where nothing is
/// within the threshold.
fn recommend(front: &[Point], usable_percent: f64) -> Option<Recommendation> {
    let best = front.last()?;
    // Nothing usable: the best there is (the text says it is not one to ship).
    let k = if best.error_percent > usable_percent {
        front.len() - 1
    } else {
        front.iter().position(|p| p.error <= RECOMMEND_WITHIN * best.error && p.error_percent <= usable_percent)?
    };
    Some(Recommendation { mode: front[k].clone(), next_cheaper: k.checked_sub(1).map(|j| front[j].clone()) })
}

/// The lowest-error candidate within each budget of storage (rows) and CPU tier (columns).
fn budget(c: &[Candidate]) -> Budget {
    let mut bytes: Vec<f64> = c.iter().map(|x| x.point.bytes).collect();
    bytes.sort_unstable_by(f64::total_cmp);
    bytes.dedup();
    let top = c.iter().map(|x| x.point.cpu_tier).max().unwrap_or(0);
    let cell = |b: f64, t: usize| -> Option<Point> {
        c.iter().filter(|x| x.point.bytes <= b && x.point.cpu_tier <= t).map(|x| &x.point).min_by(|p, q| better(p, q)).cloned()
    };
    let all: Vec<Vec<Option<Point>>> = bytes.iter().map(|b| (1..=top).map(|t| cell(*b, t)).collect()).collect();
    // Keep tier t when it is the last or the next tier changes some cell.
    let keep: Vec<usize> = (1..=top).filter(|t| *t == top || all.iter().any(|row| row[*t - 1] != row[*t])).collect();
    let best = all.iter().map(|row| keep.iter().map(|t| row[*t - 1].clone()).collect()).collect();
    Budget { bytes, cpu_tiers: keep, best }
}
