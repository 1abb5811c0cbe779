//! Light evaluation shared by the CPU estimator and the GPU upload: delta lights at a
//! point (directional, point, spot with the KHR_lights_punctual cone and range window),
//! the self-intersection-safe ray offset, and the environment's importance sampler
//! (luminance × solid angle over a lat-long grid).

use crate::scene::{Environment, Light};
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
/// WGSL twin is `offset_ray` in trace.wgsl.
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

/// Importance sampling of the environment by luminance × solid angle on a lat-long grid
/// (rows from the zenith, columns as `scene::latlong_texel`): a marginal CDF over rows,
/// a conditional CDF per row, and a direction uniform in (φ, cos θ) within the chosen
/// cell, so the solid-angle pdf is P(cell)/Ω(cell) exactly. A map uses its own texels
/// (its nearest-texel radiance is then constant per cell: zero-variance cells); analytic
/// environments are tabulated at 64 × 32. Cells of zero luminance are never chosen; the
/// point/BSDF sample covers them (MIS stays unbiased since that strategy's pdf is > 0
/// wherever the environment is seen).
#[derive(Debug, Clone, PartialEq)]
pub struct EnvSampler {
    pub width: usize,
    pub height: usize,
    /// Marginal CDF over rows (height entries, last = 1).
    pub row_cdf: Vec<f32>,
    /// Conditional CDF within each row (width × height, row-major, each row ends at 1;
    /// an all-zero row is uniform).
    pub col_cdf: Vec<f32>,
    /// Probability of each cell (row-major).
    pub cell_p: Vec<f32>,
}

impl EnvSampler {
    /// The sampler for `env`, or None for a black environment.
    pub fn new(env: &Environment) -> Option<EnvSampler> {
        type Luminance<'e> = Box<dyn Fn(usize, usize) -> f64 + 'e>;
        let (w, h, lum): (usize, usize, Luminance) = match env {
            Environment::Black => return None,
            Environment::Map(m) => {
                let w = m.geometry.width;
                (w, w / 2, Box::new(move |i, j| luminance(Vec3::from(m.texel(i, j))).max(0.0)))
            }
            e => {
                let (w, h) = (64, 32);
                let e = e.clone();
                (
                    w,
                    h,
                    Box::new(move |i, j| {
                        let th = std::f64::consts::PI * (j as f64 + 0.5) / h as f64;
                        let u = (i as f64 + 0.5) / w as f64;
                        luminance(e.radiance(dir_of(u, th.cos()))).max(0.0)
                    }),
                )
            }
        };
        let mut cell = vec![0.0f64; w * h];
        for j in 0..h {
            let omega = cell_solid_angle(j, w, h);
            for i in 0..w {
                cell[j * w + i] = lum(i, j) * omega;
            }
        }
        let total: f64 = cell.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let (mut row_cdf, mut col_cdf, mut cell_p) = (Vec::with_capacity(h), Vec::with_capacity(w * h), Vec::with_capacity(w * h));
        let mut acc_rows = 0.0;
        for j in 0..h {
            let row = &cell[j * w..(j + 1) * w];
            let rs: f64 = row.iter().sum();
            acc_rows += rs;
            row_cdf.push((acc_rows / total) as f32);
            let mut acc = 0.0;
            for (i, c) in row.iter().enumerate() {
                acc += if rs > 0.0 { c / rs } else { 1.0 / w as f64 };
                col_cdf.push(if i + 1 == w { 1.0 } else { acc as f32 });
                cell_p.push((c / total) as f32);
            }
        }
        if let Some(l) = row_cdf.last_mut() {
            *l = 1.0;
        }
        Some(EnvSampler { width: w, height: h, row_cdf, col_cdf, cell_p })
    }

    /// A direction for uniform `u` in [0,1)³ and its solid-angle pdf.
    pub fn sample(&self, u: [f64; 3]) -> (Vec3, f64) {
        let j = self.row_cdf.partition_point(|c| (*c as f64) <= u[0]).min(self.height - 1);
        let row = &self.col_cdf[j * self.width..(j + 1) * self.width];
        let i = row.partition_point(|c| (*c as f64) <= u[1]).min(self.width - 1);
        let (w, h) = (self.width as f64, self.height as f64);
        let (c0, c1) = ((std::f64::consts::PI * j as f64 / h).cos(), (std::f64::consts::PI * (j + 1) as f64 / h).cos());
        let cos_t = c0 + (c1 - c0) * u[2];
        // A second uniform for φ within the cell: the fractional position of u[1] in the
        // cell's CDF interval (stratified, no extra random number).
        let lo = if i == 0 { 0.0 } else { row[i - 1] as f64 };
        let hi = row[i] as f64;
        let f = if hi > lo { ((u[1] - lo) / (hi - lo)).clamp(0.0, 1.0) } else { 0.5 };
        let d = dir_of((i as f64 + f) / w, cos_t);
        (d, self.pdf_cell(i, j))
    }

    /// Solid-angle pdf of sampling direction `d`.
    pub fn pdf(&self, d: Vec3) -> f64 {
        let (i, j) = crate::scene::latlong_texel(d, self.width);
        self.pdf_cell(i, j.min(self.height - 1))
    }

    fn pdf_cell(&self, i: usize, j: usize) -> f64 {
        self.cell_p[j * self.width + i] as f64 / cell_solid_angle(j, self.width, self.height)
    }
}

/// Solid angle of a cell in row `j` of a w × h lat-long grid: (2π/w)(cos θ_j − cos θ_j+1).
pub fn cell_solid_angle(j: usize, w: usize, h: usize) -> f64 {
    let t = |k: usize| (std::f64::consts::PI * k as f64 / h as f64).cos();
    2.0 * std::f64::consts::PI / w as f64 * (t(j) - t(j + 1))
}

/// The direction at lat-long coordinate u (column fraction) and cos θ from +Y, inverse of
/// `scene::latlong_texel`'s mapping u = ½(1 + atan2(x, −z)/π).
fn dir_of(u: f64, cos_t: f64) -> Vec3 {
    let phi = (2.0 * u - 1.0) * std::f64::consts::PI;
    let s = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    Vec3::new((s * phi.sin()) as f32, cos_t as f32, (-s * phi.cos()) as f32)
}
