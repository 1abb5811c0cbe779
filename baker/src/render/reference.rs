//! The path-traced reference of the rendered quantity: at each pixel's visible surface x
//! (viewed along ω_o), the light it reflects towards the eye,
//! L_o = ∫ (f_d + f_s)(ω_o, ω_i) L_in(x, ω_i) cos θ_i dω_i, with L_in estimated by the
//! bake's own estimator ([`Tracer::sample_point_with`]: delta lights and area-light and
//! environment samples by next-event estimation, the point sample by the material's
//! BSDF sampling, combined by the power heuristic — Veach 1997 §9.2) and the same
//! materials (Lambert + single-scattering GGX, Schlick F0/f90 = 1). The lightmap encodes
//! exactly this L_in (same estimator, same domain: the hemisphere about the shading
//! normal, cut at the geometric horizon), so a rendered image differs from the reference
//! by the lightmap's error alone: texel resolution, basis, runtime. Emission of the
//! visible surface is not part of either image.
//!
//! Independent random numbers per (pixel, sample) — not Sobol' — so that the per-pixel
//! sample variance is an unbiased estimate of the mean's noise, which the comparison
//! subtracts. Samples whose point sample meets the back of a single-sided surface are
//! rejected, as the bake rejects them.

use super::visible::Visible;
use crate::estimator::trace::{eval_bsdf, sample_bsdf, Tracer};
use crate::sampling::sequence::{PathSampler, Sequence, DIRECTION};
use crate::scene::Scene;
use rayon::prelude::*;
use sbf::glam::{DVec3, Vec3};

/// Per pixel, mean reflected radiance split into the Lambert and GGX parts, and the
/// variance of each mean (per channel).
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    pub samples: u32,
    pub diffuse: Vec<DVec3>,
    pub specular: Vec<DVec3>,
    /// Variance of the mean of diffuse, specular and their sum.
    pub var_diffuse: Vec<DVec3>,
    pub var_specular: Vec<DVec3>,
    pub var_total: Vec<DVec3>,
    /// Accepted samples per pixel (0 where nothing lightmapped is visible).
    pub accepted: Vec<u32>,
}

/// (Lambert part, GGX part) of the material's BSDF for (ω_o, ω_i).
fn split_bsdf(m: &crate::scene::Material, ns: Vec3, wo: Vec3, wi: Vec3) -> (DVec3, DVec3) {
    let (f, _) = eval_bsdf(m, ns, wo, wi);
    if wi.dot(ns) <= 0.0 || wo.dot(ns) <= 0.0 {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    let fd = m.diffuse_albedo().as_dvec3() * std::f64::consts::FRAC_1_PI;
    (fd, f.as_dvec3() - fd)
}

/// One sample of (diffuse, specular) reflected radiance at `s` towards `eye`; None: rejected.
pub fn sample(tracer: &Tracer, scene: &Scene, s: &Visible, eye: Vec3, smp: &mut PathSampler) -> Option<(DVec3, DVec3)> {
    let m = &scene.materials[s.material as usize];
    let (ns, ng) = (s.normal, s.geometric);
    let wo = (eye - s.position).normalize();
    if wo.dot(ng) <= 0.0 || wo.dot(ns) <= 0.0 {
        return Some((DVec3::ZERO, DVec3::ZERO));
    }
    let u = smp.get(DIRECTION);
    let drawn = sample_bsdf(m, ns, wo, [u[0], u[1], u[2]]);
    let pdf_of = |w: Vec3| eval_bsdf(m, ns, wo, w).1;
    // No direction drawn: the point sample contributes nothing (a direction below the
    // horizon makes the estimator skip it) while the light samples still count.
    let dir = drawn.map(|d| d.0).unwrap_or(-ng);
    let ps = tracer.sample_point_with(s.position, Some((ns, ng)), dir, &pdf_of, smp);
    if ps.back_face {
        return None;
    }
    let (mut d, mut sp) = (DVec3::ZERO, DVec3::ZERO);
    for (wi, c) in &ps.lights {
        let (fd, fs) = split_bsdf(m, ns, wo, *wi);
        let w = c.as_dvec3() * wi.dot(ns) as f64;
        d += fd * w;
        sp += fs * w;
    }
    if let Some((wi, _, pdf)) = drawn {
        let (fd, fs) = split_bsdf(m, ns, wo, wi);
        let w = ps.radiance.as_dvec3() * (wi.dot(ns) as f64 / pdf);
        d += fd * w;
        sp += fs * w;
    }
    Some((d, sp))
}

/// The reference image of `visible` (only lightmapped surfaces; the rest stays zero) with
/// `samples` samples per pixel; `progress` is called with the rows done so far.
pub fn render(
    tracer: &Tracer,
    scene: &Scene,
    visible: &[Option<Visible>],
    eye: Vec3,
    samples: u32,
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> Reference {
    let done = std::sync::atomic::AtomicUsize::new(0);
    let per_pixel: Vec<_> = visible
        .par_iter()
        .enumerate()
        .map(|(k, s)| {
            let r = pixel(tracer, scene, s.as_ref().filter(|s| s.lightmapped), eye, samples, seed, k as u32);
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            if n % 4096 == 0 {
                progress(n);
            }
            r
        })
        .collect();
    let mut out = Reference {
        samples,
        diffuse: Vec::with_capacity(visible.len()),
        specular: Vec::with_capacity(visible.len()),
        var_diffuse: Vec::with_capacity(visible.len()),
        var_specular: Vec::with_capacity(visible.len()),
        var_total: Vec::with_capacity(visible.len()),
        accepted: Vec::with_capacity(visible.len()),
    };
    for p in per_pixel {
        out.diffuse.push(p.mean[0]);
        out.specular.push(p.mean[1]);
        out.var_diffuse.push(p.var[0]);
        out.var_specular.push(p.var[1]);
        out.var_total.push(p.var[2]);
        out.accepted.push(p.n);
    }
    out
}

/// Means (diffuse, specular) and variances of the means (diffuse, specular, total).
struct PixelStats {
    mean: [DVec3; 2],
    var: [DVec3; 3],
    n: u32,
}

fn pixel(tracer: &Tracer, scene: &Scene, s: Option<&Visible>, eye: Vec3, samples: u32, seed: u64, id: u32) -> PixelStats {
    let zero = PixelStats { mean: [DVec3::ZERO; 2], var: [DVec3::ZERO; 3], n: 0 };
    let Some(s) = s else { return zero };
    // Running sums of the three quantities and of their squares (values are O(1) and
    // the counts small: plain sums in f64 keep ~1e-12 relative accuracy).
    let (mut sum, mut sq) = ([DVec3::ZERO; 3], [DVec3::ZERO; 3]);
    let mut n = 0u32;
    for k in 0..samples {
        let mut smp = PathSampler::new(Sequence::Independent, seed, id, k as u64);
        if let Some((d, sp)) = sample(tracer, scene, s, eye, &mut smp) {
            for (i, x) in [d, sp, d + sp].into_iter().enumerate() {
                sum[i] += x;
                sq[i] += x * x;
            }
            n += 1;
        }
    }
    if n == 0 {
        return zero;
    }
    let nf = n as f64;
    let mean = sum.map(|x| x / nf);
    // Variance of the mean: the unbiased sample variance over n.
    let var = std::array::from_fn(|i| if n > 1 { ((sq[i] - sum[i] * mean[i]) / (nf - 1.0)).max(DVec3::ZERO) / nf } else { DVec3::ZERO });
    PixelStats { mean: [mean[0], mean[1]], var, n }
}
