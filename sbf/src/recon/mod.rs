//! Reconstruction of Lambert irradiance and GGX specular from basis coefficients,
//! and the reference integrators every method is judged by.
//!
//! | what | where |
//! |---|---|
//! | references: exact map irradiance, QMC irradiance of a function, GGX specular by visible-normal sampling | [`reference`](mod@reference) |
//! | the clamped-cosine band factors A_l shared by every family | [`zonal`] |
//! | SH: band factors A_l (any order), L1 Geomerics, ZH3 hallucination, windowing | [`sh`] |
//! | SG: exact convolution, Hill's fit, cosine-SG inner product, punctual; ASG and plain-SG specular warps | [`sg`] |
//! | irradiance from zonal-lobe coefficients as the best linear estimate under an isotropic radiance prior | [`prior`] |
//! | the directional lightmap formats engines ship (Godot ≥ 4.4 and 4.0–4.3 L1, Bakery MonoSH non-linear and linear, Enlighten single/RGB direction): encode from L1 irradiance, the engines' default decodes, frames, stored precision and compressed layouts | [`engine`] |
//! | f32 runtime API on glam `Vec3` (SH L1/L2/L4, Geomerics, SG Hill/ASG, AD poly / fit + LUT), batch form | [`runtime`] |
//! | GGX response of a radial lobe (SG, AD SRBF): exact quadrature and the 4D table the per-lobe runtime samples | [`lobe_ggx`] |
//! | multiple scattering: the microsurface random walk (Heitz et al. 2016) and the runtime's energy compensation | [`multiscatter`] |
//! | GGX-prefiltered cube maps with a mip chain, as engines store them for glossy specular (Karis 2013's split sum): prefilter kernel and its closed-form normalisation, mip ↔ α, seamless trilinear lookup, RGB9E5 | [`prefiltered`] |
//! | 2D LUTs with texel-centre bilinear sampling; the AD specular LUT (Listing 8.2) | [`lut`] |
//! | the committed tables of `luts/` parsed into those samplers (DFG, AD specular, lobe GGX) | [`tables`] |
//! | Ambient Dice SRBF: analytic lobe irradiance ([Roughton19 eq. 8.11]/8.13), polynomial fit (8.14), specular fit + LUT (Listings 8.1/8.2) | [`ambient_dice`] |
//!
//! Units: irradiance functions return **E/π** (what a white Lambertian surface
//! reflects), matching the reports. Specular returns ∫ L·f_r·cos with Schlick's
//! Fresnel F = f0(1 − F_c) + f90·F_c.

#[cfg(feature = "ambient-dice")]
pub mod ambient_dice;
#[cfg(feature = "sh")]
pub mod engine;
pub mod lobe_ggx;
pub mod lut;
pub mod multiscatter;
pub mod prefiltered;
pub mod prior;
pub mod reference;
pub mod runtime;
#[cfg(feature = "sg")]
pub mod sg;
#[cfg(feature = "sh")]
pub mod sh;
pub mod tables;
pub mod zonal;
