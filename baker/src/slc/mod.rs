//! Stochastic light culling of virtual point lights (VPLs) on a G-buffer ([TH17 §5–6],
//! the CPU reference of `slc/cull.wgsl`): per light a random range from its one ξ,
//! bounded by a sphere (diffuse VPL, [FTH22-supp eq. 2–3]) or a spheroid (GGX VPL, [TH17 eq. 12–15]);
//! per 16 × 16 tile the depth range split in two (Modified HalfZ), each light kept if its
//! bound meets either part (`sbf::slc::ellipsoid_hits_corners`); per pixel the kept lights
//! shaded with the stochastic falloff L/p where p > ξ ([TH17 eq. 3]). Receivers are Lambertian
//! (diffuse→diffuse and glossy→diffuse single-bounce light); visibility is not tested (as
//! in the paper's measurements). Brute force shades every light without falloff (the
//! reference); the deterministic range cut (the classic biased method) is kept for tests.
//!
//! View space: the camera at the origin looking down −z; the G-buffer holds view-space
//! positions and normals, so lights are given in view space too.

//!
//! The module tree: this file (VPLs, receivers, bounds, tiled culling and shading on the
//! CPU), [`from_scene`] (the camera, G-buffer, VPLs and random numbers a scene gives),
//! [`rsm`] (VPLs from reflective shadow maps), [`compare`] (bounds and culling schemes side by side), [`mod@filter`] (joining the interleaving subregions), [`gpu`] (the wgpu twin),
//! [`media`] (single scattering, \[FTH22-supp\]), [`media_gpu`] (its wgpu twin) and [`media_run`] (the `--medium` run), [`sweep`] (the equal-time experiment), [`harness`]
//! (what the `slc` command renders and writes).
//!
//! Uses: [`crate::scene`] and the image writers of [`crate::output`].
pub mod compare;
pub mod filter;
pub mod from_scene;
pub mod gpu;
pub mod harness;
pub mod media;
pub mod media_gpu;
pub mod media_run;
pub mod options;
pub mod rsm;
pub mod sweep;

pub use filter::{filter, Filter};
pub use from_scene::{add_bounces, gbuffer_from_scene, pixel_light_uniforms, vpl_xi, vpls_from_scene, vpls_from_scene_with, Camera};

use sbf::glam::{Mat3, Vec3};
use sbf::slc::runtime as slc;

/// Tile side in pixels.
pub const TILE: usize = 16;

/// A VPL (view space), RGB.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vpl {
    pub position: Vec3,
    /// Unit geometric normal.
    pub normal: Vec3,
    /// Unit direction towards where its light came from (ω_i, in n's hemisphere).
    pub incoming: Vec3,
    /// Flux arriving at the VPL, per channel.
    pub flux: Vec3,
    /// Diffuse reflectance k per channel (diffuse VPL) — zero for a glossy one.
    pub diffuse: Vec3,
    /// GGX α and Schlick F0 per channel (glossy VPL; ignored when `diffuse` is not zero).
    pub alpha: f32,
    pub f0: Vec3,
    /// The light's one uniform number ξ ∈ (0, 1].
    pub xi: f32,
}

/// The GGX specular BRDF f(a, b) (Cook–Torrance with the height-correlated Smith G2 and
/// Schlick's Fresnel at a·h, per channel of `f0`; [TH17 eq. 4] for the VPL, the material model
/// of the bake's path tracer for a receiver) for unit directions `a`, `b` around normal `n`;
/// zero when either is below the surface. Reciprocal: a·h = b·h.
pub fn ggx_brdf(n: Vec3, a: Vec3, b: Vec3, alpha: f32, f0: Vec3) -> Vec3 {
    let (t, bt) = crate::scene::geometry::frame(n);
    let local = |w: Vec3| sbf::glam::DVec3::new(w.dot(t) as f64, w.dot(bt) as f64, w.dot(n) as f64);
    let (la, lb) = (local(a), local(b));
    if la.z <= 0.0 || lb.z <= 0.0 {
        return Vec3::ZERO;
    }
    let alpha = alpha as f64;
    let h = (la + lb).normalize();
    let dg = sbf::ggx::d(h, alpha) * sbf::ggx::g2(la, lb, alpha) / (4.0 * la.z * lb.z);
    let w = sbf::ggx::schlick_weight(la.dot(h)) as f32;
    (f0 + (Vec3::ONE - f0) * w) * dg as f32
}

/// The one number per (light, point) that stochastic culling works with for an RGB
/// intensity: its largest channel. Any scalar keeps the estimate unbiased ([TH17 eq. 3] divides
/// every channel by the same p); the largest channel gives a coloured light the acceptance
/// its brightest channel needs, and the bounds below bound it channel by channel.
pub fn culling_intensity(i: Vec3) -> f32 {
    i.max_element()
}

impl Vpl {
    /// Whether it reflects diffusely (k > 0 in some channel) rather than by GGX.
    pub fn is_diffuse(&self) -> bool {
        self.diffuse.max_element() > 0.0
    }

    /// Radiant intensity towards unit direction `wo` per channel ([TH17 eq. 4]): Φk·cos/π for
    /// a diffuse VPL, Φ·f_GGX(ω_i, ω_o)·cos for a glossy one ([`ggx_brdf`]).
    pub fn intensity(&self, wo: Vec3) -> Vec3 {
        let c = wo.dot(self.normal);
        if c <= 0.0 {
            return Vec3::ZERO;
        }
        if self.is_diffuse() {
            return self.flux * self.diffuse * c * std::f32::consts::FRAC_1_PI;
        }
        self.flux * ggx_brdf(self.normal, self.incoming, wo, self.alpha, self.f0) * c
    }

    /// The culling transform (M = B·S, M·c) of the light's bound for random-range
    /// parameter δ: the diffuse sphere or the GGX spheroid (view space = bound space);
    /// with `Bound::Sphere` a glossy VPL gets the sphere enclosing its spheroid instead
    /// (centre c, radius r_u), with `Bound::Th16` the sphere at the VPL of radius r/α
    /// (the maximum of s(ω_o) = r√(πD), [TH17 eq. 12], πD ≤ 1/α²) — the two comparisons of
    /// [TH17 §7 and Fig. 9]. Each bounds [`culling_intensity`]: the diffuse sphere of
    /// max_c Φ_c·k_c, the spheroid of max_c Φ_c·F_max(f0_c) (each channel's intensity is at
    /// most its Φ_c·F_max,c times the channel-free rest of [TH17 eq. 12]).
    pub fn bound(&self, delta: f32, kind: Bound) -> (Mat3, Vec3) {
        let e = if self.is_diffuse() {
            let s = slc::diffuse_sphere(self.position, self.normal, culling_intensity(self.flux * self.diffuse), delta, self.xi);
            slc::Ellipsoid { center: s.center, axes: Mat3::IDENTITY, radii: Vec3::splat(s.radius) }
        } else {
            let cos_i = self.incoming.dot(self.normal);
            let f = Vec3::new(slc::schlick_max(self.f0.x, cos_i), slc::schlick_max(self.f0.y, cos_i), slc::schlick_max(self.f0.z, cos_i));
            let r = slc::spheroid_scale(culling_intensity(self.flux * f), 1.0, slc::g1_dist(cos_i, self.alpha), cos_i, delta, self.xi);
            let e = slc::ggx_spheroid(self.position, self.incoming, self.normal, self.alpha, r);
            match kind {
                Bound::Tight => e,
                Bound::Sphere => slc::Ellipsoid { center: e.center, axes: Mat3::IDENTITY, radii: Vec3::splat(e.radii.x) },
                Bound::Th16 => slc::Ellipsoid { center: self.position, axes: Mat3::IDENTITY, radii: Vec3::splat(r / self.alpha) },
            }
        };
        slc::cull_transform(&e, Mat3::IDENTITY, Vec3::ZERO)
    }
}

/// A receiver of the G-buffer (view space): Lambert albedo plus, where `f0` is not zero, a
/// GGX layer (the bake's material model: f = ρ/π + f_GGX).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    pub position: Vec3,
    /// Unit normal facing the camera.
    pub normal: Vec3,
    /// Diffuse albedo ρ per channel.
    pub albedo: Vec3,
    /// Schlick F0 per channel of the GGX layer (zero: Lambert only).
    pub f0: Vec3,
    /// GGX α of that layer (> 0).
    pub alpha: f32,
}

impl Surface {
    /// A grey Lambert receiver.
    pub fn lambert(position: Vec3, normal: Vec3, albedo: f32) -> Surface {
        Surface { position, normal, albedo: Vec3::splat(albedo), f0: Vec3::ZERO, alpha: 1.0 }
    }

    /// Whether it has a GGX layer.
    pub fn is_glossy(&self) -> bool {
        self.f0.max_element() > 0.0
    }

    /// The GGX layer's BRDF towards the camera (at the view-space origin) for light arriving
    /// from unit direction `wl` (zero without the layer).
    pub fn specular(&self, wl: Vec3) -> Vec3 {
        if !self.is_glossy() {
            return Vec3::ZERO;
        }
        ggx_brdf(self.normal, wl, -self.position.normalize(), self.alpha, self.f0)
    }

    /// Radiance towards the camera from the irradiance `e` and the specular radiance `s` the
    /// layers gathered: ρ/π·E + S.
    pub fn radiance(&self, e: Vec3, s: Vec3) -> Vec3 {
        self.albedo * std::f32::consts::FRAC_1_PI * e + s
    }
}

/// A view-space G-buffer: per pixel the receiver (None: background).
#[derive(Debug, Clone)]
pub struct GBuffer {
    pub width: usize,
    pub height: usize,
    /// tan of the half field of view in x and y (symmetric perspective).
    pub tan_xy: (f32, f32),
    pub texels: Vec<Option<Surface>>,
}

impl GBuffer {
    /// Whether any receiver has a GGX layer (the specular layer is shaded and filtered only
    /// then).
    pub fn has_glossy(&self) -> bool {
        self.texels.iter().flatten().any(Surface::is_glossy)
    }
}

/// Which bound culls a glossy VPL.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bound {
    /// The GGX spheroid ([TH17 eq. 13–15]).
    #[default]
    Tight,
    /// The sphere enclosing the spheroid (centre c, radius r_u).
    Sphere,
    /// The sphere of TH16 as [TH17 §7] sets it up: centre at the VPL, radius r/α.
    Th16,
}

impl Bound {
    /// Parses `tight`, `sphere` or `th16`.
    pub fn parse(s: &str) -> Result<Bound, String> {
        match s {
            "tight" => Ok(Bound::Tight),
            "sphere" => Ok(Bound::Sphere),
            "th16" => Ok(Bound::Th16),
            b => Err(format!("the glossy bound is tight, sphere or th16, not {b}")),
        }
    }
}

/// How lights are selected per pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Tiled culling by the random ranges' bounds, stochastic falloff (unbiased).
    Culled,
    /// Every light, no falloff (the reference).
    BruteForce,
    /// Every light within its range for ξ = ½, unweighted (the classic biased cut: tiled
    /// shading with clamped ranges, tiles culled by those ranges).
    RangeCut,
}

/// What the shading gathers per pixel before the filter: the irradiance E = Σ I·cos/d² and
/// the GGX layer's radiance S = Σ I·cos/d²·f_GGX, RGB. The filter joins each and the pixel's
/// radiance is ρ/π·E + S ([`Surface::radiance`]): the albedo never enters the filter's sums.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Layers {
    pub irradiance: Vec<Vec3>,
    pub specular: Vec<Vec3>,
}

/// A rendered image and the culling statistics.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Render {
    /// Radiance towards the camera per pixel, RGB.
    pub image: Vec<Vec3>,
    /// The image after the filter joining the interleaving subregions ([`filter()`]).
    pub filtered: Vec<Vec3>,
    /// What the image is made of (the filter's input).
    pub layers: Layers,
    /// Lights shaded per pixel (kept by its tile).
    pub lights_per_pixel: Vec<u32>,
    /// Of those, the false discoveries: lights kept whose random range does not reach the
    /// pixel (p ≤ ξ: they contribute 0). Per-pixel false discovery rate = this / shaded.
    pub false_per_pixel: Vec<u32>,
    /// Kept (tile, light) pairs, and those no pixel of the tile accepted (p ≤ ξ everywhere).
    pub kept: u64,
    pub false_positives: u64,
}

impl Render {
    /// The false discovery rate over all pixels: Σ false discoveries / Σ lights shaded
    /// ([TH17 Fig. 9]'s quantity, aggregated).
    pub fn pixel_fdr(&self) -> f64 {
        let shaded: u64 = self.lights_per_pixel.iter().map(|x| *x as u64).sum();
        self.false_per_pixel.iter().map(|x| *x as u64).sum::<u64>() as f64 / shaded.max(1) as f64
    }

    /// False discoveries summed over pixels.
    pub fn false_discoveries(&self) -> u64 {
        self.false_per_pixel.iter().map(|x| *x as u64).sum()
    }
}

/// What light `v` gives receiver `s`: (I·cos_r/d² for the irradiance, that times the GGX
/// layer's BRDF for the specular radiance, the distance d, the culling intensity towards s).
fn receive(v: &Vpl, s: &Surface) -> (Vec3, Vec3, f32, f32) {
    let to = s.position - v.position;
    let d2 = to.length_squared();
    let d = d2.sqrt();
    let wo = to / d;
    let i = v.intensity(wo);
    let e = i * (-wo).dot(s.normal).max(0.0) / d2;
    (e, e * s.specular(-wo), d, culling_intensity(i))
}

/// Renders `g` lit by `vpls` in `mode` (CPU reference of the GPU kernel). `interleave` I
/// (1: off) splits the screen into I × I subregions ([TH17 §6]): pixel (x, y) belongs to
/// subregion s = (x mod I) + I·(y mod I) and shades only the VPLs j ≡ s (mod I²), weighted
/// by I²; tiles are 16 × 16 pixels of one subregion.
pub fn render(g: &GBuffer, vpls: &[Vpl], delta: f32, mode: Mode, interleave: usize) -> Render {
    render_with(g, vpls, delta, mode, interleave, Bound::Tight)
}

/// [`render`] with a choice of bound for glossy VPLs.
pub fn render_with(g: &GBuffer, vpls: &[Vpl], delta: f32, mode: Mode, interleave: usize, bound: Bound) -> Render {
    render_filtered(g, vpls, delta, mode, interleave, bound, Filter::SEED)
}

/// [`render_with`] joining the subregions with `filter` (its `filtered` image).
pub fn render_filtered(g: &GBuffer, vpls: &[Vpl], delta: f32, mode: Mode, interleave: usize, bound: Bound, filter: Filter) -> Render {
    render_culled(g, vpls, delta, mode, interleave, bound, filter, Culling::HalfZ)
}

/// How a tile's lights are culled against its depths.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Culling {
    /// Tiled culling with the tile's depth range split in two (Modified HalfZ, Harada et
    /// al. 2012; [TH17 §5]): a light meeting either half is shaded by every pixel of the
    /// tile.
    #[default]
    HalfZ,
    /// Clustered shading (Olsson et al. 2012; [TH17 Table 2]'s baseline with "32 depth
    /// clusters for each 16×16 pixel tile"): the tile's depth range cut into `n` equal
    /// slices (2 < n ≤ 32), each light tested against every slice, and a pixel shades only
    /// the lights whose bound meets its own slice — fewer false discoveries for n bound tests
    /// per (tile, light) instead of two. Here in compute, not by conservative rasterisation.
    Clustered(u32),
}

impl Culling {
    /// The GPU's encoding (`SlcParams.clusters`): 0 HalfZ, else the slice count.
    pub fn gpu_clusters(self) -> u32 {
        match self {
            Culling::HalfZ => 0,
            Culling::Clustered(n) => n,
        }
    }

    /// Checks the slice count (3 to 32: a 32-bit mask per light).
    pub fn check(self) -> Result<(), String> {
        match self {
            Culling::Clustered(n) if !(3..=32).contains(&n) => {
                Err(format!("clustered culling takes 3 to 32 depth slices per tile, not {n}"))
            }
            _ => Ok(()),
        }
    }
}

/// Depth slice `s` of `n` over the tile's [zmin, zmax], widened on both sides by 1e-4 of the
/// range plus 1e-6 of zmax so a pixel whose slice index rounds across a boundary still lies
/// inside the slice it is shaded with (GPU twin: slc_cluster_range in cull.wgsl).
pub fn cluster_range(zmin: f32, zmax: f32, s: u32, n: u32) -> (f32, f32) {
    let w = zmax - zmin;
    let pad = 1e-4 * w + 1e-6 * zmax;
    (zmin + w * s as f32 / n as f32 - pad, zmin + w * (s + 1) as f32 / n as f32 + pad)
}

/// The slice of depth z among `n` over [zmin, zmax] (GPU twin: slc_cluster_of).
pub fn cluster_of(z: f32, zmin: f32, zmax: f32, n: u32) -> u32 {
    let w = (zmax - zmin).max(f32::MIN_POSITIVE);
    (((z - zmin) / w * n as f32).max(0.0) as u32).min(n - 1)
}

/// [`render_filtered`] with a choice of [`Culling`].
#[allow(clippy::too_many_arguments)]
pub fn render_culled(
    g: &GBuffer,
    vpls: &[Vpl],
    delta: f32,
    mode: Mode,
    interleave: usize,
    bound: Bound,
    filter: Filter,
    culling: Culling,
) -> Render {
    let il = interleave.max(1);
    let n = g.width * g.height;
    let mut out = Render {
        layers: Layers { irradiance: vec![Vec3::ZERO; n], specular: vec![Vec3::ZERO; n] },
        lights_per_pixel: vec![0; n],
        false_per_pixel: vec![0; n],
        ..Default::default()
    };
    // The range cut keeps every light within its range at ξ = ½ (tiles culled by that range).
    let bounds: Vec<(Mat3, Vec3)> =
        vpls.iter().map(|v| if mode == Mode::RangeCut { Vpl { xi: 0.5, ..*v } } else { *v }.bound(delta, bound)).collect();
    let weight = (il * il) as f32;
    for sub in 0..il * il {
        let (sx, sy) = (sub % il, sub / il);
        let subset: Vec<usize> = (sub..vpls.len()).step_by(il * il).collect();
        render_subregion(g, vpls, (&bounds, culling), delta, mode, (il, sx, sy), &subset, weight, &mut out);
    }
    out.image = compose(g, &out.layers);
    out.filtered = self::filter(g, &out.layers, il, filter);
    out
}

/// Each pixel's radiance from its layers ([`Surface::radiance`]; background 0).
pub fn compose(g: &GBuffer, layers: &Layers) -> Vec<Vec3> {
    g.texels.iter().zip(&layers.irradiance).zip(&layers.specular).map(|((t, e), s)| t.map_or(Vec3::ZERO, |t| t.radiance(*e, *s))).collect()
}

#[allow(clippy::too_many_arguments)]
fn render_subregion(
    g: &GBuffer,
    vpls: &[Vpl],
    (bounds, culling): (&[(Mat3, Vec3)], Culling),
    delta: f32,
    mode: Mode,
    (il, sx, sy): (usize, usize, usize),
    subset: &[usize],
    weight: f32,
    out: &mut Render,
) {
    let (sw, sh) = (g.width.div_ceil(il), g.height.div_ceil(il));
    for ty in 0..sh.div_ceil(TILE) {
        for tx in 0..sw.div_ceil(TILE) {
            let pixels: Vec<usize> = (ty * TILE..(ty + 1) * TILE)
                .flat_map(|y| (tx * TILE..(tx + 1) * TILE).map(move |x| (il * x + sx, il * y + sy)))
                .filter(|(x, y)| *x < g.width && *y < g.height)
                .map(|(x, y)| y * g.width + x)
                .filter(|k| g.texels[*k].is_some())
                .collect();
            if pixels.is_empty() {
                continue;
            }
            let (zmin, zmax) = pixels.iter().fold((f32::INFINITY, 0.0f32), |(a, b), k| {
                let z = -g.texels[*k].expect("valid").position.z;
                (a.min(z), b.max(z))
            });
            let mid = 0.5 * (zmin + zmax);
            let (x0, y0) = ((il * tx * TILE + sx) as f32, (il * ty * TILE + sy) as f32);
            let span = (il * (TILE - 1) + 1) as f32;
            let part = |a: f32, b: f32| {
                slc::tile_corners(x0, y0, x0 + span, y0 + span, g.width as f32, g.height as f32, g.tan_xy.0, g.tan_xy.1, a, b)
            };
            let halves = [part(zmin, mid), part(mid, zmax)];
            let slices: Vec<[Vec3; 8]> = match culling {
                Culling::HalfZ => Vec::new(),
                Culling::Clustered(n) => (0..n).map(|s| cluster_range(zmin, zmax, s, n)).map(|(a, b)| part(a, b)).collect(),
            };
            for &j in subset {
                let v = &vpls[j];
                // The slices the light's bound meets (every one for HalfZ and brute force).
                let mask: u32 = match (mode, culling) {
                    (Mode::BruteForce, _) => u32::MAX,
                    (_, Culling::HalfZ) => {
                        if halves.iter().any(|c| slc::ellipsoid_hits_corners(bounds[j].0, bounds[j].1, c)) {
                            u32::MAX
                        } else {
                            0
                        }
                    }
                    (_, Culling::Clustered(_)) => slices
                        .iter()
                        .enumerate()
                        .fold(0, |m, (s, c)| m | ((slc::ellipsoid_hits_corners(bounds[j].0, bounds[j].1, c) as u32) << s)),
                };
                if mask == 0 {
                    continue;
                }
                out.kept += 1;
                let mut accepted = false;
                for &k in &pixels {
                    let surface = g.texels[k].expect("valid");
                    if let (Culling::Clustered(n), false) = (culling, mode == Mode::BruteForce) {
                        if mask & (1 << cluster_of(-surface.position.z, zmin, zmax, n)) == 0 {
                            continue;
                        }
                    }
                    let (e, s, d, i) = receive(v, &surface);
                    // The estimator's factor on this (light, pixel): 1, L/p where p > ξ, or the cut.
                    let f = match mode {
                        Mode::BruteForce => 1.0,
                        Mode::Culled => {
                            let p = slc::acceptance_probability(i, delta, d);
                            accepted |= p > v.xi;
                            out.false_per_pixel[k] += (p <= v.xi) as u32;
                            slc::culled_estimate(1.0, p, v.xi)
                        }
                        Mode::RangeCut => (d <= slc::random_range(i, delta, 0.5)) as u8 as f32,
                    };
                    out.layers.irradiance[k] += e * (f * weight);
                    out.layers.specular[k] += s * (f * weight);
                    out.lights_per_pixel[k] += 1;
                }
                out.false_positives += (mode == Mode::Culled && !accepted) as u64;
            }
        }
    }
}
