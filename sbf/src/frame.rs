//! Tangent frames: an orthonormal (T, B) for a unit normal, used by the reference
//! integrators, the projections and the Ambient Dice derivatives.

use glam::DVec3;

/// Orthonormal tangent frame (T, B) for a unit normal n, branchless
/// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited", Listing 3).
pub fn tangent_frame(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let bt = DVec3::new(b, sign + n.y * n.y * a, -n.y);
    (t, bt)
}
