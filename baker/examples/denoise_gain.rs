//! Measures the lightmap denoiser on the built-in scene (issue 16): a bake of `passes`
//! passes with and without `--denoise` against a long reference bake (another seed), on
//! the CPU path (the same estimator as the GPU's). Prints the RMS error of E/π and of the
//! first basis's coefficients over valid texels, the reference's own standard error, and
//! the largest change of a chart's mean E/π caused by the filter.
//!
//! `cargo run --release -p baker --example denoise_gain -- [passes] [reference passes]`
//! (defaults 128 and 16384; the reference takes ~4 minutes on 2 cores).

use baker::bake::{Bake, BakeConfig, BasisKind, Solver, Targets};
use baker::bvh::Bvh;
use baker::denoise::{denoise, DenoiseOptions};
use baker::lightmap::Lightmap;
use baker::output::LightmapImages;
use baker::trace::Tracer;
use std::time::Instant;

fn bake(scene: &baker::scene::Scene, bvh: &Bvh, lm: &Lightmap, targets: &Targets, seed: u64, passes: u64) -> LightmapImages {
    let cfg = BakeConfig { seed, max_bounces: 4, bases: vec![BasisKind::ShL2, BasisKind::Ad9], solver: Solver::Nnls };
    let mut b = Bake::new(cfg, targets, Tracer::new(scene, bvh, 4));
    for _ in 0..passes {
        b.pass();
    }
    LightmapImages::new(lm, targets, &b.state)
}

fn main() {
    let args: Vec<u64> = std::env::args().skip(1).map(|a| a.parse().expect("passes are integers")).collect();
    let (passes, ref_passes) = (args.first().copied().unwrap_or(128), args.get(1).copied().unwrap_or(16384));
    let scene = baker::scene::cornell();
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, 16.0, 2).expect("built-in scene lays out");
    let targets = Targets::lightmap(&lm);
    let t = Instant::now();
    let reference = bake(&scene, &bvh, &lm, &targets, 2, ref_passes);
    eprintln!("reference: {ref_passes} passes in {:.1} s", t.elapsed().as_secs_f64());
    let noisy = bake(&scene, &bvh, &lm, &targets, 1, passes);
    let mut filtered = noisy.clone();
    let t = Instant::now();
    let st = denoise(&mut filtered, &lm, DenoiseOptions::default()).expect("sizes agree");
    let filter_s = t.elapsed().as_secs_f64();
    let valid: Vec<usize> = (0..lm.width * lm.height).filter(|t| noisy.validity[*t] > 0.0 && reference.validity[*t] > 0.0).collect();
    let rms = |a: &[[f32; 3]], b: &[[f32; 3]]| {
        let s: f64 = valid.iter().map(|t| (0..3).map(|c| ((a[*t][c] - b[*t][c]) as f64).powi(2)).sum::<f64>()).sum();
        (s / (3 * valid.len()) as f64).sqrt()
    };
    let ref_se = (valid.iter().map(|t| (0..3).map(|c| (reference.standard_error[*t][c] as f64).powi(2)).sum::<f64>()).sum::<f64>()
        / (3 * valid.len()) as f64)
        .sqrt();
    let mean_e = valid.iter().map(|t| reference.irradiance[*t].iter().sum::<f32>() as f64).sum::<f64>() / (3 * valid.len()) as f64;
    let (e0, e1) = (rms(&noisy.irradiance, &reference.irradiance), rms(&filtered.irradiance, &reference.irradiance));
    let (c0, c1) =
        (rms(&noisy.coefficients[0][0], &reference.coefficients[0][0]), rms(&filtered.coefficients[0][0], &reference.coefficients[0][0]));
    println!("built-in scene, {} valid texels, mean E/π {mean_e:.4}", valid.len());
    println!("E/π RMS vs {ref_passes}-pass reference: {passes} passes {e0:.5}, denoised {e1:.5} ({:.2}× lower); reference's own standard error {ref_se:.5}", e0 / e1);
    println!("SH L2 coefficient 0 RMS: {c0:.5} → {c1:.5} ({:.2}×)", c0 / c1);
    let mut worst: f64 = 0.0;
    for ch in 0..lm.chart_meshes.len() as u32 {
        let ts: Vec<usize> = valid.iter().copied().filter(|t| lm.texels[*t].chart == ch).collect();
        if ts.is_empty() {
            continue;
        }
        let m = |v: &[[f32; 3]]| ts.iter().map(|t| v[*t].iter().sum::<f32>() as f64).sum::<f64>() / (3 * ts.len()) as f64;
        worst = worst.max((m(&filtered.irradiance) / m(&noisy.irradiance) - 1.0).abs());
    }
    println!("largest change of a chart's mean E/π by the filter: {:.3}%", 100.0 * worst);
    println!("filter: {} texels, {:.1} effective neighbours, {filter_s:.3} s", st.texels, st.mean_effective_neighbours);
}
