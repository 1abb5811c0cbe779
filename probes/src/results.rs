//! `results.json`: the machine-readable results, written and read with serde (derive).
//!
//! One [`MapResults`] per map, in an array. Every number a report shows comes from here,
//! including the decision section ([`crate::decide`]), which a test recomputes from the
//! file. Non-finite values are written as `null` and read back as NaN.

use crate::cost::CostStat;
use crate::metrics::Metrics;
use crate::outcome::{specular_stem, MapReport, StageTimes};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Numbers that may be non-finite: `null` in JSON, NaN in memory.
pub mod nullable {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if x.is_finite() {
            s.serialize_f64(*x)
        } else {
            s.serialize_none()
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
    }
}

fn physical() -> String {
    "physical".into()
}

/// The results of one map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapResults {
    pub map: MapInfo,
    /// `sphere` or `upper hemisphere` (where errors are measured).
    pub domain: String,
    /// How every mode's coefficients were stored before reconstruction (`--storage`).
    #[serde(default)]
    pub storage: String,
    pub reference: ReferenceInfo,
    /// The lobe modes' specular runtime path (absent without specular).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub specular_runtime: String,
    /// The lighting profile the run followed (its one-line summary; absent without one).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub profile: String,
    /// The error (% of the reference's RMS) above which no mode is usable for a signal
    /// (`--usable-error`; [`crate::decide`]).
    #[serde(default = "default_usable_error")]
    pub usable_error_percent: f64,
    /// Wall time of each stage, seconds.
    pub stage_seconds: StageTimes,
    pub modes: Vec<ModeRecord>,
    /// Pareto fronts and budget tables ([`crate::decide`]).
    pub decision: Decision,
}

fn usable_default() -> bool {
    true
}

/// The default usability threshold: a mode whose error exceeds this percentage of the
/// reference's RMS is not one to ship (`--usable-error`; [`crate::decide`] applies it).
pub const USABLE_ERROR_PERCENT: f64 = 10.0;

fn default_usable_error() -> f64 {
    USABLE_ERROR_PERCENT
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapInfo {
    pub path: String,
    pub width: usize,
    pub height: usize,
    pub sanitized_texels: usize,
    /// Folder of this map's images inside the report folder (unique per run).
    pub folder: String,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceInfo {
    /// `physical` (the GGX integral) or `appendix-c` ([Roughton19 Appendix C]'s conventions,
    /// `--reference appendix-c`; see `probes::appendix_c`).
    #[serde(default = "physical")]
    pub convention: String,
    /// How the irradiance reference was computed.
    pub method: String,
    /// How the specular references were computed (absent without specular).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub specular_method: String,
    /// Per α (as written on the command line): the reference's estimated error.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub specular_error: BTreeMap<String, ReferenceError>,
    /// Seconds it took to make the irradiance reference (charged to modes that fit it).
    pub irradiance_seconds: f64,
    pub images: ReferenceImages,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceError {
    #[serde(with = "nullable")]
    pub rms: f64,
    #[serde(with = "nullable")]
    pub signal_rms: f64,
    pub texels_checked: usize,
}

/// Image paths relative to the report folder; PNG always, EXR with `--images exr`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceImages {
    pub irradiance: ImagePair,
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub specular: BTreeMap<String, ImagePair>,
}

/// A PNG preview and, when written, the float EXR of the same image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImagePair {
    pub png: String,
    pub exr: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeRecord {
    pub id: String,
    pub name: String,
    pub basis: String,
    pub solver: String,
    pub coefficient_count: usize,
    pub coefficients: Vec<[f64; 3]>,
    pub lobes: Vec<Lobe>,
    pub metrics: ModeMetrics,
    pub cost: Cost,
    /// Keys of the mode's evaluators in the CPU cost calibration ([`crate::calibration`]).
    pub cost_keys: CostKeys,
    /// Per-sample encoders: (samples taken, irradiance RMS).
    pub convergence: Vec<(u64, f64)>,
    pub images: ModeImages,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Lobe {
    pub axis: [f64; 3],
    pub sharpness: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeMetrics {
    pub radiance: Option<MetricsJson>,
    pub irradiance: MetricsJson,
    /// Per α: the specular metrics and the error split (absent without specular).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub specular: BTreeMap<String, SpecularMetrics>,
}

/// [`Metrics`] as written (non-finite as null).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MetricsJson {
    #[serde(with = "nullable")]
    pub rms: f64,
    #[serde(with = "nullable")]
    pub rms_weighted: f64,
    #[serde(with = "nullable")]
    pub rel_rms: f64,
    #[serde(with = "nullable")]
    pub max_abs: f64,
    #[serde(with = "nullable")]
    pub smape: f64,
    #[serde(with = "nullable")]
    pub negative_fraction: f64,
    /// [`Metrics::mean_ratio`] (absent from results written before it: NaN).
    #[serde(with = "nullable", default = "nan")]
    pub mean_ratio: f64,
}

fn nan() -> f64 {
    f64::NAN
}

impl From<Metrics> for MetricsJson {
    fn from(m: Metrics) -> Self {
        MetricsJson {
            rms: m.rms,
            rms_weighted: m.rms_weighted,
            rel_rms: m.rel_rms,
            max_abs: m.max_abs,
            smape: m.smape,
            negative_fraction: m.negative_fraction,
            mean_ratio: m.mean_ratio,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpecularMetrics {
    #[serde(flatten)]
    pub metrics: MetricsJson,
    /// The exact GGX integral of the mode's reconstructed radiance against the reference.
    pub basis_limited_rms: Option<f64>,
    /// The runtime path against that integral.
    pub runtime_rms: Option<f64>,
    /// Prefiltered maps: the exact split sum (the map prefiltered at α without a map's
    /// limits, times the DFG terms) against the reference.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split_sum_rms: Option<f64>,
    /// Prefiltered maps: the mode against the exact split sum (resolution, mip
    /// interpolation, storage).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map_rms: Option<f64>,
}

/// Calibration keys of a mode's irradiance and specular evaluators.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostKeys {
    pub irradiance: String,
    /// Absent without a specular path or without the specular signal in the run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular: Option<String>,
}

/// The cost axes of one mode, each measured the same way for every mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cost {
    /// What the encoder reads: `radiance map` or `irradiance reference`.
    pub encode_input: String,
    /// Median encode time from that input, seconds.
    pub encode_s: f64,
    /// Runs timed for that median (`--repeats`, fewer once the runs took 0.1 s).
    #[serde(default)]
    pub encode_runs: usize,
    /// `encode_total_s` of the fastest and the slowest run.
    #[serde(default)]
    pub encode_total_range_s: [f64; 2],
    /// Encode time from the radiance map: `encode_s` plus, for modes that fit the
    /// irradiance reference, the time it took to make it.
    pub encode_total_s: f64,
    /// Steady-state CPU cost of the irradiance runtime evaluation.
    pub eval: CostStat,
    /// Steady-state CPU cost of the specular runtime path (modes that have one; absent
    /// without specular).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular_eval: Option<CostStat>,
    /// Bytes per probe/texel as stored (`storage_precision`; BC1 halves a byte).
    pub storage_bytes: f64,
    pub storage_precision: String,
    /// GPU cost of the mode's WGSL runtime (`--gpu-cost`; None without it or without a
    /// WGSL runtime for the mode).
    pub gpu: Option<crate::gpu_cost::GpuCost>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeImages {
    pub irradiance: ImagePair,
    /// |approximation − reference| at 4 EV more.
    pub irradiance_error_png: String,
    pub radiance: Option<ImagePair>,
    /// Per α: the specular image and its error PNG (absent without specular).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub specular: BTreeMap<String, SpecularImages>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpecularImages {
    #[serde(flatten)]
    pub image: ImagePair,
    pub error_png: String,
}

/// The key of roughness α in the per-α maps (as `{α}` prints: `0.1`, `0.25`).
pub fn alpha_key(alpha: f64) -> String {
    format!("{alpha}")
}

fn pair(folder: &str, stem: &str, exr: bool) -> ImagePair {
    ImagePair { png: format!("{folder}/{stem}.png"), exr: exr.then(|| format!("{folder}/{stem}.exr")) }
}

/// The results of one map, its decision section empty ([`crate::decide::decide`] fills it).
pub fn from_report(m: &MapReport, exr: bool, gpu: Option<&crate::gpu_cost::GpuCosts>) -> MapResults {
    let f = &m.slug;
    let modes = m
        .rows
        .iter()
        .map(|r| {
            let x = &r.result;
            let specular = r
                .specular
                .iter()
                .map(|(a, mm)| {
                    let parts = r.specular_parts.iter().find(|p| p.0 == *a);
                    let split = r.split_sum_parts.iter().find(|p| p.0 == *a);
                    (
                        alpha_key(*a),
                        SpecularMetrics {
                            metrics: (*mm).into(),
                            basis_limited_rms: parts.map(|p| p.1),
                            runtime_rms: parts.map(|p| p.2),
                            split_sum_rms: split.map(|p| p.1),
                            map_rms: split.map(|p| p.2),
                        },
                    )
                })
                .collect();
            ModeRecord {
                id: x.id.to_string(),
                name: x.name.to_string(),
                basis: x.basis.clone(),
                solver: x.solver.to_string(),
                coefficient_count: x.coefficients.len(),
                coefficients: x.coefficients.clone(),
                lobes: x.lobes.iter().map(|(a, l)| Lobe { axis: [a.x, a.y, a.z], sharpness: *l }).collect(),
                metrics: ModeMetrics { radiance: r.radiance.map(Into::into), irradiance: r.irradiance.into(), specular },
                cost: Cost {
                    encode_input: if x.needs_reference { "irradiance reference" } else { "radiance map" }.into(),
                    encode_s: x.encode_s,
                    encode_runs: x.encode_runs,
                    encode_total_range_s: x.encode_range_s.map(|e| e + (x.encode_total_s(m.stages.reference_irradiance) - x.encode_s)),
                    encode_total_s: x.encode_total_s(m.stages.reference_irradiance),
                    eval: x.eval,
                    specular_eval: r.specular_cost,
                    storage_bytes: x.storage_bytes(),
                    storage_precision: x.storage_precision(),
                    gpu: gpu.filter(|_| x.wgsl_irradiance).and_then(|g| g.for_mode(x.id, m.runtime)),
                },
                cost_keys: CostKeys {
                    irradiance: crate::calibration::irradiance_key(x.id, x.irradiance_variant),
                    specular: crate::calibration::specular_key(x.id, m.runtime).filter(|_| !m.specular_reference.is_empty()),
                },
                convergence: x.convergence.clone(),
                images: ModeImages {
                    irradiance: pair(f, &format!("{}_irradiance", x.id), exr),
                    irradiance_error_png: format!("{f}/{}_irradiance_error.png", x.id),
                    radiance: x.radiance.as_ref().map(|_| pair(f, &format!("{}_radiance", x.id), exr)),
                    specular: r
                        .specular
                        .iter()
                        .map(|(a, _)| {
                            let st = format!("{}_{}", x.id, specular_stem(*a));
                            (alpha_key(*a), SpecularImages { image: pair(f, &st, exr), error_png: format!("{f}/{st}_error.png") })
                        })
                        .collect(),
                },
            }
        })
        .collect::<Vec<_>>();
    MapResults {
        map: MapInfo { path: m.path.clone(), width: m.width, height: m.height, sanitized_texels: m.sanitized, folder: f.clone() },
        domain: m.domain.to_string(),
        storage: m.storage.describe().to_string(),
        reference: ReferenceInfo {
            convention: m.convention.name().to_string(),
            method: m.reference_method.clone(),
            specular_method: m.specular_method.clone(),
            specular_error: m
                .specular_reference
                .iter()
                .map(|r| {
                    (alpha_key(r.alpha), ReferenceError { rms: r.error_rms, signal_rms: r.signal_rms, texels_checked: r.texels_checked })
                })
                .collect(),
            irradiance_seconds: m.stages.reference_irradiance,
            images: ReferenceImages {
                irradiance: pair(f, "reference_irradiance", exr),
                specular: m
                    .specular_reference
                    .iter()
                    .map(|r| (alpha_key(r.alpha), pair(f, &format!("reference_{}", specular_stem(r.alpha)), exr)))
                    .collect(),
            },
        },
        specular_runtime: m.specular_runtime.clone(),
        profile: String::new(),
        usable_error_percent: USABLE_ERROR_PERCENT,
        stage_seconds: m.stages,
        modes,
        decision: Default::default(),
    }
}

/// `results.json` text for several maps.
pub fn to_json(maps: &[MapResults]) -> String {
    serde_json::to_string_pretty(maps).expect("results serialise") + "\n"
}

/// Reads `results.json` text.
pub fn from_json(text: &str) -> Result<Vec<MapResults>, String> {
    serde_json::from_str(text).map_err(|e| format!("results.json: {e}"))
}

// The decision section's records ([`crate::decide`] computes them from the rest; they hold
// no measured time, only mode ids, errors, storage and cost tiers, so repeated runs write
// them byte for byte the same).

/// Every signal's decision for one map.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Decision {
    pub signals: Vec<SignalDecision>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SignalDecision {
    /// `irradiance`, or `specular α=<α>`.
    pub signal: String,
    /// The mode to use when nothing else is known ([`crate::decide`]); `None` without
    /// candidates.
    pub recommended: Option<Recommendation>,
    /// Whether the recommended mode's error is within [`MapResults::usable_error_percent`]:
    /// false when no candidate is (the recommendation is then the best the comparison
    /// has, not a mode to ship).
    #[serde(default = "usable_default")]
    pub usable: bool,
    /// Where the CPU costs the decision compares come from: the committed calibration
    /// (reproducible), or this run's measurement where the calibration lacks a mode.
    pub cpu_costs: String,
    /// Per timed axis, the candidates grouped into cost tiers (cheapest first): modes in one
    /// tier cost the same within the measurement's spread.
    pub tiers: Vec<Tiers>,
    /// One front per cost axis.
    pub fronts: Vec<Front>,
    pub budget: Budget,
}

/// The cost axes decisions use; `gpu_ns` only where the run measured GPU costs
/// (`--gpu-cost`), over the modes that have a WGSL runtime. (Encode times, which depend on
/// the map, are reported as measured and decide nothing.)
pub const AXES: [&str; 3] = ["storage_bytes", "eval_ns", "gpu_ns"];

/// The recommendation of one signal and the front point just cheaper than it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Recommendation {
    #[serde(flatten)]
    pub mode: Point,
    pub next_cheaper: Option<Point>,
}

/// The cost tiers of one timed axis: `tiers[k]` are the ids of tier k + 1, by id.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tiers {
    /// One of [`AXES`] (not `storage_bytes`, which is exact).
    pub axis: String,
    pub tiers: Vec<Vec<String>>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Front {
    /// One of [`AXES`].
    pub axis: String,
    /// The front, by increasing cost (and so decreasing error): at most one mode per tier.
    pub points: Vec<Point>,
}

/// A mode in a decision: its error (RMS, and as % of the reference signal's RMS), its
/// storage and its CPU cost tier.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Point {
    pub id: String,
    pub error: f64,
    pub error_percent: f64,
    pub bytes: f64,
    /// CPU cost tier (1 = cheapest), see [`Tiers`].
    pub cpu_tier: usize,
}

/// Best mode (lowest RMS) within each budget of storage and CPU cost tier.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Budget {
    /// Storage budgets (rows): the distinct storage sizes of the candidates, bytes.
    pub bytes: Vec<f64>,
    /// CPU budgets (columns): "costs no more than tier k" (1 = cheapest); a tier that
    /// changes no cell of the table is left out; the last column is every tier.
    pub cpu_tiers: Vec<usize>,
    /// `best[row][column]`: the winning mode, if any mode fits.
    pub best: Vec<Vec<Option<Point>>>,
}
