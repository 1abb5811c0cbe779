//! Lobe layouts: where to put the axes of SG / SRBF lobes.
//!
//! - [`vogel_sphere`]: Vogel / spherical-Fibonacci spiral, z from 1 − 1/N to 1/N − 1
//!   with the golden angle π(3 − √5) in φ (math.md; Probulator's "Vogel's sphere").
//! - [`vogel_hemisphere`]: the same spiral over z ∈ (0, 1]: z_i = 1 − (i + ½)/N.
//! - [`icosahedron`], [`icosahedron_hemisphere`]: the 12 icosahedron vertices and the
//!   9-vertex hemisphere set of [Roughton19 §8.3.1].
//! - [`sharpness_from_spacing`]: the lobe-spacing heuristic of math.md.

use crate::basis::Icosahedron;
use crate::error::SbfError;
use glam::DVec3;

/// The golden angle π(3 − √5) (radians).
pub const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653_3;

fn spiral(n: usize, z_of: impl Fn(f64) -> f64) -> Vec<DVec3> {
    (0..n)
        .map(|i| {
            let z = z_of(i as f64);
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = i as f64 * GOLDEN_ANGLE;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// N directions on a Vogel spiral over the whole sphere: z_i = 1 − (2i + 1)/N.
pub fn vogel_sphere(n: usize) -> Result<Vec<DVec3>, SbfError> {
    check_count(n)?;
    let nf = n as f64;
    Ok(spiral(n, |i| 1.0 - (2.0 * i + 1.0) / nf))
}

/// N directions on a Vogel spiral over the upper hemisphere: z_i = 1 − (i + ½)/N.
pub fn vogel_hemisphere(n: usize) -> Result<Vec<DVec3>, SbfError> {
    check_count(n)?;
    let nf = n as f64;
    Ok(spiral(n, |i| 1.0 - (i + 0.5) / nf))
}

/// The 12 vertices of the standard icosahedron (see [`Icosahedron::standard`]).
pub fn icosahedron() -> Vec<DVec3> {
    Icosahedron::standard().vertices().to_vec()
}

/// The 9 upper vertices of the face-up icosahedron ([Roughton19 §8.3.1]).
pub fn icosahedron_hemisphere() -> Vec<DVec3> {
    Icosahedron::face_up().vertices()[..9].to_vec()
}

fn check_count(n: usize) -> Result<(), SbfError> {
    if n == 0 || n > 1 << 24 {
        return Err(SbfError::InvalidParameter { name: "lobe count", value: n as f64, reason: "must be in 1..=2^24" });
    }
    Ok(())
}

/// Sharpness heuristic from lobe spacing (math.md, after Probulator):
/// λ = ln(0.65)·N / (minDot − 1.0001), minDot = cos of half the smallest angle
/// between two axes. Errors for fewer than two axes.
pub fn sharpness_from_spacing(axes: &[DVec3]) -> Result<f64, SbfError> {
    if axes.len() < 2 {
        return Err(SbfError::InvalidParameter { name: "lobe count", value: axes.len() as f64, reason: "need >= 2 axes" });
    }
    let mut max_cos = -1.0f64;
    for i in 0..axes.len() {
        for j in (i + 1)..axes.len() {
            max_cos = max_cos.max(axes[i].dot(axes[j]).clamp(-1.0, 1.0));
        }
    }
    let half = 0.5 * max_cos.acos();
    let min_dot = half.cos();
    Ok(0.65f64.ln() * axes.len() as f64 / (min_dot - 1.0001))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;
    #[test]
    fn golden_angle_matches_formula() {
        assert!((GOLDEN_ANGLE - PI * (3.0 - 5f64.sqrt())).abs() < 1e-15);
    }
}
