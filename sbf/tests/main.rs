//! sbf's integration tests, one module per file (one binary: see `autotests` in
//! sbf/Cargo.toml). A module that needs basis families or tables is compiled only with
//! those features, so the CI feature matrix runs what applies to each subset.

mod common;

#[cfg(feature = "ambient-cube")]
mod ambient_cube;
#[cfg(feature = "ambient-dice")]
mod ambient_dice;
#[cfg(feature = "bc")]
mod bc6h_signed;
#[cfg(feature = "sh")]
mod engine_formats;
mod envmap;
#[cfg(feature = "ambient-dice")]
mod explicit;
#[cfg(all(feature = "sg", feature = "ambient-dice"))]
mod gram;
#[cfg(feature = "h-basis")]
mod hbasis;
#[cfg(feature = "ambient-dice")]
mod lobe_ggx;
#[cfg(all(feature = "sh", feature = "sg", feature = "ambient-dice"))]
mod lsq;
mod luts_format;
#[cfg(feature = "lut-dfg")]
mod multiscatter;
mod nnls;
mod nnls_eq;
mod probe;
#[cfg(feature = "profile")]
mod profile;
#[cfg(all(feature = "sh", feature = "sg", feature = "ambient-dice"))]
mod progressive;
#[cfg(all(feature = "sh", feature = "ambient-dice", feature = "h-basis"))]
mod projection;
#[cfg(feature = "ambient-dice")]
mod recon_ad;
#[cfg(all(feature = "sh", feature = "sg"))]
mod recon_prior;
mod recon_reference;
#[cfg(all(feature = "sh", feature = "sg", feature = "ambient-dice", feature = "h-basis", feature = "ambient-cube"))]
mod recon_runtime;
#[cfg(feature = "sg")]
mod recon_sg;
#[cfg(feature = "sh")]
mod recon_sh;
#[cfg(all(feature = "sh", feature = "sg", feature = "ambient-dice", feature = "h-basis", feature = "ambient-cube"))]
mod registry;
mod sampling;
#[cfg(feature = "sg")]
mod sg;
#[cfg(feature = "sh")]
mod sh;
#[cfg(feature = "sh")]
mod sh_rotation;
mod slc;
