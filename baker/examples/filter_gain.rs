//! Filtered gather-based accumulation ([Roughton19 §3.2]) measured: for no filter, box,
//! Gaussian and Mitchell (radius 1.5), the texels a chart overlaps that are still empty
//! before dilation, the E/π RMSE at equal paths against a long unfiltered reference bake
//! (over texels valid in both), and the seconds per pass (GPU: one dispatch per pass
//! over every texel; after a warm-up, five rounds timing each configuration in turn, the
//! median per configuration).
//!
//!     cargo run --release -p baker --example filter_gain -- [scene] [texels/unit] [passes] [reference passes] [pipeline]
//!
//! Defaults: the built-in Cornell box, 4 texels/unit, 16 passes, 1024 reference passes,
//! megakernel. On a machine without a hardware GPU the CPU bake runs (slowly).

use baker::accumulate::filter::Filter;
use baker::accumulate::{Bake, BakeConfig, BakeState, BasisId, Pipeline, Solver, Targets};
use baker::estimator::trace::Tracer;
use baker::layout::lightmap::{Lightmap, NO_CHART};
use baker::post::images::LightmapImages;
use baker::scene::bvh::Bvh;
use std::time::Instant;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene_name = args.first().map_or("cornell", |s| s.as_str());
    let tpu: f32 = args.get(1).map_or(Ok(4.0), |s| s.parse()).map_err(|e| format!("texels/unit: {e}"))?;
    let passes: u64 = args.get(2).map_or(Ok(16), |s| s.parse()).map_err(|e| format!("passes: {e}"))?;
    let ref_passes: u64 = args.get(3).map_or(Ok(1024), |s| s.parse()).map_err(|e| format!("reference passes: {e}"))?;
    let pipeline = args.get(4).map_or(Some(Pipeline::Megakernel), |s| Pipeline::parse(s)).ok_or("pipeline: megakernel or wavefront")?;
    let scene = baker::scene::load::load(scene_name, None, &mut |_| {})?;
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, tpu, 2).map_err(|e| e.to_string())?;
    let targets = Targets::lightmap(&lm);
    let overlapped = lm.texel_charts.iter().filter(|c| **c != NO_CHART).count();
    println!(
        "{scene_name} at {tpu} texels/unit: {}×{} atlas, {} covered texels, {} overlapped but uncovered; {passes} passes vs a {ref_passes}-pass reference; {}",
        lm.width,
        lm.height,
        targets.items.len(),
        overlapped - targets.items.len(),
        pipeline.name()
    );
    let gpu = shaders::gpu::Gpu::new().ok().filter(|g| !g.software);
    println!("device: {}", gpu.as_ref().map_or("CPU (no hardware GPU)".to_string(), |g| g.adapter.clone()));
    let config = |filter: Option<Filter>, seed: u64| BakeConfig {
        seed,
        bases: vec![BasisId::Sh1],
        solver: Solver::Ls,
        pipeline,
        filter,
        ..Default::default()
    };
    let names = ["none", "box", "gaussian", "mitchell"];
    let filters: Vec<Option<Filter>> =
        names.iter().map(|n| if *n == "none" { Ok(None) } else { Filter::parse(n).map(Some) }).collect::<Result<_, _>>()?;
    let tracer = Tracer::new(&scene, &bvh, config(None, 0).max_bounces);
    // A bake of n passes (the GPU: one dispatch per pass over every texel, so every
    // configuration runs the same dispatches).
    let fixed = |b: &mut baker::gpu::GpuBake| {
        b.set_batch_target(None);
        b.set_chunk(targets.items.len());
    };
    let state = |cfg: &BakeConfig, n: u64| -> Result<BakeState, String> {
        match &gpu {
            Some(g) => {
                let mut b = baker::gpu::GpuBake::new(g, &tracer, &targets, cfg)?;
                fixed(&mut b);
                b.run(n)?;
                b.state()
            }
            None => {
                let mut b = Bake::new(cfg.clone(), &targets, Tracer::new(&scene, &bvh, cfg.max_bounces));
                for _ in 0..n {
                    b.pass();
                }
                Ok(b.state)
            }
        }
    };
    // Seconds per pass: one bake per configuration, warmed up, then five rounds that time
    // n passes of each in turn (so clock changes hit all alike); the median per configuration.
    let per_pass: Vec<f64> = match &gpu {
        Some(g) => {
            let mut bakes = filters
                .iter()
                .map(|f| {
                    let mut b = baker::gpu::GpuBake::new(g, &tracer, &targets, &config(*f, 7))?;
                    fixed(&mut b);
                    b.run(16)?;
                    Ok(b)
                })
                .collect::<Result<Vec<_>, String>>()?;
            let mut times = vec![Vec::new(); bakes.len()];
            for _ in 0..5 {
                for (b, t) in bakes.iter_mut().zip(times.iter_mut()) {
                    let t0 = Instant::now();
                    b.run(passes)?;
                    t.push(t0.elapsed().as_secs_f64() / passes as f64);
                }
            }
            times
                .into_iter()
                .map(|mut t| {
                    t.sort_by(f64::total_cmp);
                    t[t.len() / 2]
                })
                .collect()
        }
        None => filters
            .iter()
            .map(|f| {
                let t0 = Instant::now();
                state(&config(*f, 7), passes)?;
                Ok(t0.elapsed().as_secs_f64() / passes as f64)
            })
            .collect::<Result<_, String>>()?,
    };
    let reference = LightmapImages::new(&lm, &targets, &state(&config(None, 1_000_003), ref_passes)?);
    println!("{:<12} {:>8} {:>12} {:>10} {:>12}", "filter", "empty", "RMSE E/π", "vs none", "ms/pass");
    let mut base = None;
    for ((name, filter), per) in names.iter().zip(&filters).zip(&per_pass) {
        let st = state(&config(*filter, 7), passes)?;
        let img = LightmapImages::new(&lm, &targets, &st);
        let empty = (0..lm.texels.len()).filter(|t| lm.texel_charts[*t] != NO_CHART && img.validity[*t] == 0.0).count();
        let (mut sum, mut n) = (0.0f64, 0usize);
        for t in 0..lm.texels.len() {
            if img.validity[t] > 0.0 && reference.validity[t] > 0.0 {
                for c in 0..3 {
                    sum += (img.irradiance[t][c] as f64 - reference.irradiance[t][c] as f64).powi(2);
                    n += 1;
                }
            }
        }
        let rmse = (sum / n.max(1) as f64).sqrt();
        let b = *base.get_or_insert(rmse);
        println!("{name:<12} {empty:>8} {rmse:>12.5} {:>9.2}× {:>12.3}", b / rmse, per * 1e3);
    }
    Ok(())
}
