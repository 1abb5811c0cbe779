//! # fitgen — derives the fits and look-up tables in `luts/`
//!
//! The tool does arguments and files; integrands and models live in `sbf`
//! (`sbf::ggx::dfg_entry`, `sbf::recon::ambient_dice::specular_lut_entry`, …). This
//! library holds the drivers: which tables exist ([`outputs`]), how each is
//! generated deterministically (rayon over entries, results collected in index order:
//! identical bytes for any thread count), the nonlinear fits through argmin ([`optimise`]), the manifest ([`manifest`]) and the
//! byte-for-byte check ([`check`]), the EXR viewing twins of the tables ([`exr`]) and the `--plots` figures ([`plots`]).

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

pub mod check;
pub mod exr;
pub mod manifest;
pub mod optimise;
pub mod outputs;
pub mod plots;

pub use outputs::{generate, Output, OUTPUT_NAMES};
