//! What a scene gives stochastic light culling: the preview camera, the view-space
//! G-buffer of its receivers, and VPLs from light paths (lights, emissive triangles, the
//! environment) with their per-light random numbers.

use super::{GBuffer, Surface, Vpl};
use rayon::prelude::*;
use sbf::glam::Vec3;

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
/// BVH): view-space position, the face normal turned towards the camera, and the material's
/// diffuse albedo, GGX F0 and α (F0 zero where the material has no GGX layer); emitters
/// and misses are background.
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
            let f0 = if m.is_glossy() { m.specular_f0() } else { Vec3::ZERO };
            Some(Surface { position: p, normal: n, albedo: m.diffuse_albedo(), f0, alpha: m.alpha() })
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

/// The ξ ∈ (0, 1] of light path `path` of the bake seeded `seed` ([TH17 eq. 3]: one
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
    // A source's colour per unit of the luminance it was chosen by.
    let colour = |c: Vec3| c / luminance(c).max(f64::MIN_POSITIVE) as f32;
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
        // (origin, direction, RGB weight relative to the luminance power the choice assumed, range)
        let (o, dir, w, range) = if let (Some(e), true) = (env.as_ref(), u >= light_power + emitter_power) {
            // The environment: a direction by its sampler, a point on the disk facing it.
            let (towards, pdf) = e.sample([a, b, c]);
            let weight = scene.environment.radiance(towards) / (pdf * e.total) as f32;
            let (t, bt) = crate::scene::geometry::frame(towards);
            let [r1, r2] = rng.next_2d();
            let r = radius * (r1 as f32).sqrt();
            let phi = std::f32::consts::TAU * r2 as f32;
            (centre + towards * (2.0 * radius) + (t * phi.cos() + bt * phi.sin()) * r, -towards, weight, f32::INFINITY)
        } else if u < lights_end {
            let s = &sources[pick(u / lights_end, &sources, 1.0)];
            match scene.lights[s.0] {
                Light::Directional { direction, irradiance } => {
                    let (t, bt) = crate::scene::geometry::frame(direction);
                    let r = radius * (a as f32).sqrt();
                    let phi = std::f32::consts::TAU * b as f32;
                    (
                        centre + direction * (2.0 * radius) + (t * phi.cos() + bt * phi.sin()) * r,
                        -direction,
                        colour(irradiance),
                        f32::INFINITY,
                    )
                }
                Light::Point { position, range, intensity } => {
                    (position, sbf::sampling::uniform_sphere([a, b]).as_vec3(), colour(intensity), range)
                }
                Light::Spot { position, direction, cos_inner, cos_outer, range, intensity } => {
                    let dir = sbf::sampling::uniform_sphere([a, b]).as_vec3();
                    (
                        position,
                        dir,
                        colour(intensity) * crate::scene::lights::spot_attenuation(dir.dot(direction), cos_inner, cos_outer),
                        range,
                    )
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
            let le = scene.materials[t.material as usize].emissive;
            (crate::scene::lights::offset_ray(p, n), dir, colour(le), f32::INFINITY)
        };
        let xi = vpl_xi(seed, path as u64);
        out.extend(vpls_at_hit(scene, bvh, cam, (o, dir, range), per_path * w, xi));
    }
    out
}

/// The VPLs where the ray (origin, unit direction, light range) carrying `flux` first meets
/// a surface (view space for `cam`): a diffuse VPL (flux × the material's diffuse albedo)
/// where the albedo is not black and a GGX VPL (α, F0) where the material is glossy, both
/// with random number ξ; none where the ray leaves the scene or the light's range window
/// leaves no flux there. The emitted side is the one facing the ray.
pub(super) fn vpls_at_hit(
    scene: &crate::scene::Scene,
    bvh: &crate::scene::bvh::Bvh,
    cam: Camera,
    (o, dir, range): (Vec3, Vec3, f32),
    flux: Vec3,
    xi: f32,
) -> Vec<Vpl> {
    let Some(h) = bvh.intersect(o, dir, 0.0, f32::INFINITY) else { return Vec::new() };
    let tri = &bvh.tris[h.tri as usize];
    let m = &scene.materials[tri.material as usize];
    let ng = tri.normal();
    let n = if ng.dot(dir) > 0.0 { -ng } else { ng };
    let flux = flux * crate::scene::lights::range_window(h.t, range);
    if flux.max_element() <= 0.0 {
        return Vec::new();
    }
    let base = Vpl {
        position: o + dir * h.t - cam.eye,
        normal: n,
        incoming: -dir,
        flux,
        diffuse: Vec3::ZERO,
        alpha: m.alpha(),
        f0: m.specular_f0(),
        xi,
    };
    let k = m.diffuse_albedo();
    let mut out = Vec::with_capacity(2);
    if k.max_element() > 0.0 {
        out.push(Vpl { diffuse: k, ..base });
    }
    if m.is_glossy() {
        out.push(base);
    }
    out
}

/// `vpls` and, for `bounces` more diffuse bounces, the VPLs the light reaches next (the
/// multi-bounce part of Tokuyoshi & Harada's VPL generation: light paths continued past the first hit):
/// from each diffuse VPL (arriving flux Φ, reflectance k) a cosine-distributed direction
/// about its normal (the Lambert lobe's pdf, so the ray carries Φ·k) to the next hit, whose
/// VPLs (`vpls_at_hit`) carry Φ·k, and from its diffuse VPL on. Only the Lambert layer
/// reflects on: a glossy material's GGX layer is not continued (its light is dropped
/// beyond the first hit). Directions and ξ from (seed, VPL, bounce) hashes ([`vpl_xi`],
/// [`pixel_light_uniforms`]): the same for any order or thread count.
pub fn add_bounces(
    scene: &crate::scene::Scene,
    bvh: &crate::scene::bvh::Bvh,
    cam: Camera,
    vpls: Vec<Vpl>,
    bounces: usize,
    seed: u64,
) -> Vec<Vpl> {
    let mut out = vpls;
    let mut front: Vec<Vpl> = out.iter().filter(|v| v.is_diffuse()).copied().collect();
    for b in 1..=bounces as u64 {
        let bounce_seed = seed ^ (b << 48);
        let next: Vec<Vec<Vpl>> = front
            .par_iter()
            .enumerate()
            .map(|(j, v)| {
                let [u1, u2] = pixel_light_uniforms(bounce_seed, j as u64, 0xb0);
                let l = sbf::sampling::cosine_hemisphere([u1 as f64, u2 as f64]);
                let (t, bt) = crate::scene::geometry::frame(v.normal);
                let dir = (t * l.x as f32 + bt * l.y as f32 + v.normal * l.z as f32).normalize();
                let o = crate::scene::lights::offset_ray(v.position + cam.eye, v.normal);
                vpls_at_hit(scene, bvh, cam, (o, dir, f32::INFINITY), v.flux * v.diffuse, vpl_xi(bounce_seed, j as u64))
            })
            .collect();
        front = next.iter().flatten().filter(|v| v.is_diffuse()).copied().collect();
        out.extend(next.into_iter().flatten());
    }
    out
}
