//! Non-negative fits that keep the light the map holds.
//!
//! A non-negative least-squares fit of a small bright source keeps more than its light: no
//! negative neighbour can cancel a lobe's excess (docs/probes.md, "Irradiance bias": `sgnnls`
//! ×1.10 on the built-in sky). These modes solve NNLS under equality constraints
//! ([`sbf::solve::nnls_gram_eq`]: null-space elimination, then NNLS of the least-distance
//! problem, with its KKT check) that pin the fit's SH L0 and L1 projections to the map's.
//! E/π is the radiance convolved with the clamped cosine, band by band L₀₀Y₀₀ + ⅔·Σₘ L₁ₘY₁ₘ +
//! ¼·Σₘ L₂ₘY₂ₘ + … (Ramamoorthi & Hanrahan 2001), so the fit's irradiance keeps the map's mean
//! and linear bands exactly, and NNLS fits the rest. Where a channel's four equalities admit
//! no non-negative solution (a source more directional than any combination of lobes can be),
//! that channel keeps L0 alone, and the mode's solver text says so.
//!
//! The moments come two ways:
//! - batch (`sgnnlsc`, `adnnlsc`): the map's texel quadrature, as `sgnnls`;
//! - progressive (`sgpnnlsc`, `adpnnlsc`): per function the running mean of B_i(ω)·L(ω) (and of
//!   Y_lm(ω)·L(ω)) over [`PROGRESSIVE_SAMPLES`] uniform Halton directions, kept in f32 as a GPU
//!   texel would keep one RGB value per function. 4π times that mean is the Monte Carlo
//!   projection ∫B_i·L, unbiased after any number of samples; the fit then uses the basis'
//!   exact Gram over the sphere. Roughton's progressive encoder (§7.3, modes `sgpls` …
//!   `adpnnls`) iterates on the running sample Gram instead and lags behind its limit.

use super::common::{dot_rgb, eval_cost, reconstruct, sg_irradiance_rgb, sg_lobes, timed, EncodeJob, Prepared, PROGRESSIVE_SAMPLES};
use super::context::{Context, SgIrradiance};
use crate::cost::CostJob;
use sbf::glam::DVec3;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::nalgebra::DMatrix;
use sbf::recon::{ambient_dice as adr, sg as sgr};
use sbf::solve::{moments, nnls_gram_eq, projection_matrix, Kernel, NnlsOptions, ProjectionOptions};
use sbf::{AmbientDiceSrbf, Basis, Domain, SbfError, SgBasis, ShBasis};
use std::sync::Arc;

/// The modes of this module (listed with their descriptions in [`super::MODES`]).
pub const IDS: [&str; 4] = ["sgnnlsc", "adnnlsc", "sgpnnlsc", "adpnnlsc"];

/// Whether `id` is one of [`IDS`].
pub fn is_mode(id: &str) -> bool {
    IDS.contains(&id)
}

/// RGB coefficients, one per basis function.
type Rgb = Vec<[f64; 3]>;

/// A conserving mode run except for its cost measurement (`mode` wraps it for [`super::prepare`]).
#[derive(Debug)]
pub struct Run<'a> {
    /// The basis' name.
    pub basis: String,
    /// How the coefficients were solved (names a fallback to L0 alone).
    pub solver: &'static str,
    /// Stored coefficients.
    pub coefficients: Rgb,
    /// (axis, sharpness) per lobe (sharpness 0 for Ambient Dice).
    pub lobes: Vec<(DVec3, f64)>,
    /// The radiance image of the stored coefficients.
    pub radiance: Vec<[f64; 3]>,
    /// E/π on the output grid.
    pub irradiance: Vec<[f64; 3]>,
    /// The encode's timing job.
    pub encode: EncodeJob<'a>,
    /// The evaluation's cost job.
    pub eval: Option<CostJob<'a>>,
    /// Irradiance RMS against sample count (progressive modes).
    pub convergence: Vec<(u64, f64)>,
}

/// The fixed parts of the constrained fit: the basis, its exact Gram over the sphere, and C
/// (4 × n), the SH L0 + L1 projections ∫Y_lm·B_i of its functions.
#[derive(Clone)]
pub struct Problem {
    basis: Arc<dyn Basis + Send + Sync>,
    sh: ShBasis,
    gram: DMatrix<f64>,
    constraints: DMatrix<f64>,
}

/// How a fit met its constraints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Kept {
    /// Channels whose four equalities held.
    pub l0_l1: usize,
    /// Channels whose L0 + L1 equalities were infeasible and that kept L0 alone.
    pub l0_only: usize,
}

impl std::fmt::Debug for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Problem").field("basis", &self.basis.name()).field("constraints", &self.constraints).finish_non_exhaustive()
    }
}

impl Problem {
    /// For a basis of functions over the sphere. C by a 256 × 512 Gauss product rule (exact
    /// for SG to rounding; for the Ambient Dice lobes, whose edge is a kink, within 1e-6 of
    /// their integral).
    pub fn new(basis: Arc<dyn Basis + Send + Sync>) -> Result<Problem, SbfError> {
        let sh = ShBasis::new(1)?;
        let gram = gram_matrix(basis.as_ref(), Domain::Sphere, GramOptions::default())?.matrix;
        let opts = ProjectionOptions { outer_n_z: 256, ..ProjectionOptions::default() };
        let constraints = projection_matrix(&sh, basis.as_ref(), Kernel::Delta, opts)?;
        Ok(Problem { basis, sh, gram, constraints })
    }

    /// The basis.
    pub fn basis(&self) -> &(dyn Basis + Send + Sync) {
        self.basis.as_ref()
    }

    /// C, the SH L0 + L1 projections of the basis' functions (4 × n).
    pub fn constraints(&self) -> &DMatrix<f64> {
        &self.constraints
    }

    /// The non-negative coefficients (per channel) minimising ‖Σ b_i B_i − L‖² with the
    /// fit's SH L0 + L1 projections equal to `sh_moments` (4 × 3, ∫Y_lm·L), given the
    /// basis' moments `m` (n × 3, ∫B_i·L). A channel whose four equalities no non-negative
    /// fit meets keeps L0 alone (counted in [`Kept`]).
    pub fn solve(&self, m: &DMatrix<f64>, sh_moments: &DMatrix<f64>) -> Result<(Rgb, Kept), SbfError> {
        let n = self.basis.len();
        let mut out = vec![[0.0; 3]; n];
        let mut kept = Kept::default();
        for k in 0..3 {
            let col: Vec<f64> = m.column(k).iter().copied().collect();
            let d: Vec<f64> = sh_moments.column(k).iter().copied().collect();
            let sol = match nnls_gram_eq(&self.gram, &col, &self.constraints, &d, NnlsOptions::default()) {
                Ok(s) => {
                    kept.l0_l1 += 1;
                    s
                }
                Err(SbfError::InvalidParameter { name: "equality constraints", .. }) => {
                    kept.l0_only += 1;
                    nnls_gram_eq(&self.gram, &col, &self.constraints.rows(0, 1).into_owned(), &d[..1], NnlsOptions::default())?
                }
                Err(e) => return Err(e),
            };
            for i in 0..n {
                out[i][k] = sol.coeffs[i];
            }
        }
        Ok((out, kept))
    }

    /// The batch fit: moments by the samples' own quadrature (texel solid angles).
    pub fn solve_samples(&self, samples: &[sbf::solve::RadianceSample]) -> Result<(Rgb, Kept), SbfError> {
        self.solve(&moments(self.basis.as_ref(), samples), &moments(&self.sh, samples))
    }
}

/// Running means of B_i(ω)·L(ω) and Y_lm(ω)·L(ω) over uniformly distributed directions, in
/// f32 (what a GPU texel keeps: one RGB value per function and a count).
#[derive(Debug, Clone)]
pub struct Projections {
    basis: Vec<[f32; 3]>,
    sh: Vec<[f32; 3]>,
    count: u64,
    scratch: Vec<f64>,
}

impl Projections {
    /// Empty means for `p`'s basis.
    pub fn new(p: &Problem) -> Projections {
        Projections { basis: vec![[0.0; 3]; p.basis.len()], sh: vec![[0.0; 3]; 4], count: 0, scratch: vec![0.0; p.basis.len()] }
    }

    /// Adds the radiance `value` seen in direction `d` (drawn uniformly over the sphere).
    pub fn add(&mut self, p: &Problem, d: DVec3, value: [f64; 3]) {
        self.count += 1;
        let s = 1.0 / self.count as f32;
        let v = value.map(|x| x as f32);
        let update = |means: &mut [[f32; 3]], b: &[f64]| {
            for (m, bi) in means.iter_mut().zip(b) {
                for c in 0..3 {
                    m[c] += s * (*bi as f32 * v[c] - m[c]);
                }
            }
        };
        self.scratch.resize(p.basis.len(), 0.0);
        p.basis.eval_into(d, &mut self.scratch);
        update(&mut self.basis, &self.scratch);
        self.scratch.resize(4, 0.0);
        p.sh.eval_into(d, &mut self.scratch);
        update(&mut self.sh, &self.scratch);
    }

    /// (∫B_i·L, ∫Y_lm·L) as 4π times the means: the Monte Carlo projections.
    pub fn moments(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let to = |m: &[[f32; 3]]| DMatrix::from_fn(m.len(), 3, |i, c| 4.0 * std::f64::consts::PI * m[i][c] as f64);
        (to(&self.basis), to(&self.sh))
    }
}

/// Runs conserving mode `id` (one of [`IDS`]).
pub fn prepare<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Run<'a>, String> {
    let err = |e: SbfError| e.to_string();
    let is_sg = id.starts_with("sg");
    let (basis, lobes): (Arc<dyn Basis + Send + Sync>, Vec<(DVec3, f64)>) = if is_sg {
        let axes = sbf::layout::vogel_sphere(12).map_err(err)?;
        (Arc::new(SgBasis::new(&axes, 6.0, false).map_err(err)?), axes.iter().map(|a| (*a, 6.0)).collect())
    } else {
        let ad = AmbientDiceSrbf::twelve();
        let l = ad.lobes().iter().map(|a| (*a, 0.0)).collect();
        (Arc::new(ad), l)
    };
    let problem = Problem::new(basis.clone()).map_err(err)?;
    // Per-lobe E/π at a normal: Hill's fit for SG (the WGSL runtime's), the exact quartic for
    // the Ambient Dice lobes; one kernel per lobe layout, as the other SG and AD modes evaluate.
    let hill: Vec<sgr::HillLobe> =
        lobes.iter().map(|(a, l)| sgr::HillLobe::new(&sbf::Sg { axis: *a, sharpness: *l, amplitude: 1.0 })).collect();
    let axes: Vec<DVec3> = lobes.iter().map(|(a, _)| *a).collect();
    let kernel = |d: DVec3, i: usize| if is_sg { hill[i].eval(d) } else { adr::lobe_irradiance_cos(axes[i].dot(d)) };
    let progressive = id.contains("pnnls");
    let samples: Arc<Vec<(DVec3, [f64; 3])>> = Arc::new(if progressive {
        (0..PROGRESSIVE_SAMPLES)
            .map(|i| {
                let d = sbf::sampling::uniform_sphere(sbf::sampling::halton2(i));
                (d, ctx.map.bilinear(d))
            })
            .collect()
    } else {
        Vec::new()
    });
    let (p, smp) = (problem.clone(), samples.clone());
    let (fit, encode) = timed(repeats, move || -> Result<(Rgb, Kept), SbfError> {
        if progressive {
            let mut acc = Projections::new(&p);
            for (d, v) in smp.iter() {
                acc.add(&p, *d, *v);
            }
            let (m, sh) = acc.moments();
            p.solve(&m, &sh)
        } else {
            p.solve_samples(&ctx.samples)
        }
    });
    let (c, kept) = fit.map_err(err)?;
    let c = ctx.stored(c);
    let nb = basis.len();
    let (irradiance, eval) = if is_sg {
        // The other SG 12 modes' evaluator, Hill's fit (`sgpnnls`'s).
        let sgb = SgBasis::new(&axes, 6.0, false).map_err(err)?;
        let (l, cc) = (sg_lobes(&sgb, id), c.clone());
        eval_cost(ctx, move |d| sg_irradiance_rgb(SgIrradiance::Hill, id, &sgb, &l, &cc, d))
    } else {
        let (a, cc) = (axes.clone(), c.clone());
        eval_cost(ctx, move |d| dot_rgb(&cc, a.iter().map(|x| adr::lobe_irradiance_cos(x.dot(d)))))
    };
    // Error against sample count (progressive modes): an untimed second pass with snapshots
    // at 16, 32, … samples, each solved as the final fit is.
    let mut convergence = Vec::new();
    if progressive {
        let kmat: Vec<f64> = ctx.dirs.iter().flat_map(|d| (0..nb).map(move |i| (*d, i))).map(|(d, i)| kernel(d, i)).collect();
        let mut acc = Projections::new(&problem);
        let mut next = 16usize;
        for (k, (d, v)) in samples.iter().enumerate() {
            acc.add(&problem, *d, *v);
            let n = k + 1;
            if n == next || n == samples.len() {
                let (m, sh) = acc.moments();
                let (cs, _) = problem.solve(&m, &sh).map_err(err)?;
                let img: Vec<[f64; 3]> = {
                    use rayon::prelude::*;
                    kmat.par_chunks_exact(nb).map(|w| dot_rgb(&cs, w.iter().copied())).collect()
                };
                convergence.push((n as u64, crate::metrics::rms_rows(ctx.grid, &img, &ctx.irradiance, ctx.metric_rows())));
                while next <= n {
                    next *= 2;
                }
            }
        }
    }
    let solver = match (progressive, kept.l0_only) {
        (false, 0) => "NNLS keeping the map's SH L0 + L1 (equality constraints)",
        (false, _) => "NNLS keeping the map's SH L0 + L1; L0 alone where L1 was infeasible",
        (true, 0) => "progressive Monte Carlo projections, f32 state, exact Gram; NNLS keeping SH L0 + L1",
        (true, _) => "progressive Monte Carlo projections, exact Gram; NNLS keeping SH L0 + L1, L0 alone where L1 was infeasible",
    };
    Ok(Run {
        basis: basis.name(),
        solver,
        radiance: reconstruct(basis.as_ref(), &c, &ctx.dirs),
        coefficients: c,
        lobes,
        irradiance,
        encode,
        eval,
        convergence,
    })
}

/// Runs conserving mode `id` up to its cost measurement ([`super::prepare`]).
pub(super) fn mode<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let run = prepare(id, ctx, repeats)?;
    let mut r = super::common::mk!(id, ctx; run.basis, run.solver, run.coefficients, run.lobes, Some(run.radiance), run.irradiance, run.encode, run.eval);
    r.result.convergence = run.convergence;
    Ok(r)
}
