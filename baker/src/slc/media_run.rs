//! The `slc --medium` run: single scattering ([`super::media`], seed 001) from the scene's
//! point lights, `--point-lights N` more scattered through the scene (the supplement's
//! 2 560-point-light experiment) and the diffuse VPLs, culled and brute force, on the GPU
//! ([`super::media_gpu`]) or the CPU; its images (radiance, false discovery rate) and numbers.

use super::media::{render as render_cpu, MediaLight, MediaMode, MediaRender, Medium};
use super::options::SlcOptions;
use crate::output;
use crate::scene::Light;
use sbf::glam::Vec3;
use serde_json::json;
use std::time::Instant;

/// The lights in the medium (view space for `cam`): the scene's point lights (spot lights as
/// the point lights they are inside their cone; directional ones left out — counted), `extra`
/// point lights uniform in the scene's bounds sharing the power 4πR² W (R the bounding
/// radius: an irradiance of 1 W/m² at R from each, summed), and the diffuse VPLs (their Φk's
/// luminance: the medium renders luminance). Returns (lights, spots as points, directional
/// left out).
fn lights(
    s: &SlcOptions,
    (scene, bvh, cam): (&crate::scene::Scene, &crate::scene::bvh::Bvh, super::Camera),
    extra: usize,
    vpls: &[super::Vpl],
) -> (Vec<MediaLight>, usize, usize) {
    let mut rng = sbf::sampling::Pcg32::new(s.seed, 0x3ed1);
    let mut out: Vec<MediaLight> = Vec::new();
    let (mut spots, mut directional) = (0, 0);
    for l in &scene.lights {
        match *l {
            Light::Point { position, intensity, .. } | Light::Spot { position, intensity, .. } => {
                spots += matches!(l, Light::Spot { .. }) as usize;
                let xi = 1.0 - rng.next_f64() as f32;
                let power = (crate::scene::lights::luminance(intensity) * 4.0 * std::f64::consts::PI) as f32;
                out.push(MediaLight { position: position - cam.eye, normal: Vec3::ZERO, power, xi });
            }
            Light::Directional { .. } => directional += 1,
        }
    }
    let (lo, hi) = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let radius = 0.5 * (hi - lo).length();
    for k in 0..extra {
        let [a, b] = rng.next_2d();
        let c = rng.next_f64();
        let p = lo + (hi - lo) * Vec3::new(a as f32, b as f32, c as f32);
        let power = 4.0 * std::f32::consts::PI * radius * radius / extra as f32;
        out.push(MediaLight { position: p - cam.eye, normal: Vec3::ZERO, power, xi: super::vpl_xi(s.seed ^ 0x2560, k as u64) });
    }
    out.extend(vpls.iter().filter(|v| v.is_diffuse()).map(|v| MediaLight {
        position: v.position,
        normal: v.normal,
        power: crate::scene::lights::luminance(v.flux * v.diffuse) as f32,
        xi: v.xi,
    }));
    (out, spots, directional)
}

/// Renders the medium culled and brute force (GPU: frames timed, median; CPU: one render
/// each on every core); writes slc_medium.exr/png, slc_medium_brute.exr and
/// slc_medium_fdr.exr/png; returns slc.json's `medium`.
pub fn render(
    s: &SlcOptions,
    m: &Medium,
    gpu: Option<&shaders::gpu::Gpu>,
    scene: (&crate::scene::Scene, &crate::scene::bvh::Bvh, super::Camera),
    g: &super::GBuffer,
    vpls: &[super::Vpl],
    log: &mut dyn FnMut(String),
) -> Result<serde_json::Value, String> {
    let (lights, spots, directional) = lights(s, scene, s.point_lights, vpls);
    if spots + directional > 0 {
        log(format!(
            "slc medium: {spots} spot light(s) scatter as isotropic point lights (no cone), {directional} directional light(s) left out (single scattering from point lights and VPLs only)"
        ));
    }
    let run = |mode: MediaMode| -> Result<(MediaRender, f64), String> {
        match gpu {
            Some(gp) => {
                let mut r = super::media_gpu::MediaGpu::new(gp, g, m, &lights, s.delta)?;
                let seed = super::options::gpu_xi_seed(s.seed);
                let img = r.run(mode, seed)?;
                Ok((img, r.time(mode, if mode == MediaMode::Culled { s.frames } else { 1 })?))
            }
            None => {
                let t = Instant::now();
                Ok((render_cpu(g, m, &lights, s.delta, mode, s.seed), t.elapsed().as_secs_f64()))
            }
        }
    };
    let (culled, ct) = run(MediaMode::Culled)?;
    let (brute, bt) = run(MediaMode::BruteForce)?;
    let n = (g.width * g.height) as f64;
    let mean = |v: &[f32]| v.iter().map(|x| *x as f64).sum::<f64>() / n;
    let shaded: u64 = culled.lights_per_pixel.iter().map(|x| *x as u64).sum();
    let fd: u64 = culled.false_per_pixel.iter().map(|x| *x as u64).sum();
    let device = match gpu {
        Some(gp) => format!("GPU {}", gp.adapter),
        None => format!("CPU on {} threads", rayon::current_num_threads()),
    };
    log(format!(
        "slc medium ({} lights: {} extra point lights; {device}): culled {:.3} ms ({:.1} lights per pixel, false discovery rate {:.3}), brute force {:.3} ms; image means {:.6e} / {:.6e}",
        lights.len(),
        s.point_lights,
        ct * 1e3,
        shaded as f64 / n,
        fd as f64 / shaded.max(1) as f64,
        bt * 1e3,
        mean(&culled.image),
        mean(&brute.image)
    ));
    let gray = |v: &[f32]| -> Vec<[f32; 3]> { v.iter().map(|x| [*x; 3]).collect() };
    let ones = vec![1.0f32; g.width * g.height];
    output::write_exr(&s.out.join("slc_medium.exr"), g.width, g.height, &gray(&culled.image), &ones)?;
    output::write_exr(&s.out.join("slc_medium_brute.exr"), g.width, g.height, &gray(&brute.image), &ones)?;
    let scale = output::exposure_scale(&brute.image);
    output::save_png(&s.out.join("slc_medium.png"), &output::tonemap(g.width, g.height, &culled.image, scale))?;
    // The false discovery rate per pixel (001 supplement Fig. 1: blue 0 → red 100 %).
    let fdr: Vec<f32> = culled.false_per_pixel.iter().zip(&culled.lights_per_pixel).map(|(f, l)| *f as f32 / (*l).max(1) as f32).collect();
    let kept: Vec<f32> = culled.lights_per_pixel.iter().map(|x| (*x > 0) as u8 as f32).collect();
    output::write_exr(&s.out.join("slc_medium_fdr.exr"), g.width, g.height, &gray(&fdr), &ones)?;
    output::save_png(&s.out.join("slc_medium_fdr.png"), &output::heat(g.width, g.height, &fdr, &kept))?;
    Ok(json!({
        "sigma_s": m.sigma_s, "sigma_t": m.sigma_t, "near": m.near, "far": m.far, "lights": lights.len(), "extra_point_lights": s.point_lights,
        "spot_lights_as_points": spots, "directional_lights_left_out": directional, "device": device,
        "culled_seconds": ct, "brute_force_seconds": bt, "lights_per_pixel": shaded as f64 / n,
        "false_discovery_rate": fd as f64 / shaded.max(1) as f64, "culled_mean": mean(&culled.image), "brute_force_mean": mean(&brute.image),
        "image": "slc_medium.exr (slc_medium.png)", "brute_force_image": "slc_medium_brute.exr",
        "false_discovery_image": "slc_medium_fdr.exr (slc_medium_fdr.png: blue 0 → red 100 %)",
    }))
}
