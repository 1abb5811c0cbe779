//! "Which basis, at what cost": per signal (irradiance; specular per α), the cost tiers,
//! the Pareto front of error against each cost axis, the best mode within each budget of
//! storage and CPU cost, and one recommendation. Computed from [`MapResults`] alone, so
//! anyone can recompute it from `results.json` (a test does).
//!
//! Candidates are the modes with a runtime (coefficients stored; the Monte Carlo mode is a
//! reference, not a candidate) and a finite error.
//!
//! **Ties.** A measured cost is an interval, not a number: the spread of its timed passes
//! (CPU: the 2nd fastest to the 2nd slowest of the side-by-side rounds, [`crate::cost`];
//! encode: the fastest to the slowest run), widened to at least ±[`NOISE_FLOOR`] (encode:
//! ±[`ENCODE_NOISE_FLOOR`]) about its geometric middle. Sorted by lower end, the first
//! candidate and every candidate whose interval starts inside the first's form one
//! **tier**, and so on (the order of medians plays no part).
//! Every decision compares tiers, never medians — within a tier the lower error wins, then
//! the smaller storage, then the id — so a cost that moves within its spread changes no
//! decision, and the decision records hold no measured time.
//!
//! **Recommendation** ([`RECOMMEND_WITHIN`]): the cheapest point of the CPU front (lowest
//! tier) whose error is within 25 % of the best error any candidate reaches; with it, the
//! front point just cheaper (what one more step down in cost gives up).

use crate::results::{Budget, Decision, Front, MapResults, Point, Recommendation, SignalDecision, Tiers, AXES};

/// Smallest relative half-width of a CPU or GPU cost interval. The side-by-side medians of
/// two copies of one evaluator agreed within 1.10× in 99 % of 540 pairs on a 2-core VM with
/// a busy neighbour (worst 1.29×, `probes/tests/cost.rs`); ±10 % about each makes such a
/// pair one tier.
pub const NOISE_FLOOR: f64 = 0.10;
/// The same for encode times: single runs inside the parallel mode stage, not side by
/// side, so a machine's drift between modes is not cancelled.
pub const ENCODE_NOISE_FLOOR: f64 = 0.25;
/// A recommendation's error may exceed the best candidate's by this factor.
pub const RECOMMEND_WITHIN: f64 = 1.25;

/// A candidate: its decision point, and per timed axis (eval, encode, GPU) its cost
/// interval (None: not measured on that axis).
struct Candidate {
    point: Point,
    intervals: [Option<(f64, f64)>; 3],
}

/// `[lo, hi]` widened to at least ±`floor` about its geometric middle.
fn widen(lo: f64, hi: f64, floor: f64) -> Option<(f64, f64)> {
    if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi >= lo) {
        return None;
    }
    let mid = (lo * hi).sqrt();
    Some((lo.min(mid / (1.0 + floor)), hi.max(mid * (1.0 + floor))))
}

/// The decision for one map's results.
pub fn decide(r: &MapResults) -> Decision {
    let runtime: Vec<_> = r.modes.iter().filter(|m| m.coefficient_count > 0).collect();
    let encode = |m: &crate::results::ModeRecord| {
        let [lo, hi] = m.cost.encode_total_range_s;
        widen(lo, hi, ENCODE_NOISE_FLOOR)
    };
    let gpu = |ns: Option<f64>| ns.and_then(|x| widen(x, x, NOISE_FLOOR));
    let point = |m: &crate::results::ModeRecord, error: f64, rel: f64| Point {
        id: m.id.clone(),
        error,
        error_percent: 100.0 * rel,
        bytes: m.cost.storage_bytes,
        cpu_tier: 0,
    };
    let mut signals = Vec::new();
    let irr: Vec<Candidate> = runtime
        .iter()
        .map(|m| Candidate {
            point: point(m, m.metrics.irradiance.rms, m.metrics.irradiance.rel_rms),
            intervals: [widen(m.cost.eval.low_ns, m.cost.eval.high_ns, NOISE_FLOOR), encode(m), gpu(m.cost.gpu.as_ref().map(|g| g.ns))],
        })
        .collect();
    signals.push(signal("irradiance".into(), irr));
    for a in r.reference.specular_error.keys() {
        let c: Vec<Candidate> = runtime
            .iter()
            .filter_map(|m| {
                let e = m.metrics.specular.get(a)?;
                let s = m.cost.specular_eval?;
                Some(Candidate {
                    point: point(m, e.metrics.rms, e.metrics.rel_rms),
                    intervals: [widen(s.low_ns, s.high_ns, NOISE_FLOOR), encode(m), gpu(m.cost.gpu.as_ref().and_then(|g| g.specular_ns))],
                })
            })
            .collect();
        if !c.is_empty() {
            signals.push(signal(format!("specular α={a}"), c));
        }
    }
    Decision { signals }
}

/// Tier (1-based) of every candidate on timed axis `k` (0 where not measured), cheapest
/// first: by lower end, each tier is the first remaining candidate and every candidate whose
/// interval starts inside the first's (anchored, so a chain of overlaps cannot stretch a
/// tier across a factor of two).
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

fn signal(name: String, mut c: Vec<Candidate>) -> SignalDecision {
    c.retain(|x| x.point.error.is_finite() && x.intervals[0].is_some() && x.intervals[1].is_some());
    let tier_of: Vec<Vec<usize>> = (0..3).map(|k| tiers(&c, k)).collect();
    for (x, t) in c.iter_mut().zip(&tier_of[0]) {
        x.point.cpu_tier = *t;
    }
    let tiers = (0..3)
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
            0 => Some(c[i].point.bytes as f64),
            k => (tier_of[k - 1][i] > 0).then(|| tier_of[k - 1][i] as f64),
        }
    };
    let fronts: Vec<Front> = (0..AXES.len())
        .filter_map(|axis| {
            let on: Vec<usize> = (0..c.len()).filter(|i| rank(*i, axis).is_some()).collect();
            (!on.is_empty()).then(|| Front { axis: AXES[axis].to_string(), points: front(&c, &on, |i| rank(i, axis).expect("filtered")) })
        })
        .collect();
    let recommended = fronts.iter().find(|f| f.axis == "eval_ns").and_then(|f| recommend(&f.points));
    SignalDecision { signal: name, recommended, tiers, fronts, budget: budget(&c) }
}

/// The Pareto front of error against a cost rank: by increasing rank, each point strictly
/// better in error than every cheaper one (within a rank, the lower error, then the smaller
/// storage, then the id).
fn front(c: &[Candidate], on: &[usize], rank: impl Fn(usize) -> f64) -> Vec<Point> {
    let mut idx = on.to_vec();
    idx.sort_by(|a, b| rank(*a).total_cmp(&rank(*b)).then(better(&c[*a].point, &c[*b].point)));
    let mut out: Vec<Point> = Vec::new();
    for i in idx {
        if out.last().is_none_or(|p| c[i].point.error < p.error) {
            out.push(c[i].point.clone());
        }
    }
    out
}

/// Order of preference between two points of equal cost: lower error, smaller storage, id.
fn better(a: &Point, b: &Point) -> std::cmp::Ordering {
    a.error.total_cmp(&b.error).then(a.bytes.cmp(&b.bytes)).then(a.id.cmp(&b.id))
}

/// The recommendation on a CPU front (see the module docs).
fn recommend(front: &[Point]) -> Option<Recommendation> {
    let best = front.last()?.error;
    let k = front.iter().position(|p| p.error <= RECOMMEND_WITHIN * best)?;
    Some(Recommendation { mode: front[k].clone(), next_cheaper: k.checked_sub(1).map(|j| front[j].clone()) })
}

/// The lowest-error candidate within each budget of storage (rows) and CPU tier (columns).
fn budget(c: &[Candidate]) -> Budget {
    let mut bytes: Vec<usize> = c.iter().map(|x| x.point.bytes).collect();
    bytes.sort_unstable();
    bytes.dedup();
    let top = c.iter().map(|x| x.point.cpu_tier).max().unwrap_or(0);
    let cell = |b: usize, t: usize| -> Option<Point> {
        c.iter().filter(|x| x.point.bytes <= b && x.point.cpu_tier <= t).map(|x| &x.point).min_by(|p, q| better(p, q)).cloned()
    };
    let all: Vec<Vec<Option<Point>>> = bytes.iter().map(|b| (1..=top).map(|t| cell(*b, t)).collect()).collect();
    // Keep tier t when it is the last or the next tier changes some cell.
    let keep: Vec<usize> = (1..=top).filter(|t| *t == top || all.iter().any(|row| row[*t - 1] != row[*t])).collect();
    let best = all.iter().map(|row| keep.iter().map(|t| row[*t - 1].clone()).collect()).collect();
    Budget { bytes, cpu_tiers: keep, best }
}
