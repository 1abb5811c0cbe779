//! Ambient cube (Valve, McTaggart 2004): six functions along ±X, ±Y, ±Z,
//! B_{±a}(n) = n_a² where sign(n_a) = ±, else 0; so E(n) = Σ_a n_a²·c(sign n_a).
//! Order: +X, −X, +Y, −Y, +Z, −Z. Σ B = |n|² = 1: a partition of unity.

use super::Basis;
use crate::quadrature::Domain;
use glam::DVec3;

/// The six-function ambient cube.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AmbientCube;

impl Basis for AmbientCube {
    fn name(&self) -> String {
        "ambient cube".into()
    }
    fn len(&self) -> usize {
        6
    }
    fn domain(&self) -> Domain {
        Domain::Sphere
    }
    fn eval_into(&self, d: DVec3, out: &mut [f64]) {
        debug_assert!(super::is_unit(d), "direction must be unit length: {d:?}");
        for (a, c) in [d.x, d.y, d.z].into_iter().enumerate() {
            let sq = c * c;
            // c = 0 contributes 0 to both; assign it to the positive lobe.
            out[2 * a] = if c >= 0.0 { sq } else { 0.0 };
            out[2 * a + 1] = if c < 0.0 { sq } else { 0.0 };
        }
    }
}
