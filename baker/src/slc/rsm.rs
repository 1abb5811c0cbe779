//! VPLs from reflective shadow maps (Dachsbacher and Stamminger 2005, "Reflective Shadow
//! Maps"; [TH17 §7]: "A VPL is generated from each texel of a reflective shadow map of
//! 256² resolution"): per punctual light a regular grid of rays from the light — what a
//! rasterised RSM stores per texel: the first surface seen, its normal and material, and
//! the flux through the texel — each hit becoming a VPL ([`super::from_scene`]'s
//! `vpls_at_hit`, so a glossy material gives a GGX VPL too).
//!
//! - Directional light: orthographic; the scene's bounds projected on the plane facing the
//!   light (axes t, b of its frame), N × N texels of area A; flux E·A per texel (E the
//!   irradiance at normal incidence).
//! - Spot light with an outer cone below 84°: perspective; a square image plane at distance 1
//!   of half size tan θ_outer around the axis (the cone inscribed); flux I·att(cos θ)·Ω per
//!   texel, att the KHR_lights_punctual cone at the texel's centre.
//! - Point light (and wider spots): the six cube faces, N × N texels each, flux I·Ω (·att).
//!
//! Ω is each texel's exact solid angle: for the rectangle [x0, x1] × [y0, y1] on the plane at
//! distance 1, F(x1, y1) − F(x0, y1) − F(x1, y0) + F(x0, y0) with F(x, y) = atan2(xy,
//! √(1 + x² + y²)) (the solid angle of the rectangle [0, x] × [0, y]), so the texels of a
//! cube face sum to 4π/6 exactly. Emissive triangles and the environment have no shadow
//! map: [`vpls_from_rsm`] refuses a scene without punctual lights.

use super::from_scene::vpls_at_hit;
use super::{vpl_xi, Camera, Vpl};
use crate::scene::Light;
use rayon::prelude::*;
use sbf::glam::Vec3;

/// The solid angle of the rectangle [0, x] × [0, y] (signed) on the plane at distance 1.
fn corner(x: f64, y: f64) -> f64 {
    (x * y).atan2((1.0 + x * x + y * y).sqrt())
}

/// Solid angle of texel (i, j) of an n × n grid over [−h, h]² on the plane at distance 1.
pub fn texel_solid_angle(i: usize, j: usize, n: usize, h: f64) -> f64 {
    let at = |k: usize| -h + 2.0 * h * k as f64 / n as f64;
    let (x0, x1, y0, y1) = (at(i), at(i + 1), at(j), at(j + 1));
    corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0)
}

/// One texel's ray: (origin, unit direction, light range, flux).
type TexelRay = (Vec3, Vec3, f32, Vec3);

/// The rays of a perspective grid around unit `axis` (n × n texels over [−h, h]² at distance
/// 1) from `position`, flux `intensity`·att(direction)·Ω.
fn perspective(position: Vec3, axis: Vec3, h: f64, n: usize, range: f32, intensity: Vec3, att: &dyn Fn(Vec3) -> f32) -> Vec<TexelRay> {
    let (t, b) = crate::scene::geometry::frame(axis);
    (0..n * n)
        .filter_map(|k| {
            let (i, j) = (k % n, k / n);
            let (x, y) = ((-h + 2.0 * h * (i as f64 + 0.5) / n as f64) as f32, (-h + 2.0 * h * (j as f64 + 0.5) / n as f64) as f32);
            let dir = (axis + t * x + b * y).normalize();
            let flux = intensity * (att(dir) * texel_solid_angle(i, j, n, h) as f32);
            (flux.max_element() > 0.0).then_some((position, dir, range, flux))
        })
        .collect()
}

/// The six cube faces' rays from `position` (n × n texels each).
fn cube(position: Vec3, n: usize, range: f32, intensity: Vec3, att: &dyn Fn(Vec3) -> f32) -> Vec<TexelRay> {
    [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z]
        .iter()
        .flat_map(|a| perspective(position, *a, 1.0, n, range, intensity, att))
        .collect()
}

/// The texel rays of every punctual light of `scene` at `n` × `n` texels per map.
fn texel_rays(scene: &crate::scene::Scene, bvh: &crate::scene::bvh::Bvh, n: usize) -> Vec<TexelRay> {
    let (lo, hi) = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let (centre, radius) = (0.5 * (lo + hi), 0.5 * (hi - lo).length());
    let mut rays = Vec::new();
    for l in &scene.lights {
        match *l {
            Light::Directional { direction, irradiance } => {
                // The bounds' corners on the plane facing the light: the orthographic frustum.
                let (t, b) = crate::scene::geometry::frame(direction);
                let corners = (0..8).map(|c| Vec3::new([lo.x, hi.x][c & 1], [lo.y, hi.y][(c >> 1) & 1], [lo.z, hi.z][c >> 2]) - centre);
                let (mut u0, mut u1, mut v0, mut v1) = (f32::INFINITY, f32::NEG_INFINITY, f32::INFINITY, f32::NEG_INFINITY);
                for c in corners {
                    (u0, u1, v0, v1) = (u0.min(c.dot(t)), u1.max(c.dot(t)), v0.min(c.dot(b)), v1.max(c.dot(b)));
                }
                let (du, dv) = ((u1 - u0) / n as f32, (v1 - v0) / n as f32);
                let flux = irradiance * (du * dv);
                rays.extend((0..n * n).map(|k| {
                    let (u, v) = (u0 + du * ((k % n) as f32 + 0.5), v0 + dv * ((k / n) as f32 + 0.5));
                    (centre + direction * (2.0 * radius) + t * u + b * v, -direction, f32::INFINITY, flux)
                }));
            }
            Light::Point { position, intensity, range } => rays.extend(cube(position, n, range, intensity, &|_| 1.0)),
            Light::Spot { position, direction, intensity, cos_inner, cos_outer, range } => {
                let att = |d: Vec3| crate::scene::lights::spot_attenuation(d.dot(direction), cos_inner, cos_outer);
                if cos_outer > 0.1 {
                    let h = ((1.0 - cos_outer * cos_outer).sqrt() / cos_outer) as f64;
                    rays.extend(perspective(position, direction, h, n, range, intensity, &att));
                } else {
                    rays.extend(cube(position, n, range, intensity, &att));
                }
            }
        }
    }
    rays
}

/// VPLs of `scene` (view space for `cam`) from a reflective shadow map of `n` × `n` texels per
/// punctual light (per cube face for point lights): one ray per texel, its hit a VPL carrying
/// the texel's flux, with ξ = [`vpl_xi`]`(seed, texel)` numbered over all maps. Errors for a
/// scene without punctual lights (an RSM is rendered from a light's position or direction).
pub fn vpls_from_rsm(
    scene: &crate::scene::Scene,
    bvh: &crate::scene::bvh::Bvh,
    cam: Camera,
    n: usize,
    seed: u64,
) -> Result<Vec<Vpl>, String> {
    if n == 0 {
        return Err("a reflective shadow map needs at least 1 × 1 texels".into());
    }
    if scene.lights.is_empty() {
        return Err(format!(
            "scene '{}' has no punctual (directional, spot or point) light to render a reflective shadow map from; its emissive triangles and environment give VPLs through light paths (leave out --rsm)",
            scene.name
        ));
    }
    let rays = texel_rays(scene, bvh, n);
    let per: Vec<Vec<Vpl>> = rays
        .par_iter()
        .enumerate()
        .map(|(k, &(o, d, range, flux))| vpls_at_hit(scene, bvh, cam, (o, d, range), flux, vpl_xi(seed, k as u64)))
        .collect();
    Ok(per.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    /// The texel solid angles of a cube face sum to 4π/6 (the six faces tile the sphere), and
    /// the centre texel of a fine grid is its area (≈ flat).
    #[test]
    fn texel_solid_angles_tile_the_sphere() {
        for n in [1usize, 7, 64] {
            let sum: f64 = (0..n * n).map(|k| super::texel_solid_angle(k % n, k / n, n, 1.0)).sum();
            assert!((sum - 4.0 * std::f64::consts::PI / 6.0).abs() < 1e-12, "n {n}: {sum}");
        }
        let c = super::texel_solid_angle(500, 500, 1001, 1.0);
        assert!((c / (2.0f64 / 1001.0).powi(2) - 1.0).abs() < 1e-5, "{c}");
    }
}
