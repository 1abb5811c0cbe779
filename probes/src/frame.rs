//! Tangent space (normal +Z, the peer's lobe frame) and world (+Y up): one swap of two axes,
//! its own inverse. Below `modes` and `appendix_c`, which both lay lobes out in it.

use sbf::glam::DVec3;

/// Tangent space (normal +Z) to world (+Y up): (x, y, z) ↦ (x, z, y) — the frame in which
/// the peer (Probulator, and Roughton's fork of it) lays out its lobes, read in our world.
///
/// Both tools map a lat-long texel (u, v) to φ = π(2u − 1), θ = πv, but to different axes:
/// the peer's `latLongTexcoordToCartesian` gives (sin θ sin φ, −sin θ cos φ, cos θ) with z up;
/// ours ([`sbf::envmap::LatLong::uv_to_direction`]) gives (sin θ sin φ, cos θ, −sin θ cos φ)
/// with y up. The same texel is the same direction once the peer's (x, y, z) is read as our
/// (x, z, y): a swap of two axes, so the peer's z-up frame has the other handedness than our
/// y-up world. A proper rotation such as (x, z, −y) would put every lobe of a layout
/// without that mirror symmetry at the mirrored texel (AD 9 rotated 180° about the normal,
/// the Vogel spirals winding the other way). The map is its own inverse.
pub fn tangent_to_world(t: DVec3) -> DVec3 {
    DVec3::new(t.x, t.z, t.y)
}

/// World (+Y up) to tangent space (normal +Z): the inverse of [`tangent_to_world`] (the
/// same swap).
pub fn world_to_tangent(w: DVec3) -> DVec3 {
    DVec3::new(w.x, w.z, w.y)
}
