//! Adaptive sampling (`baker::accumulate::adaptive`, [Roughton19 §3.3]) on the `sunbeam`
//! scene — a hut on open ground lit by a sun through a slit: inside, a small bright
//! stripe lights the hut indirectly, so its texels are far noisier than the ground's.
//!
//! Oracle: a long uniform bake (4 096 passes, another seed), independent of the adaptive
//! schedule under test; the uniform estimator itself is checked against closed forms in
//! `transport.rs`. Error model: a bake's E/π RMSE over texels against the reference has
//! the reference's own variance (its mean squared standard error) subtracted; the ratio's
//! spread follows from the per-texel squared errors (delta method, printed).
//!
//! Mutations tried: the selection ignoring σ (every texel q = f) — the gain falls to
//! exactly 1.00× (the same samples as the uniform bake) and the RMSE assertion fails; the
//! GPU batch taking sample index 0 for every item (instead of its count) — 0.09×, fails.
//! The GPU-vs-CPU path count caught a real bug: several passes per dispatch ran the GPU's
//! pilot past its end (its first "batch" was a whole pass).

mod common;
use baker::accumulate::adaptive::AdaptiveOptions;
use baker::accumulate::{Bake, BakeConfig, BakeState, Pipeline, Solver, Targets};
use baker::estimator::trace::Tracer;
use baker::layout::lightmap::Lightmap;
use baker::scene::bvh::Bvh;

fn config(seed: u64, adaptive: Option<AdaptiveOptions>) -> BakeConfig {
    BakeConfig { seed, max_bounces: 3, bases: vec![], solver: Solver::Ls, adaptive, ..Default::default() }
}

fn paths(st: &BakeState) -> u64 {
    st.moments.iter().map(|m| m.count()).sum()
}

#[test]
fn adaptive_sampling_lowers_the_error_at_equal_paths_without_bias() {
    let scene = baker::scene::sunbeam();
    let lm = Lightmap::build(&scene, 8.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let reference = common::bake_on(None, &scene, &targets, &config(100, None), 4096);
    let (rm, rse) = (reference.mean(), reference.standard_error());
    let ref_var: f64 = rse.iter().flatten().map(|s| s * s).sum::<f64>() / (3 * rse.len()) as f64;
    let errors = |st: &BakeState| -> Vec<f64> {
        st.mean().iter().zip(&rm).map(|(a, b)| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>() / 3.0).collect()
    };
    let a = AdaptiveOptions::default();
    let passes = 64;
    // The GPU through both pipelines: the wavefront expands a batch's samples into paths
    // of their own (slots per job), the megakernel takes them in one thread.
    let lease = common::gpu();
    let mut engines: Vec<(&str, Option<&shaders::gpu::Gpu>, Pipeline)> = vec![("CPU", None, Pipeline::Megakernel)];
    if let Some(g) = &lease {
        engines.push(("GPU", Some(g), Pipeline::Megakernel));
        engines.push(("GPU wavefront", Some(g), Pipeline::Wavefront));
    }
    for &(name, g, pipeline) in &engines {
        let config = |seed, adaptive| BakeConfig { pipeline, ..config(seed, adaptive) };
        let uniform = common::bake_on(g, &scene, &targets, &config(1, None), passes);
        let adaptive = common::bake_on(g, &scene, &targets, &config(1, Some(a)), a.batches_for(passes));
        let (pu, pa) = (paths(&uniform), paths(&adaptive));
        let (eu, ea) = (errors(&uniform), errors(&adaptive));
        let n = eu.len() as f64;
        let (mu, ma) = (eu.iter().sum::<f64>() / n, ea.iter().sum::<f64>() / n);
        let (du, da) = ((mu - ref_var).max(0.0), (ma - ref_var).max(1e-30));
        let gain = (du / da).sqrt();
        let sd = |v: &[f64], m: f64| (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        let rel = 0.5 * ((sd(&eu, mu) / du).powi(2) + (sd(&ea, ma) / da).powi(2)).sqrt();
        println!(
            "{name} sunbeam, {} texels: uniform {passes} passes ({pu} paths) RMSE {:.5}; adaptive {} pilot + {} batches ({pa} paths) RMSE {:.5} → {gain:.2}× (± {:.2}); reference σ {:.5}",
            targets.items.len(),
            du.sqrt(),
            a.pilot_passes,
            a.batches_for(passes) - a.pilot_passes,
            da.sqrt(),
            gain * rel,
            ref_var.sqrt()
        );
        assert!(pa as f64 <= 1.02 * pu as f64, "{name}: adaptive spent {pa} paths, uniform {pu}");
        assert!(gain > 1.2, "{name}: adaptive sampling gained only {gain:.2}× (± {:.2})", gain * rel);
        // Bias (Kirk–Arvo): per chart and for the scene, the adaptive mean against the
        // reference within 3σ (σ from both bakes' per-texel standard errors).
        let long = common::bake_on(g, &scene, &targets, &config(2, Some(a)), a.batches_for(512));
        let (lm_, lse) = (long.mean(), long.standard_error());
        // (beyond 3σ, worst |d|/σ) of the mean difference over texels `ks`, per channel.
        let check = |label: &str, ks: &[usize]| -> (usize, f64) {
            let k = ks.len() as f64;
            let (mut fails, mut worst) = (0, 0.0f64);
            for c in 0..3 {
                let d: f64 = ks.iter().map(|&i| lm_[i][c] - rm[i][c]).sum::<f64>() / k;
                let s = (ks.iter().map(|&i| lse[i][c].powi(2) + rse[i][c].powi(2)).sum::<f64>()).sqrt() / k;
                worst = worst.max(d.abs() / s);
                if d.abs() > 3.0 * s {
                    fails += 1;
                    println!("{name} {label} channel {c}: adaptive − reference {d:+.3e} ({:.1}σ)", d.abs() / s);
                }
            }
            (fails, worst)
        };
        let all: Vec<usize> = (0..targets.items.len()).collect();
        let (scene_fails, mut worst) = check("scene", &all);
        let (mut fails, mut charts) = (scene_fails, 0);
        for chart in 0..lm.chart_meshes.len() {
            let ks: Vec<usize> =
                (0..targets.items.len()).filter(|&i| lm.texels[targets.items[i][2] as usize].chart == chart as u32).collect();
            if ks.len() >= 4 {
                charts += 1;
                let (f, w) = check(&format!("chart {chart}"), &ks);
                fails += f;
                worst = worst.max(w);
            }
        }
        println!(
            "{name}: adaptive (512-pass budget) vs reference: {charts} charts + scene, worst {worst:.2}σ, {fails} of {} beyond 3σ",
            3 * (charts + 1)
        );
        assert_eq!(scene_fails, 0, "{name}: the scene mean is biased");
        assert!(fails as f64 <= 0.03 * (3 * (charts + 1)) as f64 + 1.0, "{name}: {fails} chart means beyond 3σ");
    }
}

/// Adaptive bakes are reproducible: a CPU bake of 40 passes + batches equals one stopped at
/// 20, saved to a checkpoint and resumed (bit for bit: the batches depend on the moments,
/// which round-trip exactly), the adaptive settings are part of the checkpoint's identity,
/// two GPU bakes are identical, bad settings are refused with their reason, and probes
/// and guided bakes refuse adaptive sampling.
#[test]
fn adaptive_bakes_resume_exactly_and_refuse_what_they_cannot_do() {
    let scene = baker::scene::sunbeam();
    let lm = Lightmap::build(&scene, 4.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let a = AdaptiveOptions { pilot_passes: 4, ..Default::default() };
    let cfg = config(5, Some(a));
    let straight = common::bake_on(None, &scene, &targets, &cfg, 40);
    let first = common::bake_on(None, &scene, &targets, &cfg, 20);
    let fp = baker::checkpoint::content_fingerprint(&scene, &targets, &cfg, "lightmap");
    assert_ne!(fp, baker::checkpoint::content_fingerprint(&scene, &targets, &config(5, None), "lightmap"));
    let other = config(5, Some(AdaptiveOptions { batch_fraction: 0.5, ..a }));
    assert_ne!(a.batch_fraction, 0.5);
    assert_ne!(fp, baker::checkpoint::content_fingerprint(&scene, &targets, &other, "lightmap"));
    let saved = baker::checkpoint::from_bytes(&baker::checkpoint::to_bytes(&first, fp), fp, &cfg, &targets).unwrap();
    let bvh = Bvh::build(&scene);
    let mut b = Bake::resume(cfg.clone(), &targets, Tracer::new(&scene, &bvh, cfg.max_bounces), saved).unwrap();
    for _ in 0..20 {
        b.pass();
    }
    assert_eq!(b.state.moments, straight.moments, "a resumed adaptive bake differs");
    // Batches spend where the noise is: the busiest texel took far more samples than the
    // quietest.
    let counts: Vec<u64> = straight.moments.iter().map(|m| m.count()).collect();
    let (lo, hi) = (counts.iter().min().unwrap(), counts.iter().max().unwrap());
    assert!(*hi > 3 * *lo, "samples per texel {lo}..{hi}: the batches did not adapt");
    // Refusals, with their reason.
    for (bad, why) in [
        (AdaptiveOptions { batch_fraction: 0.0, ..a }, "fraction"),
        (AdaptiveOptions { batch_fraction: 8.5, ..a }, "fraction"),
        (AdaptiveOptions { max_per_batch: 0, ..a }, "per batch"),
        (AdaptiveOptions { max_per_batch: 65, ..a }, "per batch"),
        (AdaptiveOptions { floor: -0.1, ..a }, "floor"),
        (AdaptiveOptions { pilot_passes: 1, ..a }, "pilot"),
    ] {
        let e = config(5, Some(bad)).check(&targets).unwrap_err();
        assert!(e.contains(why), "{e}");
    }
    let probes = Targets::probes(&[sbf::glam::Vec3::ZERO]);
    assert!(cfg.check(&probes).unwrap_err().contains("probes"));
    let guided =
        BakeConfig { guiding: Some(baker::sampling::guiding::GuidingOptions { learn_passes: 4, guided_fraction: 0.5 }), ..cfg.clone() };
    assert!(guided.check(&targets).unwrap_err().contains("guiding"));
    let Some(g) = common::gpu() else { return };
    let (x, y) = (common::bake_on(Some(&g), &scene, &targets, &cfg, 40), common::bake_on(Some(&g), &scene, &targets, &cfg, 40));
    assert_eq!(x.moments, y.moments, "GPU adaptive bakes differ");
    // The GPU's σ comes from f32 moments: a texel near a join threshold may go the other
    // way, so the path counts agree closely, not exactly.
    let (pg, pc) = (paths(&x) as f64, paths(&straight) as f64);
    println!("paths over 40 passes + batches: GPU {pg}, CPU {pc}");
    assert!((pg - pc).abs() <= 0.02 * pc, "GPU {pg} vs CPU {pc} paths");
}
