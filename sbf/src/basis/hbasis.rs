//! H-basis (Habel & Wimmer 2010, "Efficient Irradiance Normal Mapping"): SH-like
//! polynomials orthonormal on the upper hemisphere (tangent space, normal +Z).
//!
//! H₀ = 1/√(2π) (not the SH constant 1/(2√π), a known bug in one public tool),
//! H₁,H₂,H₃ = √(3/2π)·(−y, 2z − 1, −x), H₄ = √(15/2π)·xy, H₅ = ½√(15/2π)·(x² − y²).
//! Orthonormality on z ≥ 0 is checked by quadrature in the tests (1e-8).

use super::Basis;
use crate::error::SbfError;
use crate::quadrature::Domain;
use glam::DVec3;
use std::f64::consts::PI;

/// H-basis with 4 or 6 functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HBasis {
    count: usize,
}

impl HBasis {
    /// `count` must be 4 or 6.
    pub fn new(count: usize) -> Result<Self, SbfError> {
        match count {
            4 | 6 => Ok(HBasis { count }),
            _ => Err(SbfError::InvalidParameter { name: "H-basis size", value: count as f64, reason: "must be 4 or 6" }),
        }
    }
}

impl Basis for HBasis {
    fn name(&self) -> String {
        format!("H-basis {}", self.count)
    }
    fn len(&self) -> usize {
        self.count
    }
    fn domain(&self) -> Domain {
        Domain::UpperHemisphere
    }
    /// Values are the polynomials above for any direction; they are meaningful
    /// (orthonormal) on z ≥ 0 only.
    fn eval_into(&self, d: DVec3, out: &mut [f64]) {
        debug_assert!(super::is_unit(d), "direction must be unit length: {d:?}");
        let k0 = 1.0 / (2.0 * PI).sqrt();
        let k1 = (3.0 / (2.0 * PI)).sqrt();
        out[0] = k0;
        out[1] = -k1 * d.y;
        out[2] = k1 * (2.0 * d.z - 1.0);
        out[3] = -k1 * d.x;
        if self.count == 6 {
            let k2 = (15.0 / (2.0 * PI)).sqrt();
            out[4] = k2 * d.x * d.y;
            out[5] = 0.5 * k2 * (d.x * d.x - d.y * d.y);
        }
    }
}
