//! Stochastic light culling of virtual point lights (VPLs) on a G-buffer (seed 002 §5–6,
//! the CPU reference of `wgsl/slc_cull.wgsl`): per light a random range from its one ξ,
//! bounded by a sphere (diffuse VPL, 001 eq. 2–3) or a spheroid (GGX VPL, 002 eq. 12–15);
//! per 16 × 16 tile the depth range split in two (Modified HalfZ), each light kept if its
//! bound meets either part (`sbf::slc::ellipsoid_hits_corners`); per pixel the kept lights
//! shaded with the stochastic falloff L/p where p > ξ (002 eq. 3). Receivers are Lambertian
//! (diffuse→diffuse and glossy→diffuse single-bounce light); visibility is not tested (as
//! in the paper's measurements). Brute force shades every light without falloff (the
//! reference); the deterministic range cut (the classic biased method) is kept for tests.
//!
//! View space: the camera at the origin looking down −z; the G-buffer holds view-space
//! positions and normals, so lights are given in view space too.

use sbf::glam::{Mat3, Vec3};
use sbf::slc::runtime as slc;

/// Tile side in pixels.
pub const TILE: usize = 16;

/// A VPL (view space).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vpl {
    pub position: Vec3,
    /// Unit geometric normal.
    pub normal: Vec3,
    /// Unit direction towards where its light came from (ω_i, in n's hemisphere).
    pub incoming: Vec3,
    /// Flux arriving at the VPL (one channel).
    pub flux: f32,
    /// Diffuse reflectance k (diffuse VPL) — 0 for a glossy one.
    pub diffuse: f32,
    /// GGX α and Schlick F0 (glossy VPL; ignored when `diffuse` > 0).
    pub alpha: f32,
    pub f0: f32,
    /// The light's one uniform number ξ ∈ (0, 1].
    pub xi: f32,
}

impl Vpl {
    /// Radiant intensity towards unit direction `wo` (002 eq. 4): Φk·cos/π for a diffuse
    /// VPL, Φ·f_GGX(ω_i, ω_o)·cos for a glossy one (height-correlated Smith G2, Schlick).
    pub fn intensity(&self, wo: Vec3) -> f32 {
        let c = wo.dot(self.normal);
        if c <= 0.0 {
            return 0.0;
        }
        if self.diffuse > 0.0 {
            return self.flux * self.diffuse * c * std::f32::consts::FRAC_1_PI;
        }
        let (t, b) = crate::lightmap::frame(self.normal);
        let local = |w: Vec3| sbf::glam::DVec3::new(w.dot(t) as f64, w.dot(b) as f64, w.dot(self.normal) as f64);
        let f0 = self.f0 as f64;
        sbf::slc::ggx_vpl_intensity(self.flux as f64, local(self.incoming), local(wo), self.alpha as f64, &|ch| {
            f0 + (1.0 - f0) * (1.0 - ch).powi(5)
        }) as f32
    }

    /// The culling transform (M = B·S, M·c) of the light's bound for random-range
    /// parameter δ: the diffuse sphere or the GGX spheroid (view space = bound space).
    pub fn bound(&self, delta: f32) -> (Mat3, Vec3) {
        let e = if self.diffuse > 0.0 {
            let s = slc::diffuse_sphere(self.position, self.normal, self.flux * self.diffuse, delta, self.xi);
            slc::Ellipsoid { center: s.center, axes: Mat3::IDENTITY, radii: Vec3::splat(s.radius) }
        } else {
            let cos_i = self.incoming.dot(self.normal);
            let r =
                slc::spheroid_scale(self.flux, slc::schlick_max(self.f0, cos_i), slc::g1_dist(cos_i, self.alpha), cos_i, delta, self.xi);
            slc::ggx_spheroid(self.position, self.incoming, self.normal, self.alpha, r)
        };
        slc::cull_transform(&e, Mat3::IDENTITY, Vec3::ZERO)
    }
}

/// A view-space G-buffer: per pixel position, normal and Lambert albedo (None: background).
#[derive(Debug, Clone)]
pub struct GBuffer {
    pub width: usize,
    pub height: usize,
    /// tan of the half field of view in x and y (symmetric perspective).
    pub tan_xy: (f32, f32),
    pub texels: Vec<Option<(Vec3, Vec3, f32)>>,
}

/// How lights are selected per pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Tiled culling by the random ranges' bounds, stochastic falloff (unbiased).
    Culled,
    /// Every light, no falloff (the reference).
    BruteForce,
    /// Every light within its range for ξ = ½, unweighted (the classic biased cut).
    RangeCut,
}

/// A rendered image and the culling statistics.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Render {
    /// Radiance towards the camera per pixel.
    pub image: Vec<f32>,
    /// Lights shaded per pixel (kept by its tile).
    pub lights_per_pixel: Vec<u32>,
    /// Kept (tile, light) pairs, and those no pixel of the tile accepted (p ≤ ξ everywhere).
    pub kept: u64,
    pub false_positives: u64,
}

/// The radiance a Lambert receiver at `x` (normal `n`, albedo ρ) sends to the camera from
/// a light of intensity I towards it: I·max(n·(q − x)/d, 0)/d² · ρ/π; with the distance d.
fn receive(v: &Vpl, x: Vec3, n: Vec3, albedo: f32) -> (f32, f32) {
    let to = x - v.position;
    let d2 = to.length_squared();
    let d = d2.sqrt();
    let wo = to / d;
    let cos_r = (-wo).dot(n).max(0.0);
    (v.intensity(wo) * cos_r / d2 * albedo * std::f32::consts::FRAC_1_PI, d)
}

/// Renders `g` lit by `vpls` in `mode` (CPU reference of the GPU kernel).
pub fn render(g: &GBuffer, vpls: &[Vpl], delta: f32, mode: Mode) -> Render {
    let mut out = Render { image: vec![0.0; g.width * g.height], lights_per_pixel: vec![0; g.width * g.height], ..Default::default() };
    let bounds: Vec<(Mat3, Vec3)> = vpls.iter().map(|v| v.bound(delta)).collect();
    for ty in 0..g.height.div_ceil(TILE) {
        for tx in 0..g.width.div_ceil(TILE) {
            let pixels: Vec<usize> = (ty * TILE..((ty + 1) * TILE).min(g.height))
                .flat_map(|y| (tx * TILE..((tx + 1) * TILE).min(g.width)).map(move |x| y * g.width + x))
                .filter(|k| g.texels[*k].is_some())
                .collect();
            if pixels.is_empty() {
                continue;
            }
            let (zmin, zmax) = pixels.iter().fold((f32::INFINITY, 0.0f32), |(a, b), k| {
                let z = -g.texels[*k].expect("valid").0.z;
                (a.min(z), b.max(z))
            });
            let mid = 0.5 * (zmin + zmax);
            let (x0, y0) = ((tx * TILE) as f32, (ty * TILE) as f32);
            let part = |a: f32, b: f32| {
                slc::tile_corners(x0, y0, x0 + TILE as f32, y0 + TILE as f32, g.width as f32, g.height as f32, g.tan_xy.0, g.tan_xy.1, a, b)
            };
            let halves = [part(zmin, mid), part(mid, zmax)];
            for (j, v) in vpls.iter().enumerate() {
                let keep = match mode {
                    Mode::Culled => halves.iter().any(|c| slc::ellipsoid_hits_corners(bounds[j].0, bounds[j].1, c)),
                    Mode::BruteForce | Mode::RangeCut => true,
                };
                if !keep {
                    continue;
                }
                out.kept += 1;
                let mut accepted = false;
                for &k in &pixels {
                    let (x, n, albedo) = g.texels[k].expect("valid");
                    let (l, d) = receive(v, x, n, albedo);
                    let add = match mode {
                        Mode::BruteForce => l,
                        Mode::Culled => {
                            let p = slc::acceptance_probability(v.intensity((x - v.position) / d), delta, d);
                            accepted |= p > v.xi;
                            slc::culled_estimate(l, p, v.xi)
                        }
                        Mode::RangeCut => {
                            if d <= slc::random_range(v.intensity((x - v.position) / d), delta, 0.5) {
                                l
                            } else {
                                0.0
                            }
                        }
                    };
                    out.image[k] += add;
                    out.lights_per_pixel[k] += 1;
                }
                out.false_positives += (mode == Mode::Culled && !accepted) as u64;
            }
        }
    }
    out
}
