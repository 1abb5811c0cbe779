//! bake.json and probes.json: what a bake wrote, measured and left out, as typed records.
//!
//! Every field is written by `serde`; optional stages are `null` when off (`probes` is
//! absent without probes). Single-precision settings are recorded as the f64 of the f32
//! the bake used (e.g. 0.10000000149011612 for a radius of 0.1), so the file states
//! exactly what ran.

use serde::Serialize;

/// bake.json.
#[derive(Debug, Clone, Serialize)]
pub struct BakeJson {
    pub scene: String,
    /// The bake spec (`run::BakeSpec`): every setting that defines the bake, as
    /// `baker resume` and `baker merge` read it (`spec.json` holds the same).
    pub spec: serde_json::Value,
    /// The engine that traced: "CPU: N threads (rayon)", "GPU: adapter" or the GPUs.
    pub device: String,
    /// The GPU pipeline ("megakernel", "wavefront") or "none (CPU path)".
    pub pipeline: &'static str,
    pub passes: u64,
    pub seed: u64,
    pub sampler: &'static str,
    pub adaptive: Option<AdaptiveJson>,
    /// Paths traced for the lightmap (accepted samples of every texel).
    pub paths: u64,
    pub max_bounces: u32,
    /// Indirect light only (absent: all light): what reaches a texel straight from an
    /// emitter, a delta light or the sky is not in the lightmap.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub indirect_only: bool,
    /// The textures the materials' maps sampled (absent: none; `--material-maps factors`
    /// drops them before the bake).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material_maps: Option<MapsJson>,
    pub solver: String,
    pub layout: LayoutJson,
    pub filter: Option<FilterJson>,
    pub irradiance: FileJson,
    pub normals: FileJson,
    pub bases: Vec<BasisJson>,
    pub guiding: Option<GuidingJson>,
    pub denoise: Option<DenoiseJson>,
    pub seams: SeamsJson,
    /// The lightmap in engines' directional formats (`--engine-formats`; absent: none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub engine_formats: Vec<crate::output::engine::EngineFormatJson>,
    /// BC6H copies of the lightmap images (`--compress bc6h`; absent: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compression: Option<crate::output::compress::CompressionJson>,
    pub stage_seconds: StageSecondsJson,
    /// Per mesh: its chart(s) in the atlas (see [`crate::output::mesh_mapping`]).
    pub meshes: serde_json::Value,
    pub runtime: RuntimeJson,
    pub profile: Option<ProfileJson>,
    /// The EXR files written.
    pub files: Vec<String>,
    pub preview: &'static str,
    /// Wall time of the whole bake.
    pub seconds: f64,
    /// The process's peak resident memory so far, in bytes (Linux: VmHWM of
    /// /proc/self/status; null elsewhere).
    pub peak_memory_bytes: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub probes: Option<ProbesSummaryJson>,
}

/// Adaptive sampling's settings.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct AdaptiveJson {
    pub pilot_passes: u64,
    pub batch_fraction: f64,
    pub floor: f64,
    pub max_per_batch: u32,
}

/// Samples accepted and rejected over a state's items.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ValidityJson {
    /// Items left invalid (inside geometry).
    pub invalid: usize,
    pub max_back_face_fraction: f64,
    pub back_face_samples: u64,
    pub non_finite_samples: u64,
    pub accepted_samples: u64,
}

/// The atlas.
#[derive(Debug, Clone, Serialize)]
pub struct LayoutJson {
    pub width: usize,
    pub height: usize,
    pub texels_per_unit: f64,
    pub padding: usize,
    pub valid_texels: usize,
    pub utilisation: f64,
    pub dilated_texels: usize,
    pub validity: &'static str,
    pub texel_validity: ValidityJson,
    pub overlapped_texels: usize,
    pub empty_before_dilation: usize,
}

/// Filtered gather-based accumulation.
#[derive(Debug, Clone, Serialize)]
pub struct FilterJson {
    pub kernel: &'static str,
    pub radius_texels: f64,
    pub gather_targets: usize,
    pub uncovered_targets: usize,
    pub negative_weight_samples_skipped: u64,
    pub method: &'static str,
}

/// An image file and what it holds.
#[derive(Debug, Clone, Serialize)]
pub struct FileJson {
    pub file: &'static str,
    pub quantity: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub standard_error: Option<&'static str>,
}

/// One lightmap basis: its lobes, domain, solver, frame and files.
#[derive(Debug, Clone, Serialize)]
pub struct BasisJson {
    pub name: &'static str,
    pub lobes: usize,
    pub domain: &'static str,
    pub solver: &'static str,
    pub space: &'static str,
    pub files: Vec<String>,
    pub mirrored_lower_hemisphere: bool,
    /// SG: every lobe's sharpness λ (the lobes are exp(λ(μ·ω − 1)), amplitude 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sg_sharpness: Option<f64>,
    /// SG and Ambient Dice: the lobe axes in the tangent frame, in coefficient order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lobe_axes: Option<Vec<[f64; 3]>>,
    /// What the lobes keep of the texels' E/π at the normal (so a biased fit shows in
    /// every bake).
    pub irradiance_ratio: IrradianceRatioJson,
}

/// Σ (the basis' E/π at the texel's normal, by the renderer's runtime) / Σ (the texel's
/// E/π) over the valid texels and RGB: of the written lobes (after the solver's per-texel
/// step, denoising and seams) overall and for the chart furthest from 1 (charts of ≥ 4
/// valid texels with light), and of the progressive fit before the solver's step. NaN (as
/// null) where no texel has light.
#[derive(Debug, Clone, Serialize)]
pub struct IrradianceRatioJson {
    pub mean: f64,
    pub worst_chart: Option<u32>,
    pub worst_chart_ratio: f64,
    pub worst_chart_texels: usize,
    pub fit_mean: f64,
    pub fit_worst_chart_ratio: f64,
}

/// Ray guiding.
#[derive(Debug, Clone, Serialize)]
pub struct GuidingJson {
    pub method: &'static str,
    pub clusters: usize,
    pub clusters_with_light: usize,
    pub learn_passes: u64,
    pub guided_fraction: f64,
    pub rebuilt_at_passes: Vec<u64>,
    pub learning_samples: &'static str,
}

/// The denoiser.
#[derive(Debug, Clone, Serialize)]
pub struct DenoiseJson {
    pub method: &'static str,
    pub window: usize,
    pub patch: usize,
    pub strength: f64,
    pub texels: usize,
    pub mean_effective_neighbours: f64,
    pub seconds: f64,
}

/// UV seams: the metric before and (stitched) after, and the solve.
#[derive(Debug, Clone, Serialize)]
pub struct SeamsJson {
    pub edges: usize,
    pub samples: usize,
    pub metric_before: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metric_after: Option<f64>,
    pub texel_noise: f64,
    pub stitched: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texels: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cg_iterations: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cg_converged: Option<bool>,
    /// Texels held at their own values in some colour channel, where the free least-squares
    /// solve took E/π (or another non-negative image) below zero.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_texels: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seconds: Option<f64>,
    pub metric: &'static str,
}

/// Wall time of the bake's stages.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StageSecondsJson {
    pub lightmap_passes: f64,
    pub probe_passes: Option<f64>,
    pub denoise: Option<f64>,
    pub seams: f64,
    pub outputs: f64,
}

/// The runtime shader library written beside the bake.
#[derive(Debug, Clone, Serialize)]
pub struct RuntimeJson {
    pub wgsl: &'static str,
    pub files: Vec<String>,
    pub features: Vec<&'static str>,
    pub luts: Vec<String>,
    /// The same tables as KTX 2.0 textures in the layouts the runtime's functions read
    /// (`shaders::tables`: the layout in each file's `sbf.layout` key).
    pub textures: Vec<String>,
    /// The specular runtime paths written (`fit`, `tables`; empty without specular).
    pub specular_paths: Vec<&'static str>,
    pub left_out_bytes: usize,
    pub specular: &'static str,
}

/// The lighting profile the bases came from.
#[derive(Debug, Clone, Serialize)]
pub struct ProfileJson {
    pub name: String,
    pub summary: String,
    pub lightmap_bases: Vec<String>,
    pub probe_bases: Vec<String>,
    pub specular: bool,
    pub roughness: Option<[f64; 2]>,
    pub precision: String,
    pub language: String,
}

/// bake.json's account of the probes (probes.json holds them).
#[derive(Debug, Clone, Serialize)]
pub struct ProbesSummaryJson {
    pub file: &'static str,
    pub count: usize,
    pub validity: ValidityJson,
    pub relocated: usize,
}

/// probes.json (fields in alphabetical order, as earlier versions wrote them).
#[derive(Debug, Clone, Serialize)]
pub struct ProbesJson {
    pub bases: Vec<&'static str>,
    pub passes: u64,
    pub probes: Vec<ProbeJson>,
    pub space: &'static str,
}

/// One probe: position, mean radiance, coefficients per basis, validity (fields in
/// alphabetical order).
#[derive(Debug, Clone, Serialize)]
pub struct ProbeJson {
    pub back_face_fraction: f64,
    /// Basis name → rows of RGB coefficients.
    pub coefficients: std::collections::BTreeMap<&'static str, Vec<[f64; 3]>>,
    pub mean_radiance: [f64; 3],
    pub position: [f64; 3],
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relocated_from: Option<[f64; 3]>,
    pub standard_error: [f64; 3],
    pub valid: bool,
}

/// The texture maps a bake sampled (mip 0, each sampler's magnification filter).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MapsJson {
    /// Textures, and their texels' bytes (RGBA8).
    pub textures: usize,
    pub bytes: usize,
    /// Materials with at least one map.
    pub materials: usize,
}
