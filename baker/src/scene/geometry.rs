//! Surface frames: the tangent frame every hemispherical basis is expressed in, and the
//! shading normal interpolated from vertex normals.

use sbf::glam::Vec3;

/// Duff et al.'s orthonormal frame as f32 (see `sbf::basis::ambient_dice_bezier::tangent_frame`).
pub fn frame(n: Vec3) -> (Vec3, Vec3) {
    let (t, b) = sbf::basis::ambient_dice_bezier::tangent_frame(n.as_dvec3());
    (t.as_vec3(), b.as_vec3())
}

/// The shading normal at barycentrics (w0, w1, w2): interpolated vertex normals, or the
/// face normal `ng` where they cancel or turn more than 90° away from it.
pub fn shading_normal(vn: [Vec3; 3], w: [f32; 3], ng: Vec3) -> Vec3 {
    let n = vn[0] * w[0] + vn[1] * w[1] + vn[2] * w[2];
    match n.try_normalize() {
        Some(n) if n.dot(ng) > 0.0 => n,
        _ => ng,
    }
}
