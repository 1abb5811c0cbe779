//! The `slc` command's renderer run: a G-buffer and VPLs from a scene, culled and
//! brute-force images on the CPU and the GPU, their agreement, false discovery rates and
//! frame times.

use crate::output;
use crate::scene::bvh::Bvh;
use sbf::glam::Vec3;
use serde_json::json;
use std::time::Instant;

pub use super::options::{gpu_xi_seed, SlcOptions};

/// The VPLs of the run: from reflective shadow maps or light paths, of the kind asked for;
/// an error naming why when there are none.
fn make_vpls(s: &SlcOptions, scene: &crate::scene::Scene, bvh: &Bvh, cam: crate::slc::Camera) -> Result<Vec<crate::slc::Vpl>, String> {
    use crate::slc;
    let vpls = match s.rsm {
        Some(n) => slc::rsm::vpls_from_rsm(scene, bvh, cam, n, s.seed)?,
        None => slc::vpls_from_scene_with(scene, bvh, cam, s.vpls, s.seed, s.sky),
    };
    let mut vpls = slc::add_bounces(scene, bvh, cam, vpls, s.bounces, s.seed);
    match s.kind.as_str() {
        "both" => {}
        "diffuse" => vpls.retain(slc::Vpl::is_diffuse),
        "glossy" => {
            vpls.retain(slc::Vpl::is_diffuse);
            for v in vpls.iter_mut() {
                *v = slc::Vpl { diffuse: Vec3::ZERO, alpha: s.glossy_alpha, f0: Vec3::splat(0.9), ..*v };
            }
        }
        k => return Err(format!("--kind takes both, diffuse or glossy, not {k}")),
    }
    if vpls.is_empty() {
        if let Some(n) = s.rsm {
            return Err(format!(
                "scene '{}' yields no VPLs from its {n}×{n} reflective shadow maps: no texel's ray met a surface{}",
                scene.name,
                if s.kind == "both" { "" } else { " of the kept kind" }
            ));
        }
        return Err(format!(
            "scene '{}' yields no VPLs from {} light paths: they start at its lights and emissive triangles{}, and none met a surface{}",
            scene.name,
            s.vpls,
            if s.sky { " and its environment" } else { " (not at the environment or sky: --sky adds it)" },
            if s.kind == "both" { "" } else { " of the kept kind" }
        ));
    }
    Ok(vpls)
}

/// Renders single-bounce indirect light from `s.vpls` VPLs of the scene with stochastic
/// light culling (crate::slc) on the GPU or the CPU; writes slc.exr/png, the VPLs per
/// pixel, and slc.json (counts, false discovery rate, frame time).
pub fn render(s: &SlcOptions, gpu: Option<&shaders::gpu::Gpu>, log: &mut dyn FnMut(String)) -> Result<(), String> {
    use crate::slc::{self, Camera, Mode};
    let o = s;
    std::fs::create_dir_all(&o.out).map_err(|e| format!("{}: {e}", o.out.display()))?;
    let scene = crate::scene::load::load(&o.scene, o.environment.as_deref(), log)?;
    let bvh = Bvh::build(&scene);
    let cam = Camera::preview(&bvh);
    let t = Instant::now();
    let g = slc::gbuffer_from_scene(&scene, &bvh, cam, s.width, s.height);
    let vpls = make_vpls(s, &scene, &bvh, cam)?;
    let glossy = vpls.iter().filter(|v| !v.is_diffuse()).count();
    log(format!(
        "slc: {}×{} G-buffer, {} VPLs ({} diffuse, {glossy} glossy) from {} in {:.2} s",
        s.width,
        s.height,
        vpls.len(),
        vpls.len() - glossy,
        source_name(s),
        t.elapsed().as_secs_f64()
    ));
    let mut stages = None;
    let mut isolated = None;
    let (culled, brute, seconds, device) = match gpu {
        Some(gp) => {
            let mut r = crate::slc::gpu::SlcGpu::new(gp, &g, &vpls, s.delta, s.interleave)?;
            r.set_xi_seed(Some(gpu_xi_seed(s.seed)));
            r.set_bound(s.bound);
            r.set_filter_kind(s.filter);
            let culled = r.run(Mode::Culled)?;
            // The frame time: frames back to back as a renderer runs them (the frame rate's
            // inverse). One frame submitted and waited for alone adds the host's submission
            // and wake-up, which varied between runs far more than the GPU's work (H100: 1.42
            // to 2.34 ms per frame for a 1.34 ms span on the GPU) — reported beside it.
            r.set_filter(false);
            let unfiltered = r.time_back_to_back(Mode::Culled, s.frames, BACK_TO_BACK)?;
            r.set_filter(true);
            let seconds = r.time_back_to_back(Mode::Culled, s.frames, BACK_TO_BACK)?;
            let alone = r.time(Mode::Culled, s.frames)?;
            isolated = Some(alone);
            log(format!("slc GPU frame without the filter: {:.3} ms", unfiltered * 1e3));
            stages = r.time_stages(Mode::Culled, s.frames)?;
            if let Some(st) = stages {
                log(stages_line(st));
            }
            log(format!("slc GPU one frame submitted and waited for alone (median of {}): {:.3} ms", s.frames.max(1), alone * 1e3));
            // The reference: every VPL at every pixel (no interleaving), no filter.
            let brute = if s.brute {
                let mut b = crate::slc::gpu::SlcGpu::new(gp, &g, &vpls, s.delta, 1)?;
                b.set_filter(false);
                Some((b.run(Mode::BruteForce)?, b.time(Mode::BruteForce, 1)?))
            } else {
                None
            };
            (culled, brute, seconds, format!("GPU: {} (its own ξ stream, seed {})", gp.adapter, gpu_xi_seed(s.seed)))
        }
        None => {
            let t = Instant::now();
            let culled = slc::render_filtered(&g, &vpls, s.delta, Mode::Culled, s.interleave, s.bound, s.filter);
            let seconds = t.elapsed().as_secs_f64();
            let brute = s.brute.then(|| {
                let t = Instant::now();
                (slc::render(&g, &vpls, s.delta, Mode::BruteForce, 1), t.elapsed().as_secs_f64())
            });
            (culled, brute, seconds, "CPU (one thread)".to_string())
        }
    };
    let n = (s.width * s.height) as f64;
    let lpp = culled.lights_per_pixel.iter().map(|x| *x as f64).sum::<f64>() / n;
    let fdr = culled.pixel_fdr();
    log(format!(
        "slc on {device}: {:.3} ms per frame (bounds + culling + shading + filter, {}×{} interleaving{}), {lpp:.1} VPLs per pixel, false discovery rate {fdr:.3} ({} false discoveries; {} kept (tile, VPL) pairs, {} accepted by no pixel)",
        seconds * 1e3,
        s.interleave,
        s.interleave,
        if gpu.is_some() { "; frames back to back" } else { "" },
        culled.false_discoveries(),
        culled.kept,
        culled.false_positives
    ));
    let valid = write_images(s, &g, &culled)?;
    // The glossy bounds side by side ([TH17 §7, Fig. 9]): the same VPLs and ξ culled by the
    // spheroid, the sphere enclosing it and the TH16 sphere of radius r/α.
    let bounds = if s.compare_bounds && glossy > 0 { crate::slc::compare::bounds(s, gpu, &g, &vpls, log)? } else { serde_json::Map::new() };
    let culling = if s.compare_culling { crate::slc::compare::culling(s, gpu, &g, &vpls, log)? } else { serde_json::Value::Null };
    let mut meta = json!({
        "scene": scene.name, "device": device, "vpls": vpls.len(), "sky_paths": s.sky, "glossy_vpls": glossy, "light_paths": s.rsm.is_none().then_some(s.vpls), "rsm_texels": s.rsm, "vpl_source": source_name(s),
        "width": s.width, "height": s.height, "delta": s.delta, "tile": slc::TILE, "interleave": s.interleave,
        "glossy_bound": format!("{:?}", s.bound), "kind": s.kind, "glossy_alpha": s.glossy_alpha,
        "seconds_per_frame": seconds, "vpls_per_pixel": lpp, "kept_pairs": culled.kept,
        "pairs_accepted_by_no_pixel": culled.false_positives, "false_discoveries": culled.false_discoveries(),
        "false_discovery_rate": fdr,
        "image": "slc.exr (slc.png)", "filtered_image": "slc_filtered.exr (slc_filtered.png): the subregions joined by the filter",
        "filter": filter_json(s),
        "frame_timing": if gpu.is_some() { format!("GPU: frames back to back, wall time over up to {BACK_TO_BACK} frames (about 0.3 s, at least the run's frames) with one wait") } else { "CPU: one render's wall time".to_string() },
        "seconds_per_isolated_frame": isolated,
        "stages_ms": stages.map(|t| json!({"range_determination": t.bounds * 1e3, "culling_and_shading": t.culling_shading * 1e3, "filter": t.filter * 1e3,
            "frame": t.frame * 1e3,
            "note": "GPU timestamps, medians; frame: from the range determination's start to the filter's end; the G-buffer and the VPLs (light paths) are made on the CPU and not timed"})),
        "vpls_per_pixel_image": "slc_vpls_per_pixel.exr (counts)",
        "false_discovery_image": "slc_fdr.exr (per pixel; slc_fdr.png: hue blue→red 0→100%, brightness VPLs per pixel)",
        "bounds": bounds,
        "culling_comparison": culling,
    });
    if let Some((b, bs)) = brute {
        meta["brute_force"] = brute_report(s, gpu, (&g, &vpls), (&b, bs), &culled, &valid, log)?;
        if let Some(sw) = meta["brute_force"].as_object_mut().and_then(|m| m.remove("sweep")) {
            meta["sweep"] = sw;
        }
    }
    if let Some(m) = &s.medium {
        meta["medium"] = crate::slc::media_run::render(s, m, gpu, (&scene, &bvh, cam), &g, &vpls, log)?;
    }
    std::fs::write(o.out.join("slc.json"), serde_json::to_string_pretty(&meta).expect("json")).map_err(|e| format!("slc.json: {e}"))?;
    Ok(())
}

/// The brute-force reference's part of slc.json (its image written, the culled image's error
/// against it) and, with `s.sweep`, the equal-time experiment under the key `sweep`.
fn brute_report(
    s: &SlcOptions,
    gpu: Option<&shaders::gpu::Gpu>,
    (g, vpls): (&crate::slc::GBuffer, &[crate::slc::Vpl]),
    (b, bs): (&crate::slc::Render, f64),
    culled: &crate::slc::Render,
    valid: &[f32],
    log: &mut dyn FnMut(String),
) -> Result<serde_json::Value, String> {
    output::write_exr(&s.out.join("slc_brute.exr"), s.width, s.height, &rgb(&b.image), valid)?;
    let (cm, bm) = (mean(&culled.image), mean(&b.image));
    let err = error_against(&b.image, &culled.image, &culled.filtered, valid);
    log(format!(
        "slc brute force (every VPL at every pixel): {:.3} ms per frame; image means (RGB) culled {cm:.6}, brute {bm:.6}; relative RMSE against it {:.4} before the filter, {:.4} after ({})",
        bs * 1e3,
        err["unfiltered"]["relative_rmse"].as_f64().unwrap_or(f64::NAN),
        err["filtered"]["relative_rmse"].as_f64().unwrap_or(f64::NAN),
        s.filter.name()
    ));
    let mut out = json!({"image": "slc_brute.exr", "seconds_per_frame": bs, "mean": bm, "culled_mean": cm, "error": err});
    if !s.sweep.is_empty() {
        let settings =
            crate::slc::sweep::Settings { interleave: s.interleave, filter: s.filter, frames: s.frames, xi_seed: gpu_xi_seed(s.seed) };
        let points = crate::slc::sweep::run(settings, gpu, g, vpls, &s.sweep, (&b.image, valid), log)?;
        let j = crate::slc::sweep::json(&points, s.delta);
        let at = j["equal_time"]["seconds_per_frame"].as_f64().unwrap_or(f64::NAN);
        log(format!(
            "slc equal time (at the spheroid's {:.3} ms per frame, δ {:e}): filtered relative RMSE {}",
            at * 1e3,
            s.delta,
            j["equal_time"]["relative_rmse_filtered"]
        ));
        out["sweep"] = j;
    }
    Ok(out)
}

/// Where the VPLs came from, in words.
fn source_name(s: &SlcOptions) -> String {
    let first = match s.rsm {
        Some(n) => format!("{n}×{n} reflective shadow maps"),
        None => format!("{} light paths", s.vpls),
    };
    match s.bounces {
        0 => first,
        b => format!("{first} and {b} diffuse bounce(s)"),
    }
}

/// The most frames in the back-to-back timing (one host wait for all of them).
const BACK_TO_BACK: usize = 100;

/// The per-stage GPU times as a log line.
fn stages_line(t: crate::slc::gpu::StageTimes) -> String {
    format!(
        "slc GPU stages (timestamps; [TH17 Table 1]'s rows that run here): range determination {:.3} ms, culling + shading {:.3} ms, filter {:.3} ms; the frame on the GPU {:.3} ms",
        t.bounds * 1e3,
        t.culling_shading * 1e3,
        t.filter * 1e3,
        t.frame * 1e3
    )
}

/// slc.json's description of the filter joining the subregions.
fn filter_json(s: &SlcOptions) -> serde_json::Value {
    use crate::slc::filter::{Filter, NORMAL_POWER};
    match s.filter {
        Filter::Box => json!({"kind": "box", "window": s.interleave, "max_normal_angle_deg": 25.0}),
        Filter::Bilateral { radius } => json!({
            "kind": "bilateral", "radius": radius, "spatial": format!("trapezoid box_{} * box_{} per axis", s.interleave, (2 * radius + 2).saturating_sub(s.interleave)),
            "depth_sigma_pixel_footprints": radius as f64 / 2.0, "normal_power": NORMAL_POWER,
        }),
    }
}

/// An image's mean over pixels and channels.
fn mean(img: &[Vec3]) -> f64 {
    img.iter().map(|c| c.as_dvec3().element_sum()).sum::<f64>() / (3 * img.len().max(1)) as f64
}

/// An RGB image as the EXR writer takes it.
fn rgb(img: &[Vec3]) -> Vec<[f32; 3]> {
    img.iter().map(|c| c.to_array()).collect()
}

/// The culled image's error against the brute-force reference over the valid pixels' RGB
/// values (every channel a sample), before and after the filter: RMSE, RMSE relative to
/// the reference's mean, mean bias.
fn error_against(reference: &[Vec3], unfiltered: &[Vec3], filtered: &[Vec3], valid: &[f32]) -> serde_json::Value {
    let one = |img: &[Vec3]| {
        let (mut sq, mut bias, mut mean, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
        for ((r, x), v) in reference.iter().zip(img).zip(valid) {
            if *v > 0.0 {
                for c in 0..3 {
                    let e = x[c] as f64 - r[c] as f64;
                    sq += e * e;
                    bias += e;
                    mean += r[c] as f64;
                    n += 1;
                }
            }
        }
        let n = n.max(1) as f64;
        let rmse = (sq / n).sqrt();
        json!({"rmse": rmse, "relative_rmse": rmse / (mean / n).max(f64::MIN_POSITIVE), "mean_bias": bias / n})
    };
    json!({"unfiltered": one(unfiltered), "filtered": one(filtered), "pixels": valid.iter().filter(|v| **v > 0.0).count()})
}

/// Writes the culled, filtered, VPLs-per-pixel and false-discovery images (EXR and PNG);
/// returns the G-buffer's validity mask (the images' alpha).
fn write_images(s: &SlcOptions, g: &crate::slc::GBuffer, culled: &crate::slc::Render) -> Result<Vec<f32>, String> {
    let gray = |v: &[f32]| -> Vec<[f32; 3]> { v.iter().map(|x| [*x; 3]).collect() };
    let valid: Vec<f32> = g.texels.iter().map(|t| t.is_some() as u8 as f32).collect();
    let filtered = &culled.filtered;
    output::write_exr(&s.out.join("slc.exr"), s.width, s.height, &rgb(&culled.image), &valid)?;
    output::write_exr(&s.out.join("slc_filtered.exr"), s.width, s.height, &rgb(filtered), &valid)?;
    let lp: Vec<f32> = culled.lights_per_pixel.iter().map(|x| *x as f32).collect();
    output::write_exr(&s.out.join("slc_vpls_per_pixel.exr"), s.width, s.height, &gray(&lp), &valid)?;
    let fdr_img: Vec<f32> =
        culled.false_per_pixel.iter().zip(&culled.lights_per_pixel).map(|(f, l)| *f as f32 / (*l).max(1) as f32).collect();
    output::write_exr(&s.out.join("slc_fdr.exr"), s.width, s.height, &gray(&fdr_img), &valid)?;
    let scale = output::exposure_scale(&output::luminances(filtered));
    output::save_png(&s.out.join("slc.png"), &output::tonemap_rgb(s.width, s.height, &culled.image, scale))?;
    output::save_png(&s.out.join("slc_filtered.png"), &output::tonemap_rgb(s.width, s.height, filtered, scale))?;
    output::save_png(&s.out.join("slc_fdr.png"), &output::heat(s.width, s.height, &fdr_img, &lp))?;
    Ok(valid)
}

#[cfg(test)]
mod tests {
    /// The error measures on a 4-pixel case worked by hand: reference (1, 2, 3, ·) grey with
    /// the last pixel invalid; errors +1, −1, +1 in the red channel only → 9 samples, RMSE
    /// √(3/9), relative √(1/3)/2 (mean 2), signed bias 1/9.
    #[test]
    fn error_against_is_rmse_relative_rmse_and_signed_bias() {
        use sbf::glam::Vec3;
        let reference = [1.0, 2.0, 3.0, 100.0].map(Vec3::splat);
        let img = [(1.0, 1.0), (2.0, -1.0), (3.0, 1.0), (100.0, -100.0)].map(|(r, e)| Vec3::splat(r) + Vec3::new(e, 0.0, 0.0));
        let e = super::error_against(&reference, &img, &reference, &[1.0, 1.0, 1.0, 0.0]);
        let u = &e["unfiltered"];
        let rmse = (1.0f64 / 3.0).sqrt();
        assert!((u["rmse"].as_f64().unwrap() - rmse).abs() < 1e-12, "{e}");
        assert!((u["relative_rmse"].as_f64().unwrap() - rmse / 2.0).abs() < 1e-12, "{e}");
        assert!((u["mean_bias"].as_f64().unwrap() - 1.0 / 9.0).abs() < 1e-12, "{e}");
        assert_eq!(e["filtered"]["rmse"].as_f64().unwrap(), 0.0);
        assert_eq!(e["pixels"].as_u64().unwrap(), 3);
    }
}
