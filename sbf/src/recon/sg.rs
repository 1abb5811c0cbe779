//! Lambert irradiance and GGX specular from spherical-Gaussian radiance lobes.
//!
//! Irradiance (E/π) of one lobe G(ω) = μ·exp(λ(ω·p − 1)) at normal n:
//! - [`irradiance_exact`]: numeric convolution, the oracle. In polar coordinates t
//!   about p the φ-integral of max(0, ω·n) has a closed form (see
//!   [`clamped_ring`]); the t-integral is split at the kinks t = |π/2 − θ|, π/2 + θ
//!   and geometrically around the lobe's width 1/√λ, 24-point Gauss–Legendre per
//!   piece (relative accuracy ~1e-12 for λ ∈ [0, 1e4]).
//! - [`hill_fit`]: Hill's fit (2016, as in math.md and Pettineo's SG series part 3)
//!   multiplied by the exact lobe integral, as published. Its 1/λ terms make it
//!   useless below λ ≈ 1 (error 158% of the peak at λ = 0.5, −4000 at λ = 0.01; the
//!   table is in the tests), and one public tool is off by π at λ = 0.
//! - [`irradiance_hill`]: the runtime form: Hill's fit for λ ≥ [`HILL_MIN_SHARPNESS`],
//!   and below it the exact zonal-harmonic expansion [`irradiance_zonal`] (Legendre
//!   moments of the SG are 4π·e^(−λ)·i_l(λ), modified spherical Bessel functions,
//!   convolved with the clamped cosine's A_l up to l = 8: truncation error < 1e-6 of
//!   the peak for λ ≤ 2), so λ → 0 gives exactly μ.
//! - [`irradiance_cosine_sg`]: inner product with the clamped cosine approximated as
//!   an SG (μ = 1.170, λ = 2.133; math.md), divided by π.
//! - [`irradiance_punctual`]: the lobe as a point light of its integral along p.
//!
//! Specular (∫ G·f_r·cos with height-correlated G2 and Schlick F):
//! - [`specular_sg_warp`]: the GGX NDF as an SG about n (λ = 2/α², μ = 1/(πα²)),
//!   warped to the reflection direction with λ/(4·max(n·v, ε)), inner product with
//!   the light lobe, times G2/(4 n·v n·l)·F·(n·l) at the warp axis (Pettineo, SG
//!   series part 4).
//! - [`specular_asg_warp`]: the same NDF warped to an ASG about R with
//!   λx = λ/(8·max(n·v, ε)²), λy = λ/8 (Xu et al. 2013), convolved with the light SG
//!   (ν = λ_light/2: λ' = νλ_a/(ν + λ_a), amplitude π/√((ν + λx)(ν + λy))), evaluated at
//!   the light axis, times the same visibility, Fresnel and cosine.
//!
//! - [`SplitSumWarp`] / [`specular_split_sum`] (the runtime's default): the split-sum
//!   approximation (Karis 2013, "Real Shading in Unreal Engine 4"): the BRDF's energy from the
//!   DFG table, f0·A + f90·B at (n·v, α), times the radiance prefiltered by the NDF lobe
//!   with Karis' n·l weight, L̄ = ∫ L·D̃·(n·l) / ∫ D̃·(n·l). D̃ is the SG warp above about R
//!   (Wang et al. 2009's SG NDF, λ = 2/α², warped to λ/(4 n·v); held ≥ [`HILL_MIN_SHARPNESS`]
//!   so Hill's fit stays in range). Both integrals are SG irradiances: the numerator of the
//!   product lobe D̃·G (an SG, exact), the denominator of D̃ — each by [`irradiance_hill`].
//!   Over the nine λ 6 lobes of a lightmap (unit, single and random amplitudes, α 0.1–1,
//!   θv 0.2–1.4 rad) its relative RMS error against [`crate::recon::reference::ggx_specular`]
//!   is 0.05–0.27 where the ASG warp's is 0.18–0.64 (its mean ×0.69–1.32; the ASG's NDF as
//!   an SG integrates to only 0.82 of GGX's at α 0.6, 0.69 at α 0.8); the table is in
//!   `sbf/tests/recon_sg.rs`.
//!
//! ε = 1e-4 guards n·v → 0 (public tools use 0.1 or 1e-4).

use crate::basis::sg::sg_unit_inner_product;
use crate::basis::Sg;
use crate::ggx;
use crate::quadrature::gauss_legendre;
use glam::DVec3;
use std::f64::consts::PI;

/// Guard for n·v → 0 in the warps.
pub const NV_EPSILON: f64 = 1e-4;

/// ∫₀^{2π} max(0, a + b·cos φ) dφ for b ≥ 0.
pub fn clamped_ring(a: f64, b: f64) -> f64 {
    if a >= b {
        2.0 * PI * a
    } else if a <= -b {
        0.0
    } else {
        2.0 * (a * (-a / b).acos() + (b * b - a * a).max(0.0).sqrt())
    }
}

/// Exact E/π of an SG lobe at unit normal n (numeric convolution, see module docs).
pub fn irradiance_exact(sg: &Sg, n: DVec3) -> f64 {
    let x = sg.axis.dot(n).clamp(-1.0, 1.0);
    let theta = x.acos();
    let (st, ct) = (theta.sin(), x);
    let lam = sg.sharpness;
    let f = |t: f64| {
        let (s, c) = t.sin_cos();
        // exp(λ(cos t − 1)) = exp(−2λ sin²(t/2)) without cancellation near t = 0.
        let h = (0.5 * t).sin();
        (-2.0 * lam * h * h).exp() * s * clamped_ring(c * ct, s * st)
    };
    let mut cuts = vec![0.0, PI];
    // |A| = |B| at tan t = ±cot θ: t = |π/2 − θ| and π − |π/2 − θ|.
    for k in [(0.5 * PI - theta).abs(), PI - (0.5 * PI - theta).abs()] {
        if k > 0.0 && k < PI {
            cuts.push(k);
        }
    }
    let w = 1.0 / lam.max(1e-12).sqrt();
    let mut g = 0.05 * w;
    while g < PI {
        cuts.push(g);
        g *= 2.0;
    }
    cuts.sort_by(f64::total_cmp);
    let (gx, gw) = gauss_legendre(24);
    let mut total = 0.0;
    for c in cuts.windows(2) {
        let (a, b) = (c[0], c[1]);
        if b <= a {
            continue;
        }
        for (xi, wi) in gx.iter().zip(&gw) {
            total += 0.5 * (b - a) * wi * f(a + 0.5 * (b - a) * (xi + 1.0));
        }
    }
    sg.amplitude * total / PI
}

/// Below this sharpness [`irradiance_hill`] uses the zonal expansion (Hill's fit
/// error there exceeds 1.6% of the peak; see the table in the tests).
pub const HILL_MIN_SHARPNESS: f64 = 2.0;

/// Modified spherical Bessel functions i_l(x), l = 0..=lmax, by their power series
/// x^l/(2l+1)!!·Σ_k (x²/2)^k/(k!·(2l+3)(2l+5)…(2l+2k+1)) (converges fast for x ≤ 4).
fn modified_spherical_bessel(x: f64, lmax: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(lmax + 1);
    let mut lead = 1.0; // x^l/(2l+1)!!
    for l in 0..=lmax {
        if l > 0 {
            lead *= x / (2 * l + 1) as f64;
        }
        let (mut term, mut sum) = (1.0, 1.0);
        for k in 1..60 {
            term *= 0.5 * x * x / (k as f64 * (2 * l + 2 * k + 1) as f64);
            sum += term;
            if term < 1e-17 * sum {
                break;
            }
        }
        out.push(lead * sum);
    }
    out
}

/// E/π of an SG lobe by its zonal-harmonic expansion up to band 8: exact up to
/// truncation (< 1e-6 of the peak for λ ≤ 2; use [`irradiance_exact`] beyond).
pub fn irradiance_zonal(sg: &Sg, n: DVec3) -> f64 {
    let x = sg.axis.dot(n).clamp(-1.0, 1.0);
    let lam = sg.sharpness;
    let il = modified_spherical_bessel(lam, 8);
    // Legendre P_l(x) by recurrence.
    let (mut p0, mut p1) = (1.0, x);
    let mut total = 0.0;
    for l in 0..=8usize {
        let pl = match l {
            0 => 1.0,
            1 => x,
            _ => {
                let p2 = ((2 * l - 1) as f64 * x * p1 - (l - 1) as f64 * p0) / l as f64;
                p0 = p1;
                p1 = p2;
                p2
            }
        };
        // f = Σ (2l+1)/(4π)·g_l·P_l, g_l = 4π e^(−λ) i_l(λ); convolution multiplies by A_l/π.
        let g = 4.0 * PI * (-lam).exp() * il[l];
        total += (2 * l + 1) as f64 / (4.0 * PI) * g * crate::recon::zonal::lambert_band_factor(l) / PI * pl;
    }
    sg.amplitude * total
}

/// Runtime SG irradiance E/π: Hill's curve with fitgen's re-fitted c₀
/// ([`crate::luts::committed::constants::HILL_C0`], the constant the WGSL runtime reads
/// too) for λ ≥ 2, the zonal expansion below.
pub fn irradiance_hill(sg: &Sg, n: DVec3) -> f64 {
    HillLobe::new(sg).eval(n)
}

/// [`irradiance_hill`] with everything that depends only on the lobe (e^(−λ), Hill's
/// scale and bias, the lobe integral) computed once: what a runtime keeps per basis
/// function. `eval` and [`hill_curve`] share the same steps, so the two agree bit for bit.
#[derive(Debug, Clone, Copy)]
pub struct HillLobe {
    sg: Sg,
    /// (c₀, c₁·√(1 − scale), √(1 − scale), scale, bias, integral); None below
    /// [`HILL_MIN_SHARPNESS`] (the zonal expansion is used there).
    hill: Option<[f64; 6]>,
}

impl HillLobe {
    /// What Hill's fit (or, below [`HILL_MIN_SHARPNESS`], the zonal expansion) keeps of `sg`.
    pub fn new(sg: &Sg) -> HillLobe {
        if sg.sharpness < HILL_MIN_SHARPNESS {
            return HillLobe { sg: *sg, hill: None };
        }
        let c0 = crate::luts::committed::constants::HILL_C0;
        let [x1, xs, scale, bias] = hill_constants(c0, sg.sharpness);
        HillLobe { sg: *sg, hill: Some([c0, x1, xs, scale, bias, sg.integral()]) }
    }

    /// E/π of the lobe at normal n.
    #[inline]
    pub fn eval(&self, n: DVec3) -> f64 {
        let Some([c0, x1, xs, scale, bias, integral]) = self.hill else { return irradiance_zonal(&self.sg, n) };
        (scale * hill_y(c0, x1, xs, self.sg.axis.dot(n)) + bias) * integral / PI
    }
}

/// Hill's published constant c₀ (c₁ = 1/(4c₀)).
pub const HILL_C0_PUBLISHED: f64 = 0.36;

/// Hill's fitted irradiance curve for an SG light of *unit integral*, sharpness λ > 0,
/// at x = cos(axis, normal), with a free constant c₀ (fitgen re-fits it).
pub fn hill_curve(c0: f64, lambda: f64, x: f64) -> f64 {
    let [x1, xs, scale, bias] = hill_constants(c0, lambda);
    scale * hill_y(c0, x1, xs, x) + bias
}

/// Hill's per-lobe constants for c₀ and λ: (c₁·√(1 − scale), √(1 − scale), scale, bias)
/// with c₁ = 1/(4c₀), scale = 1 + 2e^(−2λ) − 1/λ, bias = (e^(−λ) − e^(−2λ))/λ − e^(−2λ).
fn hill_constants(c0: f64, lambda: f64) -> [f64; 4] {
    let lam = lambda.max(f64::MIN_POSITIVE);
    let c1 = 1.0 / (4.0 * c0);
    let e1 = (-lam).exp();
    let e2 = e1 * e1;
    let r = 1.0 / lam;
    let scale = 1.0 + 2.0 * e2 - r;
    let bias = (e1 - e2) * r - e2;
    // 1 − scale = 1/λ − 2e^(−2λ), without the cancellation of 1 − scale at large λ.
    let xs = (r - 2.0 * e2).max(0.0).sqrt();
    [c1 * xs, xs, scale, bias]
}

/// Hill's smooth step at x = cos(axis, normal): ((c₀x + x₁)²/x_s inside the transition band,
/// the clamped cosine outside it.
#[inline]
fn hill_y(c0: f64, x1: f64, xs: f64, x: f64) -> f64 {
    let x = x.clamp(-1.0, 1.0);
    let x0 = c0 * x;
    if x0.abs() <= x1 && xs > 0.0 {
        (x0 + x1) * (x0 + x1) / xs
    } else {
        x.clamp(0.0, 1.0)
    }
}

/// Hill's fit exactly as published (times the exact lobe integral, over π), any λ > 0.
pub fn hill_fit(sg: &Sg, n: DVec3) -> f64 {
    hill_curve(HILL_C0_PUBLISHED, sg.sharpness, sg.axis.dot(n)) * sg.integral() / PI
}

/// Clamped cosine as an SG (math.md): μ = 1.170, λ = 2.133.
pub const COSINE_SG: (f64, f64) = (1.170, 2.133);

/// E/π as the inner product of the lobe with the cosine SG about n, over π.
pub fn irradiance_cosine_sg(sg: &Sg, n: DVec3) -> f64 {
    sg.amplitude * COSINE_SG.0 * sg_unit_inner_product(sg.axis, sg.sharpness, n, COSINE_SG.1) / PI
}

/// E/π with the clamped cosine replaced by an SG kernel of sharpness `kernel_sharpness`
/// about n, scaled to integrate to π (so a constant radiance c still reflects c):
/// E/π ≈ ∫ G·K / π, K = π·G(n, λ_k)/∫G(n, λ_k). This is how Probulator's SG
/// experiments reconstruct irradiance when a "BRDF lambda" is set (it uses λ_k = 8.5
/// after a naive projection and 3.0 after least squares, "chosen through
/// experimentation"); `probes --sg-irradiance peer` uses it to reproduce that tool's
/// figures. Not a cosine fit: [`irradiance_hill`] is the accurate runtime path.
pub fn irradiance_sg_kernel(sg: &Sg, n: DVec3, kernel_sharpness: f64) -> f64 {
    let k = Sg { axis: n, sharpness: kernel_sharpness, amplitude: 1.0 };
    sg.inner_product(&k) / k.integral()
}

/// E/π treating the lobe as a point light of its integral along its axis.
pub fn irradiance_punctual(sg: &Sg, n: DVec3) -> f64 {
    sg.integral() * sg.axis.dot(n).max(0.0) / PI
}

/// Height-correlated visibility G2/(4 n·v n·l), Schlick Fresnel and n·l at light
/// direction l (shared tail of both warps).
fn vis_fresnel_cos(n: DVec3, v: DVec3, l: DVec3, alpha: f64, f0: f64, f90: f64) -> f64 {
    let (nv, nl) = (n.dot(v).max(NV_EPSILON), n.dot(l));
    if nl <= 0.0 {
        return 0.0;
    }
    // Isotropic Smith Λ depends only on the cosine to n: evaluate G2 in a frame
    // where n = +Z.
    let in_frame = |c: f64| DVec3::new((1.0 - c * c).max(0.0).sqrt(), 0.0, c);
    let g2 = ggx::g2(in_frame(nv), in_frame(nl), alpha);
    let h = (v + l).normalize_or_zero();
    let fc = ggx::schlick_weight(v.dot(h));
    let f = f0 * (1.0 - fc) + f90 * fc;
    g2 / (4.0 * nv * nl) * f * nl
}

/// GGX specular from one SG light lobe with the isotropic SG warp.
pub fn specular_sg_warp(light: &Sg, n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64) -> f64 {
    let alpha = alpha.clamp(1e-4, 1.0);
    let a2 = alpha * alpha;
    let (lam, mu) = (2.0 / a2, 1.0 / (PI * a2));
    let nv = n.dot(v).max(NV_EPSILON);
    let r = ggx::reflect(v, n);
    let warped = Sg { axis: r, sharpness: lam / (4.0 * nv), amplitude: mu };
    warped.inner_product(light) * vis_fresnel_cos(n, v, r, alpha, f0, f90)
}

/// The per-pixel part of the ASG warp (Xu et al. 2013; Pettineo): the warped NDF
/// frame and bandwidths and the visibility·Fresnel·cosine tail, which do not depend on
/// the light lobe. [`AsgWarp::lobe`] adds one SG light.
#[derive(Debug, Clone, Copy)]
pub struct AsgWarp {
    x: DVec3,
    y: DVec3,
    z: DVec3,
    lx: f64,
    ly: f64,
    mu: f64,
    tail: f64,
}

impl AsgWarp {
    /// For unit normal n, unit view v, roughness α (clamped to [1e-4, 1]) and Fresnel (f0, f90).
    pub fn new(n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64) -> Self {
        Self::with_frame(n, v, alpha, f0, f90, |z| {
            // x in the plane of n and z (the stretched axis: Xu et al. 2013), y ⟂ both.
            let y0 = n.cross(z);
            let y = if y0.length_squared() > 1e-24 { y0.normalize() } else { crate::frame::tangent_frame(z).1 };
            (y.cross(z), y)
        })
    }

    /// [`AsgWarp::new`] with the warped lobe's (x, y) axes from `frame(z)` for the reflected
    /// direction z; x takes the stretched bandwidth λ/(8(n·v)²). Pettineo's code, and Roughton's
    /// Probulator fork after it, take "any orthonormal basis" about z (Duff et al. 2017's,
    /// in tangent space), which stretches the lobe along the wrong axis away from the
    /// plane of n and z — reproduced by passing that basis.
    pub fn with_frame(n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64, frame: impl FnOnce(DVec3) -> (DVec3, DVec3)) -> Self {
        let alpha = alpha.clamp(1e-4, 1.0);
        let a2 = alpha * alpha;
        let (lam, mu) = (2.0 / a2, 1.0 / (PI * a2));
        let nv = n.dot(v).max(NV_EPSILON);
        let z = ggx::reflect(v, n);
        let (x, y) = frame(z);
        AsgWarp { x, y, z, lx: lam / (8.0 * nv * nv), ly: lam / 8.0, mu, tail: vis_fresnel_cos(n, v, z, alpha, f0, f90) }
    }

    /// Specular from one SG light lobe: the ASG convolved with the SG (ν = λ/2),
    /// evaluated at the light axis, times the tail.
    pub fn lobe(&self, light: &Sg) -> f64 {
        let nu = 0.5 * light.sharpness;
        let lx2 = nu * self.lx / (nu + self.lx);
        let ly2 = nu * self.ly / (nu + self.ly);
        let amp = PI / ((nu + self.lx) * (nu + self.ly)).sqrt();
        let p = light.axis;
        let smooth = p.dot(self.z).max(0.0);
        self.mu * light.amplitude * amp * smooth * (-lx2 * p.dot(self.x).powi(2) - ly2 * p.dot(self.y).powi(2)).exp() * self.tail
    }
}

/// GGX specular from one SG light lobe with the anisotropic (ASG) warp.
pub fn specular_asg_warp(light: &Sg, n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64) -> f64 {
    AsgWarp::new(n, v, alpha, f0, f90).lobe(light)
}

/// The per-pixel part of the split-sum SG specular (module docs): the NDF lobe D̃ about the
/// reflection direction, and (f0·A + f90·B) over D̃'s cosine-weighted integral, which do
/// not depend on the light lobe. [`SplitSumWarp::lobe`] adds one SG light.
#[derive(Debug, Clone, Copy)]
pub struct SplitSumWarp {
    n: DVec3,
    nv: f64,
    ndf: Sg,
    scale: f64,
}

impl SplitSumWarp {
    /// For unit normal n, unit view v, roughness α (clamped to [1e-4, 1]), Fresnel (f0, f90)
    /// and the DFG table's (A, B) at (n·v, α) ([`crate::recon::tables::dfg`]).
    pub fn new(n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64, dfg: [f64; 2]) -> Self {
        let alpha = alpha.clamp(1e-4, 1.0);
        let nv = n.dot(v).max(NV_EPSILON);
        let sharpness = (0.5 / (alpha * alpha * nv)).max(HILL_MIN_SHARPNESS);
        let ndf = Sg { axis: ggx::reflect(v, n), sharpness, amplitude: 1.0 };
        // n·R = n·v (taken from the inputs, not R's rounding, which λ_D magnifies at grazing
        // view); ≥ 0: D̃'s irradiance is positive (Hill's curve at x ≥ 0).
        let den = hill_curve(crate::luts::committed::constants::HILL_C0, sharpness, n.dot(v)) * ndf.integral() / PI;
        let scale = if den > 0.0 { (f0 * dfg[0] + f90 * dfg[1]) / den } else { 0.0 };
        SplitSumWarp { n, nv: n.dot(v), ndf, scale }
    }

    /// The per-pixel factor (f0·A + f90·B)/E(D̃) that every lobe's E(D̃·G) is multiplied by
    /// (0 where E(D̃) is not positive): up to ~1e13 at α 1e-3 and grazing view, so it also
    /// magnifies whatever an f32 evaluation loses below `f32::MIN_POSITIVE` before it.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// Specular from one SG light lobe: E(D̃·G)/E(D̃)·(f0·A + f90·B). Where the product lobe's
    /// sharpness falls below [`HILL_MIN_SHARPNESS`] (λ_D near λ and the light facing away
    /// from R; its amplitude e^(|λ_D R + λp| − λ_D − λ) is then below e^(−2)), its E/π is
    /// Hill's curve at sharpness 2 times the lobe's own integral/π — as the f32 and WGSL
    /// runtimes, which have no zonal branch; that curve is within 0.34 of the integral/π of
    /// the exact convolution for every λ ∈ (0, 2) (tested in `recon_sg`).
    pub fn lobe(&self, light: &Sg) -> f64 {
        let p = self.ndf.product(light);
        // The product's axis·n = (λ_D n·v + λ p·n)/|λ_D R + λ p| (n·v as in `new`).
        let x = if p.sharpness > 0.0 {
            (self.ndf.sharpness * self.nv + light.sharpness * light.axis.dot(self.n)) / p.sharpness
        } else {
            self.nv
        };
        let c0 = crate::luts::committed::constants::HILL_C0;
        hill_curve(c0, p.sharpness.max(HILL_MIN_SHARPNESS), x) * p.integral() / PI * self.scale
    }
}

/// GGX specular from one SG light lobe by the split sum ([`SplitSumWarp`]).
pub fn specular_split_sum(light: &Sg, n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64, dfg: [f64; 2]) -> f64 {
    SplitSumWarp::new(n, v, alpha, f0, f90, dfg).lobe(light)
}

/// Sum over lobes of one channel: Σ b_i·method(lobe_i).
pub fn sum_lobes(axes: &[DVec3], sharpness: &[f64], coeffs: &[f64], f: impl Fn(&Sg) -> f64) -> f64 {
    axes.iter().zip(sharpness).zip(coeffs).map(|((a, l), b)| f(&Sg { axis: *a, sharpness: *l, amplitude: *b })).sum()
}

/// E/π from one channel of coefficients of an [`crate::SgBasis`] (lobes through
/// [`irradiance_hill`], the optional ambient function through its exact E/π, which
/// is its coefficient: a constant radiance c reflects c).
pub fn irradiance_basis(basis: &crate::SgBasis, coeffs: &[f64], n: DVec3) -> f64 {
    let k = basis.lobe_count();
    let mut e: f64 = (0..k).map(|i| coeffs[i] * irradiance_hill(&basis.lobe(i), n)).sum();
    if basis.has_ambient() {
        e += coeffs[k];
    }
    e
}
