//! First-bounce ray guiding (`baker::sampling::guiding`, \[HWRTL\]): the learned distribution and its
//! sampler against their definitions, the GPU build against its CPU twin, unbiasedness
//! against the unguided bake (furnace and the built-in scene, per chart), the gain on a
//! room lit through a slit, determinism and resume. (The closed-form scenes are in
//! `transport.rs`: `guided_bakes_match_the_closed_forms` and
//! `guided_disk_light_texel_encodings_match_their_projections`.)
//!
//! Mutations tried, each caught: the distribution rebuilt after every pass from one
//! quasi-random sequence (the first design: +0.3% on the furnace, 3.97σ here); the GPU
//! gather adding into the wrong bins (GPU slit gain 1.11×); the guided pdf ×1.05 on the CPU
//! or in WGSL, the light samples' MIS against the uniform pdf, the estimate weighted 2cosθ,
//! the encoders' weight left at 1 (the transport tests).

mod common;
use baker::accumulate::{Bake, BakeConfig, BakeState, BasisId, Solver, Targets};
use baker::estimator::trace::Tracer;
use baker::gpu::GpuBake;
use baker::layout::lightmap::Lightmap;
use baker::sampling::guiding::{self, GuidingOptions, BINS, BIN_COUNT};
use baker::scene::bvh::Bvh;
use baker::scene::Scene;
use common::gpu;
use sbf::sampling::Pcg32;
use std::f64::consts::PI;

fn config(seed: u64, guiding: Option<GuidingOptions>) -> BakeConfig {
    BakeConfig { seed, bases: vec![BasisId::Sh2], solver: Solver::Ls, guiding, ..Default::default() }
}

fn cpu_bake(scene: &Scene, targets: &Targets, cfg: &BakeConfig, passes: u64) -> BakeState {
    let bvh = Bvh::build(scene);
    let mut b = Bake::new(cfg.clone(), targets, Tracer::new(scene, &bvh, cfg.max_bounces));
    for _ in 0..passes {
        b.pass();
    }
    b.state
}

/// The build path a guided GPU bake of `targets` takes on this device.
fn bake_path(g: &shaders::gpu::Gpu, scene: &Scene, targets: &Targets, cfg: &BakeConfig) -> baker::gpu::GuideBuild {
    let bvh = Bvh::build(scene);
    GpuBake::new(g, &Tracer::new(scene, &bvh, cfg.max_bounces), targets, cfg).unwrap().guide_build_path().expect("guided")
}

fn gpu_bake(g: &shaders::gpu::Gpu, scene: &Scene, targets: &Targets, cfg: &BakeConfig, passes: u64) -> (BakeState, Option<Vec<f32>>) {
    let bvh = Bvh::build(scene);
    let mut b = GpuBake::new(g, &Tracer::new(scene, &bvh, cfg.max_bounces), targets, cfg).unwrap();
    b.run(passes).unwrap();
    (b.state().unwrap(), b.guide_distributions().unwrap())
}

/// Sums with a structure: a bright patch, a ramp, empty rows, and (cluster 2) nothing.
fn test_sums(clusters: usize, seed: u64) -> Vec<f32> {
    let mut r = Pcg32::new(seed, 0);
    let mut s = vec![0f32; clusters * BIN_COUNT];
    for c in 0..clusters {
        if c % 4 == 2 {
            continue;
        }
        for b in 0..BIN_COUNT {
            let (x, y) = (b % BINS, b / BINS);
            let patch = if (5..8).contains(&x) && (9..11).contains(&y) { 40.0 } else { 0.0 };
            let v = if y == 3 || y == 4 { 0.0 } else { patch + (x as f64 * 0.1) * r.next_f64() };
            s[c * BIN_COUNT + b] = v as f32;
        }
    }
    s
}

/// The relaxation against its definition on one bright bin (sums δ at bin b₀): a bin's
/// value is Σ_l w_l·(mean of its level-l ancestor), w = ½, ¼, ⅛, 1/16, 1/16, and the
/// level-l ancestor of b₀ has mean 1/4^l — so the probability of each bin is known in
/// closed form. Also: probabilities sum to 1, an empty cluster is uniform.
#[test]
fn relaxation_and_cdf_match_their_definition() {
    let b0 = 9 * BINS + 6;
    let mut sums = vec![0f32; BIN_COUNT];
    sums[b0] = 3.0;
    let dist = guiding::build(&sums);
    let w = [0.5, 0.25, 0.125, 0.0625, 0.0625];
    let mut want = [0f64; BIN_COUNT];
    for (b, v) in want.iter_mut().enumerate() {
        let (x, y, x0, y0) = (b % BINS, b / BINS, b0 % BINS, b0 / BINS);
        for (l, wl) in w.iter().enumerate() {
            if x >> l == x0 >> l && y >> l == y0 >> l {
                *v += wl * 3.0 / 4f64.powi(l as i32);
            }
        }
    }
    let total: f64 = want.iter().sum();
    let mut sum_p = 0.0;
    for (b, v) in want.iter().enumerate() {
        let p = guiding::bin_probability(&dist, b) as f64;
        sum_p += p;
        // f32 CDFs: each probability is a product of two differences of numbers ≤ 1
        // accumulated over ≤ 16 f32 additions: |error| ≤ ~64·2⁻²⁴.
        assert!((p - v / total).abs() < 64.0 * 2f64.powi(-24), "bin {b}: {p} vs {}", v / total);
    }
    assert!((sum_p - 1.0).abs() < 1e-6, "{sum_p}");
    let empty = guiding::build(&vec![0f32; BIN_COUNT]);
    for b in 0..BIN_COUNT {
        assert!((guiding::bin_probability(&empty, b) as f64 - 1.0 / 256.0).abs() < 1e-8);
    }
}

/// The sampler draws bins with the probabilities the pdf reports (χ² over the 256 bins,
/// 200 000 samples), every sample lies in its bin's cell of the concentric square, and the
/// solid-angle pdf integrates to 1 (each bin 2π/256 sr: Σ p_b·256/2π·2π/256 = 1).
#[test]
fn sampler_follows_the_pdf() {
    let sums = test_sums(1, 3);
    let dist = guiding::build(&sums);
    let n = 200_000usize;
    let mut counts = vec![0f64; BIN_COUNT];
    let mut r = Pcg32::new(4, 0);
    for _ in 0..n {
        let [a, b] = r.next_2d();
        let d = guiding::sample_guided(&dist, [a as f32, b as f32]);
        assert!((d.length() - 1.0).abs() < 1e-6 && d.z >= 0.0);
        counts[guiding::bin_of(d)] += 1.0;
        let p = guiding::guided_pdf(&dist, d);
        assert!(p > 0.0 && p.is_finite());
    }
    let mut chi2 = 0.0;
    let mut dof = 0;
    for (b, c) in counts.iter().enumerate() {
        let e = n as f64 * guiding::bin_probability(&dist, b) as f64;
        if e > 0.0 {
            chi2 += (c - e).powi(2) / e;
            dof += 1;
        } else {
            assert_eq!(*c, 0.0, "bin {b} has probability 0 but was drawn");
        }
    }
    // χ² with dof − 1 degrees of freedom: mean k, sd √(2k); 5 sd is far beyond chance.
    let k = (dof - 1) as f64;
    assert!(chi2 < k + 5.0 * (2.0 * k).sqrt(), "χ² {chi2:.1} for {k} dof");
    // A sampler that ignored the CDF (uniform u) must fail the same test (power).
    let uniform: f64 = (0..BIN_COUNT).map(|b| (n as f64 / 256.0 - n as f64 * guiding::bin_probability(&dist, b) as f64).powi(2)).sum();
    assert!(uniform > 100.0 * k, "the test has no power: {uniform}");
    let integral: f64 = (0..BIN_COUNT).map(|b| guiding::bin_probability(&dist, b) as f64).sum();
    assert!((integral - 1.0).abs() < 1e-6);
    // The mixture pdf integrates to 1 too, by a fine midpoint rule on the square.
    let m = 64;
    let mut acc = 0.0;
    for i in 0..m {
        for j in 0..m {
            let d = sbf::sampling::uniform_hemisphere_concentric([(i as f64 + 0.5) / m as f64, (j as f64 + 0.5) / m as f64]);
            acc += guiding::mixture_pdf(&dist, d, 0.5) * 2.0 * PI / (m * m) as f64;
        }
    }
    assert!((acc - 1.0).abs() < 1e-6, "∫ mixture pdf = {acc}");
}

/// The GPU's gather and build agree with the CPU twin: after a guided GPU bake the
/// distributions it built equal `guiding::build` of the sums it learned. Error model: the
/// same f32 operations in the same order; a GPU may contract a·b + c into one rounding,
/// so each CDF entry (≤ 16 additions of values ≤ the cluster total, then a division) may
/// differ by a few ulp of 1: 1e-5 absolute.
#[test]
fn gpu_build_matches_the_cpu_twin() {
    let Some(g) = gpu() else { return };
    let scene = baker::scene::slit();
    let lm = Lightmap::build(&scene, 8.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let cfg = config(5, Some(GuidingOptions { learn_passes: 4, guided_fraction: 0.5 }));
    let (st, dist) = gpu_bake(&g, &scene, &targets, &cfg, 12);
    let dist = dist.expect("built after the learning passes");
    assert_eq!(st.guide_sums.len(), targets.cluster_count * BIN_COUNT);
    let learned = (0..targets.cluster_count).filter(|c| st.guide_sums[c * BIN_COUNT..(c + 1) * BIN_COUNT].iter().any(|v| *v > 0.0)).count();
    assert!(learned * 2 > targets.cluster_count, "only {learned} of {} clusters learned anything", targets.cluster_count);
    // 12 passes with 4 learning: the last build was at pass 8 (stage 2), from the basis.
    assert_eq!(guiding::stage(11, 4), (2, 8));
    assert_ne!(st.guide_basis, st.guide_sums);
    let cpu = guiding::build(&st.guide_basis);
    let worst = cpu.iter().zip(&dist).map(|(a, b)| (a - b).abs()).fold(0f32, f32::max);
    let path = bake_path(&g, &scene, &targets, &cfg);
    println!("{} clusters ({learned} learned), {path:?} build, worst |CPU − GPU| CDF entry {worst:.2e}", targets.cluster_count);
    // Every CDF is non-decreasing and ends at exactly 1 (what the sampler relies on).
    for c in dist.chunks(guiding::CDF_LEN) {
        for row in c.chunks(BINS) {
            assert!(row.windows(2).all(|w| w[0] <= w[1]) && row[BINS - 1] == 1.0, "{path:?}: {row:?}");
        }
    }
    assert!(worst < 1e-5, "GPU build differs from the CPU twin by {worst}");
}

/// Both build kernels are valid WGSL (the subgroup one with the subgroup capabilities): CI's
/// lavapipe has subgroups of 8 and runs the workgroup build only.
#[test]
fn guide_kernels_validate() {
    let (fallback, subgroup) = baker::gpu::guide_build_sources().unwrap();
    shaders::export::validate(&fallback).unwrap();
    shaders::export::validate_subgroups(&subgroup).unwrap();
    assert!(shaders::export::validate(&subgroup).is_err(), "the subgroup kernel must need the subgroup capability");
}

/// Per-chart and scene means of E/π with their variances ([`BakeState::chart_means`]).
fn chart_means(lm: &Lightmap, targets: &Targets, st: &BakeState) -> Vec<(f64, f64)> {
    st.chart_means(lm, targets)
}

/// Guiding is unbiased where no closed form is at hand: on the furnace (every texel's
/// E/π = le·Σ_{k≤4} a^k = 1.9375 for 4 bounces at albedo ½, also checked) and on the built-in scene (sun, sky through
/// the window, an area light, glossy block), the guided bake's mean E/π per chart and over
/// the scene agrees with the unguided bake's within 3σ (σ² = the sum of both bakes'
/// variances of that mean, from their per-texel standard errors), on the CPU and the GPU.
#[test]
fn guided_bakes_agree_with_unguided_ones_per_chart() {
    let mut engines: Vec<(&str, Option<shaders::gpu::Lease>)> = vec![("CPU", None)];
    if let Some(g) = gpu() {
        engines.push(("GPU", Some(g)));
    }
    for (scene, passes, tpu) in [(baker::scene::furnace(1.0, 0.5), 128u64, 8.0f32), (baker::scene::cornell(), 256, 8.0)] {
        let lm = Lightmap::build(&scene, tpu, 2).unwrap();
        let targets = Targets::lightmap(&lm);
        for (name, g) in &engines {
            let run = |guiding| {
                let cfg = config(3, guiding);
                match g.as_deref() {
                    Some(g) => gpu_bake(g, &scene, &targets, &cfg, passes).0,
                    None => cpu_bake(&scene, &targets, &cfg, passes),
                }
            };
            let plain = chart_means(&lm, &targets, &run(None));
            let guided = chart_means(&lm, &targets, &run(Some(GuidingOptions { learn_passes: 16, guided_fraction: 0.5 })));
            let mut worst = 0f64;
            for (k, ((a, va), (b, vb))) in plain.iter().zip(&guided).enumerate() {
                let z = (a - b).abs() / (va + vb).sqrt();
                worst = worst.max(z);
                let what = if k + 1 == plain.len() { "scene".to_string() } else { format!("chart {k}") };
                assert!(z <= 3.0, "{name} {}: {what} guided {b:.5} vs unguided {a:.5} ({z:.2}σ)", scene.name);
            }
            if scene.name == "furnace" {
                let (b, vb) = guided[guided.len() - 1];
                assert!((b - 1.9375).abs() <= 3.0 * vb.sqrt() + 1e-5, "{name} furnace guided mean {b} vs 1.9375");
            }
            println!("{name} {}: {} charts, worst |guided − unguided| {worst:.2}σ", scene.name, plain.len() - 1);
        }
    }
}

/// Guiding helps where it should: the `slit` scene (a dark room lit by the sky through a
/// 0.1 m × 1.2 m slit) at 256 passes, 4 bounces, 8 learning passes: RMS error of E/π over
/// valid texels against a 2 048-pass unguided reference (another seed; its variance is an
/// eighth of a 256-pass bake's), the reference's own variance (its mean squared standard
/// error) subtracted. Asserts the guided bake's
/// error is below the unguided one's by more than 1.3× on the CPU and on the
/// GPU (whose learning records, gather and build are thereby checked to do their job);
/// prints the ratio with its standard deviation (delta method over the per-texel squared
/// errors).
#[test]
fn guiding_lowers_the_error_in_a_room_lit_through_a_slit() {
    let scene = baker::scene::slit();
    let lm = Lightmap::build(&scene, 16.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let reference = cpu_bake(&scene, &targets, &config(100, None), 2048);
    let (rm, rse) = (reference.mean(), reference.standard_error());
    let ref_var: f64 = rse.iter().flatten().map(|s| s * s).sum::<f64>() / (3 * rse.len()) as f64;
    let errors = |st: &BakeState| -> Vec<f64> {
        st.mean().iter().zip(&rm).map(|(a, b)| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>() / 3.0).collect()
    };
    let guiding = Some(GuidingOptions { learn_passes: 8, guided_fraction: 0.5 });
    let mut engines: Vec<(&str, Option<shaders::gpu::Lease>)> = vec![("CPU", None)];
    if let Some(g) = gpu() {
        engines.push(("GPU", Some(g)));
    }
    for (name, g) in &engines {
        let run = |guiding| match g.as_deref() {
            Some(g) => gpu_bake(g, &scene, &targets, &config(1, guiding), 256).0,
            None => cpu_bake(&scene, &targets, &config(1, guiding), 256),
        };
        let (plain, guided) = (errors(&run(None)), errors(&run(guiding)));
        let n = plain.len() as f64;
        let (mp, mg) = (plain.iter().sum::<f64>() / n, guided.iter().sum::<f64>() / n);
        let (ep, eg) = ((mp - ref_var).max(0.0), (mg - ref_var).max(1e-30));
        let ratio = (ep / eg).sqrt();
        // σ of each mean square error, then of the ratio of square roots (independent bakes).
        let sd = |v: &[f64], m: f64| (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        let rel = 0.5 * ((sd(&plain, mp) / ep).powi(2) + (sd(&guided, mg) / eg).powi(2)).sqrt();
        println!(
            "{name} slit, 256 passes: E/π RMSE unguided {:.5}, guided {:.5} → {ratio:.2}× (± {:.2}); reference σ {:.5}",
            ep.sqrt(),
            eg.sqrt(),
            ratio * rel,
            ref_var.sqrt()
        );
        assert!(ratio > 1.3, "{name}: guiding gained only {ratio:.2}× (± {:.2})", ratio * rel);
    }
}

#[test]
fn guided_gpu_bakes_are_deterministic_and_cpu_bakes_resume_exactly() {
    let scene = baker::scene::cornell();
    let lm = Lightmap::build(&scene, 6.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let cfg = config(9, Some(GuidingOptions { learn_passes: 4, guided_fraction: 0.5 }));
    // CPU: 12 passes straight equal 7 passes, a checkpoint round trip, then 5 more.
    let straight = cpu_bake(&scene, &targets, &cfg, 12);
    let bvh = Bvh::build(&scene);
    let first = cpu_bake(&scene, &targets, &cfg, 7);
    let fp = baker::checkpoint::content_fingerprint(&scene, &targets, &cfg, "lightmap");
    let saved = baker::checkpoint::from_bytes(&baker::checkpoint::to_bytes(&first, fp), fp, &cfg, &targets).unwrap();
    assert_eq!(saved.guide_sums, first.guide_sums);
    let mut b = Bake::resume(cfg.clone(), &targets, Tracer::new(&scene, &bvh, cfg.max_bounces), saved).unwrap();
    for _ in 0..5 {
        b.pass();
    }
    assert_eq!(b.state.moments, straight.moments, "a resumed guided bake differs");
    assert_eq!(b.state.guide_sums, straight.guide_sums);
    // A checkpoint of an unguided bake does not resume a guided one.
    let plain = config(9, None);
    let fp_plain = baker::checkpoint::content_fingerprint(&scene, &targets, &plain, "lightmap");
    assert_ne!(fp, fp_plain);
    let Some(g) = gpu() else { return };
    let a = gpu_bake(&g, &scene, &targets, &cfg, 12);
    let b = gpu_bake(&g, &scene, &targets, &cfg, 12);
    assert_eq!(a.0.guide_sums, b.0.guide_sums, "GPU learning is not deterministic");
    assert_eq!(a.0.moments, b.0.moments);
    assert_eq!(a.1, b.1);
}
