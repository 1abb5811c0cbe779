//! Camera-based lightmap sampling (`baker::accumulate::camera`, [Roughton19 §3.4.2]).
//!
//! (1) The GPU's texel raster against the CPU twin (a ray through every jittered pixel
//! centre, the hit's texel by its barycentric lightmap UV): per texel, the samples a batch
//! gives it. Error model: the two disagree only for pixels whose centre lies within the
//! rasteriser's sub-pixel precision (1/256 pixel and f32 interpolation) of a triangle or
//! texel edge; with texels about 5 pixels wide (measured: 0.8% of the samples differ), and
//! the test allows 2% of the samples (Σ|Δ| / Σ). (2) Which texels a batch takes depends on
//! the view only, so a camera-based bake is unbiased: its visible charts' means agree with
//! a long uniform bake within 3σ, and texels out of view keep their pilot pass.
//!
//! Mutations tried: the jitter's sign flipped in `view_proj` (the raster then samples
//! other positions than the CPU rays) — the raster comparison fails; the batch counting
//! every pixel for item 0 — both fail.

mod common;
use baker::accumulate::camera::{jitter, pixel_counts, CameraSampling};
use baker::accumulate::{BakeConfig, Solver, Targets};
use baker::layout::lightmap::Lightmap;
use baker::scene::bvh::Bvh;
use baker::scene::camera::ViewCamera;
use sbf::glam::Vec3;

fn config(seed: u64, camera: Option<CameraSampling>) -> BakeConfig {
    BakeConfig { seed, max_bounces: 3, bases: vec![], solver: Solver::Ls, camera, ..Default::default() }
}

fn view(width: u32, height: u32) -> ViewCamera {
    // Inside the Cornell-style room, looking at its back corner.
    ViewCamera { eye: Vec3::new(0.2, 0.5, 0.9), target: Vec3::new(-0.3, 0.35, 0.0), up: Vec3::Y, fov_y: 55f32.to_radians(), width, height }
}

#[test]
fn the_gpu_raster_takes_the_texels_the_cpu_rays_see() {
    let scene = baker::scene::cornell();
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, 24.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let cam = view(320, 240);
    let c = CameraSampling { camera: cam, pilot_passes: 1, max_per_batch: 64 };
    // Batch 1 (after one pilot pass) on the CPU twin.
    let want: Vec<u64> = pixel_counts(&cam, jitter(1), &bvh, &targets).iter().map(|n| (*n).min(64) as u64).collect();
    let total: u64 = want.iter().sum();
    let seen = want.iter().filter(|n| **n > 0).count();
    println!("CPU: {total} samples on {seen} of {} texels from {} pixels", targets.items.len(), cam.width * cam.height);
    assert!(total > (cam.width * cam.height / 2) as u64, "the view sees too little of the lightmap");
    assert!(seen < targets.items.len() / 2 && seen > 100, "the view should see some texels, not all");
    // The CPU bake takes exactly these. One bounce: the counts do not depend on it, and a
    // thread's 64 samples of three-bounce paths run past llvmpipe's 65 535 loop iterations
    // per invocation (the bake refuses such results).
    let cfg = BakeConfig { max_bounces: 1, ..config(3, Some(c)) };
    let cpu = common::bake_on(None, &scene, &targets, &cfg, 2);
    let got: Vec<u64> = cpu.moments.iter().map(|m| m.count() - 1).collect();
    assert_eq!(got, want, "the CPU bake's batch differs from its pixel counts");
    let Some(g) = common::gpu() else { return };
    let gpu = common::bake_on(Some(&g), &scene, &targets, &cfg, 2);
    let got: Vec<u64> = gpu.moments.iter().map(|m| m.count() - 1).collect();
    let diff: u64 = got.iter().zip(&want).map(|(a, b)| a.abs_diff(*b)).sum();
    println!("GPU raster vs CPU rays: Σ|Δ| = {diff} of {total} samples ({:.3}%)", 100.0 * diff as f64 / total as f64);
    assert!(diff as f64 <= 0.02 * total as f64, "the raster and the rays disagree on {diff} of {total} samples");
}

#[test]
fn camera_based_bakes_are_unbiased_and_leave_unseen_texels_alone() {
    let scene = baker::scene::cornell();
    let lm = Lightmap::build(&scene, 8.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let reference = common::bake_on(None, &scene, &targets, &config(100, None), 2048);
    let (rm, rse) = (reference.mean(), reference.standard_error());
    let c = CameraSampling { camera: view(64, 48), pilot_passes: 1, max_per_batch: 8 };
    let mut engines: Vec<(&str, Option<shaders::gpu::Lease>)> = vec![("CPU", None)];
    if let Some(g) = common::gpu() {
        engines.push(("GPU", Some(g)));
    }
    for (name, g) in &engines {
        let st = common::bake_on(g.as_deref(), &scene, &targets, &config(1, Some(c)), 257);
        let (m, se) = (st.mean(), st.standard_error());
        let seen: Vec<usize> = (0..targets.items.len()).filter(|&k| st.moments[k].count() > 1).collect();
        let unseen = targets.items.len() - seen.len();
        assert!(st.moments.iter().all(|x| x.count() >= 1), "{name}: a texel lost its pilot pass");
        assert!(unseen > 0 && seen.len() > 50, "{name}: {} seen, {unseen} unseen", seen.len());
        // Per chart over its seen texels with ≥ 2 samples, and over all of them.
        // (beyond 3σ, checks, worst |d|/σ) over texels `ks`, per channel.
        let check = |ks: &[usize]| -> (usize, usize, f64) {
            let k = ks.len() as f64;
            let (mut fails, mut worst) = (0, 0.0f64);
            for ch in 0..3 {
                let d: f64 = ks.iter().map(|&i| m[i][ch] - rm[i][ch]).sum::<f64>() / k;
                let s = ks.iter().map(|&i| se[i][ch].powi(2) + rse[i][ch].powi(2)).sum::<f64>().sqrt() / k;
                worst = worst.max(d.abs() / s);
                fails += (d.abs() > 3.0 * s) as usize;
            }
            (fails, 3, worst)
        };
        let measured: Vec<usize> =
            seen.iter().copied().filter(|&k| st.moments[k].accepted >= 2 && reference.moments[k].accepted >= 2).collect();
        let (scene_fails, mut n, mut worst) = check(&measured);
        let mut fails = scene_fails;
        for chart in 0..lm.chart_meshes.len() {
            let ks: Vec<usize> =
                measured.iter().copied().filter(|&i| lm.texels[targets.items[i][2] as usize].chart == chart as u32).collect();
            if ks.len() >= 4 {
                let (f, c, w) = check(&ks);
                fails += f;
                n += c;
                worst = worst.max(w);
            }
        }
        println!("{name}: {} texels seen, {unseen} not; seen means vs a 2048-pass uniform bake: {n} checks, worst {worst:.2}σ, {fails} beyond 3σ", seen.len());
        assert_eq!(scene_fails, 0, "{name}: the seen texels' mean is biased");
        assert!(fails as f64 <= 0.03 * n as f64 + 1.0, "{name}: {fails} of {n} chart means beyond 3σ");
        // Unseen texels took only the pilot pass.
        assert!((0..targets.items.len()).filter(|k| !seen.contains(k)).all(|k| st.moments[k].count() == 1));
    }
    // Refusals.
    let bad = CameraSampling { camera: ViewCamera { fov_y: 0.0, ..c.camera }, ..c };
    assert!(config(1, Some(bad)).check(&targets).unwrap_err().contains("field of view"));
    let up = CameraSampling { camera: ViewCamera { target: c.camera.eye + Vec3::Y, ..c.camera }, ..c };
    assert!(config(1, Some(up)).check(&targets).unwrap_err().contains("straight up"));
    let both = BakeConfig { adaptive: Some(Default::default()), ..config(1, Some(c)) };
    assert!(both.check(&targets).unwrap_err().contains("adaptive"));
    assert!(config(1, Some(c)).check(&Targets::probes(&[Vec3::ZERO])).unwrap_err().contains("probes"));
}
