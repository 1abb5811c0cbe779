//! One map's comparison in memory, as the run leaves it: every mode's result and metrics,
//! the references and the stage times. [`crate::results`] turns it into the written
//! records; [`crate::report`] and [`crate::viewer`] render it.

use crate::metrics::Metrics;
use crate::modes::ModeResult;

/// One mode's result with its metrics.
#[derive(Debug, Clone)]
pub struct Row {
    pub result: ModeResult,
    pub radiance: Option<Metrics>,
    pub irradiance: Metrics,
    /// (α, metrics) of the GGX specular signal, for modes that reconstruct it.
    pub specular: Vec<(f64, Metrics)>,
    /// The specular images, parallel to `specular`.
    pub specular_images: Vec<Vec<[f64; 3]>>,
    /// (α, basis-limited RMS, runtime RMS): the exact GGX integral of the mode's
    /// reconstructed radiance against the reference, and the runtime path against that.
    pub specular_parts: Vec<(f64, f64, f64)>,
    /// Prefiltered maps only — (α, split-sum RMS, map RMS): the exact prefiltered radiance
    /// at α times the DFG terms against the reference (the split sum's own error), and the
    /// mode against that (its map's resolution, mip interpolation and storage).
    pub split_sum_parts: Vec<(f64, f64, f64)>,
    /// Steady-state CPU cost of the specular runtime path (modes that have one).
    pub specular_cost: Option<crate::cost::CostStat>,
}

/// The specular reference for one roughness.
#[derive(Debug, Clone)]
pub struct SpecularReference {
    pub alpha: f64,
    pub image: Vec<[f64; 3]>,
    /// Estimated RMS error (vs 16× the samples on a texel subset) and the signal's RMS there.
    pub error_rms: f64,
    pub signal_rms: f64,
    pub texels_checked: usize,
}

/// Everything about one map.
#[derive(Debug, Clone)]
pub struct MapReport {
    pub path: String,
    pub width: usize,
    pub height: usize,
    pub domain: &'static str,
    pub reference_method: String,
    /// How the modes' coefficients were stored (`--storage`).
    pub storage: crate::storage::Storage,
    pub sanitized: usize,
    pub rows: Vec<Row>,
    /// How the specular references were computed ("" when no α was requested).
    pub specular_method: String,
    /// The lobe modes' specular runtime path ("" when no α was requested).
    pub specular_runtime: String,
    /// Which GGX integral the specular reference is (`--reference`).
    pub convention: sbf::ggx::Convention,
    /// That runtime (it also picks the GPU kernel of `--gpu-cost`).
    pub runtime: crate::modes::SpecularRuntime,
    /// Visible-normal samples per texel of the specular references.
    pub specular_samples: u32,
    pub specular_reference: Vec<SpecularReference>,
    /// Output grid and the reference irradiance on it (for the images).
    pub grid: sbf::envmap::LatLong,
    pub reference: Vec<[f64; 3]>,
    /// The map's radiance at the output texel centres (bilinear; for the interactive view).
    pub radiance: Vec<[f64; 3]>,
    /// Folder name of this map's images inside the report folder.
    pub slug: String,
    /// Wall time of each stage.
    pub stages: StageTimes,
}

/// Wall time of each stage of one map's comparison, seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StageTimes {
    /// The exact irradiance reference (and the map's samples).
    pub reference_irradiance: f64,
    /// Every α's specular reference with its error check.
    pub specular_reference: f64,
    /// Every mode: encode (repeats), reconstruction images, specular images.
    pub modes: f64,
    /// Basis-limited specular images of every mode and α.
    pub specular_decomposition: f64,
    /// Every mode's steady-state CPU costs, measured side by side ([`crate::cost`]).
    #[serde(default)]
    pub costs: f64,
}

/// File stem of a specular image for roughness α (`specular_a0.4`).
pub fn specular_stem(alpha: f64) -> String {
    format!("specular_a{alpha}")
}
