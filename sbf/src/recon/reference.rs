//! Reference integrators (f64), the oracles for every reconstruction method.
//!
//! - [`irradiance_map`]: exact quadrature of E/π over all texels of a lat-long map
//!   (texel radiance × exact solid angle × clamped cosine / π).
//! - [`irradiance_fn`]: E/π of any radiance function by cosine-weighted
//!   importance sampling with a Halton sequence (estimator L(ω) per sample).
//! - [`ggx_specular`]: ∫ L(l)·f_r(v, l)·(n·l) dl for single-scattering GGX with
//!   height-correlated Smith G2 and Schlick Fresnel (f0/f90 split), by
//!   visible-normal sampling (weight F·G2/G1), for any unit normal n and view v.

use crate::basis::ambient_dice_bezier::tangent_frame;
use crate::envmap::LatLongImage;
use crate::ggx;
use crate::sampling::{cosine_hemisphere, halton2};
use glam::DVec3;
use std::f64::consts::PI;

/// Exact E/π at unit normal `n` from every texel of `map`.
pub fn irradiance_map(map: &LatLongImage, n: DVec3) -> [f64; 3] {
    map.integrate(|d, l| {
        let c = n.dot(d);
        if c > 0.0 {
            l.map(|v| v * c / PI)
        } else {
            [0.0; 3]
        }
    })
}

/// E/π at unit normal `n` of radiance `f`, by `samples` cosine-weighted Halton
/// samples about n (unbiased; error ~ 1/samples for smooth f).
pub fn irradiance_fn(f: impl Fn(DVec3) -> [f64; 3], n: DVec3, samples: u32) -> [f64; 3] {
    let (t, b) = tangent_frame(n);
    let mut acc = [0.0; 3];
    let k = samples.max(1);
    for i in 0..k {
        let l = cosine_hemisphere(halton2(i as u64 + 1));
        let v = f(t * l.x + b * l.y + n * l.z);
        for c in 0..3 {
            acc[c] += v[c];
        }
    }
    acc.map(|a| a / k as f64)
}

/// GGX specular ∫ L(l) f_r(v,l) (n·l) dl for unit normal `n`, unit view `v`
/// (pointing away from the surface), roughness α, Fresnel (f0, f90), using
/// `samples` visible-normal samples (Halton). Returns 0 for v below the surface.
/// α is clamped to [1e-4, 1].
pub fn ggx_specular(f: impl Fn(DVec3) -> [f64; 3], n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64, samples: u32) -> [f64; 3] {
    let alpha = alpha.clamp(1e-4, 1.0);
    let (t, b) = tangent_frame(n);
    let vt = DVec3::new(v.dot(t), v.dot(b), v.dot(n));
    if vt.z <= 0.0 {
        return [0.0; 3];
    }
    let g1 = ggx::g1(vt, alpha);
    let k = samples.max(1);
    let mut acc = [0.0; 3];
    for i in 0..k {
        let h = ggx::sample_vndf(vt, alpha, halton2(i as u64 + 1));
        let l = ggx::reflect(vt, h);
        if l.z <= 0.0 {
            continue;
        }
        let fc = ggx::schlick_weight(vt.dot(h));
        let w = (f0 * (1.0 - fc) + f90 * fc) * ggx::g2(vt, l, alpha) / g1;
        let val = f(t * l.x + b * l.y + n * l.z);
        for c in 0..3 {
            acc[c] += w * val[c];
        }
    }
    acc.map(|a| a / k as f64)
}

/// GGX specular by exact quadrature over a sample set (e.g. every texel of a map
/// with its solid angle): Σ_k w_k·L_k·D·G2·F/(4 n·v) over samples above the surface,
/// in tangent space (normal +Z; `v` unit with v_z > 0). Deterministic and free of the
/// variance a sharp sun gives Monte Carlo; its error is the map's own resolution
/// (the BRDF is sampled at texel centres: fine for α ≳ 0.05 at 256×128).
pub fn ggx_specular_samples(samples: &[crate::solve::RadianceSample], v: DVec3, alpha: f64, f0: f64, f90: f64) -> [f64; 3] {
    if v.z <= 0.0 {
        return [0.0; 3];
    }
    let alpha = alpha.clamp(1e-4, 1.0);
    let mut acc = [0.0; 3];
    for s in samples {
        let l = s.direction;
        if l.z <= 0.0 {
            continue;
        }
        let h = (v + l).normalize();
        let fc = ggx::schlick_weight(v.dot(h));
        let w = s.weight * ggx::d(h, alpha) * ggx::g2(v, l, alpha) * (f0 * (1.0 - fc) + f90 * fc) / (4.0 * v.z);
        for c in 0..3 {
            acc[c] += w * s.value[c];
        }
    }
    acc
}
