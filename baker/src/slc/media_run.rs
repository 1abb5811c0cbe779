//! The `slc --medium` run: single scattering ([`super::media`], \[FTH22-supp\]) from the scene's
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

/// The lights in the medium, in view space (world moved by −`eye`): the scene's point
/// lights (spot lights as the point lights they are inside their cone; directional ones left
/// out — counted), `extra` point lights uniform in the scene's bounds `(lo, hi)` sharing the
/// power 4πR² W (R the bounding radius: an irradiance of 1 W/m² at R from each, summed), and
/// the diffuse VPLs (already in view space; their Φ ⊙ k). Powers are RGB. Returns (lights,
/// spots as points, directional left out).
fn lights(
    scene_lights: &[Light],
    (lo, hi): (Vec3, Vec3),
    eye: Vec3,
    seed: u64,
    extra: usize,
    vpls: &[super::Vpl],
) -> (Vec<MediaLight>, usize, usize) {
    let mut rng = sbf::sampling::Pcg32::new(seed, 0x3ed1);
    let mut out: Vec<MediaLight> = Vec::new();
    let (mut spots, mut directional) = (0, 0);
    for l in scene_lights {
        match *l {
            Light::Point { position, intensity, .. } | Light::Spot { position, intensity, .. } => {
                spots += matches!(l, Light::Spot { .. }) as usize;
                let xi = 1.0 - rng.next_f64() as f32;
                out.push(MediaLight { position: position - eye, normal: Vec3::ZERO, power: intensity * (4.0 * std::f32::consts::PI), xi });
            }
            Light::Directional { .. } => directional += 1,
        }
    }
    let radius = 0.5 * (hi - lo).length();
    for k in 0..extra {
        let [a, b] = rng.next_2d();
        let c = rng.next_f64();
        let p = lo + (hi - lo) * Vec3::new(a as f32, b as f32, c as f32);
        let power = Vec3::splat(4.0 * std::f32::consts::PI * radius * radius / extra as f32);
        out.push(MediaLight { position: p - eye, normal: Vec3::ZERO, power, xi: super::vpl_xi(seed ^ 0x2560, k as u64) });
    }
    out.extend(vpls.iter().filter(|v| v.is_diffuse()).map(|v| MediaLight {
        position: v.position,
        normal: v.normal,
        power: v.flux * v.diffuse,
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
    let (sc, bvh, cam) = scene;
    let bounds = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let (lights, spots, directional) = lights(&sc.lights, bounds, cam.eye, s.seed, s.point_lights, vpls);
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
    // Means of the images' luminance and of each channel.
    let mean = |v: &[Vec3]| output::luminances(v).iter().map(|x| *x as f64).sum::<f64>() / n;
    let mean_rgb = |v: &[Vec3]| v.iter().fold([0.0f64; 3], |a, c| [a[0] + c.x as f64 / n, a[1] + c.y as f64 / n, a[2] + c.z as f64 / n]);
    let shaded: u64 = culled.lights_per_pixel.iter().map(|x| *x as u64).sum();
    let fd: u64 = culled.false_per_pixel.iter().map(|x| *x as u64).sum();
    let device = match gpu {
        Some(gp) => format!("GPU {}", gp.adapter),
        None => format!("CPU on {} threads", rayon::current_num_threads()),
    };
    log(format!(
        "slc medium ({} lights: {} extra point lights; {device}): culled {:.3} ms ({:.1} lights per pixel, false discovery rate {:.3}), brute force {:.3} ms; image means (luminance) {:.6e} / {:.6e}",
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
    let rgb = |v: &[Vec3]| -> Vec<[f32; 3]> { v.iter().map(|c| c.to_array()).collect() };
    let ones = vec![1.0f32; g.width * g.height];
    output::write_exr(&s.out.join("slc_medium.exr"), g.width, g.height, &rgb(&culled.image), &ones)?;
    output::write_exr(&s.out.join("slc_medium_brute.exr"), g.width, g.height, &rgb(&brute.image), &ones)?;
    let scale = output::exposure_scale(&output::luminances(&brute.image));
    output::save_png(&s.out.join("slc_medium.png"), &output::tonemap_rgb(g.width, g.height, &culled.image, scale))?;
    // The false discovery rate per pixel ([FTH22-supp Fig. 1]: blue 0 → red 100 %).
    let fdr: Vec<f32> = culled.false_per_pixel.iter().zip(&culled.lights_per_pixel).map(|(f, l)| *f as f32 / (*l).max(1) as f32).collect();
    let kept: Vec<f32> = culled.lights_per_pixel.iter().map(|x| (*x > 0) as u8 as f32).collect();
    output::write_exr(&s.out.join("slc_medium_fdr.exr"), g.width, g.height, &gray(&fdr), &ones)?;
    output::save_png(&s.out.join("slc_medium_fdr.png"), &output::heat(g.width, g.height, &fdr, &kept))?;
    Ok(json!({
        "sigma_s": m.sigma_s, "sigma_t": m.sigma_t, "near": m.near, "far": m.far, "lights": lights.len(), "extra_point_lights": s.point_lights,
        "spot_lights_as_points": spots, "directional_lights_left_out": directional, "device": device,
        "culled_seconds": ct, "brute_force_seconds": bt, "lights_per_pixel": shaded as f64 / n,
        "false_discovery_rate": fd as f64 / shaded.max(1) as f64, "culled_mean": mean(&culled.image), "brute_force_mean": mean(&brute.image),
        "culled_mean_rgb": mean_rgb(&culled.image), "brute_force_mean_rgb": mean_rgb(&brute.image),
        "image": "slc_medium.exr (slc_medium.png)", "brute_force_image": "slc_medium_brute.exr",
        "false_discovery_image": "slc_medium_fdr.exr (slc_medium_fdr.png: blue 0 → red 100 %)",
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vpl(flux: Vec3, diffuse: Vec3) -> super::super::Vpl {
        super::super::Vpl {
            position: Vec3::new(0.5, -1.0, -3.0),
            normal: Vec3::Y,
            incoming: Vec3::Y,
            flux,
            diffuse,
            alpha: 0.3,
            f0: Vec3::splat(0.5),
            xi: 0.25,
        }
    }

    /// Each light's RGB power against its closed form, written here: a point light of
    /// intensity I emits Φ = 4π·I per channel; a diffuse VPL reflects Φ ⊙ k; the extra lights
    /// share 4πR² (white) with R half the bounds' diagonal, and sit inside the bounds;
    /// positions are view space (−eye); a GGX VPL and a directional light are left out.
    /// Tolerance: f32 rounding of a handful of products (1e-6 relative).
    /// Mutations tried: Φ for Φ ⊙ k; a point light's power without 4π; the extra
    /// lights' share not divided by their count; the eye not subtracted; `hi·u` for
    /// `(hi − lo)·u`; a scene light's ξ = u (may be 0); the extra lights' ξ from the VPLs'
    /// stream — each fails.
    #[test]
    fn lights_carry_their_closed_form_powers() {
        let eye = Vec3::new(1.0, 2.0, 3.0);
        let scene = [
            Light::Point { position: Vec3::new(0.0, 1.0, 0.0), intensity: Vec3::new(1.0, 2.0, 3.0), range: f32::INFINITY },
            Light::Spot {
                position: Vec3::new(1.0, 1.0, 0.0),
                direction: -Vec3::Y,
                intensity: Vec3::new(4.0, 0.0, 0.0),
                cos_inner: 0.9,
                cos_outer: 0.8,
                range: f32::INFINITY,
            },
            Light::Directional { direction: Vec3::Y, irradiance: Vec3::ONE },
        ];
        let vpls = [vpl(Vec3::new(2.0, 4.0, 8.0), Vec3::new(0.5, 0.25, 0.125)), vpl(Vec3::ONE, Vec3::ZERO)];
        let (lo, hi) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(5.0, 5.0, 5.0));
        let (l, spots, directional) = lights(&scene, (lo, hi), eye, 7, 8, &vpls);
        assert_eq!((l.len(), spots, directional), (2 + 8 + 1, 1, 1));
        let close = |a: f32, b: f64| if b == 0.0 { a == 0.0 } else { ((a as f64 - b) / b).abs() < 1e-6 };
        let close3 = |a: Vec3, b: [f64; 3]| (0..3).all(|c| close(a[c], b[c]));
        let four_pi = 4.0 * std::f64::consts::PI;
        assert!(close3(l[0].power, [four_pi, four_pi * 2.0, four_pi * 3.0]), "point light: {}", l[0].power);
        assert!(close3(l[1].power, [four_pi * 4.0, 0.0, 0.0]), "spot light: {}", l[1].power);
        assert_eq!((l[0].position, l[0].normal), (Vec3::new(-1.0, -1.0, -3.0), Vec3::ZERO));
        let r2 = 0.25 * (16.0 + 9.0 + 4.0);
        for x in &l[..2] {
            assert!(x.xi > 0.0 && x.xi <= 1.0, "scene light ξ {}", x.xi);
        }
        for c in 0..3 {
            let extra: f64 = l[2..10].iter().map(|x| x.power[c] as f64).sum();
            assert!(close(extra as f32, four_pi * r2), "extra lights, channel {c}: {extra}");
        }
        for (k, x) in l[2..10].iter().enumerate() {
            let p = x.position + eye;
            assert!(p.cmpge(lo).all() && p.cmple(hi).all() && x.normal == Vec3::ZERO && x.xi > 0.0 && x.xi <= 1.0, "{x:?}");
            // Their own stream of ξ, not the VPLs' (path k of the same seed).
            assert_ne!(x.xi, super::super::vpl_xi(7, k as u64), "extra light {k} shares a VPL's ξ");
        }
        // Φ ⊙ k = (2, 4, 8) ⊙ (0.5, 0.25, 0.125) = (1, 1, 1).
        let v = l[10];
        assert!(close3(v.power, [1.0; 3]), "diffuse VPL: {}", v.power);
        assert_eq!((v.position, v.normal, v.xi), (vpls[0].position, Vec3::Y, 0.25));
    }
}
