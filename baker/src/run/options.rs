//! What a bake is given ([`Options`]: the scene, the layout, the passes, the device, the
//! post-processing and where to write) and what it reports back ([`Summary`]).

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

/// Everything a bake needs.
#[derive(Debug, Clone)]
pub struct Options {
    /// A built-in scene's name ([`crate::scene::load::BUILTIN`]; "cornell" by default) or a
    /// .gltf/.glb path.
    pub scene: String,
    /// A lat-long .hdr/.exr environment replacing the scene's.
    pub environment: Option<PathBuf>,
    /// Sample the materials' texture maps (true; the CPU path) or bake their factors alone
    /// (false: `--material-maps factors`, which GPU bakes of textured scenes need).
    pub material_maps: bool,
    pub texels_per_unit: f32,
    pub padding: usize,
    pub passes: u64,
    pub config: BakeConfig,
    pub device: Device,
    pub out: PathBuf,
    /// Passes between checkpoints (0: none).
    pub checkpoint_every: u64,
    pub resume: bool,
    /// Probe grid (nx, ny, nz) inside the scene bounds, baked into `probe_bases`.
    pub probes: Option<[usize; 3]>,
    /// Move probes found inside geometry out through the nearest back face before baking.
    pub relocate_probes: bool,
    pub probe_bases: Vec<BasisId>,
    pub preview_width: usize,
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
    /// GPU: the most bytes one storage binding may take (None: the adapter's limit). Bases
    /// whose encoder states exceed it are baked in groups (`run/engine.rs`).
    pub max_binding: Option<u64>,
    /// The lighting profile the bases came from (`--profile`): its BRDF set decides whether
    /// the specular runtime (features, LUTs) is written, its language the exported runtime;
    /// it is recorded in bake.json.
    pub profile: Option<sbf::profile::Profile>,
    /// Joint NLM denoising of every written coefficient set before dilation
    /// ([`crate::post::denoise`]); None: off.
    pub denoise: Option<crate::post::denoise::DenoiseOptions>,
    /// Least-squares seam stitching after the denoiser, before dilation ([`crate::post::seams`]).
    /// The seam metric is reported either way.
    pub stitch_seams: bool,
    /// Bake only shard I of N (`--shard I/N`) and write its partial state for
    /// `baker merge` instead of the outputs ([`crate::checkpoint::shard`]).
    pub shard: Option<ShardSpec>,
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

/// One shard of a bake spread over machines.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShardSpec {
    pub index: usize,
    pub count: usize,
    /// The `baker` arguments that define the bake (recorded in the shard file, so `baker
    /// merge` can rebuild the scene, layout and outputs from them).
    pub recipe: Vec<String>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            scene: "cornell".into(),
            environment: None,
            material_maps: true,
            texels_per_unit: 16.0,
            padding: 2,
            passes: 128,
            config: BakeConfig::default(),
            device: Device::Auto,
            out: PathBuf::from("bake-out"),
            checkpoint_every: 32,
            resume: false,
            probes: Some([3, 3, 3]),
            relocate_probes: false,
            probe_bases: vec![BasisId::Sh2, BasisId::Ad12],
            preview_width: 480,
            measure_rays: None,
            batch_seconds: Some(crate::gpu::BATCH_TARGET_SECONDS),
            gpus: 1,
            max_binding: None,
            profile: None,
            quiet: false,
            verbose: false,
            // The CLI's defaults for 128 passes (`--denoise auto`, `--stitch-seams auto`).
            denoise: Some(crate::post::denoise::DenoiseOptions::default()),
            stitch_seams: true,
            shard: None,
            engine_formats: Vec::new(),
            engine_frame: None,
            compress_bc6h: false,
            compress_signed: crate::output::compress::SignedStorage::Sf16,
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
