//! Light evaluation shared by the CPU estimator and the GPU upload: delta lights at a
//! point (directional, point, spot with the KHR_lights_punctual cone and range window),
//! the self-intersection-safe ray offset (the environment's importance sampler is in
//! [`crate::sampling::environment`]).

use super::Light;
use sbf::glam::Vec3;

/// Luminance (Rec. 709 weights), the measure lights are chosen by.
pub fn luminance(c: Vec3) -> f64 {
    (0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) as f64
}

/// The largest light intensity, irradiance or emitted radiance a scene may hold: the
/// estimator squares per-sample values in f32 (variance, GPU moments), and 1e18² = 1e36
/// stays below f32's 3.4e38.
pub const MAX_LIGHT_VALUE: f32 = 1e18;

/// Checks a light's parameters; the error names what is wrong.
pub fn validate(l: &Light) -> Result<(), &'static str> {
    let unit = |d: Vec3| d.is_finite() && (d.length() - 1.0).abs() < 1e-3;
    let colour = |c: Vec3| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= MAX_LIGHT_VALUE;
    match *l {
        Light::Directional { direction, irradiance } => {
            if !unit(direction) {
                return Err("direction must be a finite unit vector");
            }
            if !colour(irradiance) {
                return Err("irradiance must be finite, non-negative and at most 1e18");
            }
        }
        Light::Point { position, intensity, range } => {
            if !position.is_finite() || !colour(intensity) || range.is_nan() || range <= 0.0 {
                return Err("point light: position must be finite, intensity in [0, 1e18], range > 0");
            }
        }
        Light::Spot { position, direction, intensity, cos_inner, cos_outer, range } => {
            if !position.is_finite() || !colour(intensity) || range.is_nan() || range <= 0.0 || !unit(direction) {
                return Err("spot light: finite position, unit direction, intensity in [0, 1e18] and range > 0 required");
            }
            if !(cos_outer.is_finite() && cos_inner.is_finite() && (-1.0..=1.0).contains(&cos_outer) && cos_inner >= cos_outer) {
                return Err("spot light: cone cosines must satisfy −1 ≤ cos(outer) ≤ cos(inner)");
            }
        }
    }
    Ok(())
}

/// KHR_lights_punctual's recommended range window: clamp(1 − (d/range)⁴, 0, 1)² —
/// the spec's "smooth attenuation to zero at the range", 1 for an infinite range.
pub fn range_window(d: f32, range: f32) -> f32 {
    if !range.is_finite() {
        return 1.0;
    }
    let r = (d / range).powi(4);
    (1.0 - r).clamp(0.0, 1.0).powi(2)
}

/// KHR_lights_punctual's spot attenuation: with cd = cos of the angle between the spot
/// axis and the direction to the lit point, t = clamp((cd − cos_outer)/(cos_inner −
/// cos_outer), 0, 1) (the divisor at least 1e-3 as in the spec's sample code), t².
pub fn spot_attenuation(cd: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let scale = 1.0 / (cos_inner - cos_outer).max(1e-3);
    ((cd - cos_outer) * scale).clamp(0.0, 1.0).powi(2)
}

/// A delta light seen from `o`: (unit direction towards the light, irradiance at normal
/// incidence there, distance). Evaluated at the shaded point itself; the shadow ray
/// uses [`shadow_ray`] from the offset origin. None when the light sends nothing to `o`
/// (outside the cone or the range, or at the light's position).
pub fn delta_at(l: &Light, o: Vec3) -> Option<(Vec3, Vec3, f32)> {
    match *l {
        Light::Directional { direction, irradiance } => Some((direction, irradiance, f32::INFINITY)),
        Light::Point { position, intensity, range } => {
            let to = position - o;
            let d2 = to.length_squared();
            let d = d2.sqrt();
            let w = range_window(d, range);
            (d2 > 0.0 && w > 0.0).then(|| (to / d, intensity * (w / d2), d))
        }
        Light::Spot { position, direction, intensity, cos_inner, cos_outer, range } => {
            let to = position - o;
            let d2 = to.length_squared();
            let d = d2.sqrt();
            if d2 <= 0.0 {
                return None;
            }
            let wi = to / d;
            let w = range_window(d, range) * spot_attenuation(-wi.dot(direction), cos_inner, cos_outer);
            (w > 0.0).then(|| (wi, intensity * (w / d2), d))
        }
    }
}

/// The shadow ray from offset origin `o` towards a delta light: (unit direction,
/// length), both measured from `o` (not from the surface point), shortened by 1e-4
/// relative so the ray stops before a point light's position.
pub fn shadow_ray(l: &Light, o: Vec3) -> (Vec3, f32) {
    match *l {
        Light::Directional { direction, .. } => (direction, f32::INFINITY),
        Light::Point { position, .. } | Light::Spot { position, .. } => {
            let to = position - o;
            let d = to.length();
            (to / d, d * (1.0 - 1e-4))
        }
    }
}

/// Ray origin moved off a surface at `p` towards the side of unit `n` (Wächter & Binder,
/// "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6):
/// 256 ulps of each coordinate along n, so the offset scales with the position's
/// magnitude (≈ 3e-5 at 1 unit, 3e-3 at 100), and 1/65536 of n near the origin. The
/// WGSL twin is `offset_ray` in gpu/wgsl/lights.wgsl.
pub fn offset_ray(p: Vec3, n: Vec3) -> Vec3 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let step = |p: f32, n: f32| {
        if p.abs() < ORIGIN {
            return p + FLOAT_SCALE * n;
        }
        let k = (n * INT_SCALE) as i32;
        let k = if p < 0.0 { -k } else { k };
        f32::from_bits((p.to_bits() as i32).wrapping_add(k) as u32)
    };
    Vec3::new(step(p.x, n.x), step(p.y, n.y), step(p.z, n.z))
}

/// The ray origin on the side of a surface (normal `n`) that `dir` leaves from.
pub fn offset_towards(p: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    offset_ray(p, if dir.dot(n) >= 0.0 { n } else { -n })
}
