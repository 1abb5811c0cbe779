//! Runtime reconstruction in f32 on glam types: RGB coefficients as `Vec3` (one per
//! basis function), unit normal/view as `Vec3`, results as RGB `Vec3`. Irradiance
//! is E/π; specular is ∫L·f_r·cos with Schlick (f0, f90). Batch forms evaluate many
//! normals into a slice. Everything computes in f32, as the WGSL twins do (the same
//! formulas); each function has an f64 reference in the sibling modules and a test
//! against it.
//!
//! Preconditions (debug-asserted): unit directions, slice lengths as documented.

#[cfg(feature = "ambient-dice")]
use super::ambient_dice::{DIFFUSE_FIT_LISTING_8_1, DIFFUSE_FIT_MINIMAX, SPECULAR_FIT_LISTING_8_1};
#[cfg(feature = "ambient-dice")]
use super::lut::Lut2;
#[cfg(feature = "sh")]
use crate::basis::sh_fast::{eval_sh_l1, eval_sh_l2, eval_sh_l4};
use glam::Vec3;

/// A_l/π for l = 0..=4 (E/π band factors): 1, 2/3, 1/4, 0, −1/24.
#[cfg(feature = "sh")]
pub const SH_IRRADIANCE_BAND: [f32; 5] = [1.0, 2.0 / 3.0, 0.25, 0.0, -1.0 / 24.0];

/// Band l of coefficient index i (i < 25).
#[cfg(feature = "sh")]
const BAND_OF: [usize; 25] = [0, 1, 1, 1, 2, 2, 2, 2, 2, 3, 3, 3, 3, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4];

#[cfg(feature = "sh")]
fn sh_irradiance<const N: usize>(c: &[Vec3; N], y: &[f32; N]) -> Vec3 {
    let mut e = Vec3::ZERO;
    for i in 0..N {
        e += c[i] * (y[i] * SH_IRRADIANCE_BAND[BAND_OF[i]]);
    }
    e
}

/// E/π from SH L1 (4 RGB coefficients).
#[cfg(feature = "sh")]
pub fn sh_l1_irradiance(c: &[Vec3; 4], n: Vec3) -> Vec3 {
    sh_irradiance(c, &eval_sh_l1(n))
}

/// E/π from SH L2 (9 RGB coefficients).
#[cfg(feature = "sh")]
pub fn sh_l2_irradiance(c: &[Vec3; 9], n: Vec3) -> Vec3 {
    sh_irradiance(c, &eval_sh_l2(n))
}

/// E/π from SH L4 (25 RGB coefficients).
#[cfg(feature = "sh")]
pub fn sh_l4_irradiance(c: &[Vec3; 25], n: Vec3) -> Vec3 {
    sh_irradiance(c, &eval_sh_l4(n))
}

/// E/π from SH L1 with the Geomerics reconstruction (f32 twin of
/// [`super::sh::irradiance_l1_geomerics`]).
#[cfg(feature = "sh")]
pub fn sh_l1_geomerics_irradiance(c: &[Vec3; 4], n: Vec3) -> Vec3 {
    let k0 = 0.282_094_8_f32; // 1/(2√π)
    let k1 = 0.162_867_5_f32; // √(3/4π)/3
    let mut out = [0.0f32; 3];
    for (ch, o) in out.iter_mut().enumerate() {
        let r0 = c[0][ch] * k0;
        let r1 = Vec3::new(c[3][ch], c[1][ch], c[2][ch]) * k1;
        let len = r1.length();
        *o = if r0 <= 0.0 || len.is_nan() || len <= 0.0 {
            r0 + 2.0 * r1.dot(n)
        } else {
            let q = 0.5 * (1.0 + n.dot(r1 / len));
            let ratio = len / r0;
            let p = 1.0 + 2.0 * ratio;
            let a = (1.0 - ratio) / (1.0 + ratio);
            r0 * (a + (1.0 - a) * (p + 1.0) * q.max(0.0).powf(p))
        };
    }
    Vec3::from_array(out)
}

/// E/π from SG lobes of one shared sharpness with Hill's fit (fitgen's c₀; λ ≥ 2) or, below, the
/// zonal expansion — both in f32 (twin of [`super::sg::irradiance_hill`]; the zonal branch
/// is [`sg_zonal_irradiance_f32`]).
#[cfg(feature = "sg")]
pub fn sg_irradiance(axes: &[Vec3], sharpness: f32, coeffs: &[Vec3], n: Vec3) -> Vec3 {
    debug_assert_eq!(axes.len(), coeffs.len());
    let mut e = Vec3::ZERO;
    if sharpness < super::sg::HILL_MIN_SHARPNESS as f32 {
        for (a, c) in axes.iter().zip(coeffs) {
            e += *c * sg_zonal_irradiance_f32(a.dot(n), sharpness);
        }
        return e;
    }
    let hill = HillF32::new(sharpness);
    for (a, c) in axes.iter().zip(coeffs) {
        e += *c * hill.eval(a.dot(n));
    }
    e
}

/// Hill's fit for one sharpness λ in f32 (fitgen's re-fitted c₀; the WGSL
/// `sg_hill_irradiance` reads the same constant): E/π of a unit-amplitude lobe at
/// x = axis·n. No zonal branch: as the WGSL, accurate for λ ≥ 2.
#[cfg(feature = "sg")]
#[derive(Clone, Copy)]
struct HillF32 {
    c0: f32,
    x1: f32,
    xs: f32,
    scale: f32,
    bias: f32,
    integral: f32,
}

#[cfg(feature = "sg")]
impl HillF32 {
    fn new(lam: f32) -> Self {
        let lam = lam.max(1e-30);
        let c0 = crate::luts::committed::constants::HILL_C0 as f32;
        let c1 = 1.0 / (4.0 * c0);
        let e1 = (-lam).exp();
        let e2 = e1 * e1;
        let r = 1.0 / lam;
        let scale = 1.0 + 2.0 * e2 - r;
        let bias = (e1 - e2) * r - e2;
        // 1 − scale without cancellation (1/λ − 2e^(−2λ)): f32 loses 1 − scale at large λ.
        let xs = (r - 2.0 * e2).max(0.0).sqrt();
        let integral = crate::basis::sg::sg_unit_integral_f32(lam) * std::f32::consts::FRAC_1_PI;
        HillF32 { c0, x1: c1 * xs, xs, scale, bias, integral }
    }

    fn eval(&self, x: f32) -> f32 {
        let x = x.clamp(-1.0, 1.0);
        let x0 = self.c0 * x;
        let y = if x0.abs() <= self.x1 && self.xs > 0.0 { (x0 + self.x1) * (x0 + self.x1) / self.xs } else { x.clamp(0.0, 1.0) };
        (self.scale * y + self.bias) * self.integral
    }
}

/// GGX specular from SG lobes of one shared sharpness by the split sum, in f32: the CPU twin
/// of the WGSL `sg_split_sum_setup` + `sg_split_sum_lobe` (f64 reference:
/// [`super::sg::SplitSumWarp`], with the same treatment of product lobes below λ 2).
/// `dfg` is the DFG table's (A, B) at (n·v, α).
#[cfg(feature = "sg")]
pub fn sg_specular_split_sum(
    axes: &[Vec3],
    sharpness: f32,
    coeffs: &[Vec3],
    n: Vec3,
    v: Vec3,
    alpha: f32,
    f0: f32,
    f90: f32,
    dfg: [f32; 2],
) -> Vec3 {
    debug_assert_eq!(axes.len(), coeffs.len());
    let alpha = alpha.clamp(1e-4, 1.0);
    let nv = n.dot(v).max(super::sg::NV_EPSILON as f32);
    let lw = (0.5 / (alpha * alpha * nv)).max(super::sg::HILL_MIN_SHARPNESS as f32);
    let r = 2.0 * v.dot(n) * n - v;
    // n·R = n·v from the inputs, not from R's rounding (λ_D magnifies it at grazing view).
    let nv_in = n.dot(v);
    let den = HillF32::new(lw).eval(nv_in);
    let scale = if den > 0.0 { (f0 * dfg[0] + f90 * dfg[1]) / den } else { 0.0 };
    let mut s = Vec3::ZERO;
    for (a, c) in axes.iter().zip(coeffs) {
        // The product lobe exp(λ_D(ω·R − 1))·exp(λ(ω·p − 1)) (Sg::product's stable exponent).
        let pm = lw * r + sharpness * *a;
        let d = pm.length();
        let amp = (-lw * sharpness * (r - *a).length_squared() / (lw + sharpness + d)).exp();
        // The product's axis·n = (λ_D n·v + λ p·n)/|λ_D R + λ p|.
        let x = if d > 0.0 { (lw * nv_in + sharpness * a.dot(n)) / d } else { nv_in };
        // Below λ 2 Hill's curve at 2 with the lobe's own integral (SplitSumWarp::lobe).
        let hill = HillF32::new(d.max(2.0)).eval(x);
        let e =
            if d >= 2.0 { hill } else { hill * crate::basis::sg::sg_unit_integral_f32(d) / crate::basis::sg::sg_unit_integral_f32(2.0) };
        s += *c * (amp * e);
    }
    s * scale
}

/// (band l, A_l/π) of the bands the clamped cosine keeps up to l = 8 (Ramamoorthi &
/// Hanrahan 2001; odd bands above 1 vanish): 1, 2/3, 1/4, −1/24, 1/64, −1/128.
#[cfg(feature = "sg")]
const ZONAL_BANDS: [(usize, f32); 6] = [(0, 1.0), (1, 2.0 / 3.0), (2, 0.25), (4, -1.0 / 24.0), (6, 1.0 / 64.0), (8, -1.0 / 128.0)];

/// E/π of a unit-amplitude SG lobe of sharpness λ ≤ 2 at cos θ = `x` (axis·normal), in f32:
/// Σ_l (2l+1)·e^(−λ)·i_l(λ)·(A_l/π)·P_l(x) over the bands of `ZONAL_BANDS`, with the
/// modified spherical Bessel functions by their power series
/// i_l(λ) = λ^l/(2l+1)!!·Σ_k (λ²/2)^k/(k!·(2l+3)(2l+5)…(2l+2k+1)) (12 terms: below 1e-9
/// relative for λ ≤ 2). Twin of [`super::sg::irradiance_zonal`] (f64).
#[cfg(feature = "sg")]
pub fn sg_zonal_irradiance_f32(x: f32, lambda: f32) -> f32 {
    let x = x.clamp(-1.0, 1.0);
    let h = 0.5 * lambda * lambda;
    let decay = (-lambda).exp();
    // Legendre P_0..P_8 by recurrence.
    let mut p = [0.0f32; 9];
    p[0] = 1.0;
    p[1] = x;
    for l in 2..9 {
        p[l] = ((2 * l - 1) as f32 * x * p[l - 1] - (l - 1) as f32 * p[l - 2]) / l as f32;
    }
    let mut total = 0.0f32;
    for (l, a) in ZONAL_BANDS {
        // λ^l/(2l+1)!!
        let mut lead = 1.0f32;
        for k in 1..=l {
            lead *= lambda / (2 * k + 1) as f32;
        }
        let (mut term, mut sum) = (1.0f32, 1.0f32);
        for k in 1..12 {
            term *= h / (k as f32 * (2 * l + 2 * k + 1) as f32);
            sum += term;
        }
        total += (2 * l + 1) as f32 * decay * lead * sum * a * p[l];
    }
    total
}

/// GGX specular from SG lobes of one shared sharpness with the ASG warp, in f32: the CPU
/// twin of the WGSL `sg_asg_warp` + `sg_asg_lobe` (f64 reference:
/// [`super::sg::specular_asg_warp`]). n·v is clamped to 1e-4 ([`super::sg::NV_EPSILON`]).
#[cfg(feature = "sg")]
pub fn sg_specular_asg(axes: &[Vec3], sharpness: f32, coeffs: &[Vec3], n: Vec3, v: Vec3, alpha: f32, f0: f32, f90: f32) -> Vec3 {
    let alpha = alpha.clamp(1e-4, 1.0);
    let a2 = alpha * alpha;
    let (lam, mu) = (2.0 / a2, 1.0 / (std::f32::consts::PI * a2));
    let nv = n.dot(v).max(super::sg::NV_EPSILON as f32);
    let z = 2.0 * v.dot(n) * n - v;
    let y0 = n.cross(z);
    let y = if y0.length_squared() > 1e-12 { y0.normalize() } else { tangent_frame_f32(z).1 };
    let x = y.cross(z);
    // Tail: G2/(4 n·v n·l)·F·(n·l) at l = z (Smith Λ with n = +Z).
    let nl = n.dot(z);
    let tail = if nl > 0.0 {
        let lambda_of = |c: f32| {
            let t = alpha * alpha * (1.0 - c * c).max(0.0) / (c * c);
            t / (2.0 * (1.0 + (1.0 + t).sqrt()))
        };
        let g2 = 1.0 / (1.0 + lambda_of(nv) + lambda_of(nl));
        let hv = v + z;
        let hl = hv.length();
        let fc = if hl > 0.0 { schlick_weight_f32(v.dot(hv / hl)) } else { 0.0 };
        g2 / (4.0 * nv) * (f0 * (1.0 - fc) + f90 * fc)
    } else {
        0.0
    };
    let (lx, ly) = (lam / (8.0 * nv * nv), lam / 8.0);
    let nu = 0.5 * sharpness;
    let (lx2, ly2) = (nu * lx / (nu + lx), nu * ly / (nu + ly));
    let amp = std::f32::consts::PI / ((nu + lx) * (nu + ly)).sqrt();
    let mut s = Vec3::ZERO;
    for (a, c) in axes.iter().zip(coeffs) {
        let (px, py) = (a.dot(x), a.dot(y));
        s += *c * (mu * amp * a.dot(z).max(0.0) * (-lx2 * px * px - ly2 * py * py).exp() * tail);
    }
    s
}

/// Schlick's Fresnel weight (1 − v·h)^5, f32 (as the WGSL `schlick_weight`).
#[cfg(feature = "sg")]
fn schlick_weight_f32(v_dot_h: f32) -> f32 {
    let x = (1.0 - v_dot_h).clamp(0.0, 1.0);
    let x2 = x * x;
    x2 * x2 * x
}

/// Duff et al. 2017's branchless tangent frame, f32 (twin of [`crate::frame::tangent_frame`]).
#[cfg(feature = "sg")]
fn tangent_frame_f32(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// E/π from Ambient Dice SRBF radiance lobes with the minimax quadratic (error ≤ 6.5e-4
/// per unit coefficient; [`DIFFUSE_FIT_MINIMAX`]).
#[cfg(feature = "ambient-dice")]
pub fn ad_irradiance(lobes: &[Vec3], coeffs: &[Vec3], n: Vec3) -> Vec3 {
    debug_assert_eq!(lobes.len(), coeffs.len());
    let p = DIFFUSE_FIT_MINIMAX.map(|x| x as f32);
    let mut e = Vec3::ZERO;
    for (l, c) in lobes.iter().zip(coeffs) {
        let x = l.dot(n).clamp(-1.0, 1.0);
        e += *c * (p[0] + x * (p[1] + x * p[2]));
    }
    e
}

/// GGX specular from Ambient Dice SRBF radiance lobes: Listing 8.1's fit per lobe times
/// the LUT (Listing 8.2) sampled at (n·v, α), in f32 — the CPU twin of the WGSL
/// `ad_specular_fit` + `ad_specular_lobe` + `ad_specular_scale` (f64 reference:
/// [`super::ambient_dice::SpecularFit`]).
#[cfg(feature = "ambient-dice")]
pub fn ad_specular(lobes: &[Vec3], coeffs: &[Vec3], n: Vec3, v: Vec3, alpha: f32, f0: f32, f90: f32, lut: &Lut2) -> Vec3 {
    let l = lut.sample2(n.dot(v).clamp(0.0, 1.0), alpha);
    let scale = f0 * l[0] + f90 * l[1];
    let k = SPECULAR_FIT_LISTING_8_1.map(|x| x as f32);
    let p = DIFFUSE_FIT_LISTING_8_1.map(|x| x as f32);
    let sa = alpha.sqrt();
    let focus = (k[0] * sa + k[1] * alpha + k[2] * sa * alpha + k[3] * alpha * alpha).clamp(0.0, 1.0);
    let alpha_lerp = (k[4] * sa + k[5] * alpha + k[6] * sa * alpha + k[7] * alpha * alpha).clamp(0.0, 1.0);
    let r = 2.0 * v.dot(n) * n - v;
    let mut s = Vec3::ZERO;
    for (lobe, c) in lobes.iter().zip(coeffs) {
        let (r_dot, n_dot) = (r.dot(*lobe), n.dot(*lobe));
        let mirror = crate::basis::ambient_dice::srbf_lobe_f32(r_dot);
        let x = r_dot + (n_dot - r_dot) * focus;
        let d = p[0] + x * (p[1] + x * p[2]);
        s += *c * (mirror + (d - mirror) * alpha_lerp);
    }
    s * scale
}

/// GGX specular from lobes of one radial shape through its response table
/// ([`super::lobe_ggx`]), in f32: the CPU twin of the WGSL `lobe_ggx_pixel` +
/// `lobe_ggx_lobe` (f64 reference: [`super::lobe_ggx::specular_rgb`]). Σ_i c_i·(f0·R₀ + f90·R₁)(p_i).
pub fn lobe_ggx_specular(
    table: &super::lobe_ggx::Table,
    axes: &[Vec3],
    coeffs: &[Vec3],
    n: Vec3,
    v: Vec3,
    alpha: f32,
    f0: f32,
    f90: f32,
) -> Vec3 {
    debug_assert_eq!(axes.len(), coeffs.len());
    let mut s = Vec3::ZERO;
    lobe_ggx_responses(table, axes, n, v, alpha, f0, f90, |i, r| s += coeffs[i] * r);
    s
}

/// Each lobe's response (f0·R₀ + f90·R₁)(p_i) of [`lobe_ggx_specular`], in lobe order, to
/// `each(i, response)`: the specular of any coefficients c is Σ_i c_i·response_i, summed
/// in this order (what [`lobe_ggx_specular`] does, so a sum of stored responses equals it
/// bit for bit).
#[allow(clippy::too_many_arguments)]
pub fn lobe_ggx_responses(
    table: &super::lobe_ggx::Table,
    axes: &[Vec3],
    n: Vec3,
    v: Vec3,
    alpha: f32,
    f0: f32,
    f90: f32,
    mut each: impl FnMut(usize, f32),
) {
    let g = table.grid;
    let locate = |x: f32, size: usize| {
        let t = x.clamp(0.0, 1.0) * (size - 1) as f32;
        let i = (t.floor() as usize).min(size - 2);
        (i, t - i as f32)
    };
    let (i, a) = locate(n.dot(v), g.theta_v);
    let (j, b) = locate(alpha.clamp(0.0, 1.0).sqrt(), g.alpha);
    let slab = g.gamma * g.psi;
    let layers =
        [(i * g.alpha + j) * slab, (i * g.alpha + j + 1) * slab, ((i + 1) * g.alpha + j) * slab, ((i + 1) * g.alpha + j + 1) * slab];
    let lw = [(1.0 - a) * (1.0 - b), (1.0 - a) * b, a * (1.0 - b), a * b];
    let r = 2.0 * v.dot(n) * n - v;
    let t0 = n - n.dot(r) * r;
    let t = if t0.length_squared() > 1e-12 { t0.normalize() } else { Vec3::ZERO };
    let pi = std::f32::consts::PI;
    for (idx, p) in axes.iter().enumerate() {
        let rp = r.dot(*p).clamp(-1.0, 1.0);
        let st2 = (1.0 - rp * rp).max(0.0);
        let psi = if st2 > 1e-12 && t != Vec3::ZERO { acos_f32((t.dot(*p) / st2.sqrt()).clamp(-1.0, 1.0)) } else { 0.0 };
        let (k, fc) = locate(acos_f32(rp) / pi, g.gamma);
        let (l, fd) = locate(psi / pi, g.psi);
        let mut e = [0.0f32; 2];
        for (base, w) in layers.iter().zip(lw) {
            for (dk, dl, tw) in [(0, 0, (1.0 - fc) * (1.0 - fd)), (0, 1, (1.0 - fc) * fd), (1, 0, fc * (1.0 - fd)), (1, 1, fc * fd)] {
                let o = 2 * (base + (k + dk) * g.psi + l + dl);
                e[0] += w * tw * table.values[o];
                e[1] += w * tw * table.values[o + 1];
            }
        }
        each(idx, f0 * e[0] + f90 * e[1]);
    }
}

/// Multiple-scattering energy compensation of a GGX specular response (Fdez-Agüera 2019;
/// [`crate::recon::multiscatter`]): multiply the single-scattering response of any basis
/// (SH, SG, AD, per-lobe tables) by 1 + f0·(1/E − 1), E = dfg.0 + dfg.1 the DFG table's
/// value at (n·v, α) — the single-scattering albedo at f0 = f90 = 1. A table value E ≤ 0
/// gives 1. The WGSL twin is `ggx_energy_compensation`.
pub fn ggx_energy_compensation(dfg: [f32; 2], f0: f32) -> f32 {
    let e = dfg[0] + dfg[1];
    if e > 0.0 {
        1.0 + f0 * (1.0 / e - 1.0)
    } else {
        1.0
    }
}

/// acos by Abramowitz & Stegun 4.4.46 (|error| ≤ 2e-8 rad), as the WGSL `lobe_ggx_acos`
/// (Vulkan bounds the built-in acos only loosely).
// The first coefficient is A&S's fitted 1.5707963050, not π/2.
#[allow(clippy::approx_constant)]
pub fn acos_f32(x: f32) -> f32 {
    let a = x.abs();
    let p = 1.570_796_3
        + a * (-0.214_598_8
            + a * (0.088_978_99
                + a * (-0.050_174_303 + a * (0.030_891_88 + a * (-0.017_088_126 + a * (0.006_670_09 - a * 0.001_262_491_1))))));
    let r = (1.0 - a).max(0.0).sqrt() * p;
    if x < 0.0 {
        std::f32::consts::PI - r
    } else {
        r
    }
}

/// Evaluates `f` at every normal into `out` (the batch form of any function above).
/// `out.len()` must equal `normals.len()` (debug-asserted).
pub fn batch(normals: &[Vec3], out: &mut [Vec3], f: impl Fn(Vec3) -> Vec3) {
    debug_assert_eq!(normals.len(), out.len());
    for (o, n) in out.iter_mut().zip(normals) {
        *o = f(*n);
    }
}
