//! # shaders — WGSL runtime reconstruction library
//!
//! The runtime side of `sbf` for GPUs: WGSL modules, one per concern, in `wgsl/`
//! (`common`, `ggx`, `lut`, `sh`, `sg`, `ambient_dice`, `progressive`), plus two generated ones:
//! `fits` (fitgen's `luts/fits.wgsl`: every fit constant) and `layouts` (lobe axes from
//! `sbf::layout`). Every WGSL function has a CPU twin in `sbf` and a GPU parity test.
//!
//! - [`modules`]: the sources in composition order.
//! - [`compose`]: configurations ([`compose::Config`]: presets or feature lists) and
//!   composition pruned to what a configuration reaches, with what was left out.
//! - [`export`]: naga validation and HLSL/GLSL/MSL export.
//! - [`layout`]: structs shared with Rust, checked against naga's reflection.
//! - [`profile`]: the features a lighting profile (`sbf::profile`) needs.
//! - [`progressive`]: the Rust twins of the progressive encoder's GPU structs.
//! - `gpu` (feature `gpu`, default): a wgpu compute harness for the parity tests and
//!   the throughput benchmark.
//!
//! The `shaders` binary exposes composition and export:
//! `shaders export --config ad9-irradiance --lang hlsl --out ad9.hlsl`.

#[cfg(feature = "gpu")]
pub mod bench;
pub mod compose;
pub mod export;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod layout;
pub mod modules;
pub mod profile;
pub mod progressive;
