//! Lambert irradiance from real SH coefficients (conventions of [`crate::basis::sh`]).
//!
//! - Band factors A_l of the clamped cosine (Ramamoorthi & Hanrahan 2001; math.md):
//!   A₀ = π, A₁ = 2π/3, A_l = 0 for odd l > 1, and for even l
//!   A_l = 2π·(−1)^(l/2+1)/((l+2)(l−1)) · l!/(2^l((l/2)!)²). The binomial part
//!   l!/(2^l((l/2)!)²) = C(l, l/2)/2^l is evaluated as Π_{k=1}^{l/2} (2k−1)/(2k), so any
//!   order is finite. E/π = Σ (A_l/π)·c_lm·Y_lm(n).
//! - L1 "Geomerics" (Geomerics 2015, CEDEC talk "Reconstructing Diffuse Lighting from
//!   SH L1"): with R₀ the mean radiance and R₁ the linear term scaled so
//!   that the formula's small-|R₁| limit R₀ + 2R₁·n equals the exact L1 irradiance,
//!   R₀ = c₀/(2√π), R₁ = (√(3/4π)/3)·(c₃, c₁, c₂);
//!   q = ½(1 + n·R̂₁), p = 1 + 2|R₁|/R₀, a = (1 − |R₁|/R₀)/(1 + |R₁|/R₀),
//!   E/π = R₀(a + (1 − a)(p + 1)q^p). |R₁| = 0 → R₀; R₀ ≤ 0 → the linear L1 result
//!   (the formula is undefined there).
//! - ZH3 hallucination (Roughton 2024, "ZH3: Quadratic Zonal Harmonics"): axis = the
//!   normalised luminance-weighted L1 vector; per channel r = |L1·axis|/L0 in
//!   orthonormal coefficients (√3 for a single direction), zonal l = 2 coefficient along
//!   the axis L0·(0.08r + 0.6r²) on the orthonormal Y₂₀, added to the L1 irradiance with
//!   A₂. (An earlier reading normalised r by √3 and scaled by √5; it was 20–45% worse
//!   than the peer on three probes, while this, the paper's literal form, matches the
//!   peer's figures within 2.4% — see the probes tests.)

use crate::basis::{Basis, ShBasis};
use crate::error::SbfError;
use glam::DVec3;
use std::f64::consts::PI;

pub use super::zonal::lambert_band_factor;

/// Order L of a coefficient count (L+1)², or an error.
fn order_of(n: usize) -> Result<usize, SbfError> {
    let l = (n as f64).sqrt().round() as usize;
    if l == 0 || l * l != n {
        return Err(SbfError::LengthMismatch { what: "SH coefficients ((L+1)² per channel)", expected: l.max(1) * l.max(1), got: n });
    }
    Ok(l - 1)
}

/// Coefficients of E/π: c_lm·A_l/π, in place of radiance coefficients.
pub fn irradiance_coefficients(radiance: &[f64]) -> Result<Vec<f64>, SbfError> {
    let order = order_of(radiance.len())?;
    let mut out = radiance.to_vec();
    for l in 0..=order {
        let f = lambert_band_factor(l) / PI;
        for m in 0..(2 * l + 1) {
            out[l * l + m] *= f;
        }
    }
    Ok(out)
}

/// E/π at unit normal `n` from one channel of radiance coefficients (any order).
pub fn irradiance(radiance: &[f64], n: DVec3) -> Result<f64, SbfError> {
    let order = order_of(radiance.len())?;
    let e = irradiance_coefficients(radiance)?;
    let sh = ShBasis::new(order)?;
    let mut y = vec![0.0; sh.len()];
    sh.try_eval_into(n, &mut y)?;
    Ok(e.iter().zip(&y).map(|(a, b)| a * b).sum())
}

/// Exact L1 irradiance E/π = c₀Y₀₀ + (2/3)√(3/4π)(c₃,c₁,c₂)·n (one channel).
pub fn irradiance_l1_linear(c: &[f64; 4], n: DVec3) -> f64 {
    let k1 = (3.0 / (4.0 * PI)).sqrt();
    c[0] * 0.5 / PI.sqrt() + (2.0 / 3.0) * k1 * DVec3::new(c[3], c[1], c[2]).dot(n)
}

/// L1 Geomerics irradiance E/π (one channel); see the module docs for the scaling
/// and the two degenerate cases.
#[inline]
pub fn irradiance_l1_geomerics(c: &[f64; 4], n: DVec3) -> f64 {
    let k1 = (3.0 / (4.0 * PI)).sqrt();
    geomerics_l1(c[0] * 0.5 / PI.sqrt(), DVec3::new(c[3], c[1], c[2]) * ((2.0 / 3.0) * k1), n)
}

/// Geomerics' reconstruction (module docs) from the linear L1 irradiance E/π = a₀ + a₁·n
/// of one channel: R₀ = a₀, R₁ = a₁/2 — the arguments of Bakery's
/// `shEvaluateDiffuseL1Geomerics(L0, L1, n)` (`Bakery.cginc`), which takes exactly these
/// (L0 = a₀, L1 = a₁). |a₁| = 0 → a₀ (the formula's limit: a = 1); a₀ ≤ 0 → the linear
/// value (the shader divides by zero there); q is kept in [0, 1] against rounding.
#[inline]
pub fn geomerics_l1(a0: f64, a1: DVec3, n: DVec3) -> f64 {
    let (r0, r1) = (a0, 0.5 * a1);
    let len = r1.length();
    if r0 <= 0.0 || len.is_nan() || len <= 0.0 {
        return a0 + a1.dot(n);
    }
    let q = 0.5 * (1.0 + n.dot(r1 / len));
    let ratio = len / r0;
    let p = 1.0 + 2.0 * ratio;
    let a = (1.0 - ratio) / (1.0 + ratio);
    r0 * (a + (1.0 - a) * (p + 1.0) * q.clamp(0.0, 1.0).powf(p))
}

/// Rec. 709 luminance weights used to pick the ZH3 axis.
pub const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// ZH3 hallucinated irradiance E/π for RGB L1 coefficients (`rgb[c]` = 4 per channel).
pub fn irradiance_l1_zh3(rgb: &[[f64; 4]; 3], n: DVec3) -> Result<[f64; 3], SbfError> {
    for ch in rgb {
        if let Some(v) = ch.iter().find(|v| !v.is_finite()) {
            return Err(SbfError::InvalidParameter { name: "SH L1 coefficient", value: *v, reason: "must be finite" });
        }
    }
    let l1 = |c: &[f64; 4]| DVec3::new(c[3], c[1], c[2]);
    let lum = l1(&rgb[0]) * LUMINANCE[0] + l1(&rgb[1]) * LUMINANCE[1] + l1(&rgb[2]) * LUMINANCE[2];
    // Scaled by its largest component before normalising: |lum|² overflows for
    // coefficients near f64::MAX (1e300 gave a zero axis and dropped the ZH3 term).
    let big = lum.abs().max_element();
    let axis = if big > 0.0 { (lum / big).normalize() } else { DVec3::Z };
    let y20 = |t: f64| (5.0 / (4.0 * PI)).sqrt() * 0.5 * (3.0 * t * t - 1.0);
    let a2 = lambert_band_factor(2) / PI;
    let mut out = [0.0; 3];
    for (k, c) in rgb.iter().enumerate() {
        let base = irradiance_l1_linear(c, n);
        let r = if c[0] > 0.0 { l1(c).dot(axis).abs() / c[0] } else { 0.0 };
        let zh = c[0] * (0.08 * r + 0.6 * r * r);
        out[k] = base + a2 * zh * y20(n.dot(axis));
    }
    Ok(out)
}

/// Laplacian window σ_l = 1/(1 + λ·l²(l+1)²) (Sloan 2008, "Stupid Spherical Harmonics
/// Tricks", §windowing: the minimiser of ∫(f̃ − f)² + λ∫(Δf̃)²).
pub fn laplacian_window(l: usize, lambda: f64) -> f64 {
    let k = (l * (l + 1)) as f64;
    1.0 / (1.0 + lambda * k * k)
}

/// Laplacian energy Σ_l Σ_{m=−l..l} (l(l+1)·σ_l·c_lm)² of windowed coefficients.
/// (The sum runs over all 2l+1 orders m of each band; one public tool starts at
/// m = −1, a bug.)
fn laplacian_energy(c: &[f64], order: usize, lambda: f64) -> (f64, f64) {
    let (mut e, mut de) = (0.0, 0.0);
    for l in 1..=order {
        let k = (l * (l + 1)) as f64;
        let s = laplacian_window(l, lambda);
        let band: f64 = (0..2 * l + 1).map(|m| c[l * l + m].powi(2)).sum();
        e += k * k * s * s * band;
        // dσ/dλ = −k²σ², so d(σ²)/dλ = −2k²σ³.
        de += k * k * band * (-2.0 * k * k * s * s * s);
    }
    (e, de)
}

/// λ ≥ 0 such that the windowed Laplacian energy is `target_fraction` ∈ (0, 1] of
/// the unwindowed one, by safeguarded Newton iteration (the energy decreases
/// monotonically in λ). Returns 0 when nothing needs damping.
pub fn laplacian_window_lambda(coeffs: &[f64], target_fraction: f64) -> Result<f64, SbfError> {
    let order = order_of(coeffs.len())?;
    if !(target_fraction > 0.0 && target_fraction <= 1.0) {
        return Err(SbfError::InvalidParameter { name: "Laplacian target fraction", value: target_fraction, reason: "must be in (0, 1]" });
    }
    let (e0, _) = laplacian_energy(coeffs, order, 0.0);
    if e0 == 0.0 || target_fraction == 1.0 {
        return Ok(0.0);
    }
    let target = target_fraction * e0;
    // Bracket [lo, hi] with E(lo) > target ≥ E(hi).
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while laplacian_energy(coeffs, order, hi).0 > target {
        lo = hi;
        hi *= 4.0;
        if hi > 1e30 {
            break;
        }
    }
    let mut lam = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (e, de) = laplacian_energy(coeffs, order, lam);
        let f = e - target;
        if f.abs() <= 1e-13 * e0 {
            break;
        }
        if f > 0.0 {
            lo = lam;
        } else {
            hi = lam;
        }
        let newton = if de != 0.0 { lam - f / de } else { f64::NAN };
        lam = if newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
    }
    Ok(lam)
}

/// sinc⁴ window σ_l = (sin(πl/w)/(πl/w))⁴ for l < w, else 0 (Sloan 2017,
/// "Deringing Spherical Harmonics").
pub fn sinc4_window(l: usize, w: f64) -> f64 {
    if l == 0 {
        return 1.0;
    }
    let x = PI * l as f64 / w;
    if l as f64 >= w {
        0.0
    } else {
        (x.sin() / x).powi(4)
    }
}

/// Applies per-band window factors to coefficients (one channel).
pub fn apply_window(coeffs: &[f64], window: impl Fn(usize) -> f64) -> Result<Vec<f64>, SbfError> {
    let order = order_of(coeffs.len())?;
    let mut out = coeffs.to_vec();
    for l in 0..=order {
        let s = window(l);
        for m in 0..2 * l + 1 {
            out[l * l + m] *= s;
        }
    }
    Ok(out)
}

/// Minimum of Σ c·Y over `dirs` (one channel).
pub fn minimum_over(coeffs: &[f64], dirs: &[DVec3]) -> Result<f64, SbfError> {
    let sh = ShBasis::new(order_of(coeffs.len())?)?;
    let mut y = vec![0.0; sh.len()];
    let mut min = f64::INFINITY;
    for d in dirs {
        sh.eval_into(*d, &mut y);
        min = min.min(coeffs.iter().zip(&y).map(|(a, b)| a * b).sum());
    }
    Ok(min)
}

/// Largest sinc⁴ width w (scanned downwards from L+1 in steps of 1/64) whose
/// windowed reconstruction is ≥ 0 on `dirs`; `None` if even the DC term alone is
/// negative. Returns (w, windowed coefficients).
pub fn sinc4_deringing(coeffs: &[f64], dirs: &[DVec3]) -> Result<Option<(f64, Vec<f64>)>, SbfError> {
    let order = order_of(coeffs.len())?;
    let steps = 64 * (order + 1);
    for k in (1..=steps).rev() {
        let w = k as f64 / 64.0;
        let c = apply_window(coeffs, |l| sinc4_window(l, w))?;
        if minimum_over(&c, dirs)? >= 0.0 {
            return Ok(Some((w, c)));
        }
    }
    Ok(None)
}

/// Deringing where the irradiance rings (Sloan 2017, "Deringing Spherical Harmonics"):
/// if the E/π of radiance coefficients `radiance` (one channel) is negative on any of
/// `dirs`, the radiance windowed by the widest sinc⁴ window that makes that E/π
/// non-negative there, with the window's width; None where nothing rings (or where even
/// the DC term alone is negative, which no window mends).
pub fn dering_irradiance(radiance: &[f64], dirs: &[DVec3]) -> Result<Option<(f64, Vec<f64>)>, SbfError> {
    let irr = irradiance_coefficients(radiance)?;
    if minimum_over(&irr, dirs)? >= 0.0 {
        return Ok(None);
    }
    match sinc4_deringing(&irr, dirs)? {
        Some((w, _)) => Ok(Some((w, apply_window(radiance, |l| sinc4_window(l, w))?))),
        None => Ok(None),
    }
}

/// Fraction of `dirs` where the reconstruction Σ c·Y is negative (a report metric).
pub fn negative_fraction(coeffs: &[f64], dirs: &[DVec3]) -> Result<f64, SbfError> {
    let sh = ShBasis::new(order_of(coeffs.len())?)?;
    let mut y = vec![0.0; sh.len()];
    let neg = dirs
        .iter()
        .filter(|d| {
            sh.eval_into(**d, &mut y);
            coeffs.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>() < 0.0
        })
        .count();
    Ok(neg as f64 / dirs.len().max(1) as f64)
}

/// Normalised zonal (Legendre) coefficients g_l/g_0 = i_l(λ)/i_0(λ), l = 0..=lmax, of an
/// SG lobe e^{λ(μ−1)} of sharpness λ ≥ 0 (non-finite or negative λ: the constant lobe).
///
/// - λ < max(64, lmax²): the continued fraction i_l/i_{l−1} = λ/(2l + 1 + λ·i_{l+1}/i_l)
///   evaluated backwards (Gautschi 1967) from N = lmax + 40 + ⌈2λ⌉: the start error is
///   damped by Π r_l² over the ≥ 2λ + 40 extra terms, where r_l = i_l/i_{l−1} < λ/(l + λ)…
///   falls below ½ beyond l ≈ λ (a fixed 40 terms left the odd bands wrong for λ ≳ 500).
/// - λ ≥ max(64, lmax²): the exact finite form with t = λ(1 − μ):
///   g_l/g_0 = Σ_k (−1)^k (l+k)!/((l−k)!·k!·(2λ)^k) · γ(k+1, 2λ)/(k!·γ(1, 2λ)), where the
///   incomplete-gamma factors equal 1 to within e^{−2λ}(2λ)^k/k! < 1e-25 here; the terms
///   shrink by ≤ l²/(2λ) ≤ ½ per k, so the alternating sum loses no precision.
pub fn sg_zonal_ratios(lambda: f64, lmax: usize) -> Vec<f64> {
    let mut out = vec![0.0; lmax + 1];
    out[0] = 1.0;
    if lambda.is_nan() || lambda <= 0.0 {
        return out;
    }
    let lambda = lambda.min(1e300);
    if lambda >= 64f64.max((lmax * lmax) as f64) {
        for (l, o) in out.iter_mut().enumerate().skip(1) {
            // term_k = (l+k)!/((l−k)!·k!·(2λ)^k), by the ratio of consecutive terms.
            let (mut term, mut sum) = (1.0f64, 1.0f64);
            for k in 0..l {
                term *= -((l + k + 1) as f64) * ((l - k) as f64) / (((k + 1) as f64) * 2.0 * lambda);
                sum += term;
            }
            *o = sum;
        }
        return out;
    }
    let start = lmax + 40 + (2.0 * lambda).ceil() as usize;
    let mut r = 0.0;
    let mut ratios = vec![0.0; lmax + 1];
    for l in (1..=start).rev() {
        r = lambda / ((2 * l + 1) as f64 + lambda * r);
        if l <= lmax {
            ratios[l] = r;
        }
    }
    for l in 1..=lmax {
        out[l] = out[l - 1] * ratios[l];
    }
    out
}

/// GGX specular from SH radiance coefficients (one channel) by zonal convolution
/// about the dominant direction. Approximation (stated): the lobe of f_r·cos about
/// the GGX dominant direction R_d (Lagarde & de Rousiers 2014) is taken as the
/// isotropic warped-NDF SG of sharpness λ = (2/α²)/(4·max(n·v, 1e-4)) normalised to
/// unit integral; its zonal coefficients g_l/g_0 (see [`sg_zonal_ratios`]) filter the
/// SH bands, and the split-sum term f0·dfg₀ + f90·dfg₁ carries the BRDF's energy
/// (constant radiance L gives exactly L·(f0·dfg₀ + f90·dfg₁)). Anisotropy of the
/// warp and horizon clipping are ignored.
pub fn specular_zonal(radiance: &[f64], n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64, dfg: [f64; 2]) -> Result<f64, SbfError> {
    let order = order_of(radiance.len())?;
    let g = specular_zonal_filter(order, n.dot(v), alpha);
    let rgb: Vec<[f64; 3]> = radiance.iter().map(|c| [*c, 0.0, 0.0]).collect();
    Ok(specular_zonal_rgb(&ShBasis::new(order)?, &rgb, &g, n, v, alpha, f0, f90, dfg)?[0])
}

/// The band filter g_l/g_0 of [`specular_zonal`], l = 0…order: it depends only on n·v
/// (clamped below at 1e-4) and α (clamped to [1e-4, 1]), so callers that shade many points
/// of equal n·v compute it once.
pub fn specular_zonal_filter(order: usize, nv: f64, alpha: f64) -> Vec<f64> {
    let alpha = alpha.clamp(1e-4, 1.0);
    let nv = nv.max(1e-4);
    sg_zonal_ratios(2.0 / (alpha * alpha) / (4.0 * nv), order)
}

/// [`specular_zonal`] for three channels at once with the band filter `g` from
/// [`specular_zonal_filter`] (for this n·v and α) and the basis `sh` of the radiance's
/// order (built once by the caller). Allocates nothing up to L16.
#[allow(clippy::too_many_arguments)]
pub fn specular_zonal_rgb(
    sh: &ShBasis,
    radiance: &[[f64; 3]],
    g: &[f64],
    n: DVec3,
    v: DVec3,
    alpha: f64,
    f0: f64,
    f90: f64,
    dfg: [f64; 2],
) -> Result<[f64; 3], SbfError> {
    let order = order_of(radiance.len())?;
    if sh.order() != order {
        return Err(SbfError::LengthMismatch { what: "SH coefficients for the basis", expected: sh.len(), got: radiance.len() });
    }
    if g.len() != order + 1 {
        return Err(SbfError::LengthMismatch { what: "band filter", expected: order + 1, got: g.len() });
    }
    let alpha = alpha.clamp(1e-4, 1.0);
    let r = crate::ggx::reflect(v, n);
    let rd = crate::ggx::dominant_direction(n, r, alpha);
    // Basis values on the stack up to L16 (289 values), on the heap above.
    let mut stack = [0.0; 289];
    let mut heap = Vec::new();
    let y: &mut [f64] = if sh.len() <= stack.len() {
        &mut stack[..sh.len()]
    } else {
        heap.resize(sh.len(), 0.0);
        &mut heap
    };
    sh.try_eval_into(rd, y)?;
    let mut s = [0.0; 3];
    for l in 0..=order {
        for m in 0..2 * l + 1 {
            let w = g[l] * y[l * l + m];
            for (sc, c) in s.iter_mut().zip(radiance[l * l + m]) {
                *sc += w * c;
            }
        }
    }
    // The filtered radiance at R_d is Σ g_l c_lm Y_lm; a constant L gives c₀₀Y₀₀ = L.
    Ok(s.map(|x| x * (f0 * dfg[0] + f90 * dfg[1])))
}
