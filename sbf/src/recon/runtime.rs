//! Runtime reconstruction in f32 on glam types: RGB coefficients as `Vec3` (one per
//! basis function), unit normal/view as `Vec3`, results as RGB `Vec3`. Irradiance
//! is E/π; specular is ∫L·f_r·cos with Schlick (f0, f90). Batch forms evaluate many
//! normals into a slice. Each function has an f64 twin in the sibling modules and a
//! parity test.
//!
//! Preconditions (debug-asserted): unit directions, slice lengths as documented.

#[cfg(feature = "ambient-dice")]
use super::ambient_dice::{SpecularFit, DIFFUSE_FIT_LISTING_8_1, DIFFUSE_FIT_MINIMAX, SPECULAR_FIT_LISTING_8_1};
#[cfg(feature = "ambient-dice")]
use super::lut::Lut2;
#[cfg(feature = "sh")]
use crate::basis::sh_fast::{eval_sh_l1, eval_sh_l2, eval_sh_l4};
#[cfg(feature = "sg")]
use crate::basis::Sg;
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
/// exact zonal expansion (computed in f64, as in [`super::sg::irradiance_hill`]).
#[cfg(feature = "sg")]
pub fn sg_irradiance(axes: &[Vec3], sharpness: f32, coeffs: &[Vec3], n: Vec3) -> Vec3 {
    debug_assert_eq!(axes.len(), coeffs.len());
    let mut e = Vec3::ZERO;
    if sharpness < super::sg::HILL_MIN_SHARPNESS as f32 {
        for (a, c) in axes.iter().zip(coeffs) {
            let w =
                super::sg::irradiance_zonal(&Sg { axis: a.as_dvec3(), sharpness: sharpness as f64, amplitude: 1.0 }, n.as_dvec3()) as f32;
            e += *c * w;
        }
        return e;
    }
    let lam = sharpness;
    // fitgen's re-fitted c₀ (the WGSL `sg_hill_irradiance` reads the same constant).
    let c0 = crate::luts::committed::constants::HILL_C0 as f32;
    let c1 = 1.0 / (4.0 * c0);
    let e1 = (-lam).exp();
    let e2 = e1 * e1;
    let r = 1.0 / lam;
    let scale = 1.0 + 2.0 * e2 - r;
    let bias = (e1 - e2) * r - e2;
    let xs = (1.0 - scale).max(0.0).sqrt();
    let integral = crate::basis::sg::sg_unit_integral_f32(lam) * std::f32::consts::FRAC_1_PI;
    for (a, c) in axes.iter().zip(coeffs) {
        let x = a.dot(n).clamp(-1.0, 1.0);
        let (x0, x1) = (c0 * x, c1 * xs);
        let y = if x0.abs() <= x1 && xs > 0.0 { (x0 + x1) * (x0 + x1) / xs } else { x.clamp(0.0, 1.0) };
        e += *c * ((scale * y + bias) * integral);
    }
    e
}

/// GGX specular from SG lobes of one shared sharpness with the ASG warp (f32 evaluation
/// of [`super::sg::specular_asg_warp`], computed per lobe in f64 for stability at
/// n·v → 0 and α → 1e-4, then accumulated in f32).
#[cfg(feature = "sg")]
pub fn sg_specular_asg(axes: &[Vec3], sharpness: f32, coeffs: &[Vec3], n: Vec3, v: Vec3, alpha: f32, f0: f32, f90: f32) -> Vec3 {
    let warp = super::sg::AsgWarp::new(n.as_dvec3(), v.as_dvec3(), alpha as f64, f0 as f64, f90 as f64);
    let mut s = Vec3::ZERO;
    for (a, c) in axes.iter().zip(coeffs) {
        s += *c * warp.lobe(&Sg { axis: a.as_dvec3(), sharpness: sharpness as f64, amplitude: 1.0 }) as f32;
    }
    s
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
/// the LUT (Listing 8.2) sampled at (n·v, α).
#[cfg(feature = "ambient-dice")]
pub fn ad_specular(lobes: &[Vec3], coeffs: &[Vec3], n: Vec3, v: Vec3, alpha: f32, f0: f32, f90: f32, lut: &Lut2) -> Vec3 {
    let l = lut.sample2(n.dot(v).clamp(0.0, 1.0), alpha);
    let scale = f0 * l[0] + f90 * l[1];
    let fit = SpecularFit::new(&SPECULAR_FIT_LISTING_8_1, &DIFFUSE_FIT_LISTING_8_1, n.as_dvec3(), v.as_dvec3(), alpha as f64);
    let mut s = Vec3::ZERO;
    for (lobe, c) in lobes.iter().zip(coeffs) {
        s += *c * fit.lobe(lobe.as_dvec3()) as f32;
    }
    s * scale
}

/// Evaluates `f` at every normal into `out` (the batch form of any function above).
/// `out.len()` must equal `normals.len()` (debug-asserted).
pub fn batch(normals: &[Vec3], out: &mut [Vec3], f: impl Fn(Vec3) -> Vec3) {
    debug_assert_eq!(normals.len(), out.len());
    for (o, n) in out.iter_mut().zip(normals) {
        *o = f(*n);
    }
}
