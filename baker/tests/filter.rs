//! Filtered gather-based accumulation ([Roughton19 §3.2]): the filter kernels against closed
//! forms, the one-texel box against the unfiltered bake (an identity), the measured drop
//! in empty texels and the error at equal paths against a long reference bake, and the
//! state through a checkpoint.

mod common;

use baker::accumulate::filter::GatherFilter;
use baker::accumulate::filter::{Filter, GatherLayout};
use baker::accumulate::{Bake, BakeConfig, BakeState, BasisId, Solver, Targets};
use baker::estimator::trace::Tracer;
use baker::layout::lightmap::{Lightmap, NO_CHART};
use baker::post::images::LightmapImages;
use baker::scene::bvh::Bvh;
use baker::scene::{self, Scene};

fn config(filter: Option<Filter>, seed: u64) -> BakeConfig {
    BakeConfig { seed, max_bounces: 3, bases: vec![BasisId::Sh1], solver: Solver::Ls, filter, ..Default::default() }
}

fn cpu_bake(s: &Scene, targets: &Targets, cfg: &BakeConfig, passes: u64) -> BakeState {
    common::bake_on(None, s, targets, cfg, passes)
}

/// ∫ k over its support by the composite Simpson rule (error ≤ h⁴·max|k⁗|/180 per unit
/// length on each smooth piece; the pieces' joints are nodes): Mitchell–Netravali's kernel
/// integrates to 1 over [−2, 2] in x = 2d/r, so over d to r/2; the box to 2r; the shifted
/// Gaussian (σ = r/2) to σ√(2π)·erf(√2) − 2r·e^{−2}.
#[test]
fn filter_kernels_integrate_to_their_closed_forms() {
    let integral = |k: GatherFilter, r: f32| {
        let n = 4096;
        let h = 2.0 * r as f64 / n as f64;
        (0..=n)
            .map(|i| {
                let d = -r as f64 + i as f64 * h;
                let c = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                c * k.weight_1d(r, d as f32) as f64
            })
            .sum::<f64>()
            * h
            / 3.0
    };
    for r in [1.5f32, 2.0, 3.0] {
        let sigma = r as f64 / 2.0;
        // erf(√2) = 0.954499736103642 (Abramowitz & Stegun 7.1).
        let gauss = sigma * (2.0 * std::f64::consts::PI).sqrt() * 0.954_499_736_103_642 - 2.0 * r as f64 * (-2.0f64).exp();
        // f32 weights: relative rounding ~1e-7 per term; the box's jumps at ±r are nodes
        // where it is 0 (a < r), so Simpson is off by at most h·1 there.
        let h = 2.0 * r as f64 / 4096.0;
        for (k, want, tol) in
            [(GatherFilter::Mitchell, r as f64 / 2.0, 1e-5), (GatherFilter::Gaussian, gauss, 1e-5), (GatherFilter::Box, 2.0 * r as f64, h)]
        {
            let got = integral(k, r);
            assert!((got - want).abs() <= tol * want.max(1.0), "{k:?} r {r}: ∫ = {got}, closed form {want}");
        }
    }
    assert!(Filter::parse("mitchell:0.2").is_err() && Filter::parse("lanczos").is_err() && Filter::parse("box:x").is_err());
    assert_eq!(Filter::parse("gaussian").unwrap(), Filter { kernel: GatherFilter::Gaussian, radius: 1.5 });
}

/// A box of radius ½ reaches exactly a texel's own sub-positions (at ±⅛ and ±⅜ from its
/// centre; a neighbour's are ≥ ⅝ away): the filtered bake's covered texels must then equal
/// the unfiltered bake — same samples in the same order with weight 1 — so the encoders
/// match to f32 rounding and the weighted Welford mean matches the plain mean to f64
/// rounding; uncovered texels get nothing.
#[test]
fn one_texel_box_equals_the_unfiltered_bake() {
    let s = scene::cornell();
    let lm = Lightmap::build(&s, 3.0, 1).unwrap();
    let targets = Targets::lightmap(&lm);
    let f = Filter { kernel: GatherFilter::Box, radius: 0.5 };
    let plain = cpu_bake(&s, &targets, &config(None, 5), 6);
    let filtered = cpu_bake(&s, &targets, &config(Some(f), 5), 6);
    let fs = filtered.filtered.as_ref().expect("filtered state");
    let n = targets.items.len();
    let mean = plain.mean();
    for k in 0..n {
        let m = &fs.moments[k];
        assert_eq!(m.samples, plain.moments[k].accepted, "item {k}");
        for c in 0..3 {
            assert!((m.mean[c] - mean[k][c]).abs() <= 1e-9 * mean[k][c].abs().max(1.0), "item {k}: {} vs {}", m.mean[c], mean[k][c]);
        }
        let (a, b) = (plain.encoders[0][k].coefficients(), fs.encoders[0][k].coefficients());
        assert_eq!(a, b, "item {k}: the encoders saw different samples");
    }
    assert!(fs.moments[n..].iter().all(|m| m.samples == 0), "an uncovered texel gathered a sample with a ½-texel box");
}

/// The filtered means against a direct weighted sum written here: an unfiltered bake's
/// per-pass samples (the same seed traces the same paths), each placed at its sub-texel
/// position from the texel's coverage bits, weighted by the shifted Gaussian
/// e^{−d²/2σ²} − e^{−r²/2σ²} (σ = r/2) per axis and summed over the texels of the same
/// chart — no padding between charts, so the chart test matters. Welford's running mean
/// and the direct ratio Σw·e/Σw differ only by f64 rounding (≲ 1e-12 relative here).
#[test]
fn filtered_means_equal_a_direct_weighted_sum() {
    let s = scene::cornell();
    let lm = Lightmap::build(&s, 3.0, 0).unwrap();
    let targets = Targets::lightmap(&lm);
    let f = Filter::parse("gaussian:1.5").unwrap();
    let passes = 4;
    let filtered = cpu_bake(&s, &targets, &config(Some(f), 5), passes);
    let bvh = Bvh::build(&s);
    let cfg = config(None, 5);
    let mut plain = Bake::new(cfg.clone(), &targets, Tracer::new(&s, &bvh, cfg.max_bounces));
    let per_pass: Vec<Vec<baker::accumulate::ItemSample>> = (0..passes).map(|_| plain.pass_samples()).collect();
    let w = lm.width;
    let mut item_of = vec![usize::MAX; lm.texels.len()];
    for (k, it) in targets.items.iter().enumerate() {
        item_of[it[2] as usize] = k;
    }
    let k1 = |d: f64| {
        let (r, sigma) = (1.5f64, 0.75f64);
        if d.abs() >= r {
            0.0
        } else {
            ((-d * d / (2.0 * sigma * sigma)).exp() - (-r * r / (2.0 * sigma * sigma)).exp()).max(0.0)
        }
    };
    let list = baker::accumulate::filter::gather_targets(&targets);
    let fs = filtered.filtered.as_ref().unwrap();
    let mut checked = 0;
    let basis = BasisId::Sh1.basis();
    for (j, &t) in list.iter().enumerate() {
        let t = t as usize;
        let (x, y) = ((t % w) as i64, (t / w) as i64);
        let (mut sw, mut swe) = (0.0f64, [0.0f64; 3]);
        // The same samples through an encoder of their own, in the gather's order.
        let mut enc = sbf::solve::ProgressiveEncoder::<f32>::new(4, cfg.encoder_options(BasisId::Sh1, false));
        for (p, samples) in per_pass.iter().enumerate() {
            for ny in y - 2..=y + 2 {
                for nx in x - 2..=x + 2 {
                    if nx < 0 || ny < 0 || nx as usize >= w || ny as usize >= lm.height {
                        continue;
                    }
                    let n = ny as usize * w + nx as usize;
                    if item_of[n] == usize::MAX || lm.texel_charts[n] != lm.texel_charts[t] {
                        continue;
                    }
                    let smp = &samples[item_of[n]];
                    if smp.back_face || !smp.is_finite() {
                        continue;
                    }
                    let bits: Vec<u32> = (0..16).filter(|b| lm.texels[n].coverage & (1 << b) != 0).collect();
                    let b = bits[p % bits.len()];
                    let (px, py) = (nx as f64 + ((b % 4) as f64 + 0.5) / 4.0, ny as f64 + ((b / 4) as f64 + 0.5) / 4.0);
                    let wt = k1(px - (x as f64 + 0.5)) * k1(py - (y as f64 + 0.5));
                    sw += wt;
                    for c in 0..3 {
                        swe[c] += wt * smp.estimate[c] as f64;
                    }
                    if wt > 0.0 {
                        let l = smp.radiance.to_array().map(|v| v as f64);
                        enc.add_sample_projected(basis.as_ref(), smp.local, l, smp.weight * wt, &smp.lights).unwrap();
                    }
                }
            }
        }
        let m = &fs.moments[j];
        assert!((m.weight - sw).abs() <= 1e-5 * sw.max(1e-3), "texel {t}: Σw {} vs direct {sw}", m.weight);
        if sw > 0.0 {
            for c in 0..3 {
                let want = swe[c] / sw;
                // The weights are f32 in the bake (relative 6e-8 each): the mean moves by
                // at most that times the spread of the values it averages.
                assert!((m.mean[c] - want).abs() <= 1e-5 * want.abs().max(1.0), "texel {t} channel {c}: {} vs direct {want}", m.mean[c]);
            }
            // f32 encoder state: each update rounds at ~6e-8 relative; the weights differ
            // by f32 rounding; a few dozen updates stay well inside 1e-4 of the scale.
            let (a, b) = (enc.coefficients(), fs.encoders[0][j].coefficients());
            let scale = a.abs().max().max(1e-3);
            assert!((&a - &b).abs().max() <= 1e-4 * scale, "texel {t}: encoder {b} vs direct {a}");
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked} texels checked");
}

/// Bevy's Cornell box (../shared/scenes; lightmap UVs authored outside this project, chart
/// edges at every angle) at 0.05 texels per millimetre, or None (skipped) when the folder is
/// absent — a failure under SBF_REQUIRE_PROBES=1.
fn gltf_cornell() -> Option<Scene> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/bevy_CornellBox/CornellBox.glb");
    if !path.exists() {
        assert!(std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"), "SBF_REQUIRE_PROBES=1 but {} is missing", path.display());
        println!("skipped: {} is absent", path.display());
        return None;
    }
    Some(baker::scene::load::load(path.to_str().unwrap(), None, &mut |_| {}).unwrap())
}

/// Empty texels before dilation and the error at equal paths: Bevy's Cornell box at
/// 0.05 texels per millimetre, 8 passes with and without a filter, against a 256-pass unfiltered
/// reference. Empty: texels a chart overlaps but that hold no value — the filter must
/// leave strictly fewer (every uncovered texel next to a covered one gets samples).
/// Error: RMSE of E/π over the texels valid in both bakes; at 8 paths per texel the
/// reference's own noise is √(8/256) ≈ 0.18 of the bake's, and the filter's blur bias
/// must not outweigh its variance reduction (the bar: the RMSE does not rise).
/// Fixed seeds make the comparison deterministic; as an estimate, an RMSE over ~16 000
/// texel-channels spreads by ~1/√(2N) ≈ 0.6% relative, far below the margins measured
/// (1.12–1.85×), so a filter that truly raised the error could not pass by chance.
#[test]
fn filtering_fills_edge_texels_and_does_not_raise_the_error() {
    let Some(s) = gltf_cornell() else { return };
    let lm = Lightmap::build(&s, 0.05, 1).unwrap();
    let targets = Targets::lightmap(&lm);
    let reference = LightmapImages::new(&lm, &targets, &cpu_bake(&s, &targets, &config(None, 99), 256));
    let empty = |img: &LightmapImages| (0..lm.texels.len()).filter(|t| lm.texel_charts[*t] != NO_CHART && img.validity[*t] == 0.0).count();
    let rmse = |img: &LightmapImages| {
        let (mut sum, mut n) = (0.0, 0);
        for t in 0..lm.texels.len() {
            if img.validity[t] > 0.0 && reference.validity[t] > 0.0 {
                for c in 0..3 {
                    sum += (img.irradiance[t][c] as f64 - reference.irradiance[t][c] as f64).powi(2);
                    n += 1;
                }
            }
        }
        (sum / n as f64).sqrt()
    };
    let plain = LightmapImages::new(&lm, &targets, &cpu_bake(&s, &targets, &config(None, 7), 8));
    let (e0, r0) = (empty(&plain), rmse(&plain));
    let layout = GatherLayout::new(&targets, &Filter::parse("box").unwrap()).unwrap();
    println!(
        "{} items, {} uncovered texels a chart overlaps; unfiltered: {e0} empty, RMSE {r0:.5}",
        targets.items.len(),
        layout.uncovered(targets.items.len())
    );
    assert!(layout.uncovered(targets.items.len()) > 0, "the scene must have uncovered edge texels for this test to mean anything");
    for name in ["box", "gaussian", "mitchell", "gaussian:2"] {
        let f = Filter::parse(name).unwrap();
        let st = cpu_bake(&s, &targets, &config(Some(f), 7), 8);
        let img = LightmapImages::new(&lm, &targets, &st);
        let (e, r) = (empty(&img), rmse(&img));
        println!(
            "{name}: {e} empty ({:.1}% fewer), RMSE {r:.5} ({:.2}× the unfiltered); {} negative-weight samples skipped",
            100.0 * (e0 - e) as f64 / e0.max(1) as f64,
            r0 / r,
            st.filtered.as_ref().unwrap().negative_weights
        );
        assert!(e < e0, "{name}: {e} empty texels, unfiltered {e0}");
        assert!(r <= r0, "{name}: RMSE {r} above the unfiltered {r0}");
    }
}

/// The filtered state survives a checkpoint bit for bit: 3 passes, save, load, 3 more
/// equals 6 straight passes.
#[test]
fn filtered_state_round_trips_through_a_checkpoint() {
    let s = scene::cornell();
    let bvh = Bvh::build(&s);
    let lm = Lightmap::build(&s, 3.0, 1).unwrap();
    let targets = Targets::lightmap(&lm);
    let cfg = config(Some(Filter::parse("mitchell").unwrap()), 3);
    let straight = cpu_bake(&s, &targets, &cfg, 6);
    let first = cpu_bake(&s, &targets, &cfg, 3);
    let bytes = baker::checkpoint::to_bytes(&first, 42);
    let loaded = baker::checkpoint::from_bytes(&bytes, 42, &cfg, &targets).unwrap();
    let mut b = Bake::resume(cfg.clone(), &targets, Tracer::new(&s, &bvh, cfg.max_bounces), loaded).unwrap();
    for _ in 0..3 {
        b.pass();
    }
    let (x, y) = (straight.filtered.unwrap(), b.state.filtered.unwrap());
    assert_eq!(x.moments, y.moments);
    for (a, b) in x.encoders[0].iter().zip(&y.encoders[0]) {
        assert_eq!(a.coefficients(), b.coefficients());
    }
    // A different filter is a different bake: its checkpoint is refused.
    let fp = |c: &BakeConfig| baker::checkpoint::content_fingerprint(&s, &targets, c, "lightmap");
    for other in
        [config(Some(Filter::parse("gaussian").unwrap()), 3), config(Some(Filter::parse("mitchell:2").unwrap()), 3), config(None, 3)]
    {
        assert_ne!(fp(&cfg), fp(&other));
    }
}

/// The GPU's filtered bake (`wgsl/filter.wgsl`: records per item and pass, the gather pass)
/// against its CPU twin with the same seed, through both pipelines: the same sample
/// sequences trace the same paths, so every gather target agrees up to f32 rounding —
/// except around an item whose path diverged (a comparison decided differently in f32 and
/// f64), which touches the (2·reach + 1)² targets around it. Two bases (the records' Q
/// offsets), charts without padding (the chart test), and a long batch target so that
/// dispatches grow to several passes each (the gather's per-pass loop).
#[test]
fn gpu_filtered_bake_matches_its_cpu_twin() {
    let Some(gpu) = common::gpu() else { return };
    let s = scene::cornell();
    let bvh = Bvh::build(&s);
    let lm = Lightmap::build(&s, 4.0, 0).unwrap();
    let targets = Targets::lightmap(&lm);
    let passes = 12;
    for (pipeline, filter) in
        [(baker::accumulate::Pipeline::Megakernel, "gaussian"), (baker::accumulate::Pipeline::Wavefront, "mitchell:2")]
    {
        let cfg = BakeConfig {
            bases: vec![BasisId::Ad9, BasisId::Sh2],
            solver: Solver::Nnls,
            pipeline,
            ..config(Some(Filter::parse(filter).unwrap()), 17)
        };
        let mut g = baker::gpu::GpuBake::new(&gpu, &Tracer::new(&s, &bvh, cfg.max_bounces), &targets, &cfg).unwrap();
        g.set_batch_target(Some(10.0));
        g.run(passes).unwrap();
        let most = g.passes_per_dispatch();
        let gs = g.state().unwrap();
        let cs = cpu_bake(&s, &targets, &cfg, passes);
        let (gf, cf) = (gs.filtered.as_ref().unwrap(), cs.filtered.as_ref().unwrap());
        let (mut close, mut n, mut worst) = (0, 0, 0.0f64);
        for j in 0..gf.moments.len() {
            let (a, b) = (&gf.moments[j], &cf.moments[j]);
            if b.weight <= 0.0 {
                assert_eq!(a.weight, 0.0, "target {j}: the GPU gathered where the CPU did not");
                continue;
            }
            n += 1;
            // f32 state: each Welford step and encoder update rounds at ~6e-8 relative;
            // tens of steps stay within 1e-4 of the value's scale.
            let mut rel = (0..3).map(|c| (a.mean[c] - b.mean[c]).abs() / b.mean[c].abs().max(1e-3)).fold(0.0, f64::max);
            rel = rel.max((a.weight - b.weight).abs() / b.weight);
            for (ge, ce) in gf.encoders.iter().zip(&cf.encoders) {
                let (x, y) = (ge[j].coefficients(), ce[j].coefficients());
                rel = rel.max((&x - &y).abs().max() / y.abs().max().max(1e-3));
            }
            worst = worst.max(rel);
            close += (rel <= 1e-4 && a.samples == b.samples) as usize;
        }
        println!(
            "{} + {filter}: {close}/{n} gather targets agree within 1e-4 (worst {worst:.2e}); up to {most} passes per dispatch; negative-weight samples GPU {} CPU {}",
            pipeline.name(),
            gf.negative_weights,
            cf.negative_weights
        );
        assert!(most > 1, "the dispatches never held several passes");
        assert!(close as f64 >= 0.9 * n as f64, "{}: only {close}/{n} targets agree", pipeline.name());
        assert!(gf.negative_weights.abs_diff(cf.negative_weights) <= cf.negative_weights / 100, "negative weights differ");
    }
}

/// Batches of adaptive sampling on the GPU (variable samples per texel, each item's
/// samples in slots by sample index): with a ½-texel box every covered texel gathers
/// exactly its own samples, in order, with weight 1 — so the filtered encoders must equal
/// the texel's own (the same update on the same f32 inputs: bit for bit) and the weighted
/// Welford mean its plain mean (f32 running mean against the f32 sum/count: within
/// 1e-5 relative) — on both pipelines. A slot or order mix-up changes the progressive
/// encoders (their result depends on the order).
#[test]
fn gpu_batches_gather_each_texels_own_samples_with_a_one_texel_box() {
    let Some(gpu) = common::gpu() else { return };
    let s = scene::cornell();
    let bvh = Bvh::build(&s);
    let lm = Lightmap::build(&s, 4.0, 1).unwrap();
    let targets = Targets::lightmap(&lm);
    for pipeline in [baker::accumulate::Pipeline::Megakernel, baker::accumulate::Pipeline::Wavefront] {
        let cfg = BakeConfig {
            adaptive: Some(baker::accumulate::adaptive::AdaptiveOptions {
                pilot_passes: 2,
                batch_fraction: 2.0,
                floor: 0.2,
                max_per_batch: 5,
            }),
            pipeline,
            ..config(Some(Filter { kernel: GatherFilter::Box, radius: 0.5 }), 23)
        };
        let mut g = baker::gpu::GpuBake::new(&gpu, &Tracer::new(&s, &bvh, cfg.max_bounces), &targets, &cfg).unwrap();
        g.run(8).unwrap();
        let st = g.state().unwrap();
        let fs = st.filtered.as_ref().unwrap();
        let mean = st.mean();
        let counts: Vec<u64> = st.moments.iter().map(|m| m.accepted).collect();
        let varied = counts.iter().min() != counts.iter().max();
        for k in 0..targets.items.len() {
            let m = &fs.moments[k];
            assert_eq!(m.samples, st.moments[k].accepted, "item {k}");
            for c in 0..3 {
                assert!((m.mean[c] - mean[k][c]).abs() <= 1e-5 * mean[k][c].abs().max(1e-2), "item {k}: {} vs {}", m.mean[c], mean[k][c]);
            }
            assert_eq!(st.encoders[0][k].coefficients(), fs.encoders[0][k].coefficients(), "item {k}: {}", pipeline.name());
        }
        println!(
            "{}: {} texels, samples per texel {}..{}",
            pipeline.name(),
            counts.len(),
            counts.iter().min().unwrap(),
            counts.iter().max().unwrap()
        );
        assert!(varied, "the batches gave every texel the same count");
    }
}

/// `WeightedMoments::standard_error` is the standard error of the *weighted* mean, with the
/// effective sample count n_e = (Σw)²/Σw² (the filter's weights differ per sample). Samples
/// iid uniform on [0, 1) (σ² = 1/12) with weights 1 and 10 alternating (n_e/n = 30.25/50.5
/// ≈ 0.599), so Var(weighted mean) = σ²·Σw²/(Σw)² = σ²/n_e in closed form. Two oracles:
/// (a) one large set, n = 200 000: SE² against σ²/n_e — the weighted variance estimate's
///     relative spread is √((μ₄/σ⁴ − 1)/n_e) = √(0.8/n_e) ≈ 0.26 %, tolerance 5× that;
/// (b) 4 000 independent sets of n = 64: the empirical variance of their weighted means
///     against the mean SE² (relative spread of an empirical variance √(2/4000) ≈ 2.2 %,
///     plus the SE² average's own ≈ 0.6 %; tolerance 5 × 2.3 %).
/// Mutation tried: the raw count n in place of n_e (SE² × 0.599) → (a) fails at −40.3 %.
#[test]
fn weighted_standard_error_uses_the_effective_count() {
    use baker::accumulate::filter::WeightedMoments;
    use sbf::sampling::Pcg32;
    let weight = |i: usize| if i % 2 == 0 { 1.0 } else { 10.0 };
    let (sigma2, ratio) = (1.0 / 12.0, 5.5f64 * 5.5 / 50.5);
    // (a)
    let mut rng = Pcg32::new(11, 3);
    let mut m = WeightedMoments::default();
    let n = 200_000;
    for i in 0..n {
        let x = rng.next_f64();
        m.add([x, 2.0 * x, x + 1.0], weight(i));
    }
    let want = sigma2 / (ratio * n as f64);
    let se = m.standard_error();
    for (c, scale) in [(0, 1.0), (1, 4.0), (2, 1.0)] {
        let rel = se[c] * se[c] / (scale * want) - 1.0;
        println!("(a) channel {c}: SE² {:.4e} vs σ²/n_e {:.4e} ({:+.2} %)", se[c] * se[c], scale * want, 100.0 * rel);
        assert!(rel.abs() <= 5.0 * (0.8 / (ratio * n as f64)).sqrt(), "(a) channel {c}: SE² off by {:.2} %", 100.0 * rel);
    }
    // (b)
    let (sets, k) = (4000, 64);
    let (mut means, mut se2) = (Vec::with_capacity(sets), 0.0);
    for set in 0..sets {
        let mut rng = Pcg32::new(17, set as u64);
        let mut m = WeightedMoments::default();
        for i in 0..k {
            let x = rng.next_f64();
            m.add([x; 3], weight(i));
        }
        means.push(m.mean[0]);
        se2 += m.standard_error()[0].powi(2) / sets as f64;
    }
    let mu = means.iter().sum::<f64>() / sets as f64;
    let var = means.iter().map(|x| (x - mu).powi(2)).sum::<f64>() / (sets - 1) as f64;
    let rel = se2 / var - 1.0;
    println!(
        "(b) mean SE² {se2:.4e} vs empirical variance of the weighted means {var:.4e} ({:+.1} %); closed form {:.4e}",
        100.0 * rel,
        sigma2 / (ratio * k as f64)
    );
    assert!(rel.abs() <= 5.0 * 0.023, "(b) SE² off the empirical variance by {:.1} %", 100.0 * rel);
}
