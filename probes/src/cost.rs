//! Cost axes, measured the same way for every mode: CPU reconstruction
//! cost as steady-state nanoseconds per evaluation over a batch, and storage.
//!
//! Method: a mode's runtime evaluation (coefficients → value at a direction or output
//! texel, exactly what the report's images come from) is a [`CostJob`]. The jobs of a
//! run are measured together, **side by side**, by [`measure_side_by_side`], after all
//! other work of the run is done (nothing else competes for a core):
//! 1. per job, one untimed pass over its inputs (an evenly strided subset of at most
//!    [`MIN_BATCH`]) warms caches and branch predictors and sizes its pass — at least
//!    [`MIN_BATCH`] evaluations and at least [`MIN_PASS_S`] — then one untimed pass of
//!    that size settles the clock;
//! 2. [`REPEATS`] rounds; each round times one pass of every job, in alternating order.
//!
//! A shared machine's speed drifts by more than the differences between modes — on this
//! project's 2-core CI VM the same SH L2 evaluation measured 17 ns and 29 ns a few
//! milliseconds apart, for seconds at a time, and the slowdown is not uniform across
//! workloads (SMT neighbours contend for particular execution units) — so measuring modes
//! one after the other orders them by when they ran. Side by side, the k-th passes of all
//! jobs run within a few milliseconds of each other and see the same machine: their ratios,
//! and so the decisions made from them, hold from run to run. Reported per job: the median
//! pass and the spread (fastest, slowest, and the 2nd fastest and 2nd slowest, which the
//! decisions use: one pass interrupted by the OS does not widen it). Each result goes
//! through `std::hint::black_box`, and the evaluators allocate nothing in the loop.
//!
//! Encodes (a mode's fit from the map, an [`EncodeJob`]) are timed by [`time_encodes`], just
//! before: the mode stage runs every fit once, untimed, in parallel on every core, and keeps
//! the fit as a job; the timed runs come at the end, one job per core, with nothing else
//! running — so no core waits on a timing lock during the run's other work.

use std::hint::black_box;
use std::time::Instant;

/// Timed passes (rounds) per measurement.
pub const REPEATS: usize = 15;
/// Smallest pass, in evaluations, and the most inputs a job keeps (larger input sets are
/// strided down to about this many).
pub const MIN_BATCH: usize = 1 << 9;
/// Shortest pass: cheap evaluators get larger batches, so that every timed pass lasts
/// at least this long (timer resolution and per-pass overhead stay below 0.1%).
pub const MIN_PASS_S: f64 = 2.5e-4;

/// A steady-state cost: ns per evaluation, median of `repeats` passes of `batch`
/// evaluations, with the fastest and slowest pass and the 2nd fastest and 2nd slowest
/// (`low_ns`, `high_ns`: the spread decisions use).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct CostStat {
    pub median_ns: f64,
    pub min_ns: f64,
    pub max_ns: f64,
    #[serde(default)]
    pub low_ns: f64,
    #[serde(default)]
    pub high_ns: f64,
    pub repeats: usize,
    pub batch: usize,
}

impl CostStat {
    /// A cost measured once (no spread), e.g. a Monte Carlo estimate's per-texel cost.
    pub fn single(ns: f64, batch: usize) -> CostStat {
        CostStat { median_ns: ns, min_ns: ns, max_ns: ns, low_ns: ns, high_ns: ns, repeats: 1, batch }
    }

    /// From the per-evaluation times of the timed passes (any order).
    fn from_passes(mut times: Vec<f64>, batch: usize) -> CostStat {
        times.sort_by(f64::total_cmp);
        let n = times.len();
        let inner = usize::from(n >= 5);
        CostStat {
            median_ns: times[n / 2],
            min_ns: times[0],
            max_ns: times[n - 1],
            low_ns: times[inner],
            high_ns: times[n - 1 - inner],
            repeats: n,
            batch,
        }
    }
}

/// One runtime evaluation to measure: `f` over input indices (`items`), each evaluated
/// `work` times per pass (≥ 1; the cost-axis test's "twice as expensive" mutation is
/// `work = 2`, still divided by the batch).
pub struct CostJob<'a> {
    items: Vec<usize>,
    work: usize,
    f: Box<dyn FnMut(usize) -> [f64; 3] + Send + 'a>,
}

impl std::fmt::Debug for CostJob<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CostJob").field("items", &self.items.len()).field("work", &self.work).finish_non_exhaustive()
    }
}

impl<'a> CostJob<'a> {
    /// `f` over the inputs `0..count` (strided down to about [`MIN_BATCH`]).
    pub fn over(count: usize, work: usize, f: impl FnMut(usize) -> [f64; 3] + Send + 'a) -> CostJob<'a> {
        CostJob::over_items((0..count).collect(), work, f)
    }

    /// `f` over the given input indices (strided down to about [`MIN_BATCH`]).
    pub fn over_items(items: Vec<usize>, work: usize, f: impl FnMut(usize) -> [f64; 3] + Send + 'a) -> CostJob<'a> {
        let stride = (items.len() / MIN_BATCH).max(1);
        let items = items.into_iter().step_by(stride).collect();
        CostJob { items, work: work.max(1), f: Box::new(f) }
    }

    /// One pass of `rounds` cycles over the inputs, returning its wall time in seconds.
    fn pass(&mut self, rounds: usize) -> f64 {
        let t = Instant::now();
        let mut acc = 0.0;
        for _ in 0..rounds {
            for &k in &self.items {
                for _ in 0..self.work {
                    acc += black_box((self.f)(black_box(k)))[0];
                }
            }
        }
        black_box(acc);
        t.elapsed().as_secs_f64()
    }
}

/// Measures one job alone (for a single mode; a run measures all its jobs with
/// [`measure_side_by_side`]).
pub fn measure(mut job: CostJob<'_>) -> CostStat {
    measure_side_by_side(std::slice::from_mut(&mut job)).pop().expect("one job")
}

/// Measures the jobs side by side (see the module docs); one result per job, in order.
/// Runs on the calling thread; call it when no other work of the process is running.
pub fn measure_side_by_side(jobs: &mut [CostJob<'_>]) -> Vec<CostStat> {
    // Warm-up and sizing, job by job.
    let cycles: Vec<usize> = jobs
        .iter_mut()
        .map(|job| {
            if job.items.is_empty() {
                return 0;
            }
            let per_eval = job.pass(1) / (job.items.len() * job.work) as f64;
            let want = (MIN_PASS_S / per_eval.max(1e-12)).min(64.0 * MIN_BATCH as f64) as usize;
            let cycles = MIN_BATCH.max(want).div_ceil(job.items.len() * job.work).max(1);
            job.pass(cycles);
            cycles
        })
        .collect();
    let mut times = vec![Vec::with_capacity(REPEATS); jobs.len()];
    for round in 0..REPEATS {
        let order: Vec<usize> = if round % 2 == 0 { (0..jobs.len()).collect() } else { (0..jobs.len()).rev().collect() };
        for j in order {
            if cycles[j] > 0 {
                let batch = cycles[j] * jobs[j].items.len();
                times[j].push(jobs[j].pass(cycles[j]) * 1e9 / batch as f64);
            }
        }
    }
    times
        .into_iter()
        .zip(jobs.iter().zip(&cycles))
        .map(|(t, (job, c))| if t.is_empty() { CostStat::default() } else { CostStat::from_passes(t, c * job.items.len()) })
        .collect()
}

/// Encode runs stop repeating once they have taken this long together: a run of a
/// tenth of a second is its own steady state (timer and scheduling noise are far below its
/// length), and repeating it only lengthens the run on large maps.
pub const ENCODE_BUDGET_S: f64 = 0.1;

/// An encode's timing: the median of `runs` runs, and the fastest and slowest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timing {
    pub median_s: f64,
    pub min_s: f64,
    pub max_s: f64,
    pub runs: usize,
}

/// A mode's encode (its fit from the map) to time: `f` re-runs it, `repeats` times at most.
pub struct EncodeJob<'a> {
    repeats: usize,
    f: Box<dyn FnMut() + Send + 'a>,
}

impl std::fmt::Debug for EncodeJob<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EncodeJob").field("repeats", &self.repeats).finish_non_exhaustive()
    }
}

impl<'a> EncodeJob<'a> {
    pub fn new(repeats: usize, f: impl FnMut() + Send + 'a) -> EncodeJob<'a> {
        EncodeJob { repeats: repeats.max(1), f: Box::new(f) }
    }
}

/// Times the encodes, one job per core at a time (rayon's pool), each job's runs in a row on
/// its thread until it has run `repeats` times or taken [`ENCODE_BUDGET_S`] together (at
/// least once). An encode is single-threaded, as a probe's encode in an engine is, and runs
/// beside others as a bake encodes many probes at once; timing them one at a time would
/// make a large map's run wait seconds on one core. Call it when no other work runs.
pub fn time_encodes(jobs: &mut [EncodeJob<'_>]) -> Vec<Timing> {
    use rayon::prelude::*;
    jobs.par_iter_mut()
        .with_max_len(1)
        .map(|job| {
            let mut t: Vec<f64> = Vec::with_capacity(job.repeats);
            while t.len() < job.repeats && (t.is_empty() || t.iter().sum::<f64>() < ENCODE_BUDGET_S) {
                let start = Instant::now();
                (job.f)();
                t.push(start.elapsed().as_secs_f64());
            }
            t.sort_by(f64::total_cmp);
            Timing { median_s: t[t.len() / 2], min_s: t[0], max_s: t[t.len() - 1], runs: t.len() }
        })
        .collect()
}

/// Bytes per probe (or lightmap texel) at the runtime precision (f32): the scalars the
/// runtime reads. Lobe axes and sharpness are shared by every probe of a basis and not
/// counted.
pub fn storage_bytes(scalars: usize) -> usize {
    4 * scalars
}
