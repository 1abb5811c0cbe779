//! A whole bake as the `baker` command runs it: scene → BVH → layout → passes on the
//! GPU or the CPU (progress with ETA, a checkpoint every N passes, resume) → outputs.
//! Tests drive the same function ([`bake`]) to kill and resume bakes.
//!
//! Uses every layer but `slc`.

mod devices;
mod engine;
pub mod limits;
mod options;
mod outputs;
mod runtime;
pub mod shard;

pub use options::{read_spec, BakeSpec, Device, Options, RunOptions, ShardSpec, Summary, SPEC_FILE};
pub use shard::merge;

use crate::accumulate::{BakeConfig, Partition, Solver, Targets};
use crate::estimator::trace::Tracer;
use crate::layout::lightmap::Lightmap;
use crate::layout::probes::probe_grid;
use crate::scene::bvh::Bvh;
use crate::scene::Scene;
use engine::run_targets;
use outputs::{write_outputs, OutputContext, StageTimes};
use sbf::glam::Vec3;
use std::time::Instant;

/// What a bake traces, laid out: the scene, its BVH, the atlas, the lightmap targets and
/// settings, the probes (positions and the relocated ones) — the same for a bake, each of
/// its shards and their merge.
pub(crate) struct Prepared {
    pub(crate) scene: Scene,
    pub(crate) bvh: Bvh,
    pub(crate) lm: Lightmap,
    pub(crate) targets: Targets,
    pub(crate) config: BakeConfig,
    pub(crate) probes: Option<ProbePlacement>,
}

/// The probes' positions and (index, original position) of every relocated probe.
pub(crate) type ProbePlacement = (Vec<Vec3>, Vec<(usize, Vec3)>);

/// Loads the scene, builds the BVH and the atlas, places the probes; logs each and checks
/// the state fits in memory.
pub(crate) fn prepare(o: &Options, log: &mut dyn FnMut(String)) -> Result<Prepared, String> {
    let mut scene = crate::scene::load::load(&o.spec.scene, o.spec.environment.as_deref(), log)?;
    if !o.spec.material_maps && scene.has_textures() {
        log("--material-maps factors: the materials' texture maps are dropped, their factors baked".into());
        scene = scene.without_maps();
    }
    let bvh = Bvh::build(&scene);
    let (tpu, padding) = (o.spec.texels_per_unit, o.spec.padding);
    // A shard lays out the whole atlas but keeps the points of its own texels only.
    let lm = match &o.run.shard {
        Some(s) => {
            let keep = |item: usize, items: usize| Partition::of(s.index, s.count, items).is_ok_and(|p| p.owns(item));
            Lightmap::build_part(&scene, tpu, padding, &keep)
        }
        None => Lightmap::build(&scene, tpu, padding),
    }
    .map_err(|e| e.to_string())?;
    log_scene_and_layout(o, &scene, &bvh, &lm, log);
    let share = |items: usize| o.run.shard.as_ref().map_or(Ok(items), |s| Partition::of(s.index, s.count, items).map(|p| p.share(items)));
    limits::check_memory("lightmap", share(lm.valid_count())?, &o.spec.config.bases, log)?;
    if let Some([x, y, z]) = o.spec.probes {
        limits::check_memory("probes", share(x * y * z)?, &o.spec.probe_bases, log)?;
    }
    let targets = match &o.run.shard {
        Some(s) => Targets::lightmap_part(&lm, Partition::of(s.index, s.count, lm.valid_count())?)?,
        None => Targets::lightmap(&lm),
    };
    // The camera's image (camera-based sampling) sized from the atlas where not given.
    let config = BakeConfig {
        camera: o.spec.config.camera.map(|c| c.sized_for(targets.items.len())),
        pipeline: o.run.pipeline,
        ..o.spec.config.clone()
    };
    let probes = o.spec.probes.map(|n| place_probes(o, &bvh, &scene, n, log));
    Ok(Prepared { scene, bvh, lm, targets, config, probes })
}

/// The probes' settings: the probe bases, uniform passes, no filter.
pub(crate) fn probe_config(o: &Options) -> BakeConfig {
    BakeConfig {
        bases: o.spec.probe_bases.clone(),
        adaptive: None,
        camera: None,
        filter: None,
        pipeline: o.run.pipeline,
        ..o.spec.config.clone()
    }
}

/// Runs a whole bake and writes its outputs (unless stopped early) — or, with
/// [`RunOptions::shard`], its shard's items and writes the shard file instead.
pub fn bake(o: &Options, log: &mut dyn FnMut(String)) -> Result<Summary, String> {
    let t0 = Instant::now();
    // Every bound first, then the output folder: nothing is traced for a bake that
    // cannot finish or cannot write.
    o.validate()?;
    limits::check_writable(&o.run.out)?;
    if o.run.measure_rays.is_none() {
        options::record_spec(&o.spec, &o.run.out, o.run.resume)?;
    }
    let Prepared { scene, bvh, lm, targets, config, probes } = prepare(o, log)?;
    let glossy = scene.has_glossy();
    let (gpus, device) = devices::select(o, log)?;
    if gpus.is_empty() && o.run.pipeline != crate::accumulate::Pipeline::default() {
        log(format!("notice: --pipeline {} applies to GPU bakes; this bake runs on the CPU path", o.run.pipeline.name()));
    }
    let default_batch = o.run.batch_seconds.is_some_and(|s| (s - crate::gpu::BATCH_TARGET_SECONDS).abs() < 1e-12);
    if gpus.is_empty() && !default_batch {
        log("notice: --batch-ms applies to GPU bakes; this bake runs on the CPU path".into());
    }
    let tracer_of = || Tracer::new(&scene, &bvh, o.spec.config.max_bounces).with_indirect_only(o.spec.config.indirect_only);
    log_strategies(o, &config, &targets, log);
    if let Some(passes) = o.run.measure_rays {
        let g = gpus.first().ok_or("--measure-rays needs a GPU adapter")?;
        let lightmap = devices::measure_rays(g, &tracer_of, &targets, &config, passes, log)?;
        return Ok(Summary { device, lightmap, probes: None, passes_run: passes, seconds: t0.elapsed().as_secs_f64() });
    }
    let t_passes = Instant::now();
    let (state, run) = run_targets(o, &config, &gpus, &tracer_of, &scene, &targets, "lightmap", log)?;
    let mut times = StageTimes { lightmap_passes: t_passes.elapsed().as_secs_f64(), probe_passes: None };
    log(format!("lightmap: {run} passes in {:.2} s", times.lightmap_passes));
    let (mut probe_state, mut probe_targets) = (None, None);
    let pcfg = probe_config(o);
    if let Some((positions, _)) = &probes {
        let pt = match &o.run.shard {
            Some(s) => Targets::probes(positions).part(Partition::of(s.index, s.count, positions.len())?)?,
            None => Targets::probes(positions),
        };
        let t = Instant::now();
        let (ps, prun) = run_targets(o, &pcfg, &gpus, &tracer_of, &scene, &pt, "probes", log)?;
        times.probe_passes = Some(t.elapsed().as_secs_f64());
        log(format!("probes: {prun} passes in {:.2} s", t.elapsed().as_secs_f64()));
        (probe_state, probe_targets) = (Some(ps), Some(pt));
    }
    let pipeline = if gpus.is_empty() { "none (CPU path)" } else { o.run.pipeline.name() };
    if let Some(spec) = &o.run.shard {
        let mut sets = vec![shard::BakedSet { what: "lightmap", scene: &scene, targets: &targets, config: &config, state: &state }];
        if let (Some(pt), Some(ps)) = (&probe_targets, &probe_state) {
            sets.push(shard::BakedSet { what: "probes", scene: &scene, targets: pt, config: &pcfg, state: ps });
        }
        let record = shard::ShardRun {
            index: spec.index,
            count: spec.count,
            device: device.clone(),
            pipeline: pipeline.to_string(),
            lightmap_passes_seconds: times.lightmap_passes,
            probe_passes_seconds: times.probe_passes,
            seconds: t0.elapsed().as_secs_f64(),
            peak_memory_bytes: limits::peak_memory(),
        };
        shard::write_shard(o, spec, &sets, &record, log)?;
    } else {
        let (positions, relocated) = probes.unwrap_or_default();
        let ctx = OutputContext { probe_positions: &positions, relocated: &relocated, device: &device, pipeline, glossy, t0, times };
        write_outputs(o, &scene, &bvh, &lm, &targets, &state, probe_state.as_ref(), &ctx, log)?;
    }
    Ok(Summary { device, lightmap: state, probes: probe_state, passes_run: run, seconds: t0.elapsed().as_secs_f64() })
}

/// The log lines about the scene, its layout, the solver per basis and what the scene
/// lets the bake leave out.
fn log_scene_and_layout(o: &Options, scene: &Scene, bvh: &Bvh, lm: &Lightmap, log: &mut dyn FnMut(String)) {
    log(format!(
        "scene '{}': {} meshes, {} triangles, BVH {} nodes (depth {})",
        scene.name,
        scene.meshes.len(),
        bvh.tris.len(),
        bvh.nodes.len(),
        bvh.depth()
    ));
    if !lm.generated_for.is_empty() {
        log(format!("layout: charts generated for {} mesh(es) without lightmap UVs", lm.generated_for.len()));
    }
    log(format!("layout: {}×{} atlas, {} valid texels, utilisation {:.3}", lm.width, lm.height, lm.valid_count(), lm.utilisation()));
    let mut sh: Vec<&str> = o.spec.config.bases.iter().chain(&o.spec.probe_bases).filter(|b| !b.non_negative()).map(|b| b.name()).collect();
    sh.sort_unstable();
    sh.dedup();
    if matches!(o.spec.config.solver, Solver::Nnls | Solver::NnlsIrradiance | Solver::NnlsRescaled) && !sh.is_empty() {
        log(format!(
            "solver: NNLS applies to the non-negative bases (SG, Ambient Dice); {} fitted by least squares (SH coefficients of non-negative radiance are legitimately negative)",
            sh.join(", ")
        ));
    }
    if !scene.has_glossy() {
        log("leave-out: no glossy material — specular runtime features, LUTs and the GPU kernel's GGX layer skipped".into());
    }
}

/// The log lines of camera-based sampling and ray guiding, where configured.
fn log_strategies(o: &Options, config: &BakeConfig, targets: &Targets, log: &mut dyn FnMut(String)) {
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
    if let Some(g) = config.guiding {
        log(format!(
            "guiding: {} clusters of ≤ {}×{} texels, {} learning passes, then {:.0}% of point samples from the learned distributions (rebuilt at passes {}, 2×, 4×, …)",
            targets.cluster_count,
            crate::sampling::guiding::TILE,
            crate::sampling::guiding::TILE,
            g.learn_passes,
            100.0 * g.guided_fraction,
            g.learn_passes
        ));
        if g.learn_passes >= o.spec.passes {
            log(format!("guiding: all {} passes learn (--guiding-learn {} ≥ --passes): no pass is guided", o.spec.passes, g.learn_passes));
        }
    }
}

/// The probe grid of `n` probes inside the scene bounds; with `--relocate-probes`, probes
/// inside geometry moved out. Returns the positions and (index, original position) of
/// every moved probe.
fn place_probes(o: &Options, bvh: &Bvh, scene: &Scene, n: [usize; 3], log: &mut dyn FnMut(String)) -> (Vec<Vec3>, Vec<(usize, Vec3)>) {
    let mut positions = probe_grid(bvh, n);
    let mut relocated = Vec::new();
    if !o.spec.relocate_probes {
        return (positions, relocated);
    }
    let (lo, hi) = bvh.nodes.first().map(|x| (Vec3::from(x.min), Vec3::from(x.max))).unwrap_or((Vec3::ZERO, Vec3::ONE));
    let margin = 1e-3 * (hi - lo).max_element();
    for (k, p) in positions.iter_mut().enumerate() {
        let (fraction, _) = crate::layout::probes::back_face_hits(bvh, scene, *p);
        if fraction <= crate::accumulate::MAX_BACK_FACE_FRACTION {
            continue;
        }
        match crate::layout::probes::relocate(bvh, scene, *p, crate::accumulate::MAX_BACK_FACE_FRACTION, margin) {
            Some(q) => {
                log(format!("probes: probe {k} at {p} was inside geometry (back-face fraction {fraction:.2}); moved to {q}"));
                relocated.push((k, *p));
                *p = q;
            }
            None => log(format!("probes: probe {k} at {p} is inside geometry and could not be moved out; it stays flagged")),
        }
    }
    (positions, relocated)
}
