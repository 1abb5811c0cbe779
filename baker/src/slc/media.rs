//! Stochastic light culling for single scattering in a homogeneous medium (Fujieda, Tokuyoshi & Harada 2022,
//! \[FTH22-supp\]): point lights and diffuse VPLs scatter light towards the camera from every
//! point of the camera ray inside a slab of medium. Each light has one ξ; its random range
//! is bounded by a sphere — the isosurface itself for an isotropic point light, the sphere
//! of [FTH22-supp eq. 2–3] for a diffuse VPL, whose acceptance probability is taken from the
//! bound's directional term, P(d, l) = min(I_max(d)/(δl²), 1) (001 supp. eq. 1, 7) so that
//! the accepted region along a ray is exactly the ray's chord through the sphere. Spheres
//! are culled per 16 × 16 tile against the tile's frustum from the slab's near depth to
//! the farthest surface (two depth halves, as for surfaces).
//!
//! Per pixel and kept light, one distance sample (001 supp. §2.1): inside the *inner*
//! sphere (ξ = 1: P = 1) equiangular sampling of the 1/l² falloff; between the inner and
//! the outer sphere (P < 1) the weighted integrand f/P = σ_s·phase·T·δ·I/I_max has no 1/l²
//! left, so it is sampled uniformly. The two parts are chosen by weights that ignore the
//! light's directionality (the supplement's simplification): the equiangular integral
//! I_rep·Δθ/h and δ × the outer length. The estimate f/(P·π_part·pdf) is unbiased over ξ
//! and the samples wherever I_max > 0 covers I > 0. Brute force (the twin for tests):
//! every light, equiangular sampling over the whole segment, no culling.
//!
//! Isotropic phase function 1/(4π); transmittance exp(−σ_t·length inside the slab) on the
//! camera ray and on the light's segment; no visibility (as the surface harness). Colour: a
//! light's channels share its angular shape, so each light is estimated in its largest
//! channel (its peak: the bounds hold every channel, as the surface VPLs' do) and the
//! estimate scaled by power/peak per channel — the same estimator per channel, unbiased
//! channel by channel.

use crate::slc::{pixel_light_uniforms as slc_uniforms, GBuffer, TILE};
use rayon::prelude::*;
use sbf::glam::{Mat3, Vec3};
use sbf::slc::runtime as slc;
use std::f32::consts::PI;

/// A homogeneous medium filling the view-space slab `near` ≤ −z ≤ `far`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Medium {
    pub sigma_s: f32,
    pub sigma_t: f32,
    pub near: f32,
    pub far: f32,
}

impl Medium {
    /// Checks σ_s ≥ 0, σ_t ≥ σ_s, 0 ≤ near < far, all finite (far may be infinite).
    pub fn validate(&self) -> Result<(), String> {
        let ok = self.sigma_s >= 0.0
            && self.sigma_t >= self.sigma_s
            && self.sigma_t.is_finite()
            && self.near >= 0.0
            && self.near.is_finite()
            && self.far > self.near;
        if ok {
            Ok(())
        } else {
            Err(format!("a medium needs 0 ≤ σ_s ≤ σ_t < ∞ and 0 ≤ near < far, not {self:?}"))
        }
    }

    /// The length of the segment a → b inside the slab (depth −z is linear along it).
    pub fn length_inside(&self, a: Vec3, b: Vec3) -> f32 {
        let (da, db) = (-a.z, -b.z);
        let len = (b - a).length();
        if (db - da).abs() <= f32::EPSILON * (da.abs() + db.abs()) {
            return if da >= self.near && da <= self.far { len } else { 0.0 };
        }
        let s = |depth: f32| (depth - da) / (db - da);
        let (s0, s1) = (s(self.near), s(self.far));
        let (lo, hi) = (s0.min(s1).max(0.0), s0.max(s1).min(1.0));
        (hi - lo).max(0.0) * len
    }

    /// exp(−σ_t · length inside the slab) from a to b.
    pub fn transmittance(&self, a: Vec3, b: Vec3) -> f32 {
        (-self.sigma_t * self.length_inside(a, b)).exp()
    }
}

/// A light in the medium (view space): an isotropic point light (`normal` zero) of
/// intensity power/(4π) per channel, or a diffuse VPL of intensity power·max(d·n, 0)/π.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MediaLight {
    pub position: Vec3,
    pub normal: Vec3,
    /// Emitted power Φ (point light) or reflected flux Φ ⊙ k (diffuse VPL), RGB, ≥ 0.
    pub power: Vec3,
    /// The light's one ξ ∈ (0, 1].
    pub xi: f32,
}

impl MediaLight {
    fn is_point(&self) -> bool {
        self.normal == Vec3::ZERO
    }

    /// The largest channel of the power: the channel the light is estimated and bounded in.
    pub fn peak(&self) -> f32 {
        self.power.max_element()
    }

    /// Each channel's power over the peak (0 for a black light).
    pub fn tint(&self) -> Vec3 {
        let p = self.peak();
        if p > 0.0 {
            self.power / p
        } else {
            Vec3::ZERO
        }
    }

    /// Radiant intensity of the peak channel towards unit `d`.
    pub fn intensity(&self, d: Vec3) -> f32 {
        if self.is_point() {
            self.peak() / (4.0 * PI)
        } else {
            self.peak() * d.dot(self.normal).max(0.0) / PI
        }
    }

    /// The directional term of the acceptance probability: I itself for a point light,
    /// the bound I_max(d) of 001 supp. eq. 7 for a diffuse VPL.
    pub fn intensity_bound(&self, d: Vec3) -> f32 {
        if self.is_point() {
            self.peak() / (4.0 * PI)
        } else {
            slc::diffuse_intensity_bound(d.dot(self.normal), self.peak())
        }
    }

    /// The sphere where P > ξ: the random range's bound for this light's ξ (`xi` = 1:
    /// the inner sphere, where P = 1).
    pub fn sphere(&self, delta: f32, xi: f32) -> slc::Sphere {
        if self.is_point() {
            slc::point_sphere(self.position, self.peak() / (4.0 * PI), delta, xi)
        } else {
            slc::diffuse_sphere(self.position, self.normal, self.peak(), delta, xi)
        }
    }
}

/// Culled (stochastic ranges, tiled culling) or brute force (every light).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MediaMode {
    Culled,
    BruteForce,
}

/// In-scattered radiance per pixel and the culling statistics.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MediaRender {
    /// RGB radiance per pixel.
    pub image: Vec<Vec3>,
    /// Lights kept by the pixel's tile.
    pub lights_per_pixel: Vec<u32>,
    /// Of those, lights whose sphere the pixel's ray segment misses (they add 0).
    pub false_per_pixel: Vec<u32>,
}

/// The camera ray of pixel `k` (unit direction) and its segment in the medium: from the
/// slab's near depth to its far depth or the surface, whichever comes first (None when
/// empty).
pub fn ray_segment(g: &GBuffer, m: &Medium, k: usize) -> (Vec3, Option<(f32, f32)>) {
    let (x, y) = (k % g.width, k / g.width);
    let d = Vec3::new(
        (2.0 * (x as f32 + 0.5) / g.width as f32 - 1.0) * g.tan_xy.0,
        (1.0 - 2.0 * (y as f32 + 0.5) / g.height as f32) * g.tan_xy.1,
        -1.0,
    )
    .normalize();
    let per_depth = 1.0 / -d.z;
    let surface = g.texels[k].map_or(f32::INFINITY, |s| s.position.length());
    let (t0, t1) = (m.near * per_depth, (m.far * per_depth).min(surface));
    (d, (t1 > t0).then_some((t0, t1)))
}

/// The single-scattering integrand along the ray d at distance t from light `l`:
/// σ_s/(4π)·I(ω)/l²·T(camera → y)·T(light → y), with ω, l the direction and distance
/// from the light to y = t·d. Returns (f, unit ω, l).
pub fn integrand(m: &Medium, l: &MediaLight, d: Vec3, t: f32) -> (f32, Vec3, f32) {
    let y = d * t;
    let to = y - l.position;
    let dist = to.length();
    if dist.is_nan() || dist <= 0.0 {
        return (0.0, Vec3::Z, 0.0);
    }
    let w = to / dist;
    let f = m.sigma_s / (4.0 * PI) * l.intensity(w) / (dist * dist) * m.transmittance(Vec3::ZERO, y) * m.transmittance(l.position, y);
    (f, w, dist)
}

/// The closest point of the ray d to `q` (t_c ≥ −∞) and its distance h, clamped to
/// 1e-6 × (1 + |q|) so the equiangular map stays finite for a light on the ray.
fn closest(d: Vec3, q: Vec3) -> (f32, f32) {
    let tc = d.dot(q);
    (tc, (q - d * tc).length().max(1e-6 * (1.0 + q.length())))
}

/// One estimate of light `l`'s in-scattering (its peak channel) along the ray d over
/// [t0, t1] in `mode`, from two uniforms; in culled mode None when the ray misses the
/// light's sphere (a false discovery of the tile).
pub fn estimate(m: &Medium, l: &MediaLight, delta: f32, mode: MediaMode, d: Vec3, (t0, t1): (f32, f32), u: [f32; 2]) -> Option<f32> {
    let (tc, h) = closest(d, l.position);
    if mode == MediaMode::BruteForce {
        let (t, pdf) = slc::equiangular_sample(tc, h, t0, t1, u[1]);
        return Some(if pdf > 0.0 { integrand(m, l, d, t).0 / pdf } else { 0.0 });
    }
    let clip = |c: Option<(f32, f32)>| c.map(|(a, b)| (a.max(t0), b.min(t1))).filter(|(a, b)| b > a);
    let outer = clip(slc::ray_sphere(Vec3::ZERO, d, &l.sphere(delta, l.xi)))?;
    // The inner sphere lies inside the outer one (the spheres grow by homothety about the
    // light, a point of both), so its chord lies inside the outer chord.
    let inner = clip(slc::ray_sphere(Vec3::ZERO, d, &l.sphere(delta, 1.0))).map(|(a, b)| (a.max(outer.0), b.min(outer.1)));
    let parts: Vec<(f32, f32)> = match inner {
        Some((a, b)) => [(outer.0, a), (b, outer.1)].into_iter().filter(|(x, y)| y > x).collect(),
        None => vec![outer],
    };
    let outer_len: f32 = parts.iter().map(|(a, b)| b - a).sum();
    let representative = if l.is_point() { l.peak() / (4.0 * PI) } else { l.peak() / PI };
    let w_in = inner.map_or(0.0, |(a, b)| {
        let angle = (b - tc).atan2(h) - (a - tc).atan2(h);
        representative * angle / h
    });
    let w_out = delta * outer_len;
    // Which part to sample: all-inner or all-outer when the other is empty; a weight that
    // overflows (h → 0: a light on the ray) takes the inner part.
    let p_in = match (inner.is_some(), parts.is_empty()) {
        (false, _) => 0.0,
        (true, true) => 1.0,
        (true, false) if !w_in.is_finite() => 1.0,
        (true, false) => w_in / (w_in + w_out),
    };
    let (t, pdf) = if parts.is_empty() || u[0] < p_in {
        let (a, b) = inner.expect("an inner chord when the outer parts are empty or p_in > 0");
        let (t, pdf) = slc::equiangular_sample(tc, h, a, b, u[1]);
        (t, p_in * pdf)
    } else {
        let mut s = u[1] * outer_len;
        let mut t = parts[parts.len() - 1].1;
        for (a, b) in &parts {
            if s <= b - a {
                t = a + s;
                break;
            }
            s -= b - a;
        }
        (t, (1.0 - p_in) / outer_len)
    };
    let (f, w, dist) = integrand(m, l, d, t);
    let p = slc::acceptance_probability(l.intensity_bound(w), delta, dist);
    Some(if pdf > 0.0 && p > 0.0 { f / (p * pdf) } else { 0.0 })
}

/// Renders the single-scattered RGB radiance of `lights` in `m` seen through `g`'s pixels
/// (the G-buffer only ends rays at surfaces), one sample per pixel and light from
/// (`seed`, pixel, light) — identical for any thread count.
pub fn render(g: &GBuffer, m: &Medium, lights: &[MediaLight], delta: f32, mode: MediaMode, seed: u64) -> MediaRender {
    let (tw, th) = (g.width.div_ceil(TILE), g.height.div_ceil(TILE));
    let tiles: Vec<Vec<(usize, Vec3, u32, u32)>> = (0..tw * th)
        .into_par_iter()
        .map(|tile| {
            let (tx, ty) = (tile % tw, tile / tw);
            let pixels: Vec<usize> = (ty * TILE..((ty + 1) * TILE).min(g.height))
                .flat_map(|y| (tx * TILE..((tx + 1) * TILE).min(g.width)).map(move |x| y * g.width + x))
                .collect();
            // The tile's medium: from the near depth to the farthest surface (or far).
            let zmax = pixels.iter().map(|k| g.texels[*k].map_or(m.far, |s| (-s.position.z).min(m.far))).fold(m.near, f32::max);
            let mid = 0.5 * (m.near + zmax);
            let (x0, y0) = ((tx * TILE) as f32, (ty * TILE) as f32);
            let (x1, y1) = ((x0 + TILE as f32).min(g.width as f32), (y0 + TILE as f32).min(g.height as f32));
            let part =
                |a: f32, b: f32| slc::tile_corners(x0, y0, x1, y1, g.width as f32, g.height as f32, g.tan_xy.0, g.tan_xy.1, a.max(1e-6), b);
            let halves = [part(m.near, mid), part(mid, zmax)];
            let kept: Vec<usize> = (0..lights.len())
                .filter(|j| match mode {
                    MediaMode::BruteForce => true,
                    MediaMode::Culled => {
                        let s = lights[*j].sphere(delta, lights[*j].xi);
                        let e = slc::Ellipsoid { center: s.center, axes: Mat3::IDENTITY, radii: Vec3::splat(s.radius) };
                        let (mm, mc) = slc::cull_transform(&e, Mat3::IDENTITY, Vec3::ZERO);
                        zmax > m.near && halves.iter().any(|c| slc::ellipsoid_hits_corners(mm, mc, c))
                    }
                })
                .collect();
            pixels
                .iter()
                .map(|&k| {
                    let (d, seg) = ray_segment(g, m, k);
                    let Some(seg) = seg else { return (k, Vec3::ZERO, kept.len() as u32, kept.len() as u32) };
                    let (mut sum, mut misses) = (Vec3::ZERO, 0u32);
                    for &j in &kept {
                        let u = slc_uniforms(seed, k as u64, j as u64);
                        match estimate(m, &lights[j], delta, mode, d, seg, u) {
                            Some(v) => sum += v * lights[j].tint(),
                            None => misses += 1,
                        }
                    }
                    (k, sum, kept.len() as u32, misses)
                })
                .collect()
        })
        .collect();
    let n = g.width * g.height;
    let mut out = MediaRender { image: vec![Vec3::ZERO; n], lights_per_pixel: vec![0; n], false_per_pixel: vec![0; n] };
    for (k, v, c, f) in tiles.into_iter().flatten() {
        out.image[k] = v;
        out.lights_per_pixel[k] = c;
        out.false_per_pixel[k] = f;
    }
    out
}
