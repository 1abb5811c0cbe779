//! # baker — bakes lightmaps and light probes into any `sbf` basis, progressively
//!
//! - [`scene`]: meshes, materials (Lambert + GGX layers), lights, environment, and the
//!   built-in scenes ([`scene::cornell`], the default; [`scene::furnace`] for tests).
//! - [`bvh`]: binned-SAH BVH flattened into GPU-shaped nodes, CPU traversal.
//! - [`lightmap`]: planar charts, shelf packing, 16 sub-texel sample positions per texel.
//! - [`trace`]: the path-traced L_in estimator (NEE + MIS, Russian roulette).
//! - [`bake`]: progressive passes feeding plain irradiance and the per-sample encoders.
//!
//! Status: the CPU reference path. The wgpu path (WGSL traversal with the `shaders`
//! progressive update), glTF import, probes, checkpoints and previews follow.

pub mod bake;
pub mod bvh;
pub mod checkpoint;
pub mod gpu;
pub mod import;
pub mod lightmap;
pub mod output;
pub mod run;
pub mod scene;
pub mod trace;
