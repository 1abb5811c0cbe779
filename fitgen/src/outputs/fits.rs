//! Fit constants: AD diffuse polynomials, SG cosine-lobe sharpness, Hill's constant.

use sbf::glam::DVec3;
use sbf::recon::{ambient_dice as ad, sg as sgr};
use std::f64::consts::PI;

/// All derived constants with their errors.
#[derive(Debug, Clone)]
pub struct Fits {
    /// The degree-2 least-squares fit on Chebyshev nodes of the exact lobe irradiance
    /// (the runtime quadratic), with (max, rms) errors on a 4001-point uniform grid in c.
    /// (Degrees 3–6 are gone: degree 4 is the exact quartic the f64 code evaluates, and
    /// nothing at run time used the others.)
    pub ad_diffuse: Vec<(usize, Vec<f64>, f64, f64)>,
    pub quadratic_max: f64,
    pub quadratic_rms: f64,
    pub seed_quadratic_max: f64,
    /// Hill's c0: (published 0.36 max error, refit c0, refit max error), over λ ∈ [2, 64].
    pub hill: (f64, f64, f64),
    /// How the c0 minimax fit converged.
    pub hill_convergence: crate::optimise::Convergence,
    /// Listing 8.1's eight parameters (Roughton's, which the committed LUT uses): (rms,
    /// max) error on 8 α × 8 n·v × 48 lobes after normalising at the GGX dominant
    /// direction as the 2D LUT does. The committed LUT and runtime keep these constants:
    /// the refits below lower the RMS by 7–9 % but raise the max (see `specular_refits`).
    pub specular: (f64, f64),
    /// Listing 8.1's parameters refitted by Nelder–Mead (least squares over the same
    /// cases) against each ground truth — the physical one and Appendix C's G2·G1
    /// weighting — from Roughton's constants: (ground truth, Roughton's (rms, max), refit's
    /// (rms, max), refit parameters, convergence). Reported, not used: see `parameters`.
    pub specular_refits: Vec<SpecularRefit>,
}

/// One refit of Listing 8.1's parameters.
#[derive(Debug, Clone)]
pub struct SpecularRefit {
    pub ground_truth: &'static str,
    pub seed: (f64, f64),
    pub refit: (f64, f64),
    pub params: Vec<f64>,
    pub convergence: crate::optimise::Convergence,
}

/// Ground truth and geometry for the specular-parameter fit: 8 α × 8 n·v × 48 lobe
/// axes, F = 1 (f0 + f90 channels), by the lobe quadrature (n = 64).
struct SpecularProblem {
    cases: Vec<(f64, f64, DVec3, f64)>,
    dominant: Vec<(f64, f64, DVec3, f64)>,
    /// Per (α, n·v) case group: G1(v)², the factor Appendix C's G2·G1 weighting puts on
    /// ground truth and table alike (v is fixed per group), so on each error.
    g1_squared: Vec<f64>,
}

impl SpecularProblem {
    fn new() -> Self {
        use rayon::prelude::*;
        let lobes: Vec<DVec3> = (0..48).map(|i| sbf::sampling::spherical_fibonacci(i, 48)).collect();
        let grid: Vec<(f64, f64)> = (0..8).flat_map(|a| (0..8).map(move |n| ((a as f64 + 0.5) / 8.0, (n as f64 + 0.5) / 8.0))).collect();
        let cases = grid
            .par_iter()
            .flat_map_iter(|&(alpha, nv)| {
                lobes.iter().map(move |l| {
                    let g = ad::lobe_specular_quadrature(*l, nv, alpha, 64);
                    (alpha, nv, *l, g[0] + g[1])
                })
            })
            .collect();
        let dominant = grid
            .par_iter()
            .map(|&(alpha, nv)| {
                let v = DVec3::new(0.0, (1.0 - nv * nv).sqrt(), nv);
                let lobe = ad::ggx_dominant_direction(DVec3::Z, sbf::ggx::reflect(v, DVec3::Z), alpha);
                let g = ad::lobe_specular_quadrature(lobe, nv, alpha, 64);
                (alpha, nv, lobe, g[0] + g[1])
            })
            .collect();
        let g1_squared = grid.iter().map(|&(alpha, nv)| sbf::ggx::g1(DVec3::new(0.0, (1.0 - nv * nv).sqrt(), nv), alpha).powi(2)).collect();
        SpecularProblem { cases, dominant, g1_squared }
    }

    /// (rms, max) of fit·(gt_dom/fit_dom) − gt over all cases.
    fn errors(&self, p: &[f64; 8]) -> (f64, f64) {
        self.errors_weighted(p, false)
    }

    /// [`Self::errors`], each error times G1(v)² with `appendix_c` (Roughton's weighting).
    fn errors_weighted(&self, p: &[f64; 8], appendix_c: bool) -> (f64, f64) {
        let (mut ss, mut mx) = (0.0f64, 0.0f64);
        for (k, &(alpha, nv, lobe, gt)) in self.cases.iter().enumerate() {
            let (_, _, dl, dgt) = self.dominant[k / 48];
            let v = DVec3::new(0.0, (1.0 - nv * nv).sqrt(), nv);
            let fit = ad::SpecularFit::new(p, &ad::DIFFUSE_FIT_LISTING_8_1, DVec3::Z, v, alpha);
            let fd = fit.lobe(dl);
            let scale = if fd > 1e-12 { dgt / fd } else { 0.0 };
            let w = if appendix_c { self.g1_squared[k / 48] } else { 1.0 };
            let e = (fit.lobe(lobe) * scale - gt) * w;
            ss += e * e;
            mx = mx.max(e.abs());
        }
        ((ss / self.cases.len() as f64).sqrt(), mx)
    }
}

/// Listing 8.1's parameters refitted against both ground truths (least squares: the
/// RMS is smooth in the parameters, the max is not), from Roughton's constants.
fn specular_refits(problem: &SpecularProblem) -> Result<Vec<SpecularRefit>, String> {
    [("physical", false), ("appendix-c (G2·G1)", true)]
        .into_iter()
        .map(|(name, seed_weighting)| {
            let seed = problem.errors_weighted(&ad::SPECULAR_FIT_LISTING_8_1, seed_weighting);
            let cost = |p: &[f64]| problem.errors_weighted(&p.try_into().expect("8 parameters"), seed_weighting).0;
            let (params, convergence) = crate::optimise::nelder_mead(&ad::SPECULAR_FIT_LISTING_8_1, 0.05, 4000, cost)?;
            let refit = problem.errors_weighted(&params.as_slice().try_into().expect("8 parameters"), seed_weighting);
            Ok(SpecularRefit { ground_truth: name, seed, refit, params, convergence })
        })
        .collect()
}

fn solve_normal(rows: &[Vec<f64>], y: &[f64]) -> Vec<f64> {
    let n = rows[0].len();
    let a = sbf::nalgebra::DMatrix::from_fn(rows.len(), n, |r, c| rows[r][c]);
    let b = sbf::nalgebra::DMatrix::from_column_slice(y.len(), 1, y);
    sbf::solve::solve_design(&a, &b, None, Default::default()).expect("well-posed fit").coeffs.iter().copied().collect()
}

fn poly(p: &[f64], c: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, k| acc * c + k)
}

/// Derives every constant (deterministic; a fraction of a second).
pub fn derive() -> Fits {
    // AD diffuse: fit on 512 Chebyshev nodes (near-minimax), measure on a uniform grid.
    let nodes: Vec<f64> = (0..512).map(|k| (PI * (k as f64 + 0.5) / 512.0).cos()).collect();
    let grid: Vec<f64> = (0..=4000).map(|k| -1.0 + 2.0 * k as f64 / 4000.0).collect();
    let exact = |c: f64| ad::lobe_irradiance_cos(c);
    let mut ad_diffuse = Vec::new();
    for d in 2..=2 {
        let rows: Vec<Vec<f64>> = nodes.iter().map(|c| (0..=d).map(|k| c.powi(k as i32)).collect()).collect();
        let y: Vec<f64> = nodes.iter().map(|c| exact(*c)).collect();
        let p = solve_normal(&rows, &y);
        let errs: Vec<f64> = grid.iter().map(|c| poly(&p, *c) - exact(*c)).collect();
        let max = errs.iter().fold(0.0f64, |a, e| a.max(e.abs()));
        let rms = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt();
        ad_diffuse.push((d, p, max, rms));
    }
    let seed_quadratic_max =
        grid.iter().map(|c| (ad::lobe_irradiance_fit(&ad::DIFFUSE_FIT_EQ_8_14, *c) - exact(*c)).abs()).fold(0.0, f64::max);
    let (quadratic_max, quadratic_rms) = (ad_diffuse[0].2, ad_diffuse[0].3);

    // Hill's c0: max error over λ ∈ {2, 4, …, 64} × 91 angles vs exact convolution,
    // relative to each lobe's peak.
    let lambdas = [2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 48.0, 64.0];
    let cases: Vec<(f64, f64, f64, f64)> = lambdas
        .iter()
        .flat_map(|&l| {
            let peak = sgr::irradiance_exact(&sbf::Sg { axis: DVec3::Z, sharpness: l, amplitude: 1.0 }, DVec3::Z);
            (0..=90).map(move |k| {
                let t = PI * k as f64 / 90.0;
                let sg = sbf::Sg { axis: DVec3::new(t.sin(), 0.0, t.cos()), sharpness: l, amplitude: 1.0 };
                (l, t, sgr::irradiance_exact(&sg, DVec3::Z), peak)
            })
        })
        .collect();
    let hill_err = |c0: f64| cases.iter().map(|&(l, t, e, peak)| (hill_with(c0, l, t) - e).abs() / peak).fold(0.0, f64::max);
    // The max over cases is unimodal in c0 on [0.2, 0.6] (a V at the minimax); Brent's
    // method falls back to golden sections where its parabolas do not fit.
    let (refit, hill_convergence) = crate::optimise::brent(0.2, 0.6, hill_err).expect("Hill c0 minimisation");
    let hill = (hill_err(sgr::HILL_C0_PUBLISHED), refit, hill_err(refit));
    let problem = SpecularProblem::new();
    let specular = problem.errors(&ad::SPECULAR_FIT_LISTING_8_1);
    let specular_refits = specular_refits(&problem).expect("Listing 8.1 refit");
    Fits { ad_diffuse, quadratic_max, quadratic_rms, seed_quadratic_max, hill, hill_convergence, specular, specular_refits }
}

/// Hill's fit with a free constant c0, for a unit-amplitude lobe (E/π).
fn hill_with(c0: f64, lam: f64, theta: f64) -> f64 {
    sgr::hill_curve(c0, lam, theta.cos()) * sbf::basis::sg::sg_unit_integral(lam) / PI
}

impl Fits {
    /// One-line parameter summary for the manifest.
    pub fn parameters(&self) -> String {
        let refits: Vec<String> = self
            .specular_refits
            .iter()
            .map(|r| {
                format!(
                    "against the {} ground truth: seed rms {:.3e} max {:.3e}, refit rms {:.3e} max {:.3e} ({})",
                    r.ground_truth,
                    r.seed.0,
                    r.seed.1,
                    r.refit.0,
                    r.refit.1,
                    r.convergence.summary()
                )
            })
            .collect();
        format!(
            "AD diffuse quadratic on 512 Chebyshev nodes; Hill c0 minimax over λ 2-64 × 91 angles (published 0.36: max {:.3e}; refit {:.5}: max {:.3e}; {}); AD specular seed params (Listing 8.1) error rms {:.3e} max {:.3e}; Listing 8.1 refitted (least squares), not used: {}",
            self.hill.0,
            self.hill.1,
            self.hill.2,
            self.hill_convergence.summary(),
            self.specular.0,
            self.specular.1,
            refits.join("; ")
        )
    }

    /// Renders fits.rs and fits.wgsl; `tables` supplies the byte sizes that sbf
    /// asserts at compile time.
    pub fn render(&self, tables: &[(&str, &str, usize)]) -> (String, String) {
        let f = |x: f64| format!("{x:.17e}");
        let mut rs = String::new();
        rs += "// generated by `fitgen fits` — do not edit. Errors and commands: luts/MANIFEST.\n";
        rs += "// Included by sbf (src/luts/committed.rs).\n\n";
        for (d, p, max, rms) in &self.ad_diffuse {
            rs += &format!("/// AD SRBF lobe irradiance (E/π) as a degree-{d} polynomial in cos θ, constant term first; max error {max:.3e}, RMS {rms:.3e}.\n");
            rs += &format!(
                "pub const AD_DIFFUSE_DEGREE_{d}: [f64; {}] = [{}];\n",
                p.len(),
                p.iter().map(|x| f(*x)).collect::<Vec<_>>().join(", ")
            );
        }
        rs += &format!("/// Max error of [Roughton19 eq. 8.14] on the same grid: {:.3e}.\n", self.seed_quadratic_max);
        rs += &format!("pub const AD_DIFFUSE_SEED_EQ_8_14_MAX_ERROR: f64 = {};\n", f(self.seed_quadratic_max));
        rs += &format!(
            "/// Hill's c0 re-fitted (minimax over λ ∈ [2, 64]); max error / peak {:.3e} (published 0.36: {:.3e}).\n",
            self.hill.2, self.hill.0
        );
        rs += &format!("pub const HILL_C0: f64 = {};\n", f(self.hill.1));
        rs += &format!(
            "/// The error HILL_C0 reaches: max |Hill − exact| / peak E/π over λ ∈ {{2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64}} × 91 angles θ = kπ/90.\npub const HILL_C0_MAX_ERROR: f64 = {};\n",
            f(self.hill.2)
        );
        for (name, file, size) in tables {
            let c = name.to_uppercase().replace('-', "_");
            rs += &format!("/// Byte size of luts/{file} (asserted by sbf at compile time).\n");
            rs += &format!("pub const {c}_BYTES: usize = {size};\n");
        }
        let mut w = String::new();
        w += "// generated by `fitgen fits` — do not edit. Errors and commands: luts/MANIFEST.\n\n";
        let q = &self.ad_diffuse[0].1;
        w += &format!("// AD SRBF lobe irradiance quadratic (E/π), max error {:.3e}.\n", self.quadratic_max);
        w += &format!("const AD_DIFFUSE_QUADRATIC: vec3<f32> = vec3<f32>({:.9}, {:.9}, {:.9});\n", q[0], q[1], q[2]);
        w += &format!("const HILL_C0: f32 = {:.9};\n", self.hill.1);
        let se = &self.specular;
        w += &format!(
            "// Seed Listing 8.1 specular blend parameters and its diffuse quadratic (what the committed AD LUTs\n// were built with); LUT-normalised error RMS {:.3e}, max {:.3e}.\n",
            se.0, se.1
        );
        let sp = sbf::recon::ambient_dice::SPECULAR_FIT_LISTING_8_1;
        w += &format!(
            "const AD_SPECULAR_PARAMS: array<f32, 8> = array<f32, 8>({});\n",
            sp.iter().map(|x| format!("{x:.9}")).collect::<Vec<_>>().join(", ")
        );
        let sd = sbf::recon::ambient_dice::DIFFUSE_FIT_LISTING_8_1;
        w += &format!("const AD_SPECULAR_DIFFUSE: vec3<f32> = vec3<f32>({:.9}, {:.9}, {:.9});\n", sd[0], sd[1], sd[2]);
        let g = super::LOBE_GRID;
        rs += &format!(
            "/// Node counts of the lobe GGX tables: n·v, √α, γ, ψ.\npub const LOBE_GGX_NODES: [usize; 4] = [{}, {}, {}, {}];\n",
            g.theta_v, g.alpha, g.gamma, g.psi
        );
        w += &format!("// Lobe GGX tables (texture_2d_array: x = ψ, y = γ, layer = n·v node × this + √α node).\nconst LOBE_GGX_SQRT_ALPHA_NODES: i32 = {};\n", g.alpha);
        (rs, w)
    }
}
