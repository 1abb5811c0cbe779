//! Anisotropic spherical Gaussians (Xu et al. 2013, "Anisotropic Spherical
//! Gaussians", eq. 4): ASG(v) = μ·max(0, v·z)·exp(−λx(v·x)² − λy(v·y)²)
//! with an orthonormal frame (x, y, z).
//!
//! The exponent is a sum of non-positive terms, so evaluation is finite for any
//! λx, λy ≥ 0, including extreme anisotropy λx/λy = 1e4 (tested).

use crate::error::{normalize_direction, SbfError};
use glam::{DVec3, Vec3};

/// One anisotropic spherical Gaussian.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Asg {
    /// Tangent axis x (bandwidth λx).
    pub x: DVec3,
    /// Tangent axis y (bandwidth λy).
    pub y: DVec3,
    /// Lobe axis z.
    pub z: DVec3,
    /// Bandwidth along the tangent axis x.
    pub lambda_x: f64,
    /// Bandwidth along the tangent axis y.
    pub lambda_y: f64,
    /// Value at the lobe axis.
    pub amplitude: f64,
}

impl Asg {
    /// Builds an ASG from a lobe axis and a tangent direction; the tangent is
    /// Gram–Schmidt-orthogonalised against the axis. Errors on degenerate frames or
    /// negative/non-finite bandwidths.
    pub fn new(axis: DVec3, tangent: DVec3, lambda_x: f64, lambda_y: f64, amplitude: f64) -> Result<Self, SbfError> {
        let z = normalize_direction(axis)?;
        let x = normalize_direction(tangent - z * tangent.dot(z))?;
        let y = z.cross(x);
        for (name, v) in [("ASG lambda_x", lambda_x), ("ASG lambda_y", lambda_y)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SbfError::InvalidParameter { name, value: v, reason: "must be finite and >= 0" });
            }
        }
        if !amplitude.is_finite() {
            return Err(SbfError::InvalidParameter { name: "ASG amplitude", value: amplitude, reason: "must be finite" });
        }
        Ok(Asg { x, y, z, lambda_x, lambda_y, amplitude })
    }

    /// Value in unit direction v.
    #[inline]
    pub fn eval(&self, v: DVec3) -> f64 {
        let s = v.dot(self.z).max(0.0);
        let (a, b) = (v.dot(self.x), v.dot(self.y));
        self.amplitude * s * (-self.lambda_x * a * a - self.lambda_y * b * b).exp()
    }

    /// f32 evaluation for runtime use.
    #[inline]
    pub fn eval_f32(&self, v: Vec3) -> f32 {
        let (x, y, z) = (self.x.as_vec3(), self.y.as_vec3(), self.z.as_vec3());
        let s = v.dot(z).max(0.0);
        let (a, b) = (v.dot(x), v.dot(y));
        self.amplitude as f32 * s * (-(self.lambda_x as f32) * a * a - self.lambda_y as f32 * b * b).exp()
    }
}
