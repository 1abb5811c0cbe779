//! # probes — compare spherical bases and solvers on HDR environment maps
//!
//! Error against run time for every mode: the tool loads lat-long maps ([`input`]),
//! computes exact references ([`reference`](mod@reference)), runs each mode ([`modes`]: the
//! table [`modes::MODES`] and one file per family — among them the engines' directional
//! lightmap formats, [`modes::engine`], and non-negative fits that keep the map's light,
//! [`modes::conserving`], and the GGX-prefiltered cube maps engines ship for glossy specular,
//! [`modes::prefiltered`], prefiltered by [`prefilter`]) including the GGX specular signal
//! ([`specular`]), measures errors
//! ([`metrics`]) and writes reports ([`report`]) with images and plots ([`images`]).
//! `--reference appendix-c` reproduces [Roughton19 Appendix C]'s conventions ([`appendix_c`]).
//! Irradiance images store E/π (what a white Lambertian surface reflects), as the
//! peer tool (Probulator) does, so numbers are comparable.

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

pub mod appendix_c;
pub mod azimuthal;
pub mod calibration;
pub mod compare;
pub mod cost;
pub mod decide;
pub mod decision_text;
pub mod frame;
pub mod gpu_cost;
pub mod images;
/// Map loading lives in `sbf::io` (shared with the baker); re-exported under its old name.
pub use sbf::io as input;
pub mod memo;
pub mod metrics;
pub mod modes;
pub use modes::{conserving, engine as engine_modes};
pub mod outcome;
pub mod outdir;
pub mod prefilter;
pub mod profile;
pub mod reference;
pub mod report;
pub mod results;
pub mod specular;
pub mod storage;
pub mod viewer;
