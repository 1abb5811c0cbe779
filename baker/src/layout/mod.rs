//! # The layout layer: where a bake samples
//!
//! The lightmap atlas — charts (the mesh's own lightmap UVs, or charts generated for
//! meshes without them), their packing, 16 sub-texel sample points per texel with a
//! coverage mask and shading normals ([`lightmap`]) — the tile order of texel indices
//! ([`tiles`]), the probe grid with the inside-geometry test ([`probes`]) and the content
//! digests a bake's identity is made of ([`digest`]).
//!
//! Uses: [`crate::scene`].

pub mod digest;
pub mod lightmap;
pub mod probes;
pub mod tiles;
