//! Look-up tables: the `.sbflut` format ([`format`](mod@format)), the committed tables and fit
//! constants from `luts/` ([`committed`]), and samplers over them
//! ([`crate::recon::lut`]). The files in `luts/` are produced by fitgen.

pub mod committed;
pub mod format;

pub use format::{Axis, LutFile, ValueFormat};
