//! Probe placement: the default grid, and probes inside geometry — found by the fraction
//! of rays from the probe whose first hit is the back face of a single-sided surface
//! (the same test as texel validity) — moved out through the nearest such face.

use crate::scene::bvh::Bvh;
use crate::scene::lights::offset_ray;
use crate::scene::Scene;
use sbf::glam::Vec3;

/// Rays per inside test (spherical Fibonacci directions: deterministic, even).
pub const INSIDE_TEST_RAYS: u64 = 256;

/// Probe positions: an nx × ny × nz grid inside the scene bounds (cell centres).
pub fn probe_grid(bvh: &Bvh, n: [usize; 3]) -> Vec<Vec3> {
    let (lo, hi) = bvh.nodes.first().map(|x| (Vec3::from(x.min), Vec3::from(x.max))).unwrap_or((Vec3::ZERO, Vec3::ONE));
    let mut v = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let f = Vec3::new((i as f32 + 0.5) / n[0] as f32, (j as f32 + 0.5) / n[1] as f32, (k as f32 + 0.5) / n[2] as f32);
                v.push(lo + (hi - lo) * f);
            }
        }
    }
    v
}

/// The fraction of rays from `p` whose first hit is a single-sided back face, and the
/// nearest such hit (distance, direction, face normal).
pub fn back_face_hits(bvh: &Bvh, scene: &Scene, p: Vec3) -> (f64, Option<(f32, Vec3, Vec3)>) {
    let mut back = 0;
    let mut nearest: Option<(f32, Vec3, Vec3)> = None;
    for k in 0..INSIDE_TEST_RAYS {
        let d = sbf::sampling::spherical_fibonacci(k, INSIDE_TEST_RAYS).as_vec3();
        let Some(hit) = bvh.intersect(p, d, 0.0, f32::INFINITY) else { continue };
        let tri = &bvh.tris[hit.tri as usize];
        let ng = tri.normal();
        if d.dot(ng) > 0.0 && !scene.materials[tri.material as usize].double_sided {
            back += 1;
            if nearest.is_none_or(|n| hit.t < n.0) {
                nearest = Some((hit.t, d, ng));
            }
        }
    }
    (back as f64 / INSIDE_TEST_RAYS as f64, nearest)
}

/// Moves a probe that is inside geometry (back-face fraction above `max_fraction`) out
/// through the nearest back face it sees, a `margin` beyond it, up to four times (nested
/// or overlapping solids). Returns the new position, or None when the probe was outside
/// already or could not be freed.
pub fn relocate(bvh: &Bvh, scene: &Scene, p: Vec3, max_fraction: f64, margin: f32) -> Option<Vec3> {
    let mut q = p;
    for _ in 0..4 {
        let (fraction, nearest) = back_face_hits(bvh, scene, q);
        if fraction <= max_fraction {
            return (q != p).then_some(q);
        }
        let (t, d, ng) = nearest?;
        q = offset_ray(q + d * t, ng) + ng * margin;
    }
    (back_face_hits(bvh, scene, q).0 <= max_fraction).then_some(q)
}
