//! # sbf — spherical basis functions for real-time lighting
//!
//! The core library of the workspace: bases, sampling, quadrature, Gram
//! matrices and solvers, reconstruction and LUT readers. The core does no file I/O,
//! prints nothing and does not depend on wgpu; the optional `io` feature (off by
//! default) adds the `io` module, the lat-long HDR/EXR loader both tools use.
//!
//! ## Start here
//!
//! [`probe`]: project an HDR map onto a basis, then irradiance and GGX specular at any
//! normal — from a probe or a baked lightmap texel — in a few lines:
//!
//! ```
//! # #[cfg(all(feature = "sh", feature = "sg", feature = "ambient-dice", feature = "h-basis", feature = "ambient-cube", feature = "lut-dfg", feature = "lut-ad-specular-2d"))] {
//! use sbf::envmap::{LatLongImage, ProceduralSky};
//! use sbf::probe::{Probe, ProbeBasis};
//! let sky = ProceduralSky::default();
//! let map = LatLongImage::from_fn(64, 32, |d| sky.radiance(d)).unwrap();
//! let probe = Probe::project(&map, ProbeBasis::Sh2).unwrap();
//! let e = probe.irradiance(sbf::glam::Vec3::Y); // E/π, RGB
//! # assert!(e.min_element() > 0.0);
//! # }
//! ```
//!
//! ## Map of the crate
//!
//! | module | holds |
//! |---|---|
//! | [`basis`] | the [`Basis`] trait and every basis: [`ShBasis`] (any order), its rotation ([`ShRotation`], any order) and the f32 SH fast paths ([`basis::sh_fast`]), [`SgBasis`]/[`Sg`], [`Asg`], Ambient Dice ([`AmbientDiceSrbf`] 12 and 9, [`AmbientDiceBezier`], [`AmbientDiceYCoCg`], [`AmbientDiceLinear`]), [`HBasis`], [`AmbientCube`] |
//! | [`layout`] | lobe layouts: Vogel spiral (sphere, hemisphere), icosahedron (standard, face-up), sharpness heuristic |
//! | [`sampling`] | Halton, Hammersley, R2; sphere/hemisphere/cosine/disk warps with pdfs and inverses; spherical Fibonacci; PCG32 |
//! | [`ggx`] | GGX D, Λ, G1, G2 and visible-normal sampling (Heitz 2018) |
//! | [`luts`] | the `.sbflut` table format (f32/f16, self-describing header) that fitgen writes and sbf reads |
//! | [`quadrature`] | Gauss–Legendre, product rules on sphere/hemisphere, compensated sums, [`Domain`] |
//! | [`envmap`] | lat-long and cube-map geometry, exact texel solid angles, bilinear lookup, map quadrature, the built-in [`envmap::ProceduralSky`] |
//! | [`gram`] | Gram matrices (closed form or quadrature with error estimate), condition numbers, Cholesky solve |
//! | `probe` | (features sh, sg, ambient-dice, h-basis, ambient-cube, lut-dfg, lut-ad-specular-2d) `Probe`: project a map, irradiance and specular from a probe or a lightmap texel — the profiles' radiance bases, the ambient cube and the H-basis |
//! | [`recon`] | Lambert irradiance and GGX specular from coefficients (SH, SG, Ambient Dice, projected), reference integrators |
//! | [`solve`] | batch LS (Gram and design forms), NNLS (Lawson–Hanson), progressive per-sample LS/NNLS, projection matrices and basis conversion |
//! | [`slc`] | stochastic light culling ([TH17; TH17-supp; FTH22-supp]): random light ranges, the diffuse VPL sphere, the GGX VPL spheroid, maximum Fresnel, the stretching and test-space matrices; f64 reference and f32 runtime twins |
//! | [`registry`] | the basis registry: [`BasisId`] and one `const` row per basis — name, lobes, domain, sign, layout, storage, its runtime's shader features and tables, its GPU slot kind (docs/adding-a-basis.md) |
//! | [`error`] | [`SbfError`] and input checks |
//! | [`frame`] | an orthonormal tangent frame for a unit normal (Duff et al. 2017) |
//! | `bc` | (feature `bc`) block-compressed storage: BC6H (UF16 by ISPC, SF16 by its own mode-11 encoder), BC1 and BC7 encode, an independent decode (bcdec) and DDS files |
//! | `ktx` | (feature `ktx2`) KTX 2.0 files: one level, a Khronos data format descriptor, key/value pairs |
//! | `io` | (feature `io`) loading and validating lat-long `.hdr`/`.exr` maps |
//! | `profile` | (feature `profile`) the lighting profile (TOML) every tool takes with `--profile` |
//! | `serial` | (feature `serde`) serde for bases, engine formats and frames as their names, a profile as its TOML |
//!
//! ## Conventions
//!
//! - **Frames.** Right-handed. World space is +Y up (lat-long maps, probes).
//!   Tangent space for BRDFs and hemispherical bases has the normal at **+Z**;
//!   "upper hemisphere" ([`Domain::UpperHemisphere`]) always means z ≥ 0 there.
//! - **Lat-long maps.** u = (1 + atan2(x, −z)/π)/2, v = acos(y)/π; row 0 is the
//!   zenith, the image centre faces −Z (the convention of the bundled probes).
//! - **SH.** Real, orthonormal, index i = l(l+1) + m, **no Condon–Shortley phase**:
//!   band 1 is √(3/4π)·(y, z, x). The constant function 1 projects to c₀₀ = 2√π.
//! - **SG.** G(v) = μ·exp(λ(v·p − 1)); as a basis, B_i = exp(λ_i(v·p_i − 1)) (μ = 1).
//! - **Ambient Dice.** SRBF lobe 0.35c² + 0.25c⁴ on c = v·p > 0 ([Roughton19 eq. 8.3]);
//!   icosahedron vertex order as in [`Icosahedron::standard`].
//! - **Radiance vs E/π.** Bases store radiance unless a name says otherwise;
//!   irradiance images in reports store E/π (what a white Lambertian reflects), as
//!   Probulator does.
//! - **Precision.** Runtime evaluation APIs are `f32` on glam types (`Vec3`);
//!   fitting, quadrature and reference integration are `f64` (`DVec3`).
//! - **Determinism.** Fixed seeds, ordered (compensated) reductions: identical
//!   inputs give bit-identical outputs for any thread count.
//! - **Bad input.** Public constructors and `try_*` functions return
//!   [`SbfError`]; hot-path evaluators document their preconditions (unit
//!   direction, slice length) and check them with debug assertions.

#![warn(missing_docs)]
#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

pub mod basis;
#[cfg(feature = "bc")]
pub mod bc;
pub mod envmap;
pub mod error;
pub mod frame;
pub mod ggx;
pub mod gram;
#[cfg(feature = "io")]
pub mod io;
#[cfg(feature = "ktx2")]
pub mod ktx;
pub mod layout;
pub mod luts;
#[cfg(all(
    feature = "sh",
    feature = "sg",
    feature = "ambient-dice",
    feature = "h-basis",
    feature = "ambient-cube",
    feature = "lut-dfg",
    feature = "lut-ad-specular-2d"
))]
pub mod probe;
#[cfg(feature = "profile")]
pub mod profile;
pub mod quadrature;
pub mod recon;
pub mod registry;
pub mod sampling;
#[cfg(feature = "serde")]
pub mod serial;
pub mod slc;
pub mod solve;

#[cfg(feature = "ambient-cube")]
pub use basis::AmbientCube;
#[cfg(feature = "h-basis")]
pub use basis::HBasis;
#[cfg(feature = "ambient-dice")]
pub use basis::{AmbientDiceBezier, AmbientDiceLinear, AmbientDiceSrbf, AmbientDiceYCoCg};
#[cfg(feature = "sg")]
pub use basis::{Asg, Sg, SgBasis};
pub use basis::{Basis, Icosahedron};
#[cfg(feature = "sh")]
pub use basis::{ShBasis, ShRotation};
pub use error::SbfError;
pub use glam;
pub use nalgebra;
pub use quadrature::Domain;
pub use registry::BasisId;
