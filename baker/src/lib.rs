//! # baker — GPU path tracer that bakes lightmaps and probes into any basis
//!
//! Not implemented yet (issue "baker"). Planned: glTF scenes, chart packing,
//! CPU-built BVH traversed in WGSL, progressive path tracing with the `shaders`
//! per-sample encoder, CPU reference path, checkpoints and previews.
