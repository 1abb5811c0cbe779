//! Time to a fixed error (a benchmark, not a test): bakes a scene on the GPU with
//! each sampling configuration and reports the GPU time each needs to bring the E/π RMSE
//! over texels — against a long reference bake with another seed, its own variance
//! subtracted — down to a target, plus the time to the first full-atlas preview (every
//! texel with at least one sample).
//!
//!     cargo run --release -p baker --example time_to_error -- \
//!         [--scene sunbeam] [--texels-per-unit 16] [--reference-passes 8192] \
//!         [--target-passes 256] [--bounces 4] [--adaptive 1:8,2:4] [--camera 0,1,3:0,1,0:60] \
//!         [--filter gaussian]
//!
//! Configurations: megakernel uniform with white noise (the baseline), then per pipeline
//! (`--pipelines megakernel,wavefront`) uniform with the Sobol' sequences, adaptive with
//! the Sobol' sequences (one per `--adaptive f:L`: batch fraction f, at most L samples per
//! texel and batch), camera-based (`--camera`) and uniform with filtered accumulation
//! (`--filter`, judged by its filtered means against the unfiltered reference). The target
//! RMSE is what the baseline reaches at `--target-passes`; each configuration then runs in
//! doubling steps of passes (batches count as 1/f of a pass) and the time to the target is
//! interpolated log-linearly between the two steps around it (RMSE falls like a power of
//! the time). The error curve is found first (untimed, with read-backs); then, after
//! ~0.3 s of passes to bring the GPU's clocks up, the passes to the two steps around the
//! target are timed from an empty state without any read-back between them, three times,
//! the median reported (steady-state timing; pipeline compilation and upload precede it). Camera-based sampling is judged on the
//! texels its camera sees (its error and its target, the baseline's error there).

use baker::accumulate::adaptive::AdaptiveOptions;
use baker::accumulate::{BakeConfig, BakeState, BasisId, Pipeline, Solver, Targets};
use baker::estimator::trace::Tracer;
use baker::gpu::GpuBake;
use baker::layout::lightmap::Lightmap;
use baker::sampling::sequence::Sequence;
use baker::scene::bvh::Bvh;
use baker::scene::load::load as load_scene;
use std::time::Instant;

/// Timed runs per configuration (the median is reported: sub-second runs vary with the
/// GPU's clocks).
const REPEATS: usize = 3;

fn arg<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> Result<T, String> {
    match args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)) {
        Some(s) => s.parse().map_err(|_| format!("{name}: cannot parse '{s}'")),
        None => Ok(default),
    }
}

fn main() {
    if let Err(e) = run() {
        eprintln!("time_to_error: {e}");
        std::process::exit(1);
    }
}

/// Mean squared error of E/π over the texels the reference measured (≥ 2 accepted
/// samples: a finite standard error), minus the reference's own mean variance there. A
/// filtered bake is judged by its filtered means (the gather targets start with the items).
fn mse(st: &BakeState, rm: &[[f64; 3]], keep: &[bool], ref_var: f64) -> f64 {
    let m = match &st.filtered {
        Some(f) => f.moments[..rm.len()].iter().map(|m| m.mean).collect(),
        None => st.mean(),
    };
    let (mut sq, mut n) = (0.0, 0usize);
    for k in (0..m.len()).filter(|k| keep[*k]) {
        sq += (0..3).map(|c| (m[k][c] - rm[k][c]).powi(2)).sum::<f64>() / 3.0;
        n += 1;
    }
    (sq / n.max(1) as f64 - ref_var).max(1e-30)
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene_name: String = arg(&args, "--scene", "sunbeam".to_string())?;
    let tpu: f32 = arg(&args, "--texels-per-unit", 16.0)?;
    let ref_passes: u64 = arg(&args, "--reference-passes", 8192)?;
    let target_passes: u64 = arg(&args, "--target-passes", 256)?;
    let bounces: u32 = arg(&args, "--bounces", 4)?;
    // Adaptive configurations: "f:L,f:L" (batch fraction, most samples per batch).
    let adaptive: Vec<(f64, u32)> = arg(&args, "--adaptive", "1:8".to_string())?
        .split(',')
        .map(|p| {
            let (f, l) = p.split_once(':').ok_or_else(|| format!("--adaptive: '{p}' is not f:L"))?;
            Ok((f.parse().map_err(|_| format!("--adaptive: {f}"))?, l.parse().map_err(|_| format!("--adaptive: {l}"))?))
        })
        .collect::<Result<_, String>>()?;
    // Pipelines to compare: "megakernel,wavefront".
    let pipelines: Vec<Pipeline> = arg(&args, "--pipelines", "megakernel,wavefront".to_string())?
        .split(',')
        .map(|p| Pipeline::parse(p).ok_or_else(|| format!("--pipelines: unknown '{p}'")))
        .collect::<Result<_, String>>()?;
    // Filtered accumulation (`--filter box|gaussian|mitchell[:r]`): each pipeline's uniform
    // Sobol' bake once more with it (judged against the unfiltered reference, so its blur
    // counts as error).
    let filter: Option<baker::accumulate::filter::Filter> = match args.iter().position(|a| a == "--filter") {
        Some(i) => Some(baker::accumulate::filter::Filter::parse(args.get(i + 1).ok_or("--filter needs a value")?)?),
        None => None,
    };
    // Camera-based sampling: "eye:target[:fov]" (its error is over every texel, seen or not).
    let camera: Option<String> = args.iter().position(|a| a == "--camera").and_then(|i| args.get(i + 1).cloned());
    let scene = load_scene(&scene_name, None, &mut |l| println!("{l}"))?;
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, tpu, 2).map_err(|e| e.to_string())?;
    let targets = Targets::lightmap(&lm);
    let gpu = shaders::gpu::Gpu::new()?;
    println!("{} on {}: {} texels, {} triangles", scene.name, gpu.adapter, targets.items.len(), bvh.tris.len());
    let cfg = |seed, sampler, adaptive| BakeConfig {
        seed,
        max_bounces: bounces,
        bases: vec![BasisId::Sh2],
        solver: Solver::Ls,
        sampler,
        adaptive,
        ..Default::default()
    };
    let tracer = || Tracer::new(&scene, &bvh, bounces);
    // The reference: uniform, Sobol', another seed.
    let t = Instant::now();
    let mut r = GpuBake::new(&gpu, &tracer(), &targets, &cfg(1000, Sequence::Sobol, None))?;
    r.run(ref_passes)?;
    let reference = r.state()?;
    drop(r);
    let (rm, rse) = (reference.mean(), reference.standard_error());
    let keep: Vec<bool> = rse.iter().map(|s| s.iter().all(|x| x.is_finite())).collect();
    let kept = keep.iter().filter(|k| **k).count();
    let ref_var: f64 =
        rse.iter().zip(&keep).filter(|(_, k)| **k).flat_map(|(s, _)| s.iter()).map(|s| s * s).sum::<f64>() / (3 * kept) as f64;
    println!("{kept} of {} texels measured by the reference (the rest met back faces)", rse.len());
    println!("reference: {ref_passes} passes in {:.1} s, its RMS standard error {:.3e}", t.elapsed().as_secs_f64(), ref_var.sqrt());
    let a = AdaptiveOptions::default();
    let base = |pipeline| BakeConfig { pipeline, ..cfg(1, Sequence::Sobol, None) };
    let mut configs: Vec<(String, BakeConfig)> =
        vec![("megakernel uniform, white noise".into(), BakeConfig { sampler: Sequence::Independent, ..base(Pipeline::Megakernel) })];
    for p in &pipelines {
        let name = p.name();
        configs.push((format!("{name} uniform, Sobol'"), base(*p)));
        if let Some(f) = filter {
            configs
                .push((format!("{name} uniform, Sobol', {} filter r {}", f.name(), f.radius), BakeConfig { filter: Some(f), ..base(*p) }));
        }
        for &(f, l) in &adaptive {
            let o = AdaptiveOptions { batch_fraction: f, max_per_batch: l, ..a };
            configs.push((format!("{name} adaptive (f {f}, L {l}), Sobol'"), BakeConfig { adaptive: Some(o), ..base(*p) }));
        }
        if let Some(spec) = &camera {
            let c = baker::accumulate::camera::CameraSampling {
                camera: baker::scene::camera::ViewCamera::parse(spec, 0, 0)?,
                pilot_passes: 1,
                max_per_batch: 8,
            };
            configs
                .push((format!("{name} camera-based, Sobol'"), BakeConfig { camera: Some(c.sized_for(targets.items.len())), ..base(*p) }));
        }
    }
    // Camera-based sampling converges what the camera sees: its error (and the target it
    // must reach, the baseline's error on the same texels) is over the texels seen by
    // every one of the first 16 jittered batches (texels smaller than a pixel, seen by
    // some jitters only, take samples at the rate their pixel coverage allows).
    let seen: Vec<bool> = match configs.iter().find_map(|(_, c)| c.camera) {
        Some(c) => {
            let mut every = vec![true; targets.items.len()];
            for b in 0..16 {
                for (k, n) in baker::accumulate::camera::pixel_counts(&c.camera, baker::accumulate::camera::jitter(b), &bvh, &targets)
                    .iter()
                    .enumerate()
                {
                    every[k] &= *n > 0;
                }
            }
            every.iter().zip(&keep).map(|(a, k)| *a && *k).collect()
        }
        None => keep.clone(),
    };
    let seen_count = seen.iter().filter(|k| **k).count();
    let seen_var: f64 =
        rse.iter().zip(&seen).filter(|(_, k)| **k).flat_map(|(s, _)| s.iter()).map(|s| s * s).sum::<f64>() / (3 * seen_count.max(1)) as f64;
    let mut target: Option<(f64, f64)> = None;
    println!("| configuration | first full preview (ms) | passes to target | paths to target | GPU s to target (median of {REPEATS}) | × vs baseline |");
    println!("|---|---|---|---|---|---|");
    let mut baseline_s = None;
    for (name, c) in configs {
        let mut b = GpuBake::new(&gpu, &tracer(), &targets, &c)?;
        // Warm-up (pipeline compilation, first-use costs of every kernel: a few uniform
        // passes and batches), then the state is reset to empty.
        b.run(c.adaptive.map_or(2, |a| a.pilot_passes + 2))?;
        let steps_to = |passes: u64| c.adaptive.map_or(passes, |a| a.batches_for(passes));
        let (mask, var) = if c.camera.is_some() { (&seen, seen_var) } else { (&keep, ref_var) };
        // The error curve (untimed): doubling steps from an empty state until the error is
        // at or below the target; the crossing is (previous step, this step).
        b.upload(&BakeState::new(&c, &targets))?;
        b.run(1)?;
        let mut done_passes = 1u64;
        let mut prev: Option<(f64, u64, u64)> = None; // (mse, passes, paths)
        let mut crossing = None;
        let limit = ref_passes.min(1 << 14);
        while done_passes <= limit {
            let next = (done_passes * 2).max(2);
            b.run(steps_to(next) - steps_to(done_passes))?;
            done_passes = next;
            let st = b.state()?;
            let e = mse(&st, &rm, mask, var);
            let paths: u64 = st.moments.iter().map(|m| m.count()).sum();
            if std::env::var_os("TTE_DEBUG").is_some() {
                eprintln!("{name}: {done_passes} steps, {paths} paths, rmse {:.4e}", e.sqrt());
            }
            if target.is_none() && done_passes >= target_passes {
                target = Some((e, mse(&st, &rm, &seen, seen_var)));
            }
            if let Some((all, on_seen)) = target {
                let tg = if c.camera.is_some() { on_seen } else { all };
                if e <= tg {
                    // Log-linear weight of the target between the previous step and this one.
                    crossing = Some(match prev {
                        Some((e0, p0, q0)) if e0 > tg => ((e0.ln() - tg.ln()) / (e0.ln() - e.ln()), (p0, q0), (done_passes, paths)),
                        _ => (1.0, (done_passes, paths), (done_passes, paths)),
                    });
                    break;
                }
            }
            prev = Some((e, done_passes, paths));
        }
        let last_rmse = prev.map_or(f64::NAN, |(e, _, _)| e.sqrt());
        // The timing (steady state): about 0.3 s of passes to bring the clocks up, then from
        // an empty state the first pass (the preview), the passes to the previous step and
        // on to the crossing step — uninterrupted (no read-back), REPEATS times.
        let warm = Instant::now();
        while warm.elapsed().as_secs_f64() < 0.3 {
            b.run(steps_to(8))?;
        }
        let mut runs = Vec::new();
        let lerp = |w: f64, a: f64, b: f64| (a.ln() + w * (b.ln() - a.ln())).exp();
        for _ in 0..REPEATS {
            let Some((w, (p0, q0), (p1, q1))) = crossing else { break };
            b.upload(&BakeState::new(&c, &targets))?;
            let t = Instant::now();
            b.run(1)?;
            let preview_ms = 1e3 * t.elapsed().as_secs_f64();
            b.run(steps_to(p0) - 1)?;
            let s0 = t.elapsed().as_secs_f64();
            b.run(steps_to(p1) - steps_to(p0))?;
            let s1 = t.elapsed().as_secs_f64();
            runs.push((preview_ms, Some((lerp(w, s0, s1), lerp(w, p0 as f64, p1 as f64), lerp(w, q0 as f64, q1 as f64)))));
        }
        if runs.is_empty() {
            runs.push((0.0, None));
        }
        // The median run by its time to target.
        runs.sort_by(|a, b| {
            let key = |r: &(f64, Option<(f64, f64, f64)>)| r.1.map_or(f64::INFINITY, |x| x.0);
            key(a).total_cmp(&key(b))
        });
        let (preview_ms, result) = runs[runs.len() / 2];
        let scope = if c.camera.is_some() { format!(" (error over the {seen_count} texels it sees)") } else { String::new() };
        match result {
            Some((s, p, q)) => {
                let base = *baseline_s.get_or_insert(s);
                println!("| {name}{scope} | {preview_ms:.1} | {p:.0} | {q:.3e} | {s:.3} | {:.2} |", base / s);
            }
            // Not reached: the error it got to instead (a filtered bake's blur is a floor).
            None => {
                println!("| {name}{scope} | — | not reached in {} passes (RMSE {last_rmse:.4e} there) | | | |", ref_passes.min(1 << 14))
            }
        }
    }
    if let Some((all, on_seen)) = target {
        println!(
            "target: E/π RMSE {:.4e} over every texel, {:.4e} over the camera's (the baseline's at {target_passes} passes)",
            all.sqrt(),
            on_seen.sqrt()
        );
    }
    Ok(())
}
