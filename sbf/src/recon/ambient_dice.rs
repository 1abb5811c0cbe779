//! Lambert irradiance and GGX specular from radiance-encoding Ambient Dice SRBF
//! lobes ([Roughton19 §8.4]).
//!
//! Irradiance of one lobe, in E/π units, as a function of c = cos θ, θ the angle
//! between the lobe axis and the normal, is the quartic
//!   I(c) = 19/320 + 31c/240 + 3c²/40 − c⁴/192,   valid for all θ ∈ [0, π].
//! Derivation (ours): in polar coordinates t about the lobe axis, the φ-integral of
//! max(0, ω·n) is 2π·cos t·c where the ring is fully visible and
//! 2(A·acos(−A/B) + √(B² − A²)) (A = cos t·c, B = sin t·s) where it is clipped;
//! with x = cos t, the acos term integrates by parts (d/dx asin(xc/(s√(1 − x²))) =
//! c/((1 − x²)√(s² − x²))) and every remaining integral is a Wallis integral, so all
//! π factors cancel. Checks: I(1) = 2∫(0.35x² + 0.25x⁴)x dx = 0.258333…, I(−1) = 0,
//! and Σ over the 12 icosahedron lobes of I(c_i) = 1 (Σc_i = 0, Σc_i² = 4,
//! Σc_i⁴ = 12/5), the partition of unity carried through the convolution.
//!
//! \[Roughton19\] prints a longer closed form (eq. 8.13 for θ < π/2, eq. 8.11 with an
//! arctangent for θ ≥ π/2). In our copy of \[Roughton19\] it agrees with the quartic at
//! θ = 0, π/2 and π but deviates by up to 2.0e-3 in between (a test measures it
//! against an independent quadrature); we use the quartic, which matches that
//! quadrature to rounding.
//!
//! Quadratic fits (c clamped to [−1, 1]): [Roughton19 eq. 8.14], 0.05981 + 0.12918c + 0.07056c²,
//! and the constants of [Roughton19 Listing 8.1], 0.06 + 0.129c + 0.0697c², which are the
//! minimax quadratic of the quartic to three digits (c⁴ ≈ c² − 1/8, error 1/1536).
//!
//! Specular (Listing 8.1): per lobe, a blend between the lobe evaluated in the mirror
//! direction and the diffuse fit evaluated at a direction between R and N, with two
//! polynomial blend weights in √α; multiplied by a LUT value (Listing 8.2) that
//! holds ground truth / fit for the GGX dominant direction.

use crate::basis::ambient_dice::srbf_lobe;
use crate::ggx;
use crate::sampling::hammersley2;
use glam::DVec3;

/// Exact E/π of one SRBF lobe at c = cos θ (axis·normal), the quartic above.
#[inline]
pub fn lobe_irradiance_cos(cos_theta: f64) -> f64 {
    let c = cos_theta.clamp(-1.0, 1.0);
    let c2 = c * c;
    19.0 / 320.0 + c * (31.0 / 240.0) + c2 * (3.0 / 40.0 - c2 / 192.0)
}

/// Exact E/π of one SRBF lobe whose axis is at angle `theta` ∈ [0, π] from the normal.
pub fn lobe_irradiance(theta: f64) -> f64 {
    lobe_irradiance_cos(theta.cos())
}

/// Quadratic fit coefficients of [Roughton19 eq. 8.14].
pub const DIFFUSE_FIT_EQ_8_14: [f64; 3] = [0.05981, 0.12918, 0.07056];
/// The rounded constants used in [Roughton19 Listing 8.1].
pub const DIFFUSE_FIT_LISTING_8_1: [f64; 3] = [0.06, 0.129, 0.0697];
/// The minimax quadratic of the exact quartic on c ∈ [−1, 1]: replace c⁴ by its
/// best quadratic approximation c² − 1/8 (Chebyshev: c⁴ − (c² − 1/8) = T₄(c)/8), so
/// [19/320 + 1/1536, 31/240, 3/40 − 1/192] with max error exactly 1/1536 ≈ 6.5e-4.
pub const DIFFUSE_FIT_MINIMAX: [f64; 3] = [19.0 / 320.0 + 1.0 / 1536.0, 31.0 / 240.0, 3.0 / 40.0 - 1.0 / 192.0];

/// Quadratic lobe-irradiance fit p₀ + p₁c + p₂c² at c = cos θ ∈ [−1, 1].
#[inline]
pub fn lobe_irradiance_fit(p: &[f64; 3], cos_theta: f64) -> f64 {
    let c = cos_theta.clamp(-1.0, 1.0);
    p[0] + c * (p[1] + c * p[2])
}

/// E/π at unit normal `n` from one channel of SRBF radiance coefficients, exact.
pub fn irradiance(lobes: &[DVec3], coeffs: &[f64], n: DVec3) -> f64 {
    lobes.iter().zip(coeffs).map(|(p, b)| b * lobe_irradiance_cos(p.dot(n))).sum()
}

/// E/π at unit normal `n` with the quadratic fit `p`.
pub fn irradiance_fit(lobes: &[DVec3], coeffs: &[f64], n: DVec3, p: &[f64; 3]) -> f64 {
    lobes.iter().zip(coeffs).map(|(l, b)| b * lobe_irradiance_fit(p, l.dot(n))).sum()
}

/// The eight blend-polynomial parameters of [Roughton19 Listing 8.1] (`kAmbientDiceParameters`).
pub const SPECULAR_FIT_LISTING_8_1: [f64; 8] = [
    3.0498910522220495,
    -6.983002509990005,
    7.388270435580356,
    -2.662756921813306,
    -0.4005429486854629,
    5.626699351644211,
    -6.040098716506305,
    1.9006124935607012,
];

/// The per-pixel part of Listing 8.1's fit: reflection vector and the two blend
/// weights focus = saturate(k₀√α + k₁α + k₂α√α + k₃α²) and
/// alpha_lerp = saturate(k₄√α + k₅α + k₆α√α + k₇α²); [`SpecularFit::lobe`] blends
/// B(R·lobe) with the diffuse fit at mix(R·lobe, N·lobe, focus) for one lobe.
#[derive(Debug, Clone, Copy)]
pub struct SpecularFit {
    n: DVec3,
    r: DVec3,
    focus: f64,
    alpha_lerp: f64,
    diffuse: [f64; 3],
}

impl SpecularFit {
    /// For unit normal n, unit view v and roughness α with the given parameter sets.
    pub fn new(params: &[f64; 8], diffuse: &[f64; 3], n: DVec3, v: DVec3, alpha: f64) -> Self {
        let r = ggx::reflect(v, n); // reflect(−v, n) in shading-language convention
        let sa = alpha.sqrt();
        let poly = |k: &[f64]| (k[0] * sa + k[1] * alpha + k[2] * sa * alpha + k[3] * alpha * alpha).clamp(0.0, 1.0);
        SpecularFit { n, r, focus: poly(&params[0..4]), alpha_lerp: poly(&params[4..8]), diffuse: *diffuse }
    }

    /// The reflection vector R = 2(v·n)n − v.
    pub fn reflection(&self) -> DVec3 {
        self.r
    }
    /// The blend weight towards the normal (`focus`).
    pub fn focus(&self) -> f64 {
        self.focus
    }
    /// The blend weight from the mirror lobe to the diffuse fit (`alpha_lerp`).
    pub fn alpha_lerp(&self) -> f64 {
        self.alpha_lerp
    }

    /// The fit's value for one lobe axis.
    pub fn lobe(&self, lobe: DVec3) -> f64 {
        let r_dot = self.r.dot(lobe);
        let n_dot = self.n.dot(lobe);
        let mirror = srbf_lobe(r_dot);
        let d = lobe_irradiance_fit(&self.diffuse, r_dot + (n_dot - r_dot) * self.focus);
        mirror + (d - mirror) * self.alpha_lerp
    }
}

/// Per-lobe specular fit of Listing 8.1 *before* the LUT factor (see [`SpecularFit`]).
pub fn lobe_specular_fit(params: &[f64; 8], diffuse: &[f64; 3], lobe: DVec3, n: DVec3, v: DVec3, alpha: f64) -> f64 {
    SpecularFit::new(params, diffuse, n, v, alpha).lobe(lobe)
}

pub use crate::ggx::dominant_direction as ggx_dominant_direction;

/// Ground-truth GGX response of one SRBF lobe for f0 and f90 (∫B·(1 − F_c)·f·cos,
/// ∫B·F_c·f·cos) with the normal at +Z, view at cos θ_v = `n_dot_v` in the YZ plane,
/// and the lobe axis `lobe`, by `samples` Hammersley visible-normal samples.
pub fn lobe_specular_reference(lobe: DVec3, n_dot_v: f64, alpha: f64, samples: u32) -> [f64; 2] {
    lobe_specular_reference_with(lobe, n_dot_v, alpha, samples, ggx::Convention::Physical)
}

/// [`lobe_specular_reference`] with the sample weight of `convention`; light only from
/// above the surface in both (Listing 8.2's `lightDirectionTangent.z > 0`).
pub fn lobe_specular_reference_with(lobe: DVec3, n_dot_v: f64, alpha: f64, samples: u32, convention: ggx::Convention) -> [f64; 2] {
    let nv = n_dot_v.clamp(1e-6, 1.0);
    let alpha = alpha.clamp(1e-4, 1.0);
    let v = DVec3::new(0.0, (1.0 - nv * nv).max(0.0).sqrt(), nv);
    let k = samples.max(1);
    let mut acc = [0.0; 2];
    for i in 0..k {
        let h = ggx::sample_vndf(v, alpha, hammersley2(i as u64, k as u64));
        let l = ggx::reflect(v, h);
        if l.z <= 0.0 {
            continue;
        }
        let w = convention.vndf_weight(v, l, alpha) * srbf_lobe(lobe.dot(l));
        let fc = ggx::schlick_weight(v.dot(h));
        acc[0] += (1.0 - fc) * w;
        acc[1] += fc * w;
    }
    acc.map(|a| a / k as f64)
}

/// [`lobe_specular_reference`] by deterministic quadrature ([`crate::recon::lobe_ggx`],
/// `n` nodes per dimension) — the independent method the tables' errors are stated against.
pub fn lobe_specular_quadrature(lobe: DVec3, n_dot_v: f64, alpha: f64, n: usize) -> [f64; 2] {
    use crate::recon::lobe_ggx as lg;
    // lobe_ggx's frame has v in the xz-plane: rotate (x, y) → (y, −x).
    let p = DVec3::new(lobe.y, -lobe.x, lobe.z);
    lg::response_from_nodes(lg::RadialLobe::AdSrbf, &lg::nodes(n_dot_v, alpha, n), p)
}

/// One entry of the Ambient Dice specular LUT ([Roughton19 Listing 8.2]): ground truth for a
/// lobe along the GGX dominant direction, divided by the fit's value there.
pub fn specular_lut_entry(n_dot_v: f64, alpha: f64, samples: u32) -> [f64; 2] {
    specular_lut_entry_with(n_dot_v, alpha, samples, ggx::Convention::Physical)
}

/// [`specular_lut_entry`] with the ground truth's sample weight of `convention`
/// (`AppendixC`: the table [Roughton19 App. C] printed its figures with).
pub fn specular_lut_entry_with(n_dot_v: f64, alpha: f64, samples: u32, convention: ggx::Convention) -> [f64; 2] {
    let nv = n_dot_v.clamp(1e-6, 1.0);
    let alpha = alpha.clamp(1e-4, 1.0);
    let n = DVec3::Z;
    let v = DVec3::new(0.0, (1.0 - nv * nv).max(0.0).sqrt(), nv);
    let r = ggx::reflect(v, n);
    let lobe = crate::ggx::dominant_direction(n, r, alpha);
    let fit = lobe_specular_fit(&SPECULAR_FIT_LISTING_8_1, &DIFFUSE_FIT_LISTING_8_1, lobe, n, v, alpha);
    let gt = lobe_specular_reference_with(lobe, nv, alpha, samples, convention);
    if fit > 0.0 {
        gt.map(|g| g / fit)
    } else {
        [0.0; 2]
    }
}

/// GGX specular from one channel of SRBF radiance coefficients with the Listing 8.1
/// fit and a LUT value `lut` = (f0 scale, f90 scale) for (n·v, α) (Listing 8.2):
/// Σ b_i·fit_i·(f0·lut₀ + f90·lut₁).
pub fn specular(lobes: &[DVec3], coeffs: &[f64], n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64, lut: [f64; 2]) -> f64 {
    let s: f64 = lobes
        .iter()
        .zip(coeffs)
        .map(|(l, b)| b * lobe_specular_fit(&SPECULAR_FIT_LISTING_8_1, &DIFFUSE_FIT_LISTING_8_1, *l, n, v, alpha))
        .sum();
    s * (f0 * lut[0] + f90 * lut[1])
}

/// [`specular`] for RGB coefficients: each lobe's fit computed once.
pub fn specular_rgb(lobes: &[DVec3], coeffs: &[[f64; 3]], n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64, lut: [f64; 2]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (l, b) in lobes.iter().zip(coeffs) {
        let w = lobe_specular_fit(&SPECULAR_FIT_LISTING_8_1, &DIFFUSE_FIT_LISTING_8_1, *l, n, v, alpha);
        for c in 0..3 {
            s[c] += b[c] * w;
        }
    }
    s.map(|x| x * (f0 * lut[0] + f90 * lut[1]))
}
