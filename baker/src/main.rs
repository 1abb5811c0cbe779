//! baker: bake lightmaps and light probes into sbf bases, on the GPU or the CPU.

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

use baker::accumulate::{BasisId, Solver};
use baker::run::{self, Device, Options};
use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;

/// An optional stage: `auto` lets the measurements decide (see each option).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Toggle {
    Auto,
    On,
    Off,
}

/// `--denoise auto` denoises bakes of at most this many passes: the largest pass count at
/// which the denoiser lowered the error of E/π *and* of the SH coefficients on both measured
/// scenes (docs/baker.md, "Denoiser": H200, one 65 536-pass reference per scene; built-in
/// scene E/π 2.0× lower at 128 passes, the glTF room 1.3×). At 512 passes the room's SH
/// coefficients came out 3 % worse while its E/π still improved 1.2×.
const DENOISE_AUTO_MAX_PASSES: u64 = 128;

/// How a bake runs — where it writes, on which engine, with what checkpoints and logging,
/// which shard — never what it bakes: `baker` and `baker resume` take the same ones.
#[derive(clap::Args, Debug)]
struct RunArgs {
    /// auto (a hardware GPU if one exists, else the CPU path), gpu (any adapter, software
    /// rasterisers such as lavapipe included), or cpu.
    #[arg(long, default_value = "auto")]
    device: String,
    /// How the GPU runs a pass: megakernel (one thread per texel through whole paths) or
    /// wavefront (generate, then per bounce intersect, shade and compact the active paths,
    /// then accumulate). The same bake either way; which is faster depends on the scene
    /// (docs/baker.md).
    #[arg(long, default_value = "megakernel")]
    pipeline: String,
    /// Output folder.
    #[arg(long, default_value = "bake-out")]
    out: PathBuf,
    /// GPU: use at most this many bytes per storage binding (default: the adapter's limit);
    /// bases whose encoder states exceed it are baked in groups over the same paths.
    #[arg(long)]
    max_storage_binding: Option<u64>,
    /// Passes between checkpoints (0: none).
    #[arg(long, default_value_t = 32)]
    checkpoint_every: u64,
    /// GPU: target milliseconds per dispatch — a pass over a large atlas is split into
    /// dispatches of about this length (the size follows the measured time), far below
    /// driver watchdogs; 0: one dispatch per pass.
    #[arg(long, default_value_t = 16.0)]
    batch_ms: f64,
    /// Bake on this many GPUs of this host (hardware adapters; the texels and probes are
    /// dealt out in blocks of consecutive items, block b to GPU b mod N, and the results
    /// merged into exactly the one-GPU bake). Not with --guiding, --filter, --adaptive or
    /// --camera (each needs the whole atlas every pass).
    #[arg(long, default_value_t = 1)]
    gpus: usize,
    /// Bake on the host's GPU at this index (hardware adapters first, in --gpus' order; an
    /// out-of-range index lists them) instead of the best one: a farm pins a shard to the GPU
    /// its scheduler assigned. Default: the environment's SBF_GPU_INDEX, if set.
    #[arg(long)]
    gpu_index: Option<usize>,
    /// Bake only shard I of N (0 ≤ I < N) of this bake — the blocks of texels and probes
    /// dealt to it, as --gpus deals them to GPUs — and write its partial state to
    /// OUT/shard-I-of-N.sbfshard (plus a record of the run) instead of the outputs; `baker
    /// merge OUT SHARD…` puts the N shards together into exactly the single bake's outputs.
    /// Same bytes on a re-run; with --resume a retried shard continues from its checkpoint.
    /// Not with --guiding, --filter, --adaptive or --camera.
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    /// Also log what each stage left out (e.g. the GPU kernel's unused features) and the
    /// wavefront pass graph.
    #[arg(short, long)]
    verbose: bool,
    /// Exit (status 1, with a message) as soon as the process that started this one ends
    /// (Unix: checked every 0.5 s), so a bake started by a farm's worker does not outlive
    /// a killed worker and race its retry (the Dask driver passes it).
    #[arg(long)]
    exit_with_parent: bool,
}

#[derive(Parser, Debug)]
#[command(
    version,
    about = "Bake lightmaps and light probes into spherical bases (SH, SG, Ambient Dice), progressively, on the GPU (wgpu) or the CPU.",
    after_help = "With no arguments, bakes the built-in Cornell-style scene into ./bake-out/.\n\nExamples:\n  baker\n  baker --scene room.glb --bases sh2,ad12 --passes 512\n  baker --device cpu --passes 64 --out quick\n  baker resume --passes 512 (continues the bake in ./bake-out from its checkpoints and recorded spec)\n  baker --shard 0/4 --out shards; … --shard 3/4 --out shards; baker merge bake-out shards/*.sbfshard"
)]
struct Cli {
    #[arg(long, default_value = "cornell", help = baker::scene::load::SCENE_HELP)]
    scene: String,
    /// Lat-long .hdr/.exr environment map replacing the scene's environment.
    #[arg(long)]
    env: Option<PathBuf>,
    /// glTF materials' texture maps (base colour, metallic-roughness, emissive): `sample`
    /// them at every path vertex (the CPU and GPU bakes alike), or bake the materials'
    /// `factors` alone, the maps dropped (what `render --bake` shades).
    #[arg(long, default_value = "sample", value_parser = ["sample", "factors"])]
    material_maps: String,
    /// Also write the lightmap in the directional formats engines ship, repackaged from the
    /// SH L1 bake (needs `sh1` in --bases), each decoded as its engine does by default:
    /// comma-separated `godot-l1` (Godot ≥ 4.4 LightmapGI SH), `godot-l1-legacy` (Godot
    /// 4.0–4.3), `monosh` (Bakery MonoSH, its default non-linear decode), `monosh-linear`
    /// (non-linear mode off), `enlighten` (Unity's directional lightmaps), `enlighten-rgb`
    /// (a research layout no engine ships), or `all`. bake.json says what each loses at and
    /// off the baked normal and in storage.
    #[arg(long)]
    engine_formats: Option<String>,
    /// The frame of the engine formats' directions: `engine` (each engine's: glTF's axes for
    /// Godot, x negated for Unity and Bakery, as Unity's glTF importers flip the scene) or
    /// `gltf` (the scene's own axes for every format).
    #[arg(long, default_value = "engine", value_parser = ["engine", "gltf"])]
    engine_frame: String,
    /// Also write every lightmap image (E/π and each basis lobe) as a BC6H DDS file and its
    /// KTX2 twin (1 byte per texel); bake.json gives the error it adds per image and per
    /// basis (E/π at the texel normal), next to f16's. `bc6h`: signed images (SH lobes,
    /// probe coefficients) as BC6H_SF16, which any reader decodes to the values;
    /// `bc6h-offset`: as BC6H_UF16 shifted by a per-channel offset that bake.json and the
    /// KTX2 carry and the runtime subtracts (less error where a lobe changes sign).
    #[arg(long, value_parser = ["bc6h", "bc6h-offset"])]
    compress: Option<String>,
    /// Lightmap texels per scene unit.
    #[arg(long, default_value_t = 16.0)]
    texels_per_unit: f32,
    /// Texels of padding around each chart (also the dilation rings, + 1).
    #[arg(long, default_value_t = 2)]
    padding: usize,
    /// Passes (one path per texel and probe each).
    #[arg(long, default_value_t = 128)]
    passes: u64,
    /// First-bounce ray guiding of lightmap texels: learn a directional
    /// distribution per 8×8-texel cluster from the first passes, then draw half of the
    /// point samples from it (mixture pdf, unbiased).
    #[arg(long)]
    guiding: bool,
    /// Learning passes of --guiding (default: 1/16 of --passes, 4 to 32); the learned
    /// distributions are rebuilt at this pass count, twice it, four times, …
    #[arg(long)]
    guiding_learn: Option<u64>,
    /// Adaptive sampling of lightmap texels: after --adaptive-pilot
    /// uniform passes, batches whose texels join with probability from their 8×8 tile's
    /// noise (σ); the batches spend about the paths of --passes uniform passes. Not with
    /// --guiding or several GPUs; probes stay uniform.
    #[arg(long)]
    adaptive: bool,
    /// Uniform passes before adapting (with --adaptive).
    #[arg(long, default_value_t = 8)]
    adaptive_pilot: u64,
    /// Expected paths per batch as a fraction of the texels, (0, 8] (with --adaptive; 1: a
    /// batch costs about a pass): a texel takes at most 8 samples per batch.
    #[arg(long, default_value_t = 1.0)]
    adaptive_fraction: f64,
    /// The most samples a texel takes per batch (with --adaptive; one GPU thread takes
    /// them in order, so this bounds a batch's longest thread), 1 to 64.
    #[arg(long, default_value_t = 8)]
    adaptive_max: u32,
    /// Camera-based sampling: after one uniform pass, each batch traces
    /// one path per pixel of this view (jittered), so the texels it sees converge first
    /// and the rest keep their first pass; the preview uses the same view.
    /// EYE:TARGET[:FOV] in scene units and degrees (vertical), e.g. 0,1,2.5:0,1,0:60.
    /// The image has about as many pixels as the atlas has texels (4:3). Not with
    /// --adaptive, --guiding or several GPUs.
    #[arg(long)]
    camera: Option<String>,
    /// Denoise the lightmap (joint non-local means within charts, guided by position and
    /// normal; the same weights for irradiance and every coefficient) before dilation.
    /// `auto`: on up to 128 passes, where it was measured to lower the error of E/π and of
    /// the coefficients on the built-in scene and a glTF room (E/π 2.0× and 1.3× lower),
    /// off above (from 512 passes the room's coefficients got worse; docs/baker.md).
    /// `--denoise` alone means `on`.
    #[arg(long, value_enum, num_args = 0..=1, default_value = "auto", default_missing_value = "on")]
    denoise: Toggle,
    /// Denoiser window radius in texels (with --denoise).
    #[arg(long, default_value_t = 5)]
    denoise_radius: usize,
    /// Stitch UV seams (least squares on the bilinear lookups across every seam edge) after
    /// the denoiser, before dilation; the seam metric is reported either way. `auto` (=
    /// `on`): wherever the scene has seams (measured: the mixed-lighting glTF's seam metric
    /// 42.6 → 0.90 against a texel noise of 33.6). `--stitch-seams` alone means `on`.
    #[arg(long, value_enum, num_args = 0..=1, default_value = "auto", default_missing_value = "on")]
    stitch_seams: Toggle,
    /// Maximum bounces per path.
    #[arg(long, default_value_t = 4)]
    bounces: u32,
    /// Lightmap bases: sh1, sh2, sg9, sg12, ad9, ad12, zh3 (SH L1's coefficients, read with ZH3's reconstruction) (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "sh2,ad9")]
    bases: Vec<String>,
    /// A lighting profile (TOML, see profiles/): lightmap and probe bases from it (no probes
    /// if it names none), the specular runtime only if its BRDF set has GGX, the runtime
    /// exported in its language too; recorded in bake.json. Replaces --bases/--probe-bases.
    #[arg(long, conflicts_with_all = ["bases", "probe_bases"])]
    profile: Option<PathBuf>,
    /// Sharpness λ of the SG lobes (sg9, sg12), in [2, 64]; recorded in bake.json.
    /// Roughton's comparisons use 6 for the hemisphere sets and 8 for NNLS SG 12 ([Roughton19 §8.4.3]).
    #[arg(long, default_value_t = baker::accumulate::SG_HEMISPHERE_SHARPNESS)]
    sg_sharpness: f64,
    /// Bake indirect light only: the light reaching a texel straight from an emitter, a
    /// delta light or the sky is left out (an engine adds it at run time); recorded in
    /// bake.json. The thesis' Fig. 8.6 compares bases on indirect light.
    #[arg(long)]
    indirect_only: bool,
    /// Progressive solver: nnls-rescaled, nnls, ls or nnls-irradiance. NNLS applies to the
    /// non-negative bases (SG, Ambient Dice); SH is always least squares (its coefficients are
    /// legitimately negative). Plain NNLS of a small source keeps up to ~1.8× its irradiance,
    /// so by default (nnls-rescaled) the lightmap's SG/AD lobes are scaled per texel so that
    /// their E/π at the normal is the texel's (the light the bake measured).
    /// nnls-irradiance: SG/AD baked by least squares, then refitted per texel as NNLS with
    /// their E/π at the normal pinned. Probes: NNLS.
    #[arg(long, default_value = "nnls-rescaled")]
    solver: String,
    /// Seed of every random number of the bake (the same seed gives the same bake, on
    /// any thread count).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Sample sequences: sobol (shuffled, Owen-scrambled Sobol' points per path vertex:
    /// lower error at equal passes) or independent (white noise, for comparison).
    #[arg(long, default_value = "sobol")]
    sampler: String,
    /// Filtered gather-based accumulation: box, gaussian or mitchell,
    /// optionally :radius in texels (default 1.5). Every texel a chart's triangles
    /// overlap gathers the samples within the radius, so edge texels whose sub-positions
    /// all miss get values rather than dilation. Default: none (each sample feeds its own
    /// texel).
    #[arg(long)]
    filter: Option<String>,
    /// Continue from the checkpoints in the output folder. The other arguments must define
    /// the bake recorded there (OUT/spec.json; the fields that differ are named), --passes
    /// aside; `baker resume` continues it with no other argument.
    #[arg(long)]
    resume: bool,
    /// Probe grid NX,NY,NZ inside the scene bounds (0,0,0: no probes).
    #[arg(long, value_delimiter = ',', default_value = "3,3,3")]
    probes: Vec<usize>,
    /// Move probes that sit inside geometry out through the nearest back face (else they
    /// are only flagged "valid": false in probes.json).
    #[arg(long)]
    relocate_probes: bool,
    /// Probe bases (sphere bases: sh1, sh2, ad12, zh3).
    #[arg(long, value_delimiter = ',', default_value = "sh2,ad12")]
    probe_bases: Vec<String>,
    /// Preview image width in pixels (at least 8; 4:3).
    #[arg(long, default_value_t = 480)]
    preview_width: usize,
    /// Measure GPU rays/s (primary and secondary) over this many passes instead of
    /// baking (scene `dense` has a ≥ 1 M-triangle sphere).
    #[arg(long)]
    measure_rays: Option<u64>,
    // How the bake runs (the options `baker resume` takes too).
    #[command(flatten)]
    run: RunArgs,
}

fn parse_bases(v: &[String]) -> Result<Vec<BasisId>, String> {
    v.iter().map(|s| baker::accumulate::lightmap_basis(s.trim())).collect()
}

/// `--engine-formats`: the formats named (or every one for `all`); they are encoded from
/// the SH L1 bake, so `sh1` must be among the lightmap bases.
fn engine_formats(arg: Option<&str>, bases: &[BasisId]) -> Result<Vec<sbf::recon::engine::EngineFormat>, String> {
    use sbf::recon::engine::EngineFormat;
    let Some(arg) = arg else { return Ok(Vec::new()) };
    let ids: Vec<&str> = EngineFormat::ALL.iter().map(|f| f.id()).collect();
    let mut out = Vec::new();
    for part in arg.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        if part == "all" {
            out.extend(EngineFormat::ALL);
            continue;
        }
        let f = EngineFormat::ALL
            .into_iter()
            .find(|f| f.id() == part)
            .ok_or_else(|| format!("unknown engine format '{part}' (expected {} or all)", ids.join(", ")))?;
        out.push(f);
    }
    if out.is_empty() {
        return Err(format!("--engine-formats needs at least one of {} or all", ids.join(", ")));
    }
    let mut unique = Vec::new();
    for f in out {
        if !unique.contains(&f) {
            unique.push(f);
        }
    }
    if !bases.contains(&BasisId::Sh1) {
        return Err(format!(
            "--engine-formats repackages the SH L1 lightmap: add sh1 to the bases (they are {})",
            bases.iter().map(|b| b.name()).collect::<Vec<_>>().join(",")
        ));
    }
    Ok(unique)
}

fn options(c: Cli) -> Result<Options, String> {
    let run = run_options(&c.run, c.resume, c.measure_rays)?;
    Ok(Options { spec: spec(c)?, run })
}

/// How the bake runs, from the arguments `baker` and `baker resume` share.
fn run_options(r: &RunArgs, resume: bool, measure_rays: Option<u64>) -> Result<run::RunOptions, String> {
    let device = match r.device.as_str() {
        "auto" => Device::Auto,
        "gpu" => Device::Gpu,
        "cpu" => Device::Cpu,
        s => return Err(format!("unknown device '{s}' (auto, gpu or cpu)")),
    };
    if !(r.batch_ms.is_finite() && r.batch_ms >= 0.0) {
        return Err(format!("--batch-ms must be ≥ 0 (0: one dispatch per pass), not {}", r.batch_ms));
    }
    Ok(run::RunOptions {
        device,
        out: r.out.clone(),
        checkpoint_every: r.checkpoint_every,
        resume,
        quiet: false,
        verbose: r.verbose,
        measure_rays,
        batch_seconds: (r.batch_ms > 0.0).then_some(r.batch_ms * 1e-3),
        gpus: r.gpus,
        gpu_index: run::RunOptions::gpu_index_or_env(r.gpu_index)?,
        max_binding: r.max_storage_binding,
        pipeline: baker::accumulate::Pipeline::parse(&r.pipeline)
            .ok_or_else(|| format!("unknown --pipeline '{}': megakernel or wavefront", r.pipeline))?,
        shard: r.shard.as_deref().map(run::ShardSpec::parse).transpose()?,
    })
}

/// A file the spec names, absolute (so a merge or resume finds it from any folder); a
/// name that is not a file (a built-in scene) as given.
fn absolute(v: &str) -> String {
    match std::fs::canonicalize(v) {
        Ok(p) if std::path::Path::new(v).is_file() => p.to_string_lossy().into_owned(),
        _ => v.to_string(),
    }
}

/// What is baked, from the arguments.
fn spec(c: Cli) -> Result<run::BakeSpec, String> {
    let solver = match c.solver.as_str() {
        "ls" => Solver::Ls,
        "nnls" => Solver::Nnls,
        "nnls-irradiance" => Solver::NnlsIrradiance,
        "nnls-rescaled" => Solver::NnlsRescaled,
        s => return Err(format!("unknown solver '{s}' (ls, nnls, nnls-irradiance or nnls-rescaled)")),
    };
    let probes = match c.probes.as_slice() {
        [0, 0, 0] => None,
        [x, y, z] if *x > 0 && *y > 0 && *z > 0 => Some([*x, *y, *z]),
        p => return Err(format!("--probes takes NX,NY,NZ (all > 0, or 0,0,0 for none), not {p:?}")),
    };
    let profile = c.profile.as_deref().map(sbf::profile::Profile::load).transpose()?;
    let (bases, probe_bases) = match &profile {
        Some(p) => (p.lightmap_bases.clone(), p.probe_bases.clone()),
        None => (parse_bases(&c.bases)?, parse_bases(&c.probe_bases)?),
    };
    let probes = if profile.as_ref().is_some_and(|p| p.probe_bases.is_empty()) { None } else { probes };
    if let Some(p) = &profile {
        log_profile(p, &bases, &probe_bases);
    }
    if let Some(b) = probe_bases.iter().find(|b| !b.is_sphere()) {
        let sphere: Vec<&str> = BasisId::probe().map(BasisId::name).collect();
        return Err(format!("probe basis '{}' covers a hemisphere; probes need one of {}", b.name(), sphere.join(", ")));
    }
    if c.passes == 0 {
        return Err("--passes must be at least 1".into());
    }
    let (adaptive, guiding, camera) = strategies(&c)?;
    let engine_formats = engine_formats(c.engine_formats.as_deref(), &bases)?;
    Ok(run::BakeSpec {
        engine_formats,
        engine_frame: (c.engine_frame == "gltf").then_some(sbf::recon::engine::EngineFrame::Gltf),
        compress_bc6h: c.compress.is_some(),
        compress_signed: if c.compress.as_deref() == Some("bc6h-offset") {
            baker::output::compress::SignedStorage::Offset
        } else {
            baker::output::compress::SignedStorage::Sf16
        },
        scene: absolute(&c.scene),
        environment: c.env.as_deref().map(|e| PathBuf::from(absolute(&e.to_string_lossy()))),
        material_maps: c.material_maps == "sample",
        texels_per_unit: c.texels_per_unit,
        padding: c.padding,
        passes: c.passes,
        config: baker::accumulate::BakeConfig {
            seed: c.seed,
            max_bounces: c.bounces,
            bases,
            solver,
            guiding,
            sampler: baker::sampling::sequence::Sequence::parse(&c.sampler)
                .ok_or_else(|| format!("unknown --sampler '{}': sobol or independent", c.sampler))?,
            adaptive,
            camera,
            // How, not what: the run options' pipeline is the one a bake uses.
            pipeline: Default::default(),
            filter: c.filter.as_deref().map(baker::accumulate::filter::Filter::parse).transpose().map_err(|e| format!("--filter: {e}"))?,
            sg_sharpness: sg_sharpness(c.sg_sharpness)?,
            indirect_only: c.indirect_only,
        },
        probes,
        relocate_probes: c.relocate_probes,
        probe_bases,
        preview_width: c.preview_width,
        profile,
        denoise: match c.denoise {
            Toggle::On => true,
            Toggle::Off => false,
            Toggle::Auto => c.passes <= DENOISE_AUTO_MAX_PASSES,
        }
        .then_some(baker::post::denoise::DenoiseOptions { radius: c.denoise_radius, ..Default::default() }),
        stitch_seams: c.stitch_seams != Toggle::Off,
    })
}

/// The log line of a profile's bases against the defaults.
fn log_profile(p: &sbf::profile::Profile, bases: &[BasisId], probe_bases: &[BasisId]) {
    let d = run::BakeSpec::default();
    let names = |v: &[BasisId]| v.iter().map(|b| b.name()).collect::<Vec<_>>().join(",");
    eprintln!(
        "profile '{}': lightmap bases {} (default {}), probe bases {} (default {}){}",
        p.name,
        names(bases),
        names(&d.config.bases),
        if probe_bases.is_empty() { "none — no probes baked".to_string() } else { names(probe_bases) },
        names(&d.probe_bases),
        if p.specular { String::new() } else { "; BRDF Lambert only: no specular runtime features or LUTs".to_string() }
    );
}

/// `baker merge OUT SHARD…`.
#[derive(Parser, Debug)]
#[command(
    name = "baker merge",
    about = "Merge the N shard files of a bake (baker --shard I/N) into the outputs of the single bake: the same files, bit for bit.",
    after_help = "The scene, layout and settings come from the bake spec recorded in the shards; the files it names must be readable here. Refused, with the reason: shards of different bakes (the fields that differ named) or splits, a shard given twice, a missing shard, a scene that changed since."
)]
struct MergeCli {
    /// Output folder.
    out: PathBuf,
    /// The shard files (shard-I-of-N.sbfshard), all N of them, in any order.
    #[arg(required = true)]
    shards: Vec<PathBuf>,
}

fn merge_main(args: &[String]) -> ExitCode {
    let m = MergeCli::parse_from(std::iter::once("baker merge".to_string()).chain(args.iter().cloned()));
    match run::merge(&m.out, &m.shards, &mut |s| eprintln!("{s}")) {
        Ok(s) => {
            eprintln!("done: merged {} passes into {}", s.lightmap.passes, m.out.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("baker merge: {e}");
            ExitCode::from(2)
        }
    }
}

/// `baker resume [--passes M] [run options]`.
#[derive(Parser, Debug)]
#[command(
    name = "baker resume",
    about = "Continue the bake in the output folder from its checkpoints, with the bake spec it recorded (OUT/spec.json): no other argument needed.",
    after_help = "Examples:\n  baker resume                       (the bake in ./bake-out, to the passes it was started with)\n  baker resume --out big --passes 4096 --device gpu\n\nOnly --passes changes what is baked; the other options say how this run goes."
)]
struct ResumeCli {
    #[command(flatten)]
    run: RunArgs,
    /// Passes to reach (default: the recorded bake's). More than the checkpoints hold
    /// continues the bake; a checkpoint already past it is refused.
    #[arg(long)]
    passes: Option<u64>,
}

/// The options of `baker resume`: the recorded spec (with `--passes`), the run options
/// given.
fn resume_options(args: &[String]) -> Result<Options, String> {
    let r = ResumeCli::parse_from(std::iter::once("baker resume".to_string()).chain(args.iter().cloned()));
    let run = run_options(&r.run, true, None)?;
    let mut spec = run::read_spec(&run.out)?;
    if let Some(p) = r.passes {
        spec.passes = p;
    }
    if r.run.exit_with_parent {
        run::limits::exit_with_parent();
    }
    Ok(Options { spec, run })
}

/// The accumulation strategies the arguments ask for — adaptive sampling, ray guiding,
/// camera-based sampling — with the combinations a bake cannot run refused.
type Strategies = (
    Option<baker::accumulate::adaptive::AdaptiveOptions>,
    Option<baker::sampling::guiding::GuidingOptions>,
    Option<baker::accumulate::camera::CameraSampling>,
);

fn strategies(c: &Cli) -> Result<Strategies, String> {
    if c.guiding_learn.is_some() && !c.guiding {
        return Err("--guiding-learn needs --guiding".into());
    }
    if (c.adaptive_pilot != 8 || c.adaptive_fraction != 1.0 || c.adaptive_max != 8) && !c.adaptive {
        return Err("--adaptive-pilot, --adaptive-fraction and --adaptive-max need --adaptive".into());
    }
    let adaptive = if c.adaptive {
        if c.guiding {
            return Err("--adaptive and --guiding cannot be combined (guiding learns from whole passes)".into());
        }
        let a = baker::accumulate::adaptive::AdaptiveOptions {
            pilot_passes: c.adaptive_pilot,
            batch_fraction: c.adaptive_fraction,
            max_per_batch: c.adaptive_max,
            ..Default::default()
        };
        a.validate()?;
        Some(a)
    } else {
        None
    };
    let guiding = if c.guiding {
        let mut g = baker::sampling::guiding::GuidingOptions::for_passes(c.passes);
        if let Some(n) = c.guiding_learn {
            g.learn_passes = n;
        }
        g.validate()?;
        Some(g)
    } else {
        None
    };
    let camera = match &c.camera {
        Some(spec) => {
            if c.adaptive || c.guiding {
                return Err("--camera cannot be combined with --adaptive or --guiding".into());
            }
            // Image size 0 × 0: sized from the atlas once it is laid out.
            Some(baker::accumulate::camera::CameraSampling {
                camera: baker::scene::camera::ViewCamera::parse(spec, 0, 0)?,
                pilot_passes: 1,
                max_per_batch: 8,
            })
        }
        None => None,
    };
    Ok((adaptive, guiding, camera))
}

/// --sg-sharpness within the range the SG runtime's fits are stated over.
fn sg_sharpness(l: f64) -> Result<f64, String> {
    let (lo, hi) = baker::accumulate::SG_SHARPNESS_RANGE;
    if (lo..=hi).contains(&l) {
        Ok(l)
    } else {
        Err(format!("--sg-sharpness {l}: must be in [{lo}, {hi}] (the range the SG runtime's fits are stated over)"))
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    if args.get(1).map(String::as_str) == Some("merge") {
        return merge_main(&args[2..]);
    }
    // Every bound is checked here too (run::bake checks again for library callers), so a
    // bad argument exits with 2 before anything is loaded.
    let parsed = if args.get(1).map(String::as_str) == Some("resume") {
        resume_options(&args[2..])
    } else {
        let cli = Cli::parse();
        if cli.run.exit_with_parent {
            run::limits::exit_with_parent();
        }
        options(cli)
    };
    let o = match parsed.and_then(|o| o.validate().map(|_| o)) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("baker: {e}");
            return ExitCode::from(2);
        }
    };
    match run::bake(&o, &mut |s| eprintln!("{s}")) {
        Ok(s) => {
            let what = if o.run.shard.is_some() { "shard" } else { "bake" };
            eprintln!("done: {what} of {} passes in {:.1} s on {}", s.lightmap.passes, s.seconds, s.device);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("baker: {e}");
            ExitCode::FAILURE
        }
    }
}
