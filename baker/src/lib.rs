//! # baker — bakes lightmaps and light probes into any `sbf` basis, progressively
//!
//! The crate is layered; each layer is a folder whose module doc says what it holds and
//! which layers it may use. Imports only go down this list (a test,
//! `tests/tests/shape.rs` at the workspace root, fails on an upward import or a cycle):
//!
//! | layer | holds |
//! |---|---|
//! | [`scene`] | meshes, materials, lights, environment; built-in scenes, glTF import, BVH, view camera |
//! | [`layout`] | the lightmap atlas (charts, sub-texel points, normals), tile order, probe grid |
//! | [`sampling`] | sample sequences (Sobol', white noise), the environment sampler, ray-guiding distributions |
//! | [`estimator`] | the CPU reference path tracer (the oracle of the GPU kernels) |
//! | [`accumulate`] | bake settings, targets, the shared state, the CPU bake; adaptive, camera-based and filtered accumulation |
//! | [`checkpoint`] | the state on disk (atomic writes, resume, content fingerprints) |
//! | [`gpu`] | the same bake on wgpu: megakernel, the wavefront pass graph, multi-GPU, GPU primitives |
//! | [`post`] | the lightmap as images: dilation, denoising, seams |
//! | [`output`] | EXR, bake.json, probes.json, previews, the runtime shader library a bake needs |
//! | [`render`] | the baked scene rasterised in real time with the exported runtime (GPU) and its CPU twin, the path-traced reference of the same quantity, their errors |
//! | [`run`] | a whole bake as the `baker` command runs it: `run::bake(&Options)`, the options being a [`run::BakeSpec`] (what is baked; its JSON is bake.json's `spec`, spec.json and every shard's header) and [`run::RunOptions`] (how it runs); `baker merge` and `baker resume` rebuild a bake from its spec |
//! | [`slc`] | stochastic light culling ([TH17; TH17-supp; FTH22-supp]), its own renderer and `slc` command; uses the scene layer and the image writers |
//!
//! Binaries: `baker` (`src/main.rs`: arguments → [`run::Options`] → [`run::bake`]; `baker merge`, `baker resume`),
//! `render` (`src/bin/render.rs`: a bake, made or read, → [`render::session::run`]) and
//! `slc` (`src/bin/slc.rs`: arguments → [`slc::harness::SlcOptions`] →
//! [`slc::harness::render`]).
//!
//! Embedding the CPU reference bake of the built-in scene:
//!
//! ```
//! use baker::accumulate::{Bake, BakeConfig, Targets};
//! use baker::estimator::trace::Tracer;
//! use baker::layout::lightmap::Lightmap;
//! use baker::scene::bvh::Bvh;
//!
//! let scene = baker::scene::cornell();
//! let (bvh, lightmap) = (Bvh::build(&scene), Lightmap::build(&scene, 2.0, 1).unwrap());
//! let targets = Targets::lightmap(&lightmap);
//! let config = BakeConfig::default(); // SH L2 + Ambient Dice 9, NNLS, Sobol'
//! let mut bake = Bake::new(config.clone(), &targets, Tracer::new(&scene, &bvh, config.max_bounces));
//! bake.pass();
//! let irradiance = bake.state.mean(); // E/π per texel
//! assert_eq!(irradiance.len(), targets.items.len());
//! ```

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

pub mod accumulate;
pub mod checkpoint;
pub mod estimator;
pub mod gpu;
pub mod layout;
pub mod output;
pub mod post;
pub mod render;
pub mod run;
pub mod sampling;
pub mod scene;
pub mod slc;
