//! What a bake is given ([`Options`]: the [`BakeSpec`] — what is baked: the scene, the
//! layout, the passes, the settings, the post-processing — and the [`RunOptions`] — where
//! and how it runs) and what it reports back ([`Summary`]).

use crate::accumulate::{BakeConfig, BakeState, BasisId};
use std::path::PathBuf;

/// Which engine traces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Device {
    /// A hardware GPU adapter if one exists, else the CPU path (a software rasteriser
    /// such as lavapipe/llvmpipe is slower than the CPU path: used only with `Gpu`).
    Auto,
    Gpu,
    Cpu,
}

/// Everything a bake needs: what it bakes and how it runs.
#[derive(Debug, Clone, Default)]
pub struct Options {
    pub spec: BakeSpec,
    pub run: RunOptions,
}

/// What is baked: the scene, the layout, the passes, the bake settings, the probes and
/// what is written. Its canonical serialisation ([`BakeSpec::canonical`]) is the bake's
/// record: `spec` in bake.json, `spec.json` in the output folder (what `baker resume`
/// continues), the header of every shard (what `baker merge` rebuilds the bake from); the
/// checkpoint fingerprint hashes its `config` part. Nothing in it says where or how the
/// bake runs ([`RunOptions`]), so shards baked on different machines and devices merge.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakeSpec {
    /// A built-in scene's name ([`crate::scene::load::BUILTIN`]; "cornell" by default) or a
    /// .gltf/.glb path (absolute when it came from the command line).
    pub scene: String,
    /// A lat-long .hdr/.exr environment replacing the scene's.
    pub environment: Option<PathBuf>,
    /// Sample the materials' texture maps (true) or bake their factors alone
    /// (false: `--material-maps factors`).
    pub material_maps: bool,
    pub texels_per_unit: f32,
    pub padding: usize,
    pub passes: u64,
    /// The bake settings (seed, bounces, bases, solver, strategies). Its `pipeline` is not
    /// part of the spec (not serialised; [`RunOptions::pipeline`] sets it).
    pub config: BakeConfig,
    /// Probe grid (nx, ny, nz) inside the scene bounds, baked into `probe_bases`.
    pub probes: Option<[usize; 3]>,
    /// Move probes found inside geometry out through the nearest back face before baking.
    pub relocate_probes: bool,
    pub probe_bases: Vec<BasisId>,
    pub preview_width: usize,
    /// The lighting profile the bases came from (`--profile`): its BRDF set decides whether
    /// the specular runtime (features, LUTs) is written, its language the exported runtime;
    /// recorded as its TOML text.
    pub profile: Option<sbf::profile::Profile>,
    /// Joint NLM denoising of every written coefficient set before dilation
    /// ([`crate::post::denoise`]); None: off.
    pub denoise: Option<crate::post::denoise::DenoiseOptions>,
    /// Least-squares seam stitching after the denoiser, before dilation ([`crate::post::seams`]).
    /// The seam metric is reported either way.
    pub stitch_seams: bool,
    /// The directional formats engines ship to write beside the bases
    /// (`--engine-formats`, [`crate::output::engine`]; needs the `sh1` basis).
    pub engine_formats: Vec<sbf::recon::engine::EngineFormat>,
    /// Every engine format's directions in this frame instead of its engine's
    /// (`--engine-frame gltf`; None: each engine's own, [`sbf::recon::engine::EngineFormat::frame`]).
    pub engine_frame: Option<sbf::recon::engine::EngineFrame>,
    /// Also write every lightmap image as BC6H DDS (`--compress bc6h`,
    /// [`crate::output::compress`]).
    pub compress_bc6h: bool,
    /// How signed images are compressed: BC6H_SF16 (`--compress bc6h`) or UF16 with an
    /// offset (`--compress bc6h-offset`).
    pub compress_signed: crate::output::compress::SignedStorage,
}

impl BakeSpec {
    /// The canonical serialisation: compact JSON, fields in declaration order, floats in
    /// their shortest round-trip form — equal specs give equal bytes.
    pub fn canonical(&self) -> String {
        serde_json::to_string(self).expect("a bake spec serialises")
    }

    /// Reads a spec back from its serialisation (errors name the field at fault).
    pub fn from_json(text: &[u8]) -> Result<BakeSpec, String> {
        serde_json::from_slice(text).map_err(|e| format!("bake spec: {e}"))
    }

    /// The fields of `self` and `other` that differ, as "name: A vs B" (nested fields
    /// dotted, e.g. `config.bases`), sorted by name; `passes` left out where `with_passes`
    /// is false.
    pub fn differences(&self, other: &BakeSpec, with_passes: bool) -> Vec<String> {
        let (a, b) = (serde_json::to_value(self).expect("json"), serde_json::to_value(other).expect("json"));
        let mut out = Vec::new();
        differences(&a, &b, "", &mut out);
        out.retain(|d| with_passes || !d.starts_with("passes:"));
        out
    }
}

/// The file in a bake's output folder that records its spec (what `baker resume` reads).
pub const SPEC_FILE: &str = "spec.json";

/// The spec recorded in the output folder `out`.
pub fn read_spec(out: &std::path::Path) -> Result<BakeSpec, String> {
    let path = out.join(SPEC_FILE);
    let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e} (no bake was started in {})", path.display(), out.display()))?;
    BakeSpec::from_json(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Records `spec` in the output folder `out` (atomically; shards of one bake write the
/// same bytes). With `resume`, first refuses a folder that records another bake.
pub(crate) fn record_spec(spec: &BakeSpec, out: &std::path::Path, resume: bool) -> Result<(), String> {
    if resume && out.join(SPEC_FILE).exists() {
        let recorded = read_spec(out)?;
        let diff = recorded.differences(spec, false);
        if !diff.is_empty() {
            return Err(format!(
                "--resume: the checkpoints in {} belong to a different bake ({}; {SPEC_FILE} vs the arguments): give the same arguments, or continue that bake with `baker resume --out {}`",
                out.display(),
                diff.join("; "),
                out.display()
            ));
        }
    }
    let json = serde_json::to_string_pretty(spec).expect("a bake spec serialises");
    crate::checkpoint::write_atomic(&out.join(SPEC_FILE), json.as_bytes())
}

/// The leaves of `a` and `b` that differ, dotted from `path`.
fn differences(a: &serde_json::Value, b: &serde_json::Value, path: &str, out: &mut Vec<String>) {
    match (a, b) {
        (serde_json::Value::Object(x), serde_json::Value::Object(y)) => {
            for (k, v) in x {
                let p = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
                differences(v, y.get(k).unwrap_or(&serde_json::Value::Null), &p, out);
            }
        }
        _ if a != b => out.push(format!("{path}: {a} vs {b}")),
        _ => {}
    }
}

/// How a bake runs: where it writes, on which engine, with what checkpoints, logging and
/// sharding. None of it changes what is baked.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub device: Device,
    pub out: PathBuf,
    /// Passes between checkpoints (0: none).
    pub checkpoint_every: u64,
    pub resume: bool,
    /// No progress bar.
    pub quiet: bool,
    /// Log what each stage left out, one line each (otherwise a count per stage).
    pub verbose: bool,
    /// Instead of baking: measure GPU rays/s over this many passes and print them.
    pub measure_rays: Option<u64>,
    /// GPU: target seconds per dispatch (frame-time load balancing, [Roughton19 §3.4.1]); None:
    /// one dispatch per pass.
    pub batch_seconds: Option<f64>,
    /// GPUs to bake on (hardware adapters, one thread and queue each; [`crate::gpu::multi`]).
    /// 1: the best adapter.
    pub gpus: usize,
    /// Bake on the adapter at this index of the host ([`shaders::gpu::Gpu::at`]: hardware
    /// adapters first, in `--gpus`' order): a farm pins a shard to the GPU it assigned.
    pub gpu_index: Option<usize>,
    /// GPU: the most bytes one storage binding may take (None: the adapter's limit). Bases
    /// whose encoder states exceed it are baked in groups (`run/engine.rs`).
    pub max_binding: Option<u64>,
    /// How a GPU bake runs its passes (the same bake either way).
    pub pipeline: crate::accumulate::Pipeline,
    /// Bake only shard I of N (`--shard I/N`) and write its partial state for
    /// `baker merge` instead of the outputs ([`crate::checkpoint::shard`]).
    pub shard: Option<ShardSpec>,
}

/// One shard of a bake spread over machines: shard `index` of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShardSpec {
    pub index: usize,
    pub count: usize,
}

impl ShardSpec {
    /// `--shard I/N` (0 ≤ I < N).
    pub fn parse(s: &str) -> Result<ShardSpec, String> {
        let bad = || format!("--shard takes I/N (shard I of N, 0 ≤ I < N), not '{s}'");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(ShardSpec { index, count })
    }
}

impl Default for BakeSpec {
    fn default() -> Self {
        BakeSpec {
            scene: "cornell".into(),
            environment: None,
            material_maps: true,
            texels_per_unit: 16.0,
            padding: 2,
            passes: 128,
            config: BakeConfig::default(),
            probes: Some([3, 3, 3]),
            relocate_probes: false,
            probe_bases: vec![BasisId::Sh2, BasisId::Ad12],
            preview_width: 480,
            profile: None,
            // The CLI's defaults for 128 passes (`--denoise auto`, `--stitch-seams auto`).
            denoise: Some(crate::post::denoise::DenoiseOptions::default()),
            stitch_seams: true,
            engine_formats: Vec::new(),
            engine_frame: None,
            compress_bc6h: false,
            compress_signed: crate::output::compress::SignedStorage::Sf16,
        }
    }
}

impl RunOptions {
    /// `--gpu-index` as given, else the environment's `SBF_GPU_INDEX` (how a farm's worker
    /// passes its GPU to every shard it runs), else None.
    pub fn gpu_index_or_env(given: Option<usize>) -> Result<Option<usize>, String> {
        match (given, std::env::var("SBF_GPU_INDEX")) {
            (Some(i), _) => Ok(Some(i)),
            (None, Ok(v)) => v.trim().parse().map(Some).map_err(|_| format!("SBF_GPU_INDEX={v}: expected an adapter index (0, 1, …)")),
            (None, Err(_)) => Ok(None),
        }
    }
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            device: Device::Auto,
            out: PathBuf::from("bake-out"),
            checkpoint_every: 32,
            resume: false,
            quiet: false,
            verbose: false,
            measure_rays: None,
            batch_seconds: Some(crate::gpu::BATCH_TARGET_SECONDS),
            gpus: 1,
            gpu_index: None,
            max_binding: None,
            pipeline: Default::default(),
            shard: None,
        }
    }
}

/// What a bake produced.
#[derive(Debug, Clone)]
pub struct Summary {
    pub device: String,
    pub lightmap: BakeState,
    pub probes: Option<BakeState>,
    /// Passes run by this invocation (the rest came from a checkpoint).
    pub passes_run: u64,
    pub seconds: f64,
}
