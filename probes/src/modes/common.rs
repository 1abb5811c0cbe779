//! What the mode families share: timing and cost jobs, the runtime's RGB dot product, the
//! SG evaluators, reconstruction images, and [`Prepared`] with its maker `mk!`.

use super::context::{Context, ModeResult, SgIrradiance};
use crate::cost::CostJob;
use sbf::glam::DVec3;
use sbf::nalgebra::DMatrix;
use sbf::recon::sg as sgr;
use sbf::solve::RadianceSample;
use sbf::{Basis, SgBasis};

/// RGB coefficients, one per basis function.
pub(crate) type Rgb = Vec<[f64; 3]>;

/// Y (36), Co (12), Cg (12) coefficient vectors of the YCoCg mode.
pub(crate) type YCoCgCoeffs = (Vec<f64>, Vec<f64>, Vec<f64>);

/// Draws of the Monte Carlo mode (the peer's MCIS default).
pub const MCIS_SAMPLES: usize = 5000;

/// Samples taken by the progressive modes.
pub const PROGRESSIVE_SAMPLES: u64 = 4096;

pub(crate) fn channels(m: &DMatrix<f64>) -> Vec<[f64; 3]> {
    (0..m.nrows()).map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]).collect()
}

pub(crate) fn channel(c: &[[f64; 3]], k: usize) -> Vec<f64> {
    c.iter().map(|v| v[k]).collect()
}

pub use crate::cost::{EncodeJob, Timing, ENCODE_BUDGET_S};

/// `f` run once (untimed) for its result, and `f` as the job that times it later
/// (`repeats` runs, [`crate::cost::time_encodes`]). `f` owns what it reads, so
/// the job outlives this mode's other work.
pub(crate) fn timed<'a, T: 'a>(repeats: usize, mut f: impl FnMut() -> T + Send + 'a) -> (T, EncodeJob<'a>) {
    let out = f();
    (out, EncodeJob::new(repeats, move || drop(std::hint::black_box(f()))))
}

/// The image of `f` over the output directions, and `f` as the job that measures its
/// steady-state cost later ([`crate::cost`]: a run measures every mode's job side by side).
pub(crate) fn eval_cost<'a>(ctx: &'a Context, mut f: impl FnMut(DVec3) -> [f64; 3] + Send + 'a) -> (Vec<[f64; 3]>, Option<CostJob<'a>>) {
    let out: Vec<[f64; 3]> = ctx.dirs.iter().map(|d| f(*d)).collect();
    let dirs = &ctx.dirs;
    (out, Some(CostJob::over(dirs.len(), ctx.eval_work, move |k| f(dirs[k]))))
}

/// Σ_i w_i·c_i over RGB coefficients: the runtime's form (each basis function's weight
/// computed once, then one multiply-add per channel).
pub(crate) fn dot_rgb(c: &[[f64; 3]], w: impl Iterator<Item = f64>) -> [f64; 3] {
    let mut e = [0.0; 3];
    for (ci, wi) in c.iter().zip(w) {
        for k in 0..3 {
            e[k] += wi * ci[k];
        }
    }
    e
}

/// E/π of an SG 12 mode from RGB coefficients (each lobe's kernel once), the same
/// function as `sbf::recon::sg::irradiance_basis` per channel (test
/// `runtime_evaluators_equal_the_per_channel_library`).
pub(crate) fn sg_irradiance_rgb(method: SgIrradiance, id: &str, basis: &SgBasis, lobes: &SgLobes, c: &[[f64; 3]], n: DVec3) -> [f64; 3] {
    let k = basis.lobe_count();
    let mut e = match method.for_mode(id) {
        // (The prior estimate has its own evaluator, `PriorRgb`; Hill stands in here.)
        SgIrradiance::Hill | SgIrradiance::Auto | SgIrradiance::Prior => dot_rgb(&c[..k], lobes.hill.iter().map(|h| h.eval(n))),
        SgIrradiance::Peer => dot_rgb(&c[..k], lobes.axes.iter().zip(&lobes.peer).map(|(a, p)| p.eval(a.dot(n).clamp(-1.0, 1.0)))),
    };
    // The ambient function (a constant) reflects its coefficient under any kernel of integral π.
    if basis.has_ambient() {
        for ch in 0..3 {
            e[ch] += c[k][ch];
        }
    }
    e
}

/// The isotropic-prior irradiance estimate of an SG basis from RGB coefficients c' =
/// Σ⁻¹G·c ([`sbf::recon::prior`]): each function's kernel once per direction.
#[derive(Clone)]
pub(crate) struct PriorRgb {
    est: sbf::recon::prior::PriorIrradiance,
    weights: Vec<f64>,
}

impl PriorRgb {
    pub(crate) fn new(basis: &SgBasis) -> Result<PriorRgb, sbf::SbfError> {
        let est = sbf::recon::prior::PriorIrradiance::for_sg_basis(basis, sbf::recon::prior::RadiancePrior::default())?;
        Ok(PriorRgb { weights: vec![0.0; est.len()], est })
    }

    /// c' per channel (what a probe stores for this reconstruction; c follows back by the
    /// inverse transform for radiance and specular).
    pub(crate) fn coefficients(&self, c: &[[f64; 3]]) -> Result<Vec<[f64; 3]>, sbf::SbfError> {
        let per: Vec<Vec<f64>> = (0..3).map(|k| self.est.coefficients(&channel(c, k))).collect::<Result<_, _>>()?;
        Ok((0..c.len()).map(|i| [per[0][i], per[1][i], per[2][i]]).collect())
    }

    pub(crate) fn eval(&mut self, cp: &[[f64; 3]], n: DVec3) -> [f64; 3] {
        self.est.weights(n, &mut self.weights);
        dot_rgb(cp, self.weights.iter().copied())
    }
}

/// The lobes of an SG basis with each reconstruction's per-lobe constants precomputed:
/// Hill's, and the peer's kernel (sharpness for mode `id`) as a zonal series
/// (`sbf::recon::prior::sg_kernel_series`, = `sg::irradiance_sg_kernel` to 1e-12).
pub(crate) struct SgLobes {
    pub(crate) axes: Vec<DVec3>,
    pub(crate) hill: Vec<sgr::HillLobe>,
    pub(crate) peer: Vec<sbf::recon::prior::Kernel>,
}

pub(crate) fn sg_lobes(basis: &SgBasis, id: &str) -> SgLobes {
    let kl = SgIrradiance::peer_kernel_sharpness(id);
    let lobes: Vec<sbf::Sg> = (0..basis.lobe_count()).map(|i| basis.lobe(i)).collect();
    SgLobes {
        axes: lobes.iter().map(|l| l.axis).collect(),
        hill: lobes.iter().map(sgr::HillLobe::new).collect(),
        peer: lobes.iter().map(|l| sbf::recon::prior::sg_kernel_series(l.sharpness, kl)).collect(),
    }
}

/// A basis's reconstruction from RGB coefficients as the irradiance evaluation (fits to
/// the irradiance image), with its cost.
pub(crate) fn eval_basis<'a, B: Basis + Send + 'a>(ctx: &'a Context, basis: B, c: Vec<[f64; 3]>) -> (Vec<[f64; 3]>, Option<CostJob<'a>>) {
    let mut s = vec![0.0; basis.len()];
    eval_cost(ctx, move |d| {
        basis.eval_into(d, &mut s);
        dot_rgb(&c, s.iter().copied())
    })
}

/// The radiance image of RGB coefficients (basis evaluated once per direction; parallel,
/// untimed).
pub(crate) fn reconstruct(basis: &(dyn Basis + Sync), c: &[[f64; 3]], dirs: &[DVec3]) -> Vec<[f64; 3]> {
    use rayon::prelude::*;
    dirs.par_iter()
        .map_init(
            || vec![0.0; basis.len()],
            |s, d| {
                basis.eval_into(*d, s);
                dot_rgb(c, s.iter().copied())
            },
        )
        .collect()
}

/// Irradiance image as samples for fits to E/π. Like the peer, every output texel
/// weighs the same: these fits minimise exactly the unweighted RMS the reports quote.
pub(crate) fn irradiance_samples(ctx: &Context) -> Vec<RadianceSample> {
    ctx.dirs.iter().zip(&ctx.irradiance).map(|(d, e)| RadianceSample { direction: *d, value: *e, weight: 1.0 }).collect()
}

/// Clamps an irradiance image at 0 (as the peer displays and measures SH
/// reconstructions) and returns the fraction of texels that were negative.
pub(crate) fn clamp_negative(img: &mut [[f64; 3]]) -> f64 {
    let mut neg = 0usize;
    for t in img.iter_mut() {
        if t.iter().any(|v| *v < 0.0) {
            neg += 1;
        }
        for v in t.iter_mut() {
            *v = v.max(0.0);
        }
    }
    neg as f64 / img.len().max(1) as f64
}

/// A mode run except for its steady-state cost: the result (with `eval` not yet
/// measured) and the job that measures it (none for the Monte Carlo mode, whose cost is
/// its encode). A run measures every mode's job side by side
/// ([`crate::cost::measure_side_by_side`]) and stores each cost in `result.eval`.
#[derive(Debug)]
pub struct Prepared<'a> {
    pub result: ModeResult,
    pub eval: Option<CostJob<'a>>,
    /// The encode's timing job ([`Prepared::set_encode`] stores its result).
    pub encode: Option<EncodeJob<'a>>,
    /// The Monte Carlo mode: its per-texel cost is its encode time per output texel.
    pub eval_from_encode: bool,
}

impl Prepared<'_> {
    /// Stores the encode's timing (and, for the Monte Carlo mode, the cost it implies).
    pub fn set_encode(result: &mut ModeResult, t: Timing, eval_from_encode: bool, texels: usize) {
        result.encode_s = t.median_s;
        result.encode_runs = t.runs;
        result.encode_range_s = [t.min_s, t.max_s];
        if eval_from_encode {
            result.eval = crate::cost::CostStat::single(t.median_s * 1e9 / texels.max(1) as f64, texels);
        }
    }
}

/// An [`sbf::SbfError`] as the modes report it.
pub(crate) fn err(e: sbf::SbfError) -> String {
    e.to_string()
}

/// What a fit produced, before the run measures its cost (`mk!` builds it).
pub(crate) struct Parts<'a> {
    pub basis: String,
    pub solver: &'static str,
    pub coefficients: Vec<[f64; 3]>,
    pub lobes: Vec<(DVec3, f64)>,
    pub radiance: Option<Vec<[f64; 3]>>,
    pub irradiance: Vec<[f64; 3]>,
    pub encode: EncodeJob<'a>,
    pub eval: Option<CostJob<'a>>,
}

impl<'a> Prepared<'a> {
    /// Mode `id`'s result from its parts, every other field at its default (the caller
    /// sets what differs; `prepare` sets the description).
    pub(crate) fn from_parts(id: &'static str, ctx: &Context, p: Parts<'a>) -> Prepared<'a> {
        Prepared {
            eval: p.eval,
            encode: Some(p.encode),
            eval_from_encode: false,
            result: ModeResult {
                id,
                name: "",
                basis: p.basis,
                solver: p.solver,
                lobes: p.lobes,
                radiance: p.radiance,
                irradiance: p.irradiance,
                clamped_negative_fraction: None,
                stored_scalars: 3 * p.coefficients.len(),
                engine_bytes: None,
                storage: ctx.storage,
                precision: None,
                wgsl_irradiance: true,
                irradiance_variant: "",
                encode_s: 0.0,
                encode_runs: 0,
                encode_range_s: [0.0; 2],
                needs_reference: false,
                eval: Default::default(),
                coefficients: p.coefficients,
                convergence: Vec::new(),
            },
        }
    }
}

/// `mk!(id, ctx; basis, solver, coefficients, lobes, radiance, irradiance, encode, eval)`:
/// [`Prepared::from_parts`] with the parts in that order.
macro_rules! mk {
    ($id:expr, $ctx:expr; $basis:expr, $solver:expr, $coefficients:expr, $lobes:expr, $radiance:expr, $irradiance:expr, $encode:expr, $eval:expr $(,)?) => {
        $crate::modes::common::Prepared::from_parts(
            $id,
            $ctx,
            $crate::modes::common::Parts {
                basis: $basis,
                solver: $solver,
                coefficients: $coefficients,
                lobes: $lobes,
                radiance: $radiance,
                irradiance: $irradiance,
                encode: $encode,
                eval: $eval,
            },
        )
    };
}
pub(crate) use mk;
