//! The comparison modes. Ids follow the peer tool's suffixes (lower case).
//!
//! Every mode turns the input map into coefficients (timed) and produces an
//! irradiance image (E/π) on the output grid, plus a radiance image where the basis
//! stores radiance. Radiance fits use the map's texels weighted by their exact solid
//! angles (the integral least-squares problem). Fits to the irradiance image (`ac`,
//! `adrbf-irr`) weigh texels equally, as the peer does, so they minimise the unweighted
//! RMS reported. SH modes clamp the reconstructed irradiance at 0, as the peer does;
//! the fraction of texels that were negative is reported separately.
//!
//! One file per family; [`MODES`] is the table of every mode (id, description, the
//! family function that runs it) that [`prepare`] dispatches on.

mod ad;
pub mod common;
pub mod conserving;
pub mod context;
mod cube;
pub mod engine;
mod hemisphere;
mod mc;
pub mod prefiltered;
mod progressive;
mod sg;
mod sh;

pub use crate::cost::{EncodeJob, Timing, ENCODE_BUDGET_S};
pub use crate::frame::{tangent_to_world, world_to_tangent};
pub use common::{Prepared, MCIS_SAMPLES, PROGRESSIVE_SAMPLES};
pub use context::{Context, ModeResult, SgIrradiance, SpecularRuntime};

/// A mode: its id, its one-line description (`probes list`) and the family function that
/// runs it up to its cost measurement.
#[derive(Debug, Clone, Copy)]
pub struct Mode {
    /// The id (`--modes`), the peer's suffix where it has one.
    pub id: &'static str,
    /// One line for `probes list` and the reports.
    pub description: &'static str,
    /// The family's runner.
    pub prepare: for<'a> fn(&'static str, &'a Context, usize) -> Result<Prepared<'a>, String>,
}

/// Every mode, in report order.
pub const MODES: &[Mode] = &[
    Mode { id: "mcis", description: "Monte Carlo importance sampling as the peer's reference: 5000 texels drawn by luminance × solid angle (fixed seed, shared by all output texels), vs our exact reference", prepare: mc::prepare },
    Mode { id: "ac", description: "ambient cube fitted to the irradiance image, NNLS", prepare: cube::prepare },
    Mode { id: "acproj", description: "ambient cube: irradiance sampled at the six axes", prepare: cube::prepare },
    Mode { id: "shl1g", description: "SH L1, Geomerics reconstruction", prepare: sh::prepare },
    Mode { id: "shl1zh3", description: "SH L1, ZH3 hallucination", prepare: sh::prepare },
    Mode { id: "shl1", description: "SH L1 (4 coefficients), A_l convolution", prepare: sh::prepare },
    Mode { id: "shl2", description: "SH L2 (9), A_l convolution", prepare: sh::prepare },
    Mode { id: "shl3", description: "SH L3 (16)", prepare: sh::prepare },
    Mode { id: "shl4", description: "SH L4 (25)", prepare: sh::prepare },
    Mode { id: "shl5", description: "SH L5 (36)", prepare: sh::prepare },
    Mode { id: "shl6", description: "SH L6 (49)", prepare: sh::prepare },
    Mode { id: "shl7", description: "SH L7 (64)", prepare: sh::prepare },
    Mode { id: "shl8", description: "SH L8 (81)", prepare: sh::prepare },
    Mode { id: "shl9", description: "SH L9 (100)", prepare: sh::prepare },
    Mode { id: "shl10", description: "SH L10 (121)", prepare: sh::prepare },
    Mode { id: "shl11", description: "SH L11 (144)", prepare: sh::prepare },
    Mode { id: "shl12", description: "SH L12 (169)", prepare: sh::prepare },
    Mode { id: "shl13", description: "SH L13 (196)", prepare: sh::prepare },
    Mode { id: "shl14", description: "SH L14 (225)", prepare: sh::prepare },
    Mode { id: "shl15", description: "SH L15 (256)", prepare: sh::prepare },
    Mode { id: "shl16", description: "SH L16 (289)", prepare: sh::prepare },
    Mode { id: "adrbf", description: "Ambient Dice SRBF 12, radiance LS, irradiance by the exact lobe integral", prepare: ad::prepare },
    Mode { id: "adrbf-irr", description: "Ambient Dice SRBF 12 fitted to the irradiance image (as the peer)", prepare: ad::prepare },
    Mode { id: "sg", description: "SG 12 (λ 6, Vogel), naive projection with the peer's normalisation, irradiance by the peer's kernel (λ 8.5; `--sg-irradiance hill` for Hill)", prepare: sg::prepare },
    Mode { id: "sgls", description: "SG 12, least squares; irradiance by the isotropic-prior estimate (`--sg-irradiance hill` for Hill)", prepare: sg::prepare },
    Mode { id: "sglsa", description: "SG 12 + ambient lobe, least squares; irradiance by the isotropic-prior estimate", prepare: sg::prepare },
    Mode { id: "sgnnls", description: "SG 12, non-negative least squares; irradiance by the peer's kernel (λ 3)", prepare: sg::prepare },
    Mode { id: "shl2w", description: "SH L2 with sinc⁴ deringing where its irradiance would be negative", prepare: sh::prepare },
    Mode { id: "ad", description: "Ambient Dice hybrid Bézier (36), fitted to the irradiance image (as the peer)", prepare: ad::prepare },
    Mode { id: "adycocg", description: "Ambient Dice YCoCg (Bézier Y + linear Co/Cg, 60), fitted to the irradiance image", prepare: ad::prepare },
    Mode { id: "sgra", description: "SG 12, running average over the map's texels in a fixed shuffled order (as the peer)", prepare: progressive::prepare },
    Mode { id: "sgnnra", description: "SG 12, non-negative running average", prepare: progressive::prepare },
    Mode { id: "sgpls", description: "SG 12, progressive least squares ([Roughton19 §7.3]), 4096 Halton samples, f32 state", prepare: progressive::prepare },
    Mode { id: "sgpnnls", description: "SG 12, progressive non-negative least squares", prepare: progressive::prepare },
    Mode { id: "adpls", description: "Ambient Dice SRBF 12, progressive least squares, 4096 Halton samples", prepare: progressive::prepare },
    Mode { id: "adpnnls", description: "Ambient Dice SRBF 12, progressive non-negative least squares", prepare: progressive::prepare },
    Mode { id: "sgnnlsc", description: "SG 12, NNLS keeping the map's SH L0 + L1 (equality-constrained; `conserving`); Hill irradiance", prepare: conserving::mode },
    Mode { id: "adnnlsc", description: "Ambient Dice SRBF 12, NNLS keeping the map's SH L0 + L1 (equality-constrained)", prepare: conserving::mode },
    Mode { id: "sgpnnlsc", description: "SG 12, progressive Monte Carlo projections (4096 Halton samples, f32 state), exact Gram, NNLS keeping SH L0 + L1", prepare: conserving::mode },
    Mode { id: "adpnnlsc", description: "Ambient Dice SRBF 12, progressive Monte Carlo projections, exact Gram, NNLS keeping SH L0 + L1", prepare: conserving::mode },
    Mode { id: "ad9", description: "Ambient Dice SRBF 9, Roughton's hemisphere set (§8.3.1), LS over the sphere, eq. 8.14 irradiance (Appendix C)", prepare: hemisphere::prepare },
    Mode { id: "sg9h", description: "SG 9, λ 6, Vogel spiral over the upper hemisphere, LS over the sphere, Hill irradiance (Appendix C)", prepare: hemisphere::prepare },
    Mode { id: "sg12h", description: "SG 12, λ 6, Vogel spiral over the upper hemisphere (Appendix C)", prepare: hemisphere::prepare },
    Mode { id: "adrbf-tangent", description: "Ambient Dice SRBF 12 on the icosahedron in tangent space, eq. 8.14 irradiance (Appendix C's AD12)", prepare: hemisphere::prepare },
    Mode { id: "h4", description: "H-basis 4 (tangent space, normal +Y in the map), fitted to the irradiance image over the upper hemisphere", prepare: hemisphere::prepare },
    Mode { id: "h6", description: "H-basis 6, fitted to the irradiance image over the upper hemisphere", prepare: hemisphere::prepare },
    Mode { id: "pf8", description: "SH L2 (diffuse) + GGX-prefiltered cube map (specular): 8² faces, 4 mips, Karis 2013's prefilter and split sum, stored as --storage", prepare: prefiltered::prepare },
    Mode { id: "pf16", description: "SH L2 + GGX-prefiltered cube map, 16² faces, 5 mips", prepare: prefiltered::prepare },
    Mode { id: "pf32", description: "SH L2 + GGX-prefiltered cube map, 32² faces, 6 mips", prepare: prefiltered::prepare },
    Mode { id: "pf64", description: "SH L2 + GGX-prefiltered cube map, 64² faces, 7 mips", prepare: prefiltered::prepare },
    Mode { id: "pf8-ni", description: "SH L2 + cube map prefiltered with the GGX BRDF × cosine at normal incidence (exact split sum where the view is along the normal), 8² faces", prepare: prefiltered::prepare },
    Mode { id: "pf16-ni", description: "SH L2 + cube map prefiltered at normal incidence, 16² faces", prepare: prefiltered::prepare },
    Mode { id: "pf32-ni", description: "SH L2 + cube map prefiltered at normal incidence, 32² faces", prepare: prefiltered::prepare },
    Mode { id: "pf64-ni", description: "SH L2 + cube map prefiltered at normal incidence, 64² faces", prepare: prefiltered::prepare },
    Mode { id: "pf8-ni-rgb9e5", description: "SH L2 + cube map prefiltered at normal incidence, 8² faces, RGB9E5 (4 bytes per texel)", prepare: prefiltered::prepare },
    Mode { id: "pf16-ni-rgb9e5", description: "SH L2 + cube map prefiltered at normal incidence, 16² faces, RGB9E5", prepare: prefiltered::prepare },
    Mode { id: "pf32-ni-rgb9e5", description: "SH L2 + cube map prefiltered at normal incidence, 32² faces, RGB9E5", prepare: prefiltered::prepare },
    Mode { id: "pf64-ni-rgb9e5", description: "SH L2 + cube map prefiltered at normal incidence, 64² faces, RGB9E5", prepare: prefiltered::prepare },
    Mode { id: "godot-l1", description: "Godot ≥ 4.4 LightmapGI SH: L0 + L1/L0 packed in three RGBA16F layers, Godot's decode", prepare: engine::mode },
    Mode { id: "godot-l1-legacy", description: "Godot 4.0–4.3 LightmapGI SH: L0 + signed L1 coefficients in three RGBA16F layers, its decode", prepare: engine::mode },
    Mode { id: "monosh", description: "Bakery MonoSH: RGB L0 + one luminance L1 direction (RGBA8), Bakery's default non-linear decode", prepare: engine::mode },
    Mode { id: "monosh-linear", description: "Bakery MonoSH with SH non-linear mode off: the linear decode", prepare: engine::mode },
    Mode { id: "enlighten", description: "Unity/Enlighten directional lightmap: one luminance direction + rescaling factor (RGBA8), Unity's half-Lambert decode", prepare: engine::mode },
    Mode { id: "enlighten-rgb", description: "one Enlighten direction + rescaling factor per channel (3 × RGBA8): a research layout no engine ships", prepare: engine::mode },
];

/// Default modes for `--domain hemisphere` ([Roughton19 Appendix C]).
pub const HEMISPHERE_MODES: &[&str] = &["ad9", "adrbf-tangent", "sg9h", "sg12h", "h4", "h6"];

/// The default set: every mode with a peer figure, plus adrbf, the progressive modes and the
/// prefiltered maps (engines' representation for glossy specular) with both kernels.
pub const DEFAULT_MODES: &[&str] = &[
    "ac",
    "acproj",
    "shl1g",
    "shl1zh3",
    "shl1",
    "shl2",
    "shl4",
    "shl2w",
    "ad",
    "adycocg",
    "adrbf-irr",
    "adrbf",
    "sg",
    "sgls",
    "sglsa",
    "sgnnls",
    "sgra",
    "sgnnra",
    "sgpls",
    "sgpnnls",
    "adpls",
    "adpnnls",
    "pf8",
    "pf16",
    "pf32",
    "pf64",
    "pf8-ni",
    "pf16-ni",
    "pf32-ni",
    "pf64-ni",
];

/// SH order of the SH modes: `shl1g`, `shl1zh3` and `shlN` for N = 1…16.
pub fn sh_order(id: &str) -> Option<usize> {
    match id {
        "shl1g" | "shl1zh3" => Some(1),
        _ => id.strip_prefix("shl").and_then(|n| n.parse::<usize>().ok()).filter(|n| (1..=16).contains(n) && id == format!("shl{n}")),
    }
}

/// The mode of id `id`.
pub fn mode(id: &str) -> Option<&'static Mode> {
    MODES.iter().find(|m| m.id == id)
}

/// Runs one mode alone, its cost measured on its own (a run of several modes uses
/// [`prepare`] and measures them side by side); `repeats` encode runs are timed and
/// their median reported.
pub fn run(id: &str, ctx: &Context, repeats: usize) -> Result<ModeResult, String> {
    let p = prepare(id, ctx, repeats)?;
    let mut r = p.result;
    if let Some(mut job) = p.encode {
        let t = crate::cost::time_encodes(std::slice::from_mut(&mut job)).remove(0);
        Prepared::set_encode(&mut r, t, p.eval_from_encode, ctx.dirs.len());
    }
    if let Some(job) = p.eval {
        r.eval = crate::cost::measure(job);
    }
    Ok(r)
}

/// Runs one mode up to its cost measurement (see [`Prepared`]); `repeats` encode runs are
/// timed and their median reported.
pub fn prepare<'a>(id: &str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let m = mode(id).ok_or_else(|| format!("unknown mode '{id}' (see `probes list`)"))?;
    let mut p = (m.prepare)(m.id, ctx, repeats)?;
    p.result.name = m.description;
    Ok(p)
}
