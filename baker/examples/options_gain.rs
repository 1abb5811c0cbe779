//! Measures the bake options — ray guiding, the denoiser and seam stitching —
//! as error against time: bakes of several pass counts with each combination against a
//! long unguided reference bake (another seed). Prints per pass count and option the bake
//! time, the post-process time, the RMS error of E/π and of the first SH coefficient over
//! valid texels (the reference's own standard error subtracted in quadrature), and the
//! gain over the plain bake at the same pass count.
//!
//! `cargo run --release -p baker --example options_gain -- [--gpu] [--scene cornell|slit]
//!  [--learn N] [--fraction m] [--tpu T] [--bounces B] [--images DIR] [reference passes]
//!  [passes…]` (defaults: CPU path, cornell, the CLI's learning passes and guided fraction,
//! 16 texels per unit, 4 bounces, 16384, 128). `--images` writes a preview PNG per option at
//! the first pass count.

use baker::accumulate::{Bake, BakeConfig, BakeState, BasisId, Targets};
use baker::estimator::trace::Tracer;
use baker::gpu::GpuBake;
use baker::layout::lightmap::Lightmap;
use baker::post::denoise::{denoise, DenoiseOptions};
use baker::post::images::LightmapImages;
use baker::sampling::guiding::GuidingOptions;
use baker::scene::bvh::Bvh;
use std::time::Instant;

fn config(seed: u64, bounces: u32, guiding: Option<GuidingOptions>) -> BakeConfig {
    BakeConfig { seed, max_bounces: bounces, bases: vec![BasisId::Sh2, BasisId::Ad9], guiding, ..Default::default() }
}

/// A bake's state and the wall time of its passes (GPU: the passes and the read-back;
/// set-up and pipeline compilation excluded — steady state).
fn bake(gpu: Option<&shaders::gpu::Gpu>, tracer: Tracer, targets: &Targets, cfg: BakeConfig, passes: u64) -> (BakeState, f64) {
    let mut t = Instant::now();
    let state = match gpu {
        Some(g) => {
            let mut b = GpuBake::new(g, &tracer, targets, &cfg).expect("GPU bake");
            g.wait().expect("set-up");
            t = Instant::now();
            b.run(passes).expect("GPU passes");
            b.state().expect("read-back")
        }
        None => {
            let mut b = Bake::new(cfg, targets, tracer);
            for _ in 0..passes {
                b.pass();
            }
            b.state
        }
    };
    (state, t.elapsed().as_secs_f64())
}

fn take(args: &mut Vec<String>, flag: &str) -> Option<String> {
    let i = args.iter().position(|a| a == flag)?;
    args.remove(i);
    Some(args.remove(i))
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let use_gpu = args.iter().position(|a| a == "--gpu").map(|i| args.remove(i)).is_some();
    let scene_name = take(&mut args, "--scene").unwrap_or_else(|| "cornell".into());
    let learn: Option<u64> = take(&mut args, "--learn").map(|s| s.parse().expect("--learn N"));
    let images = take(&mut args, "--images").map(std::path::PathBuf::from);
    let tpu: f32 = take(&mut args, "--tpu").map_or(16.0, |s| s.parse().expect("--tpu x"));
    let bounces: u32 = take(&mut args, "--bounces").map_or(4, |s| s.parse().expect("--bounces n"));
    let fraction: Option<f64> = take(&mut args, "--fraction").map(|s| s.parse().expect("--fraction m"));
    let nums: Vec<u64> = args.iter().map(|a| a.parse().expect("pass counts are integers")).collect();
    let ref_passes = nums.first().copied().unwrap_or(16384);
    let pass_list: Vec<u64> = if nums.len() > 1 { nums[1..].to_vec() } else { vec![128] };
    let gpu = if use_gpu { Some(shaders::gpu::Gpu::new().expect("--gpu needs an adapter")) } else { None };
    let device = gpu.as_ref().map_or("CPU (rayon)".to_string(), |g| g.adapter.clone());
    let scene = match scene_name.as_str() {
        "cornell" => baker::scene::cornell(),
        "slit" => baker::scene::slit(),
        other => panic!("unknown scene {other}"),
    };
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, tpu, 2).expect("built-in scene lays out");
    let targets = Targets::lightmap(&lm);
    let (rs, rt) = bake(gpu.as_ref(), Tracer::new(&scene, &bvh, bounces), &targets, config(2, bounces, None), ref_passes);
    let reference = LightmapImages::new(&lm, &targets, &rs);
    println!("device {device}; scene {scene_name}; reference: {ref_passes} passes in {rt:.2} s; {} clusters", targets.cluster_count);
    let valid: Vec<usize> = (0..lm.width * lm.height).filter(|t| reference.validity[*t] > 0.0).collect();
    let ref_var = |v: &[[f32; 3]]| {
        valid.iter().map(|t| (0..3).map(|c| (v[*t][c] as f64).powi(2)).sum::<f64>()).sum::<f64>() / (3 * valid.len()) as f64
    };
    let ref_se2 = ref_var(&reference.standard_error);
    // RMS difference from the reference with the reference's own variance subtracted;
    // None where that variance is more than half of the mean square (too close to call).
    let rms = |a: &[[f32; 3]], b: &[[f32; 3]], se2: f64| {
        let s: f64 = valid.iter().map(|t| (0..3).map(|c| ((a[*t][c] - b[*t][c]) as f64).powi(2)).sum::<f64>()).sum();
        let ms = s / (3 * valid.len().max(1)) as f64;
        (ms > 2.0 * se2).then(|| (ms - se2).sqrt())
    };
    let cell = |v: Option<f64>, base: Option<f64>| match (v, base) {
        (Some(v), Some(b)) => format!("{v:.5} | {:.2}×", b / v),
        (Some(v), None) => format!("{v:.5} | —"),
        (None, _) => "< 1.41 × reference σ | —".to_string(),
    };
    println!("{} valid texels; reference standard error (RMS) {:.5}", valid.len(), ref_se2.sqrt());
    println!("| passes | option | passes s | post s | E/π RMS | gain | SH c0 RMS | gain |");
    println!("|---|---|---|---|---|---|---|---|");
    for (pi, passes) in pass_list.into_iter().enumerate() {
        let d = GuidingOptions::for_passes(passes);
        let g = GuidingOptions { learn_passes: learn.unwrap_or(d.learn_passes), guided_fraction: fraction.unwrap_or(d.guided_fraction) };
        let mut base: Option<(Option<f64>, Option<f64>)> = None;
        let mut shots = Vec::new();
        for (guided, post) in [(false, 0), (true, 0), (false, 1), (true, 1), (true, 2)] {
            let (st, bt) =
                bake(gpu.as_ref(), Tracer::new(&scene, &bvh, bounces), &targets, config(1, bounces, guided.then_some(g)), passes);
            let mut img = LightmapImages::new(&lm, &targets, &st);
            let t = Instant::now();
            if post >= 1 {
                denoise(&mut img, &lm, DenoiseOptions::default()).expect("sizes agree");
            }
            if post >= 2 {
                let samples = baker::post::seams::samples(&baker::post::seams::find_seams(&scene, &lm), lm.width, lm.height);
                let mut dilated = img.clone();
                dilated.dilate(3);
                baker::post::seams::stitch(&mut img, &dilated, &samples);
            }
            let pt = t.elapsed().as_secs_f64();
            let e = rms(&img.irradiance, &reference.irradiance, ref_se2);
            let c0 = rms(&img.coefficients[0][0], &reference.coefficients[0][0], 0.0);
            let (e0, c00) = *base.get_or_insert((e, c0));
            let name = match (guided, post) {
                (false, 0) => "plain".to_string(),
                (true, 0) => format!("guiding (learn {})", g.learn_passes),
                (false, 1) => "denoise".to_string(),
                (true, 1) => "guiding + denoise".to_string(),
                _ => "guiding + denoise + stitch".to_string(),
            };
            println!("| {passes} | {name} | {bt:.3} | {pt:.3} | {} | {} |", cell(e, e0), cell(c0, c00));
            if images.is_some() && pi == 0 {
                shots.push(baker::output::preview(&scene, &bvh, &lm, &img, 480, None));
            }
        }
        if let (Some(dir), false) = (&images, shots.is_empty()) {
            // One strip per scene: plain, guiding, denoise, guiding + denoise, + stitch.
            std::fs::create_dir_all(dir).expect("image folder");
            let (w, h) = (shots[0].width(), shots[0].height());
            let mut strip = image::RgbImage::new(w * shots.len() as u32, h);
            for (k, s) in shots.iter().enumerate() {
                image::imageops::replace(&mut strip, s, (k as u32 * w) as i64, 0);
            }
            let file = dir.join(format!("{scene_name}_{passes}.png"));
            baker::output::save_png(&file, &strip).expect("preview strip");
            println!("previews (plain, guiding, denoise, guiding + denoise, + stitch): {}", file.display());
        }
    }
}
