//! Measures the lightmap denoiser on a scene: bakes of several pass counts with and without
//! `--denoise` (window radius 3, 5, 7) against one long reference bake (another seed).
//! Prints, per pass count, the bake time, the filter time and the RMS error of E/π and of
//! the first SH coefficient over valid texels, the reference's own standard error, and the
//! bias the filter adds: the largest change of a chart's mean E/π it causes, and the
//! largest distance of a denoised chart mean from the reference's against the raw bake's.
//!
//! `cargo run --release -p baker --example denoise_gain -- [--gpu] [--scene NAME|PATH]
//! [--texels-per-unit T] [reference passes] [passes…]` (defaults: CPU path, the built-in
//! scene at 16 texels per unit, 16384, 128; the CPU reference takes ~6 minutes on 2 cores).
//! The documented figures (docs/baker.md) use `--gpu` and a 65 536-pass reference.

use baker::accumulate::{Bake, BakeConfig, BakeState, BasisId, Targets};
use baker::estimator::trace::Tracer;
use baker::gpu::GpuBake;
use baker::layout::lightmap::Lightmap;
use baker::post::denoise::{denoise, DenoiseOptions};
use baker::post::images::LightmapImages;
use baker::scene::bvh::Bvh;
use std::time::Instant;

fn config(seed: u64) -> BakeConfig {
    BakeConfig { seed, bases: vec![BasisId::Sh2, BasisId::Ad9], ..Default::default() }
}

/// A bake's state and its wall time (GPU: including the read-back).
fn bake(gpu: Option<&shaders::gpu::Gpu>, tracer: Tracer, targets: &Targets, seed: u64, passes: u64) -> (BakeState, f64) {
    let t = Instant::now();
    let state = match gpu {
        Some(g) => {
            let mut b = GpuBake::new(g, &tracer, targets, &config(seed)).expect("GPU bake");
            b.run(passes).expect("GPU passes");
            b.state().expect("read-back")
        }
        None => {
            let mut b = Bake::new(config(seed), targets, tracer);
            for _ in 0..passes {
                b.pass();
            }
            b.state
        }
    };
    (state, t.elapsed().as_secs_f64())
}

/// Removes `--name VALUE` from `args` and returns VALUE.
fn take(args: &mut Vec<String>, name: &str) -> Option<String> {
    let i = args.iter().position(|a| a == name)?;
    args.remove(i);
    (i < args.len()).then(|| args.remove(i))
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let use_gpu = args.iter().position(|a| a == "--gpu").map(|i| args.remove(i)).is_some();
    let scene_name = take(&mut args, "--scene").unwrap_or_else(|| "cornell".into());
    let tpu: f32 = take(&mut args, "--texels-per-unit").map_or(16.0, |t| t.parse().expect("--texels-per-unit takes a number"));
    let nums: Vec<u64> = args.iter().map(|a| a.parse().expect("pass counts are integers")).collect();
    let ref_passes = nums.first().copied().unwrap_or(16384);
    let pass_list: Vec<u64> = if nums.len() > 1 { nums[1..].to_vec() } else { vec![128] };
    let gpu = if use_gpu { Some(shaders::gpu::Gpu::new().expect("--gpu needs an adapter")) } else { None };
    let device = gpu.as_ref().map_or("CPU (rayon)".to_string(), |g| g.adapter.clone());
    let scene = baker::scene::load::load(&scene_name, None, &mut |l| eprintln!("{l}")).expect("scene loads");
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, tpu, 2).expect("the scene lays out");
    let targets = Targets::lightmap(&lm);
    let (rs, rt) = bake(gpu.as_ref(), Tracer::new(&scene, &bvh, 4), &targets, 2, ref_passes);
    let reference = LightmapImages::new(&lm, &targets, &rs);
    println!(
        "scene '{scene_name}' at {tpu} texels per unit ({}×{} atlas); device {device}; reference: {ref_passes} passes in {rt:.2} s",
        lm.width, lm.height
    );
    let valid: Vec<usize> = (0..lm.width * lm.height).filter(|t| reference.validity[*t] > 0.0).collect();
    let rms = |a: &[[f32; 3]], b: &[[f32; 3]], on: &[usize]| {
        let s: f64 = on.iter().map(|t| (0..3).map(|c| ((a[*t][c] - b[*t][c]) as f64).powi(2)).sum::<f64>()).sum();
        (s / (3 * on.len().max(1)) as f64).sqrt()
    };
    let ref_se = (valid.iter().map(|t| (0..3).map(|c| (reference.standard_error[*t][c] as f64).powi(2)).sum::<f64>()).sum::<f64>()
        / (3 * valid.len()) as f64)
        .sqrt();
    println!("{} valid texels; reference standard error (RMS) {ref_se:.5}", valid.len());
    println!("| passes | bake s | E/π RMS raw | radius 3 | radius 5 | radius 7 | SH c0 raw → radius 5 | filter s (r 5) | worst chart mean change (r 5) | worst chart mean vs reference: raw → r 5 |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for passes in pass_list {
        let (st, bt) = bake(gpu.as_ref(), Tracer::new(&scene, &bvh, 4), &targets, 1, passes);
        let noisy = LightmapImages::new(&lm, &targets, &st);
        let on: Vec<usize> = valid.iter().copied().filter(|t| noisy.validity[*t] > 0.0).collect();
        let mut cells = Vec::new();
        let (mut c5, mut f5, mut worst) = (0.0, 0.0, 0.0f64);
        let (mut off_raw, mut off_den) = (0.0f64, 0.0f64);
        for radius in [3, 5, 7] {
            let mut f = noisy.clone();
            let t = Instant::now();
            denoise(&mut f, &lm, DenoiseOptions { radius, ..Default::default() }).expect("sizes agree");
            let ft = t.elapsed().as_secs_f64();
            cells.push(rms(&f.irradiance, &reference.irradiance, &on));
            if radius == 5 {
                (c5, f5) = (rms(&f.coefficients[0][0], &reference.coefficients[0][0], &on), ft);
                for ch in 0..lm.chart_meshes.len() as u32 {
                    let ts: Vec<usize> = on.iter().copied().filter(|t| lm.texels[*t].chart == ch).collect();
                    if !ts.is_empty() {
                        let m = |v: &[[f32; 3]]| ts.iter().map(|t| v[*t].iter().sum::<f32>() as f64).sum::<f64>();
                        worst = worst.max((m(&f.irradiance) / m(&noisy.irradiance) - 1.0).abs());
                        let r = m(&reference.irradiance);
                        off_raw = off_raw.max((m(&noisy.irradiance) / r - 1.0).abs());
                        off_den = off_den.max((m(&f.irradiance) / r - 1.0).abs());
                    }
                }
            }
        }
        let raw = rms(&noisy.irradiance, &reference.irradiance, &on);
        let c0 = rms(&noisy.coefficients[0][0], &reference.coefficients[0][0], &on);
        println!(
            "| {passes} | {bt:.2} | {raw:.5} | {:.5} ({:.2}×) | {:.5} ({:.2}×) | {:.5} ({:.2}×) | {c0:.5} → {c5:.5} | {f5:.3} | {:.2}% | {:.2}% → {:.2}% |",
            cells[0],
            raw / cells[0],
            cells[1],
            raw / cells[1],
            cells[2],
            raw / cells[2],
            100.0 * worst,
            100.0 * off_raw,
            100.0 * off_den
        );
    }
}
