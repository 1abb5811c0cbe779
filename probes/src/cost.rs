//! Cost axes, measured the same way for every mode: CPU reconstruction
//! cost as steady-state nanoseconds per direction over a large batch, and storage.
//!
//! Method: the mode's runtime evaluation (coefficients → value at a direction, exactly
//! what the report's images come from) runs over the output directions, cycled to at
//! least [`MIN_BATCH`] evaluations and at least [`MIN_PASS_S`] per pass; one untimed pass
//! over the batch's directions warms caches and branch predictors and sizes the batch, a
//! full-size untimed pass settles the clock, then [`REPEATS`] timed passes; each result goes through `std::hint::black_box` and
//! nothing is allocated inside the loop (the evaluators hoist their scratch). Reported:
//! the median pass and the spread (min, max).
//!
//! Timed sections (these passes and the modes' encode timings) run one at a time, each
//! on one thread, under [`exclusive`]: no other timed work competes for a core, while
//! other modes' untimed work (images, metrics) may run on the remaining cores. A timed
//! section never calls into rayon, so a thread holding the lock never picks up another
//! mode's work.

use sbf::glam::DVec3;
use std::hint::black_box;
use std::sync::Mutex;
use std::time::Instant;

static TIMING: Mutex<()> = Mutex::new(());

/// Runs `f` while no other timed section of this process runs (see the module docs).
/// `f` must not use rayon (a thread waiting in rayon may pick up a job that also wants
/// the lock).
pub fn exclusive<T>(f: impl FnOnce() -> T) -> T {
    let _guard = TIMING.lock().unwrap_or_else(|e| e.into_inner());
    f()
}

/// Timed passes per measurement (5 medians once disagreed by 1.20× on a shared 2-core CI
/// machine, the first run the slow one; 7 after a full-size warm-up pass stayed within
/// 1.13× in 90 pairs (30 runs) here with a busy loop on the other core, for +0.05 s on `probes
/// compare pisa.hdr --no-specular`; 9 passes of 2 ms cost +0.35 s).
pub const REPEATS: usize = 7;
/// Smallest batch, in evaluations.
pub const MIN_BATCH: usize = 1 << 13;
/// Shortest pass: cheap evaluators get larger batches, so that every timed pass lasts
/// at least this long (timer resolution and per-pass overhead stay below 0.1%).
pub const MIN_PASS_S: f64 = 5e-4;

/// A steady-state cost: ns per evaluation, median of `repeats` passes of `batch`
/// evaluations, with the fastest and slowest pass.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct CostStat {
    pub median_ns: f64,
    pub min_ns: f64,
    pub max_ns: f64,
    pub repeats: usize,
    pub batch: usize,
}

impl CostStat {
    /// A cost measured once (no spread), e.g. a Monte Carlo estimate's per-texel cost.
    pub fn single(ns: f64, batch: usize) -> CostStat {
        CostStat { median_ns: ns, min_ns: ns, max_ns: ns, repeats: 1, batch }
    }
}

/// Steady-state ns per direction of `f` (see the module docs). `work` ≥ 1 evaluates each
/// direction that many times and still divides by the batch: the cost-axis test uses
/// `work = 2` as its "twice as expensive" mutation.
pub fn ns_per_direction(dirs: &[DVec3], work: usize, f: impl FnMut(DVec3) -> [f64; 3]) -> CostStat {
    ns_per_item(dirs, work, f)
}

/// [`ns_per_direction`] over any inputs (e.g. output texel indices).
pub fn ns_per_item<T: Copy>(dirs: &[T], work: usize, f: impl FnMut(T) -> [f64; 3]) -> CostStat {
    exclusive(|| measure(dirs, work, f))
}

fn measure<T: Copy>(dirs: &[T], work: usize, mut f: impl FnMut(T) -> [f64; 3]) -> CostStat {
    if dirs.is_empty() {
        return CostStat::default();
    }
    // Large inputs: an evenly strided subset of about MIN_BATCH items.
    let stride = (dirs.len() / MIN_BATCH).max(1);
    let subset: Vec<T> = dirs.iter().step_by(stride).copied().collect();
    let dirs = &subset[..];
    let work = work.max(1);
    // One untimed pass over the subset — the warm-up (caches, branch predictors) —
    // estimates the cost per evaluation; the batch is MIN_BATCH evaluations or MIN_PASS_S
    // worth, whichever is larger.
    let t = Instant::now();
    let mut acc = 0.0;
    for d in dirs {
        for _ in 0..work {
            acc += black_box(f(black_box(*d)))[0];
        }
    }
    black_box(acc);
    let per_eval = t.elapsed().as_secs_f64() / dirs.len() as f64;
    let want = (MIN_PASS_S / per_eval.max(1e-12)).min(64.0 * MIN_BATCH as f64) as usize;
    let passes = MIN_BATCH.max(want).div_ceil(dirs.len());
    let batch = passes * dirs.len();
    let mut pass = || {
        let mut acc = 0.0;
        for _ in 0..passes {
            for d in dirs {
                for _ in 0..work {
                    let v = black_box(f(black_box(*d)));
                    acc += v[0];
                }
            }
        }
        black_box(acc);
    };
    // A full-size untimed pass: the core reaches its steady clock before timing (the first
    // of two measurements was the slow one when CI saw them disagree).
    pass();
    let mut times: Vec<f64> = (0..REPEATS)
        .map(|_| {
            let t = Instant::now();
            pass();
            t.elapsed().as_secs_f64() * 1e9 / batch as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    CostStat { median_ns: times[REPEATS / 2], min_ns: times[0], max_ns: times[REPEATS - 1], repeats: REPEATS, batch }
}

/// Bytes per probe (or lightmap texel) at the runtime precision (f32): the scalars the
/// runtime reads. Lobe axes and sharpness are shared by every probe of a basis and not
/// counted.
pub fn storage_bytes(scalars: usize) -> usize {
    4 * scalars
}
