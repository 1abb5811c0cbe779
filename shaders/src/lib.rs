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
//! - [`lang`]: the target languages and naga validation of composed WGSL.
//! - [`export`]: the export in WGSL, HLSL, GLSL and MSL.
//! - [`emit`]: the structured emitter that writes the library in HLSL, GLSL and MSL
//!   (readable include files: WGSL names, loops, comments, no entry point).
//! - [`library`]: the exported include files (every preset and profile, four languages)
//!   with an example shader each; `shaders library` writes or checks them.
//! - [`layout`]: structs shared with Rust, checked against naga's reflection.
//! - [`profile`]: the features a lighting profile (`sbf::profile`) needs.
//! - [`tables`]: the committed tables as KTX 2.0 textures in the layouts the library reads
//!   (`shaders tables --out DIR`; the baker writes its runtime's beside the bake).
//! - [`progressive`]: the Rust twins of the progressive encoder's GPU structs.
//! - `gpu` (feature `gpu`, default): a wgpu compute harness for the parity tests and
//!   the throughput benchmark; `spirv`: the same harness in HLSL and GLSL (glslang →
//!   SPIR-V), around the exported library; `sampler`: the adapter's texture filter
//!   precision (weight bits, result rounding), measured, for the filtered lookups' error
//!   models.
//!
//! The `shaders` binary exposes composition and export:
//! `shaders export --config ad9-irradiance --lang hlsl --out ad9.hlsl`.

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

#[cfg(feature = "gpu")]
pub mod bench;
pub mod compose;
pub mod emit;
pub mod export;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod lang;
pub mod layout;
pub mod library;
pub mod modules;
pub mod profile;
pub mod progressive;
#[cfg(feature = "gpu")]
pub mod sampler;
#[cfg(feature = "gpu")]
pub use gpu::spirv;
pub mod tables;
