//! Content digests: FNV-1a 64 (Fowler–Noll–Vo; stable across builds and platforms, unlike
//! `std`'s hasher) and the terms of the order-free digest of a texel's surface points
//! ([`super::lightmap::points_digest`]), with which a bake's identity
//! ([`crate::checkpoint::content_fingerprint`]) covers every sample point without holding
//! them ([`super::lightmap::Lightmap::build_part`]).

/// FNV-1a 64, fed with the bytes that determine a bake.
#[derive(Debug, Clone, Copy)]
pub struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    pub fn bytes(&mut self, b: &[u8]) {
        for x in b {
            self.0 = (self.0 ^ *x as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    pub fn u64(&mut self, x: u64) {
        self.bytes(&x.to_le_bytes());
    }
    pub fn f32s(&mut self, v: &[f32]) {
        for x in v {
            self.bytes(&x.to_bits().to_le_bytes());
        }
    }
    pub fn vec3(&mut self, v: sbf::glam::Vec3) {
        self.f32s(&v.to_array());
    }
    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// The digest term of a sample point at `rank` among its texel's points (bit order): FNV-1a
/// of the rank and the point's nine f32 (position, shading normal, geometric normal).
pub fn point_term(rank: usize, point: [sbf::glam::Vec3; 3]) -> u64 {
    let mut h = Fnv::default();
    h.u64(rank as u64);
    point.iter().for_each(|v| h.vec3(*v));
    h.finish()
}
