//! Reference integrators (f64), the oracles for every reconstruction method.
//!
//! - [`irradiance_map`]: exact quadrature of E/π over all texels of a lat-long map
//!   (texel radiance × exact solid angle × clamped cosine / π).
//! - [`irradiance_fn`]: E/π of any radiance function by cosine-weighted
//!   importance sampling with a Halton sequence (estimator L(ω) per sample).
//! - [`ggx_specular`]: ∫ L(l)·f_r(v, l)·(n·l) dl for single-scattering GGX with
//!   height-correlated Smith G2 and Schlick Fresnel (f0/f90 split), by
//!   visible-normal sampling (weight F·G2/G1), for any unit normal n and view v.
//! - [`ggx_specular_mis`]: the same integral for a lat-long map with a small bright
//!   source (a sun): visible-normal samples and map samples ([`MapSampler`], texels by
//!   luminance × solid angle) combined by the balance heuristic (Veach 1997, §9.2).

use crate::envmap::{LatLong, LatLongImage};
use crate::frame::tangent_frame;
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

/// Importance sampling of a lat-long map: a texel with probability ∝ mean channel ×
/// exact solid angle, then a point uniform in solid angle inside it (u uniform, cos θ
/// uniform between the row's bounds). The pdf is piecewise constant per texel.
#[derive(Debug, Clone)]
pub struct MapSampler {
    geometry: LatLong,
    /// Inclusive prefix sums of the texel weights, row-major.
    cdf: Vec<f64>,
    total: f64,
    /// Texels whose weight was not finite (NaN/∞ radiance), given weight 0.
    non_finite: usize,
}

impl MapSampler {
    /// `None` when the map has no positive texel (nothing to importance-sample). Texels
    /// with non-finite radiance get weight 0 and are counted ([`MapSampler::non_finite_texels`]).
    pub fn new(map: &LatLongImage) -> Option<Self> {
        let g = map.geometry;
        let mut cdf = Vec::with_capacity(g.texel_count());
        let mut acc = 0.0;
        let mut non_finite = 0;
        for j in 0..g.height {
            let omega = g.texel_solid_angle(j);
            for i in 0..g.width {
                let t = map.texel(i, j);
                // (f64::max would turn a NaN mean into 0 unnoticed: check the texel first.)
                if t.iter().all(|c| c.is_finite()) {
                    acc += ((t[0] as f64 + t[1] as f64 + t[2] as f64) / 3.0).max(0.0) * omega;
                } else {
                    non_finite += 1;
                }
                cdf.push(acc);
            }
        }
        (acc > 0.0).then_some(MapSampler { geometry: g, cdf, total: acc, non_finite })
    }

    /// How many texels had non-finite radiance (sampled with probability 0).
    pub fn non_finite_texels(&self) -> usize {
        self.non_finite
    }

    fn cos_bounds(&self, j: usize) -> (f64, f64) {
        let h = self.geometry.height as f64;
        ((PI * j as f64 / h).cos(), (PI * (j + 1) as f64 / h).cos())
    }

    /// A direction and its pdf (per steradian) from a point of the unit square.
    pub fn sample(&self, u: [f64; 2]) -> (DVec3, f64) {
        let x = u[0] * self.total;
        let k = self.cdf.partition_point(|c| *c <= x).min(self.cdf.len() - 1);
        let lo = if k == 0 { 0.0 } else { self.cdf[k - 1] };
        let w = self.cdf[k] - lo;
        let fu = if w > 0.0 { ((x - lo) / w).clamp(0.0, 1.0) } else { 0.5 };
        let (i, j) = (k % self.geometry.width, k / self.geometry.width);
        let (c0, c1) = self.cos_bounds(j);
        let ct = (c0 + u[1] * (c1 - c0)).clamp(-1.0, 1.0);
        let d = LatLong::uv_to_direction((i as f64 + fu) / self.geometry.width as f64, ct.acos() / PI);
        (d, w / self.total / self.geometry.texel_solid_angle(j))
    }

    /// pdf (per steradian) of direction `d` (unit).
    pub fn pdf(&self, d: DVec3) -> f64 {
        let (u, v) = LatLong::direction_to_uv(d);
        self.pdf_uv(u, v)
    }

    /// pdf (per steradian) at texture coordinates (u, v).
    pub fn pdf_uv(&self, u: f64, v: f64) -> f64 {
        let (w, h) = (self.geometry.width, self.geometry.height);
        let i = ((u * w as f64) as usize).min(w - 1);
        let j = ((v * h as f64) as usize).min(h - 1);
        let k = j * w + i;
        let wk = self.cdf[k] - if k == 0 { 0.0 } else { self.cdf[k - 1] };
        wk / self.total / self.geometry.texel_solid_angle(j)
    }
}

/// [`ggx_specular`] of a lat-long map with multiple importance sampling: `samples`
/// visible-normal directions (Halton) and `samples` map directions (R2 through
/// [`MapSampler`]), each weighted by the balance heuristic, f·L/(N·(p_vndf + p_map))
/// (Veach 1997, eq. 9.8 with equal counts). Radiance is `map.bilinear`, as in
/// [`ggx_specular`]; without a sampler (a black map) this is plain VNDF sampling.
/// Unbiased for the bilinear radiance; a sun a few texels wide, which VNDF sampling
/// alone finds by chance, is found by the map samples every time.
pub fn ggx_specular_mis(
    map: &LatLongImage,
    sampler: Option<&MapSampler>,
    n: DVec3,
    v: DVec3,
    alpha: f64,
    f0: f64,
    f90: f64,
    samples: u32,
) -> [f64; 3] {
    let Some(ms) = sampler else { return ggx_specular(|w| map.bilinear(w), n, v, alpha, f0, f90, samples) };
    ggx_specular_mis_shifted(map, ms, n, v, alpha, f0, f90, samples, [0.0; 4])
}

/// [`ggx_specular_mis`] with both point sets moved by a Cranley–Patterson rotation
/// (u ↦ frac(u + shift), the first two shift components for the visible-normal Halton
/// points, the last two for the map's R2 points): with a uniformly random shift each
/// estimate is unbiased and independent of the others, so replicates give a standard
/// error (Owen 2013, "Monte Carlo theory, methods and examples", §17.3).
#[allow(clippy::too_many_arguments)]
pub fn ggx_specular_mis_shifted(
    map: &LatLongImage,
    ms: &MapSampler,
    n: DVec3,
    v: DVec3,
    alpha: f64,
    f0: f64,
    f90: f64,
    samples: u32,
    shift: [f64; 4],
) -> [f64; 3] {
    let rot = |u: [f64; 2], s: [f64; 2]| [(u[0] + s[0]).fract(), (u[1] + s[1]).fract()];
    let alpha = alpha.clamp(1e-4, 1.0);
    let (t, b) = tangent_frame(n);
    let vt = DVec3::new(v.dot(t), v.dot(b), v.dot(n));
    if vt.z <= 0.0 {
        return [0.0; 3];
    }
    let k = samples.max(1) as f64;
    // BRDF × cosine in tangent space: F·D·G2/(4 v_z), and the VNDF pdf of l.
    let fcos_pdf = |l: DVec3| -> Option<(f64, f64, DVec3)> {
        if l.z <= 0.0 {
            return None;
        }
        let h = (vt + l).normalize();
        let vh = vt.dot(h);
        if vh.is_nan() || vh <= 0.0 {
            return None;
        }
        let fc = ggx::schlick_weight(vh);
        let fr = (f0 * (1.0 - fc) + f90 * fc) * ggx::d(h, alpha) * ggx::g2(vt, l, alpha) / (4.0 * vt.z);
        let pb = ggx::vndf_pdf(vt, h, alpha) / (4.0 * vh);
        Some((fr, pb, t * l.x + b * l.y + n * l.z))
    };
    let mut acc = [0.0; 3];
    let mut add = |l: DVec3| {
        if let Some((fr, pb, w)) = fcos_pdf(l) {
            let (u, vv) = LatLong::direction_to_uv(w);
            let den = k * (pb + ms.pdf_uv(u, vv));
            if fr > 0.0 && den > 0.0 {
                let val = map.bilinear_uv(u, vv);
                for c in 0..3 {
                    acc[c] += fr * val[c] / den;
                }
            }
        }
    };
    for i in 0..samples.max(1) {
        let h = ggx::sample_vndf(vt, alpha, rot(halton2(i as u64 + 1), [shift[0], shift[1]]));
        add(ggx::reflect(vt, h));
    }
    let r2 = crate::sampling::R2::new();
    for i in 0..samples.max(1) {
        let (w, _) = ms.sample(rot(r2.point(i as u64), [shift[2], shift[3]]));
        add(DVec3::new(w.dot(t), w.dot(b), w.dot(n)));
    }
    acc
}
