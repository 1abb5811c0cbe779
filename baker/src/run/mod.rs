//! A whole bake as the `baker` command runs it: scene → BVH → layout → passes on the
//! GPU or the CPU (progress with ETA, a checkpoint every N passes, resume) → outputs.
//! Tests drive the same function ([`bake`]) to kill and resume bakes.

use crate::accumulate::{Bake, BakeConfig, BakeState, BasisKind, Solver, Targets};
use crate::checkpoint;
use crate::estimator::trace::Tracer;
use crate::gpu::multi::MultiGpuBake;
use crate::gpu::GpuBake;
use crate::layout::lightmap::Lightmap;
use crate::output;
use crate::post::images::LightmapImages;
use crate::scene::bvh::Bvh;
use crate::scene::Scene;
use sbf::glam::Vec3;
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

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
    /// "cornell" (default), "furnace", or a .gltf/.glb path.
    pub scene: String,
    /// A lat-long .hdr/.exr environment replacing the scene's.
    pub environment: Option<PathBuf>,
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
    pub probe_bases: Vec<BasisKind>,
    pub preview_width: usize,
    /// No progress bar.
    pub quiet: bool,
    /// Instead of baking: measure GPU rays/s over this many passes and print them.
    pub measure_rays: Option<u64>,
    /// GPU: target seconds per dispatch (frame-time load balancing, seed 004 §3.4.1); None:
    /// one dispatch per pass.
    pub batch_seconds: Option<f64>,
    /// GPUs to bake on (hardware adapters, one thread and queue each; [`crate::gpu::multi`]).
    /// 1: the best adapter.
    pub gpus: usize,
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
}

impl Default for Options {
    fn default() -> Self {
        Options {
            scene: "cornell".into(),
            environment: None,
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
            probe_bases: vec![BasisKind::ShL2, BasisKind::Ad12],
            preview_width: 480,
            measure_rays: None,
            batch_seconds: Some(crate::gpu::BATCH_TARGET_SECONDS),
            gpus: 1,
            profile: None,
            quiet: false,
            // The CLI's defaults for 128 passes (`--denoise auto`, `--stitch-seams auto`).
            denoise: Some(crate::post::denoise::DenoiseOptions::default()),
            stitch_seams: true,
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

enum Engine<'a> {
    Cpu(Box<Bake<'a>>),
    Gpu(Box<MultiGpuBake<'a>>),
}

impl Engine<'_> {
    fn run(&mut self, n: u64) -> Result<(), String> {
        match self {
            Engine::Cpu(b) => {
                for _ in 0..n {
                    b.pass();
                }
                Ok(())
            }
            Engine::Gpu(g) => g.run(n),
        }
    }
    fn state(&self) -> Result<BakeState, String> {
        match self {
            Engine::Cpu(b) => Ok(b.state.clone()),
            Engine::Gpu(g) => g.state(),
        }
    }
    fn passes(&self) -> u64 {
        match self {
            Engine::Cpu(b) => b.state.passes,
            Engine::Gpu(g) => g.passes(),
        }
    }
}

/// Runs passes on `targets` with progress, checkpoints and resume; returns the state.
#[allow(clippy::too_many_arguments)]
fn run_targets<'s>(
    o: &Options,
    config: &BakeConfig,
    gpus: &'s [shaders::gpu::Gpu],
    tracer_of: &dyn Fn() -> Tracer<'s>,
    scene: &Scene,
    targets: &Targets,
    what: &str,
    log: &mut dyn FnMut(String),
) -> Result<(BakeState, u64), String> {
    config.check(targets)?;
    let ckpt = o.out.join(format!("{what}.checkpoint"));
    let fp = checkpoint::content_fingerprint(scene, targets, config, what);
    let saved = if o.resume && ckpt.exists() {
        let bytes = std::fs::read(&ckpt).map_err(|e| format!("{}: {e}", ckpt.display()))?;
        let st = checkpoint::from_bytes(&bytes, fp, config, targets).map_err(|e| format!("{}: {e}", ckpt.display()))?;
        log(format!("{what}: resuming from {} at pass {}", ckpt.display(), st.passes));
        Some(st)
    } else {
        if o.resume {
            log(format!("{what}: --resume given but no checkpoint at {}; starting from pass 0", ckpt.display()));
        }
        None
    };
    let mut engine = match gpus {
        [] => match saved {
            Some(st) => Engine::Cpu(Box::new(Bake::resume(config.clone(), targets, tracer_of(), st)?)),
            None => Engine::Cpu(Box::new(Bake::new(config.clone(), targets, tracer_of()))),
        },
        gpus => {
            let mut b = MultiGpuBake::new(gpus, tracer_of, targets, config)?;
            match o.batch_seconds {
                Some(s) => b.set_batch_target(Some(s)),
                None => b.set_chunk(usize::MAX),
            }
            for l in &b.devices()[0].kernel.left_out {
                log(format!("{what}: left out of the GPU kernel: {l}"));
            }
            if gpus.len() > 1 {
                let shares: Vec<String> = b.devices().iter().map(|d| d.share().to_string()).collect();
                log(format!("{what}: items dealt to {} GPUs in blocks of {}: {} items each", gpus.len(), b.block(), shares.join(", ")));
            }
            if let Some(st) = &saved {
                b.upload(st)?;
            }
            Engine::Gpu(Box::new(b))
        }
    };
    // Adaptive bakes count pilot passes and batches (about the paths of o.passes passes).
    let total = config.adaptive.map_or(o.passes, |a| a.batches_for(o.passes));
    let unit = if config.adaptive.is_some() { "passes + batches" } else { "passes" };
    let start = engine.passes();
    let todo = total.saturating_sub(start);
    let bar = if o.quiet { indicatif::ProgressBar::hidden() } else { indicatif::ProgressBar::new(total) };
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!("{{msg}} [{{bar:30}}] {{pos}}/{{len}} {unit}, {{per_sec}}, ETA {{eta}}"))
            .expect("template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar.set_position(start);
    let chunk = if o.checkpoint_every > 0 { o.checkpoint_every } else { todo.max(1) };
    let mut run = 0;
    while engine.passes() < total {
        let n = chunk.min(total - engine.passes());
        // Progress granularity: at most 8 passes per call between bar updates.
        let mut left = n;
        while left > 0 {
            let k = left.min(8);
            engine.run(k)?;
            bar.inc(k);
            left -= k;
        }
        run += n;
        if o.checkpoint_every > 0 {
            let st = engine.state()?;
            checkpoint::write_atomic(&ckpt, &checkpoint::to_bytes(&st, fp))?;
        }
    }
    bar.finish_and_clear();
    Ok((engine.state()?, run))
}

pub use crate::layout::probes::probe_grid;

/// Runs a whole bake and writes its outputs (unless stopped early).
pub fn bake(o: &Options, log: &mut dyn FnMut(String)) -> Result<Summary, String> {
    let t0 = Instant::now();
    std::fs::create_dir_all(&o.out).map_err(|e| format!("{}: {e}", o.out.display()))?;
    let scene = crate::scene::load::load(&o.scene, o.environment.as_deref(), log)?;
    let bvh = Bvh::build(&scene);
    let tris: usize = bvh.tris.len();
    log(format!(
        "scene '{}': {} meshes, {tris} triangles, BVH {} nodes (depth {})",
        scene.name,
        scene.meshes.len(),
        bvh.nodes.len(),
        bvh.depth()
    ));
    let lm = Lightmap::build(&scene, o.texels_per_unit, o.padding).map_err(|e| e.to_string())?;
    if !lm.generated_for.is_empty() {
        log(format!("layout: charts generated for {} mesh(es) without lightmap UVs", lm.generated_for.len()));
    }
    log(format!("layout: {}×{} atlas, {} valid texels, utilisation {:.3}", lm.width, lm.height, lm.valid_count(), lm.utilisation()));
    let mut sh: Vec<&str> = o.config.bases.iter().chain(&o.probe_bases).filter(|b| !b.non_negative()).map(|b| b.name()).collect();
    sh.sort_unstable();
    sh.dedup();
    if o.config.solver == Solver::Nnls && !sh.is_empty() {
        log(format!(
            "solver: NNLS applies to the non-negative bases (SG, Ambient Dice); {} fitted by least squares (SH coefficients of non-negative radiance are legitimately negative)",
            sh.join(", ")
        ));
    }
    let glossy = scene.has_glossy();
    if !glossy {
        log("leave-out: no glossy material — specular runtime features, LUTs and the GPU kernel's GGX layer skipped".into());
    }
    if o.gpus == 0 || (o.gpus > 1 && o.device == Device::Cpu) {
        return Err(format!("--gpus {} with --device {:?}: give ≥ 1 GPU, and more than one only on a GPU device", o.gpus, o.device));
    }
    let gpus: Vec<shaders::gpu::Gpu> = match o.device {
        _ if o.gpus > 1 => shaders::gpu::Gpu::hardware(o.gpus)?,
        Device::Cpu => Vec::new(),
        Device::Gpu => vec![shaders::gpu::Gpu::new()?],
        Device::Auto => match shaders::gpu::Gpu::new() {
            Ok(g) if g.software => {
                log(format!("the only adapter is a software rasteriser ({}); baking on the CPU path (--device gpu forces it)", g.adapter));
                Vec::new()
            }
            Ok(g) => vec![g],
            Err(e) => {
                log(format!("no GPU adapter ({e}); baking on the CPU"));
                Vec::new()
            }
        },
    };
    let gpu = gpus.first();
    let device = match gpus.as_slice() {
        [] => format!("CPU: {} threads (rayon)", rayon::current_num_threads()),
        [g] => format!("GPU: {}", g.adapter),
        gs => format!("{} GPUs: {}", gs.len(), gs.iter().map(|g| g.adapter.as_str()).collect::<Vec<_>>().join("; ")),
    };
    log(format!("device: {device}"));
    let tracer_of = || Tracer::new(&scene, &bvh, o.config.max_bounces);
    let targets = Targets::lightmap(&lm);
    // The camera's image (camera-based sampling) sized from the atlas where not given.
    let config = BakeConfig { camera: o.config.camera.map(|c| c.sized_for(targets.items.len())), ..o.config.clone() };
    if let Some(c) = &config.camera {
        let v = &c.camera;
        log(format!(
            "camera sampling: {}×{} pixels from {} towards {}, {:.0}° vertical field of view, {} uniform pass(es) first, ≤ {} samples per texel and batch",
            v.width,
            v.height,
            v.eye,
            v.target,
            v.fov_y.to_degrees(),
            c.pilot_passes,
            c.max_per_batch
        ));
    }
    if let Some(passes) = o.measure_rays {
        let g = gpu.ok_or("--measure-rays needs a GPU adapter")?;
        let mut b = GpuBake::new(g, &tracer_of(), &targets, &config)?;
        let r = b.time_rays(passes)?;
        log(format!(
            "rays over {passes} passes × {} texels: primary {} in {:.4} s = {:.3} G rays/s; secondary {} extension + {} shadow in {:.4} s (full − primary) = {:.3} G rays/s; all rays {:.3} G rays/s",
            targets.items.len(),
            r.primary,
            r.primary_seconds,
            r.primary_rate() * 1e-9,
            r.extension,
            r.shadow,
            r.full_seconds - r.primary_seconds,
            r.secondary_rate() * 1e-9,
            (r.primary + r.extension + r.shadow) as f64 / r.full_seconds * 1e-9
        ));
        if config.pipeline == crate::accumulate::Pipeline::Wavefront {
            if g.timestamps {
                // Per-pass GPU times of a fresh bake over the same passes.
                let mut p = GpuBake::new(g, &tracer_of(), &targets, &config)?;
                let times = p.profile_passes(passes)?;
                let total: f64 = times.iter().map(|t| t.1).sum();
                let parts: Vec<String> = times
                    .iter()
                    .map(|(pass, s, n)| format!("{pass} {:.2} ms ({:.1}%, {n}×)", 1e3 * s, 100.0 * s / total.max(1e-30)))
                    .collect();
                log(format!("wavefront GPU time over {passes} passes: {:.2} ms — {}", 1e3 * total, parts.join(", ")));
            } else {
                log("wavefront per-pass GPU times: the adapter has no timestamp queries".into());
            }
        }
        return Ok(Summary { device, lightmap: b.state()?, probes: None, passes_run: passes, seconds: t0.elapsed().as_secs_f64() });
    }
    if let Some(g) = o.config.guiding {
        log(format!(
            "guiding: {} clusters of ≤ {}×{} texels, {} learning passes, then {:.0}% of point samples from the learned distributions (rebuilt at passes {}, 2×, 4×, …)",
            targets.cluster_count,
            crate::sampling::guiding::TILE,
            crate::sampling::guiding::TILE,
            g.learn_passes,
            100.0 * g.guided_fraction,
            g.learn_passes
        ));
        if g.learn_passes >= o.passes {
            log(format!("guiding: all {} passes learn (--guiding-learn {} ≥ --passes): no pass is guided", o.passes, g.learn_passes));
        }
    }
    let t_passes = Instant::now();
    let (state, run) = run_targets(o, &config, &gpus, &tracer_of, &scene, &targets, "lightmap", log)?;
    let mut times = StageTimes { lightmap_passes: t_passes.elapsed().as_secs_f64(), probe_passes: None };
    log(format!("lightmap: {run} passes in {:.2} s", times.lightmap_passes));
    let mut probe_state = None;
    let mut probe_positions = Vec::new();
    let mut relocated: Vec<(usize, Vec3)> = Vec::new();
    if let Some(n) = o.probes {
        probe_positions = probe_grid(&bvh, n);
        if o.relocate_probes {
            let (lo, hi) = bvh.nodes.first().map(|x| (Vec3::from(x.min), Vec3::from(x.max))).unwrap_or((Vec3::ZERO, Vec3::ONE));
            let margin = 1e-3 * (hi - lo).max_element();
            for (k, p) in probe_positions.iter_mut().enumerate() {
                let (fraction, _) = crate::layout::probes::back_face_hits(&bvh, &scene, *p);
                if fraction <= crate::accumulate::MAX_BACK_FACE_FRACTION {
                    continue;
                }
                match crate::layout::probes::relocate(&bvh, &scene, *p, crate::accumulate::MAX_BACK_FACE_FRACTION, margin) {
                    Some(q) => {
                        log(format!("probes: probe {k} at {p} was inside geometry (back-face fraction {fraction:.2}); moved to {q}"));
                        relocated.push((k, *p));
                        *p = q;
                    }
                    None => log(format!("probes: probe {k} at {p} is inside geometry and could not be moved out; it stays flagged")),
                }
            }
        }
        let pt = Targets::probes(&probe_positions);
        let pcfg = BakeConfig { bases: o.probe_bases.clone(), adaptive: None, camera: None, filter: None, ..o.config.clone() };
        let t = Instant::now();
        let (ps, prun) = run_targets(o, &pcfg, &gpus, &tracer_of, &scene, &pt, "probes", log)?;
        times.probe_passes = Some(t.elapsed().as_secs_f64());
        log(format!("probes: {prun} passes in {:.2} s", t.elapsed().as_secs_f64()));
        probe_state = Some(ps);
    }
    let ctx = OutputContext { probe_positions: &probe_positions, relocated: &relocated, device: &device, glossy, t0, times };
    write_outputs(o, &scene, &bvh, &lm, &targets, &state, probe_state.as_ref(), &ctx, log)?;
    Ok(Summary { device, lightmap: state, probes: probe_state, passes_run: run, seconds: t0.elapsed().as_secs_f64() })
}

/// Wall time of the bake's stages, for bake.json.
#[derive(Debug, Clone, Copy)]
struct StageTimes {
    lightmap_passes: f64,
    probe_passes: Option<f64>,
}

/// What the outputs record besides the states.
struct OutputContext<'a> {
    probe_positions: &'a [Vec3],
    relocated: &'a [(usize, Vec3)],
    device: &'a str,
    glossy: bool,
    t0: Instant,
    times: StageTimes,
}

/// bake.json's account of ray guiding (null when off).
fn guiding_json(o: &Options, targets: &Targets, state: &BakeState) -> serde_json::Value {
    let Some(g) = o.config.guiding else { return json!(null) };
    let bins = crate::sampling::guiding::BIN_COUNT;
    let learned = state.guide_sums.chunks(bins).filter(|c| c.iter().any(|v| *v > 0.0)).count();
    let mut rebuilds = Vec::new();
    let mut p = g.learn_passes;
    while p < state.passes && p > 0 {
        rebuilds.push(p);
        p *= 2;
    }
    json!({"method": "first-bounce ray guiding (seed 003): 8x8-texel clusters split by chart and normal, 16x16 equal-area concentric bins, quadtree relaxation, mixture with the uniform hemisphere",
           "clusters": targets.cluster_count, "clusters_with_light": learned, "learn_passes": g.learn_passes,
           "guided_fraction": g.guided_fraction, "rebuilt_at_passes": rebuilds,
           "learning_samples": "kept (uniform samples with their correct pdf)"})
}

#[allow(clippy::too_many_arguments)]
fn write_outputs(
    o: &Options,
    scene: &Scene,
    bvh: &Bvh,
    lm: &Lightmap,
    targets: &Targets,
    state: &BakeState,
    probes: Option<&BakeState>,
    ctx: &OutputContext,
    log: &mut dyn FnMut(String),
) -> Result<(), String> {
    let OutputContext { probe_positions, relocated, device, glossy, t0, times } = *ctx;
    let mut img = LightmapImages::new(lm, targets, state);
    let validity = |st: &BakeState| {
        let valid = st.valid();
        let sum = |f: &dyn Fn(&crate::accumulate::Moments) -> u64| st.moments.iter().map(f).sum::<u64>();
        json!({"invalid": valid.iter().filter(|v| !**v).count(),
               "max_back_face_fraction": crate::accumulate::MAX_BACK_FACE_FRACTION,
               "back_face_samples": sum(&|m| m.back_faces), "non_finite_samples": sum(&|m| m.non_finite),
               "accepted_samples": sum(&|m| m.accepted)})
    };
    let lm_validity = validity(state);
    // Texels a chart overlaps that hold no value before dilation (with a filter, fewer:
    // uncovered edge texels gather their neighbours' samples).
    let overlapped = lm.texel_charts.iter().filter(|c| **c != crate::layout::lightmap::NO_CHART).count();
    let empty =
        (0..lm.texels.len()).filter(|t| lm.texel_charts[*t] != crate::layout::lightmap::NO_CHART && img.validity[*t] == 0.0).count();
    let filter_json = match (&o.config.filter, &state.filtered) {
        (Some(f), Some(fs)) => {
            let uncovered = overlapped - lm.valid_count();
            log(format!(
                "filter: {} radius {} texels over {} gather targets ({uncovered} overlapped but uncovered); {empty} of {overlapped} overlapped texels empty before dilation; {} negative-weight samples not gathered",
                f.name(),
                f.radius,
                fs.moments.len(),
                fs.negative_weights
            ));
            json!({"kernel": f.name(), "radius_texels": f.radius, "gather_targets": fs.moments.len(), "uncovered_targets": uncovered,
                   "negative_weight_samples_skipped": fs.negative_weights,
                   "method": "gather-based filtered accumulation (seed 004 §3.2): every texel a chart overlaps gathers the samples of its chart within the radius, weight x filter weight into its own encoders and weighted Welford moments; negative filter weights (Mitchell's lobes) are not gathered (the encoders need positive weights)"})
        }
        _ => json!(null),
    };
    log(format!(
        "validity: {} of {} texels inside geometry (back-face fraction > {}) left invalid and dilated over; {} back-face and {} non-finite samples rejected",
        lm_validity["invalid"], targets.items.len(), crate::accumulate::MAX_BACK_FACE_FRACTION, lm_validity["back_face_samples"], lm_validity["non_finite_samples"]
    ));
    // Denoise (optional) before dilation: the filter reads valid texels only.
    let denoised = match o.denoise {
        Some(opts) => {
            let t = Instant::now();
            let st = crate::post::denoise::denoise(&mut img, lm, opts)?;
            let secs = t.elapsed().as_secs_f64();
            log(format!(
                "denoise: joint NLM over {} texels (window {}, patch {}, k {}), {:.1} effective neighbours on average, {secs:.2} s",
                st.texels,
                2 * opts.radius + 1,
                2 * opts.patch + 1,
                opts.strength,
                st.mean_effective_neighbours
            ));
            json!({"method": "joint non-local means (Rousselle et al. 2012 patch distance; position, normal, chart guides)",
                   "window": 2 * opts.radius + 1, "patch": 2 * opts.patch + 1, "strength": opts.strength,
                   "texels": st.texels, "mean_effective_neighbours": st.mean_effective_neighbours, "seconds": secs})
        }
        None => json!(null),
    };
    // Seams: the metric on the dilated images (what a runtime's bilinear lookups read),
    // before and (with --stitch-seams) after stitching.
    let t = Instant::now();
    let seam_edges = crate::post::seams::find_seams(scene, lm);
    let seam_samples = crate::post::seams::samples(&seam_edges, lm.width, lm.height);
    let mut plain = img.clone();
    plain.dilate(o.padding + 1);
    let metric_before = crate::post::seams::seam_metric(&plain, &seam_samples);
    let noise = {
        let (mut s, mut n) = (0.0f64, 0usize);
        for x in &seam_samples {
            for (t, _) in x.a.iter().chain(&x.b) {
                if img.validity[*t] > 0.0 {
                    s += img.standard_error[*t].iter().map(|v| *v as f64).sum::<f64>() / 3.0;
                    n += 1;
                }
            }
        }
        s / n.max(1) as f64
    };
    let (dilated, seams) = if o.stitch_seams && !seam_samples.is_empty() {
        let st = crate::post::seams::stitch(&mut img, &plain, &seam_samples);
        let dilated = img.dilate_keeping(o.padding + 1, &st.written_empty);
        let after = crate::post::seams::seam_metric(&img, &seam_samples);
        let secs = t.elapsed().as_secs_f64();
        log(format!(
            "seams: {} edges, {} samples; mean |ΔE/π| across them {metric_before:.3e} → {after:.3e} (texel noise {noise:.3e}), {} texels solved in ≤ {} CG iterations{}, {secs:.2} s",
            seam_edges.len(),
            seam_samples.len(),
            st.texels,
            st.iterations,
            if st.converged { "" } else { " (NOT converged to 1e-7: the result is the last iterate)" }
        ));
        (
            dilated,
            json!({"edges": seam_edges.len(), "samples": seam_samples.len(), "metric_before": metric_before, "metric_after": after,
                         "texel_noise": noise, "stitched": true, "texels": st.texels, "cg_iterations": st.iterations, "cg_converged": st.converged, "seconds": secs,
                         "metric": "mean |E/pi lookup A - lookup B| over seam samples and channels, after dilation"}),
        )
    } else {
        log(format!(
            "seams: {} edges, mean |ΔE/π| across them {metric_before:.3e} (texel noise {noise:.3e}); not stitched, {:.2} s",
            seam_edges.len(),
            t.elapsed().as_secs_f64()
        ));
        let dilated = img.dilate(o.padding + 1);
        (
            dilated,
            json!({"edges": seam_edges.len(), "samples": seam_samples.len(), "metric_before": metric_before, "texel_noise": noise, "stitched": false,
                         "metric": "mean |E/pi lookup A - lookup B| over seam samples and channels, after dilation"}),
        )
    };
    let seam_seconds = t.elapsed().as_secs_f64();
    let t_out = Instant::now();
    let files = output::write_lightmap(&o.out, &img, &o.config)?;
    let png = output::preview(scene, bvh, lm, &img, o.preview_width, o.config.camera.map(|c| c.camera));
    png.save(o.out.join("preview.png")).map_err(|e| format!("preview.png: {e}"))?;
    // Specular runtime: only for a scene with a glossy material and a profile (if any) whose
    // BRDF set has GGX.
    let specular = glossy && o.profile.as_ref().is_none_or(|p| p.specular);
    let (features, luts) = output::runtime_features(&o.config.bases, specular);
    let cfg = shaders::compose::Config::parse(&features.join(","))?;
    let runtime = shaders::compose::compose(&cfg)?;
    std::fs::write(o.out.join("runtime.wgsl"), &runtime.source).map_err(|e| format!("runtime.wgsl: {e}"))?;
    let mut runtime_files = vec!["runtime.wgsl".to_string()];
    if let Some(p) = &o.profile {
        let lang = shaders::export::Lang::parse(&p.language)?;
        if p.language != "wgsl" {
            let name = format!("runtime.{}", lang.extension());
            std::fs::write(o.out.join(&name), shaders::export::export(&runtime.source, lang)?).map_err(|e| format!("{name}: {e}"))?;
            runtime_files.push(name);
        }
        if glossy && !p.specular {
            let (spec_features, spec_luts) = output::runtime_features(&o.config.bases, true);
            let with = shaders::compose::compose(&shaders::compose::Config::parse(&spec_features.join(","))?)?;
            let lut_bytes: usize =
                spec_luts.iter().filter(|l| *l == &"ad_specular_2d.sbflut").map(|_| sbf::luts::committed::AD_SPECULAR_2D_DATA.len()).sum();
            let saved = with.source.len() - runtime.source.len();
            log(if saved + lut_bytes == 0 {
                format!(
                    "profile '{}': Lambert only — the scene is glossy, but these bases have no specular runtime path to leave out",
                    p.name
                )
            } else {
                format!("profile '{}': Lambert only — specular runtime left out although the scene is glossy: {saved} WGSL bytes and {lut_bytes} LUT bytes not written", p.name)
            });
        }
    }
    for l in &luts {
        let data = match *l {
            "ad_specular_2d.sbflut" => sbf::luts::committed::AD_SPECULAR_2D_DATA,
            other => return Err(format!("no embedded LUT named {other}")),
        };
        std::fs::write(o.out.join(l), data).map_err(|e| format!("{l}: {e}"))?;
    }
    let bases: Vec<serde_json::Value> = o
        .config
        .bases
        .iter()
        .map(|b| {
            let lobes = b.basis().len();
            let files: Vec<String> = (0..lobes).map(|l| format!("{}_{l:02}.exr", b.name())).collect();
            let solver = if o.config.solver == Solver::Nnls && b.non_negative() { "progressive NNLS" } else { "progressive LS" };
            json!({"name": b.name(), "lobes": lobes, "domain": if b.is_sphere() { "sphere" } else { "upper hemisphere" }, "solver": solver,
                   "space": "tangent: normal +Z, tangent frame of Duff et al. 2017 (sbf::basis::ambient_dice_bezier::tangent_frame, WGSL tangent_frame) about the texel's shading normal in normals.exr (world space, the normalised mean of the interpolated vertex normals at its sub-texel points)",
                   "files": files, "mirrored_lower_hemisphere": b.is_sphere()})
        })
        .collect();
    log(format!("outputs: images, preview and runtime written in {:.2} s", t_out.elapsed().as_secs_f64()));
    let mut meta = json!({
        "scene": scene.name,
        "device": device,
        "passes": state.passes,
        "seed": o.config.seed,
        "sampler": o.config.sampler.name(),
        "adaptive": o.config.adaptive.map(|a| json!({"pilot_passes": a.pilot_passes, "batch_fraction": a.batch_fraction, "floor": a.floor, "max_per_batch": a.max_per_batch})),
        "paths": state.moments.iter().map(crate::accumulate::Moments::count).sum::<u64>(),
        "max_bounces": o.config.max_bounces,
        "solver": format!("{:?}", o.config.solver),
        "layout": {"width": lm.width, "height": lm.height, "texels_per_unit": lm.texels_per_unit, "padding": lm.padding,
                   "valid_texels": lm.valid_count(), "utilisation": lm.utilisation(), "dilated_texels": dilated,
                   "validity": "alpha channel of every EXR: 1 = baked, 0 = empty, inside geometry or dilated",
                   "texel_validity": lm_validity, "overlapped_texels": overlapped, "empty_before_dilation": empty},
        "filter": filter_json,
        "irradiance": {"file": "irradiance.exr", "quantity": "E/pi (linear RGB)", "standard_error": "irradiance_se.exr"},
        "normals": {"file": "normals.exr", "quantity": "world-space unit shading normal per texel (the basis frame's +Z)"},
        "bases": bases,
        "guiding": guiding_json(o, targets, state),
        "denoise": denoised,
        "seams": seams,
        "stage_seconds": {"lightmap_passes": times.lightmap_passes, "probe_passes": times.probe_passes,
                          "denoise": denoised.get("seconds"), "seams": seam_seconds, "outputs": t_out.elapsed().as_secs_f64()},
        "meshes": output::mesh_mapping(scene, lm),
        "runtime": {"wgsl": "runtime.wgsl", "files": runtime_files, "features": features, "luts": luts, "left_out_bytes": runtime.left_out_bytes(),
                    "specular": if specular { "included" } else if glossy { "left out: the profile's BRDF set is Lambert only" } else { "left out: no glossy material" }},
        "profile": o.profile.as_ref().map(|p| json!({"name": p.name, "summary": p.summary(), "lightmap_bases": p.lightmap_bases,
                    "probe_bases": p.probe_bases, "specular": p.specular, "roughness": p.roughness.map(|(a, b)| [a, b]),
                    "precision": p.precision, "language": p.language})),
        "files": files,
        "preview": "preview.png",
        "seconds": t0.elapsed().as_secs_f64(),
    });
    if let Some(ps) = probes {
        let (mean, se) = (ps.mean(), ps.standard_error());
        let list: Vec<serde_json::Value> = probe_positions
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let coeffs: serde_json::Map<String, serde_json::Value> = o
                    .probe_bases
                    .iter()
                    .enumerate()
                    .map(|(b, kind)| {
                        let c = ps.encoders[b][k].coefficients();
                        let rows: Vec<[f64; 3]> = (0..c.nrows()).map(|i| [c[(i, 0)], c[(i, 1)], c[(i, 2)]]).collect();
                        (kind.name().to_string(), json!(rows))
                    })
                    .collect();
                let m = &ps.moments[k];
                let mut j = json!({"position": [p.x, p.y, p.z], "mean_radiance": mean[k], "standard_error": se[k], "coefficients": coeffs,
                       "valid": ps.valid()[k], "back_face_fraction": m.back_face_fraction()});
                if let Some((_, from)) = relocated.iter().find(|r| r.0 == k) {
                    j["relocated_from"] = json!([from.x, from.y, from.z]);
                }
                j
            })
            .collect();
        let pj = json!({"space": "world (+Y up)", "passes": ps.passes, "bases": o.probe_bases.iter().map(|b| b.name()).collect::<Vec<_>>(), "probes": list});
        std::fs::write(o.out.join("probes.json"), serde_json::to_string_pretty(&pj).expect("json"))
            .map_err(|e| format!("probes.json: {e}"))?;
        let pv = validity(ps);
        log(format!("probes: {} of {} inside geometry (flagged \"valid\": false in probes.json)", pv["invalid"], probe_positions.len()));
        meta["probes"] = json!({"file": "probes.json", "count": probe_positions.len(), "validity": pv, "relocated": relocated.len()});
    }
    std::fs::write(o.out.join("bake.json"), serde_json::to_string_pretty(&meta).expect("json")).map_err(|e| format!("bake.json: {e}"))?;
    log(format!(
        "wrote {} ({} EXR files, bake.json, preview.png, runtime.wgsl{})",
        o.out.display(),
        files.len(),
        if probes.is_some() { ", probes.json" } else { "" }
    ));
    Ok(())
}
