//! Stochastic light culling of virtual point lights (VPLs) on a G-buffer (seed 002 §5–6,
//! the CPU reference of `slc/cull.wgsl`): per light a random range from its one ξ,
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

//!
//! The module tree: this file (VPLs, G-buffer, bounds, tiled culling and shading on the
//! CPU), [`mod@filter`] (joining the interleaving subregions), [`gpu`] (the wgpu twin),
//! [`media`] (single scattering, seed 001), [`sweep`] (the equal-time experiment), [`harness`]
//! (what the `slc` command renders and writes).
//!
//! Uses: [`crate::scene`] and the image writers of [`crate::output`].
pub mod filter;
pub mod gpu;
pub mod harness;
pub mod media;
pub mod sweep;

pub use filter::{filter, Filter};

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
        let (t, b) = crate::scene::geometry::frame(self.normal);
        let local = |w: Vec3| sbf::glam::DVec3::new(w.dot(t) as f64, w.dot(b) as f64, w.dot(self.normal) as f64);
        let f0 = self.f0 as f64;
        sbf::slc::ggx_vpl_intensity(self.flux as f64, local(self.incoming), local(wo), self.alpha as f64, &|ch| {
            f0 + (1.0 - f0) * (1.0 - ch).powi(5)
        }) as f32
    }

    /// The culling transform (M = B·S, M·c) of the light's bound for random-range
    /// parameter δ: the diffuse sphere or the GGX spheroid (view space = bound space);
    /// with `Bound::Sphere` a glossy VPL gets the sphere enclosing its spheroid instead
    /// (centre c, radius r_u), with `Bound::Th16` the sphere at the VPL of radius r/α
    /// (the maximum of s(ω_o) = r√(πD), 002 eq. 12, πD ≤ 1/α²) — the two comparisons of
    /// 002 §7 and Fig. 9.
    pub fn bound(&self, delta: f32, kind: Bound) -> (Mat3, Vec3) {
        let e = if self.diffuse > 0.0 {
            let s = slc::diffuse_sphere(self.position, self.normal, self.flux * self.diffuse, delta, self.xi);
            slc::Ellipsoid { center: s.center, axes: Mat3::IDENTITY, radii: Vec3::splat(s.radius) }
        } else {
            let cos_i = self.incoming.dot(self.normal);
            let r =
                slc::spheroid_scale(self.flux, slc::schlick_max(self.f0, cos_i), slc::g1_dist(cos_i, self.alpha), cos_i, delta, self.xi);
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

/// A view-space G-buffer: per pixel position, normal and Lambert albedo (None: background).
#[derive(Debug, Clone)]
pub struct GBuffer {
    pub width: usize,
    pub height: usize,
    /// tan of the half field of view in x and y (symmetric perspective).
    pub tan_xy: (f32, f32),
    pub texels: Vec<Option<(Vec3, Vec3, f32)>>,
}

/// Which bound culls a glossy VPL.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bound {
    /// The GGX spheroid (002 eq. 13–15).
    #[default]
    Tight,
    /// The sphere enclosing the spheroid (centre c, radius r_u).
    Sphere,
    /// The sphere of TH16 as 002 §7 sets it up: centre at the VPL, radius r/α.
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

/// A rendered image and the culling statistics.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Render {
    /// Radiance towards the camera per pixel.
    pub image: Vec<f32>,
    /// The image after the filter joining the interleaving subregions ([`filter()`]).
    pub filtered: Vec<f32>,
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
    /// (002 Fig. 9's quantity, aggregated).
    pub fn pixel_fdr(&self) -> f64 {
        let shaded: u64 = self.lights_per_pixel.iter().map(|x| *x as u64).sum();
        self.false_per_pixel.iter().map(|x| *x as u64).sum::<u64>() as f64 / shaded.max(1) as f64
    }

    /// False discoveries summed over pixels.
    pub fn false_discoveries(&self) -> u64 {
        self.false_per_pixel.iter().map(|x| *x as u64).sum()
    }
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

/// Renders `g` lit by `vpls` in `mode` (CPU reference of the GPU kernel). `interleave` I
/// (1: off) splits the screen into I × I subregions (002 §6): pixel (x, y) belongs to
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
    let il = interleave.max(1);
    let n = g.width * g.height;
    let mut out = Render { image: vec![0.0; n], lights_per_pixel: vec![0; n], false_per_pixel: vec![0; n], ..Default::default() };
    // The range cut keeps every light within its range at ξ = ½ (tiles culled by that range).
    let bounds: Vec<(Mat3, Vec3)> =
        vpls.iter().map(|v| if mode == Mode::RangeCut { Vpl { xi: 0.5, ..*v } } else { *v }.bound(delta, bound)).collect();
    let weight = (il * il) as f32;
    for sub in 0..il * il {
        let (sx, sy) = (sub % il, sub / il);
        let subset: Vec<usize> = (sub..vpls.len()).step_by(il * il).collect();
        render_subregion(g, vpls, &bounds, delta, mode, (il, sx, sy), &subset, weight, &mut out);
    }
    out.filtered = self::filter(g, &out.image, il, filter);
    out
}

#[allow(clippy::too_many_arguments)]
fn render_subregion(
    g: &GBuffer,
    vpls: &[Vpl],
    bounds: &[(Mat3, Vec3)],
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
                let z = -g.texels[*k].expect("valid").0.z;
                (a.min(z), b.max(z))
            });
            let mid = 0.5 * (zmin + zmax);
            let (x0, y0) = ((il * tx * TILE + sx) as f32, (il * ty * TILE + sy) as f32);
            let span = (il * (TILE - 1) + 1) as f32;
            let part = |a: f32, b: f32| {
                slc::tile_corners(x0, y0, x0 + span, y0 + span, g.width as f32, g.height as f32, g.tan_xy.0, g.tan_xy.1, a, b)
            };
            let halves = [part(zmin, mid), part(mid, zmax)];
            for &j in subset {
                let v = &vpls[j];
                let keep = match mode {
                    Mode::Culled | Mode::RangeCut => halves.iter().any(|c| slc::ellipsoid_hits_corners(bounds[j].0, bounds[j].1, c)),
                    Mode::BruteForce => true,
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
                            out.false_per_pixel[k] += (p <= v.xi) as u32;
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
                    out.image[k] += add * weight;
                    out.lights_per_pixel[k] += 1;
                }
                out.false_positives += (mode == Mode::Culled && !accepted) as u64;
            }
        }
    }
}

/// A pinhole camera at `eye` looking down −z (world axes; the bake preview's camera):
/// view space is world space moved by −eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    /// tan of the horizontal half field of view (80° like the preview).
    pub tan_x: f32,
}

impl Camera {
    /// The preview camera of a scene: at the front of its bounds, centred.
    pub fn preview(bvh: &crate::scene::bvh::Bvh) -> Camera {
        let (lo, hi) = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
        let centre = 0.5 * (lo + hi);
        Camera { eye: centre + Vec3::new(0.0, 0.0, 0.49 * (hi.z - lo.z)), tan_x: (40f32).to_radians().tan() }
    }
}

/// The G-buffer of `scene` seen by `cam` at `width` × `height` (primary rays through the
/// BVH): view-space position, the face normal turned towards the camera, and the
/// luminance of the diffuse albedo; emitters and misses are background.
pub fn gbuffer_from_scene(scene: &crate::scene::Scene, bvh: &crate::scene::bvh::Bvh, cam: Camera, width: usize, height: usize) -> GBuffer {
    let tan_y = cam.tan_x * height as f32 / width as f32;
    let texels = (0..width * height)
        .map(|k| {
            let (x, y) = (k % width, k / width);
            let d = Vec3::new(
                (2.0 * (x as f32 + 0.5) / width as f32 - 1.0) * cam.tan_x,
                (1.0 - 2.0 * (y as f32 + 0.5) / height as f32) * tan_y,
                -1.0,
            );
            let h = bvh.intersect(cam.eye, d.normalize(), 0.0, f32::INFINITY)?;
            let tri = &bvh.tris[h.tri as usize];
            let m = &scene.materials[tri.material as usize];
            if m.emissive.max_element() > 0.0 {
                return None;
            }
            let n = tri.normal();
            let n = if n.dot(d) > 0.0 { -n } else { n };
            let p = d.normalize() * h.t;
            Some((p, n, crate::scene::lights::luminance(m.diffuse_albedo()) as f32))
        })
        .collect();
    GBuffer { width, height, tan_xy: (cam.tan_x, tan_y), texels }
}

/// SplitMix64's output function (Steele, Lea and Flood 2014, "Fast splittable
/// pseudorandom number generators"): a bijective 64-bit mix whose outputs for consecutive
/// or related inputs are statistically independent.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The ξ ∈ (0, 1] of light path `path` of the bake seeded `seed` (seed 002 eq. 3: one
/// uniform number per light): a hash of (seed, path, this use) — the seed mixed first, so
/// that no two (seed, path) pairs share a value by any linear relation (a PCG stream per
/// path seeded by `seed` made ξ depend on about seed + 2·path) — its top 24 bits as the
/// f32 1 − k/2²⁴.
pub fn vpl_xi(seed: u64, path: u64) -> f32 {
    const USE_XI: u64 = 0x5c1_0001;
    let h = splitmix64(splitmix64(splitmix64(seed) ^ path) ^ USE_XI);
    1.0 - (h >> 40) as f32 / (1u64 << 24) as f32
}

/// Two uniforms in [0, 1) (24 bits each) for (seed, pixel, light): the same hash chain as
/// [`vpl_xi`] with another use — independent across seeds, pixels and lights.
pub fn pixel_light_uniforms(seed: u64, pixel: u64, light: u64) -> [f32; 2] {
    const USE_PIXEL_LIGHT: u64 = 0x5c1_0002;
    let h = splitmix64(splitmix64(splitmix64(splitmix64(seed) ^ pixel) ^ light) ^ USE_PIXEL_LIGHT);
    [(h >> 40) as f32 / (1u64 << 24) as f32, ((h >> 16) & 0xff_ffff) as f32 / (1u64 << 24) as f32]
}

/// `count` VPLs of `scene` (view space for `cam`) — the reflective-shadow-map equivalent:
/// light paths start at a light chosen by luminance power (directional lights over a disk
/// covering the scene bounds, point and spot lights over the sphere weighted by their cone,
/// emissive triangles by area with cosine directions) and end at their first surface hit,
/// which becomes a diffuse VPL (flux × Lambert albedo) and, on a glossy material, a GGX VPL
/// (α, F0); each carries the total light power / count. One ξ per VPL from `seed`. The
/// environment is not a source here: [`vpls_from_scene_with`] adds it.
pub fn vpls_from_scene(scene: &crate::scene::Scene, bvh: &crate::scene::bvh::Bvh, cam: Camera, count: usize, seed: u64) -> Vec<Vpl> {
    vpls_from_scene_with(scene, bvh, cam, count, seed, false)
}

/// [`vpls_from_scene`], with the environment (sky or map) as a source too when `sky`: its
/// power over the disk of radius R (the bounding sphere's) facing each direction is
/// πR²·∫ luminance(L) dω; a path picks a direction ω by the environment's importance sampler
/// (luminance × solid angle, pdf p), starts on that disk 2R out along ω and travels along
/// −ω, weighted luminance(L(ω))/(p(ω)·∫ luminance(L) dω) (1 in expectation: the light's
/// power is kept). Paths that miss the scene carry their power out of it.
pub fn vpls_from_scene_with(
    scene: &crate::scene::Scene,
    bvh: &crate::scene::bvh::Bvh,
    cam: Camera,
    count: usize,
    seed: u64,
    sky: bool,
) -> Vec<Vpl> {
    use crate::scene::lights::luminance;
    use crate::scene::Light;
    let (lo, hi) = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let (centre, radius) = (0.5 * (lo + hi), 0.5 * (hi - lo).length());
    // Sources with their power (luminance, W).
    let mut sources: Vec<(usize, f64)> = Vec::new();
    for (k, l) in scene.lights.iter().enumerate() {
        let p = match *l {
            Light::Directional { irradiance, .. } => luminance(irradiance) * std::f64::consts::PI * (radius as f64).powi(2),
            Light::Point { intensity, .. } | Light::Spot { intensity, .. } => luminance(intensity) * 4.0 * std::f64::consts::PI,
        };
        sources.push((k, p));
    }
    let emitters: Vec<(usize, f64)> = bvh
        .tris
        .iter()
        .enumerate()
        .filter_map(|(k, t)| {
            let le = scene.materials[t.material as usize].emissive;
            (le.max_element() > 0.0).then(|| (k, luminance(le) * t.area() as f64 * std::f64::consts::PI))
        })
        .collect();
    let emitter_power: f64 = emitters.iter().map(|e| e.1).sum();
    let env = if sky { crate::sampling::environment::EnvSampler::new(&scene.environment) } else { None };
    let env_power = env.as_ref().map_or(0.0, |e| std::f64::consts::PI * (radius as f64).powi(2) * e.total);
    let light_power: f64 = sources.iter().map(|s| s.1).sum();
    // Lights take u in [0, lights_end), emitters [lights_end, light + emitter power), the
    // environment the rest (the first two as without it, to the bit).
    let lights_end = (light_power + emitter_power) - emitter_power;
    let total: f64 = light_power + emitter_power + env_power;
    let mut out = Vec::with_capacity(count);
    if total <= 0.0 || count == 0 {
        return out;
    }
    let per_path = (total / count as f64) as f32;
    let mut rng = sbf::sampling::Pcg32::new(seed, 0x5c1);
    let pick = |u: f64, items: &[(usize, f64)], sum: f64| -> usize {
        let mut acc = 0.0;
        for (k, (_, p)) in items.iter().enumerate() {
            acc += p / sum;
            if u < acc {
                return k;
            }
        }
        items.len() - 1
    };
    for path in 0..count {
        let u = rng.next_f64() * total;
        let [a, b] = rng.next_2d();
        let [c, d] = rng.next_2d();
        // (origin, direction, weight relative to the power the choice assumed, range)
        let (o, dir, w, range) = if let (Some(e), true) = (env.as_ref(), u >= light_power + emitter_power) {
            // The environment: a direction by its sampler, a point on the disk facing it.
            let (towards, pdf) = e.sample([a, b, c]);
            let weight = luminance(scene.environment.radiance(towards)) / (pdf * e.total);
            let (t, bt) = crate::scene::geometry::frame(towards);
            let [r1, r2] = rng.next_2d();
            let r = radius * (r1 as f32).sqrt();
            let phi = std::f32::consts::TAU * r2 as f32;
            (centre + towards * (2.0 * radius) + (t * phi.cos() + bt * phi.sin()) * r, -towards, weight as f32, f32::INFINITY)
        } else if u < lights_end {
            let s = &sources[pick(u / lights_end, &sources, 1.0)];
            match scene.lights[s.0] {
                Light::Directional { direction, .. } => {
                    let (t, bt) = crate::scene::geometry::frame(direction);
                    let r = radius * (a as f32).sqrt();
                    let phi = std::f32::consts::TAU * b as f32;
                    (centre + direction * (2.0 * radius) + (t * phi.cos() + bt * phi.sin()) * r, -direction, 1.0, f32::INFINITY)
                }
                Light::Point { position, range, .. } => (position, sbf::sampling::uniform_sphere([a, b]).as_vec3(), 1.0, range),
                Light::Spot { position, direction, cos_inner, cos_outer, range, .. } => {
                    let dir = sbf::sampling::uniform_sphere([a, b]).as_vec3();
                    (position, dir, crate::scene::lights::spot_attenuation(dir.dot(direction), cos_inner, cos_outer), range)
                }
            }
        } else {
            let (ti, _) = emitters[pick((u - lights_end) / emitter_power, &emitters, 1.0)];
            let t = &bvh.tris[ti];
            let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
            let p = t.v0() + t.e1() * a as f32 + t.e2() * b as f32;
            let n = t.normal();
            let l = sbf::sampling::cosine_hemisphere([c, d]);
            let (tt, bt) = crate::scene::geometry::frame(n);
            let dir = (tt * l.x as f32 + bt * l.y as f32 + n * l.z as f32).normalize();
            (crate::scene::lights::offset_ray(p, n), dir, 1.0, f32::INFINITY)
        };
        let Some(h) = bvh.intersect(o, dir, 0.0, f32::INFINITY) else { continue };
        let tri = &bvh.tris[h.tri as usize];
        let m = &scene.materials[tri.material as usize];
        let ng = tri.normal();
        let n = if ng.dot(dir) > 0.0 { -ng } else { ng };
        let x = o + dir * h.t - cam.eye;
        let xi = vpl_xi(seed, path as u64);
        let flux = per_path * w * crate::scene::lights::range_window(h.t, range);
        if flux <= 0.0 {
            continue;
        }
        let base =
            Vpl { position: x, normal: n, incoming: -dir, flux, diffuse: 0.0, alpha: m.alpha(), f0: luminance(m.specular_f0()) as f32, xi };
        let k = luminance(m.diffuse_albedo()) as f32;
        if k > 0.0 {
            out.push(Vpl { diffuse: k, ..base });
        }
        if m.is_glossy() {
            out.push(base);
        }
    }
    out
}
