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

/// The reference image of `visible` (lightmapped surfaces and dynamic objects; the rest
/// stays zero) with
/// `samples` samples per pixel; `progress` is called with the pixels done so far.
pub fn render(
    tracer: &Tracer,
    scene: &Scene,
    visible: &[Option<Visible>],
    eye: Vec3,
    samples: u32,
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> Reference {
    let mut acc = vec![PixelAcc::default(); visible.len()];
    accumulate(tracer, scene, visible, eye, 0..samples, seed, &mut acc, progress);
    finish(&acc, samples)
}

/// The reference rendered progressively to a stated noise level: batches of samples
/// (`first`, then doubling the total) until the relative noise of the total —
/// √mean(σ²) over the RMS of the image, lightmapped pixels — is at most `noise`, or
/// `max_samples` are taken. `report` is called after each batch with (samples, noise).
#[allow(clippy::too_many_arguments)]
pub fn render_to_noise(
    tracer: &Tracer,
    scene: &Scene,
    visible: &[Option<Visible>],
    eye: Vec3,
    noise: f64,
    first: u32,
    max_samples: u32,
    seed: u64,
    report: &mut dyn FnMut(u32, f64),
) -> Reference {
    let mut add = |range: std::ops::Range<u32>, acc: &mut [PixelAcc]| {
        accumulate(tracer, scene, visible, eye, range, seed, acc, &|_| {});
        Ok(())
    };
    progressive(visible.len(), noise, first, max_samples, report, &mut add).expect("the CPU reference does not fail")
}

/// Takes a range of samples of every pixel into the pixels' sums.
pub(super) type AddSamples<'a> = dyn FnMut(std::ops::Range<u32>, &mut [PixelAcc]) -> Result<(), String> + 'a;

/// [`render_to_noise`] with the samples taken by `add` (samples range, every pixel's sums).
pub(super) fn progressive(
    pixels: usize,
    noise: f64,
    first: u32,
    max_samples: u32,
    report: &mut dyn FnMut(u32, f64),
    add: &mut AddSamples,
) -> Result<Reference, String> {
    let mut acc = vec![PixelAcc::default(); pixels];
    let mut taken = 0u32;
    let mut batch = first.clamp(1, max_samples.max(1));
    loop {
        add(taken..taken + batch, &mut acc)?;
        taken += batch;
        let r = finish(&acc, taken);
        let rel = relative_noise(&r);
        report(taken, rel);
        if rel <= noise || taken >= max_samples {
            return Ok(r);
        }
        batch = taken.min(max_samples - taken);
    }
}

/// √mean(σ²) of the total over its RMS, over the pixels with samples.
pub fn relative_noise(r: &Reference) -> f64 {
    let (mut var, mut sig, mut n) = (0.0, 0.0, 0usize);
    for k in 0..r.accepted.len() {
        if r.accepted[k] > 0 {
            let t = r.diffuse[k] + r.specular[k];
            var += r.var_total[k].element_sum() / 3.0;
            sig += t.length_squared() / 3.0;
            n += 1;
        }
    }
    if n == 0 || sig <= 0.0 {
        0.0
    } else {
        (var / sig).sqrt()
    }
}

/// Running sums of one pixel: (diffuse, specular, total) and their squares (values are
/// O(1) and the counts ≤ 2³²: plain sums in f64 keep ~1e-12 relative accuracy).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct PixelAcc {
    pub(super) sum: [DVec3; 3],
    pub(super) sq: [DVec3; 3],
    pub(super) n: u32,
}

/// Adds samples `range` of every lightmapped pixel (each pixel's numbers depend on the
/// seed, the pixel and the sample index only: any batching gives the same image).
#[allow(clippy::too_many_arguments)]
fn accumulate(
    tracer: &Tracer,
    scene: &Scene,
    visible: &[Option<Visible>],
    eye: Vec3,
    range: std::ops::Range<u32>,
    seed: u64,
    acc: &mut [PixelAcc],
    progress: &(dyn Fn(usize) + Sync),
) {
    let done = std::sync::atomic::AtomicUsize::new(0);
    acc.par_iter_mut().zip(visible.par_iter()).enumerate().for_each(|(k, (a, s))| {
        if let Some(s) = s.as_ref().filter(|s| s.lightmapped || s.probed) {
            for i in range.clone() {
                let mut smp = PathSampler::new(Sequence::Independent, seed, k as u32, i as u64);
                if let Some((d, sp)) = sample(tracer, scene, s, eye, &mut smp) {
                    for (j, x) in [d, sp, d + sp].into_iter().enumerate() {
                        a.sum[j] += x;
                        a.sq[j] += x * x;
                    }
                    a.n += 1;
                }
            }
        }
        let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if n % 4096 == 0 {
            progress(n);
        }
    });
}

/// Means and variances of the means from the running sums.
pub(super) fn finish(acc: &[PixelAcc], samples: u32) -> Reference {
    let mut out = Reference {
        samples,
        diffuse: Vec::with_capacity(acc.len()),
        specular: Vec::with_capacity(acc.len()),
        var_diffuse: Vec::with_capacity(acc.len()),
        var_specular: Vec::with_capacity(acc.len()),
        var_total: Vec::with_capacity(acc.len()),
        accepted: Vec::with_capacity(acc.len()),
    };
    for a in acc {
        let nf = a.n.max(1) as f64;
        let mean = a.sum.map(|x| x / nf);
        // Variance of the mean: the unbiased sample variance over n.
        let var: [DVec3; 3] =
            std::array::from_fn(
                |i| if a.n > 1 { ((a.sq[i] - a.sum[i] * mean[i]) / (nf - 1.0)).max(DVec3::ZERO) / nf } else { DVec3::ZERO },
            );
        out.diffuse.push(mean[0]);
        out.specular.push(mean[1]);
        out.var_diffuse.push(var[0]);
        out.var_specular.push(var[1]);
        out.var_total.push(var[2]);
        out.accepted.push(a.n);
    }
    out
}
