//! A whole bake as the `baker` command runs it: scene → BVH → layout → passes on the
//! GPU or the CPU (progress with ETA, a checkpoint every N passes, resume) → outputs.
//! Tests drive the same function ([`bake`]) to kill and resume bakes.
//!
//! Uses every layer but `slc`.

mod engine;
mod options;
mod outputs;

pub use options::{Device, Options, Summary};

use crate::accumulate::{BakeConfig, Solver, Targets};
use crate::estimator::trace::Tracer;
use crate::gpu::GpuBake;
use crate::layout::lightmap::Lightmap;
use crate::layout::probes::probe_grid;
use crate::scene::bvh::Bvh;
use engine::run_targets;
use outputs::{write_outputs, OutputContext, StageTimes};
use sbf::glam::Vec3;
use std::time::Instant;

/// Runs a whole bake and writes its outputs (unless stopped early).
#[allow(clippy::too_many_lines)] // To split: over the 120-line limit the crate holds (lib.rs).
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
