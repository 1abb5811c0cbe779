//! The GGX specular signal (f0 = f90 = 1, single scattering, height-correlated Smith).
//!
//! Geometry per output texel with direction d: over the sphere, normal = view = d
//! (normal incidence: the prefiltered environment); over the upper hemisphere, the
//! normal is the map's up (+Y) and the view is d (seed 004 Appendix C), zero below.
//!
//! Reference: visible-normal samples plus map samples (by texel luminance) combined by
//! multiple importance sampling ([`sbf::recon::reference::ggx_specular_mis`]), a
//! reported number of each per texel, radiance by bilinear lookup; its error is
//! estimated against 16× the samples on a texel subset ([`reference_error`]).
//! Reconstructions, from the coefficients a mode stored: SH by zonal convolution about
//! the dominant direction with the committed DFG table; SG lobes by the ASG warp; Ambient
//! Dice SRBF lobes by the seed's fit (Listing 8.1) times the committed 2D LUT
//! (Listing 8.2). Other modes store irradiance, not radiance, and have no specular.

use crate::modes::{Context, ModeResult};
use rayon::prelude::*;
use sbf::glam::DVec3;
use sbf::recon::reference::MapSampler;
use sbf::recon::{ambient_dice as adr, sg as sgr, sh as shr};
use sbf::Domain;

/// (normal, view) of output texel `k`, or `None` where the signal is zero.
fn geometry(ctx: &Context, k: usize) -> Option<(DVec3, DVec3)> {
    let d = ctx.dirs[k];
    match ctx.domain {
        Domain::Sphere => Some((d, d)),
        Domain::UpperHemisphere => (d.y > 0.0).then_some((DVec3::Y, d)),
    }
}

/// One reference texel: `samples` visible-normal plus `samples` map samples, MIS.
fn reference_texel(ctx: &Context, sampler: Option<&MapSampler>, k: usize, alpha: f64, samples: u32) -> [f64; 3] {
    match geometry(ctx, k) {
        Some((n, v)) => sbf::recon::reference::ggx_specular_mis(&ctx.map, sampler, n, v, alpha, 1.0, 1.0, samples),
        None => [0.0; 3],
    }
}

/// Reference specular image for roughness `alpha`.
pub fn reference(ctx: &Context, alpha: f64, samples: u32) -> Vec<[f64; 3]> {
    let sampler = MapSampler::new(&ctx.map);
    (0..ctx.dirs.len()).into_par_iter().map(|k| reference_texel(ctx, sampler.as_ref(), k, alpha, samples)).collect()
}

/// Texel stride of the reference's convergence check.
pub const CHECK_STRIDE: usize = 101;
/// Sample-count multiplier of the convergence check.
pub const CHECK_FACTOR: u32 = 16;

/// Estimated error of a [`reference`] image: on every [`CHECK_STRIDE`]-th texel where
/// the signal is defined, the RMS difference (unweighted, over channels) between the
/// estimate with `samples` and with [`CHECK_FACTOR`]× as many points of the same
/// Halton sequence (whose own error is far smaller for a QMC rule), and the RMS of
/// the 16× estimate itself. Returns (error RMS, signal RMS, texels checked).
pub fn reference_error(ctx: &Context, alpha: f64, samples: u32, reference: &[[f64; 3]]) -> (f64, f64, usize) {
    let ks: Vec<usize> = (0..ctx.dirs.len()).step_by(CHECK_STRIDE).filter(|k| geometry(ctx, *k).is_some()).collect();
    let sampler = MapSampler::new(&ctx.map);
    let fine: Vec<[f64; 3]> =
        ks.par_iter().map(|&k| reference_texel(ctx, sampler.as_ref(), k, alpha, samples.saturating_mul(CHECK_FACTOR))).collect();
    let (mut e2, mut s2) = (0.0, 0.0);
    for (i, &k) in ks.iter().enumerate() {
        for c in 0..3 {
            e2 += (reference[k][c] - fine[i][c]).powi(2);
            s2 += fine[i][c].powi(2);
        }
    }
    let m = (3 * ks.len()).max(1) as f64;
    ((e2 / m).sqrt(), (s2 / m).sqrt(), ks.len())
}

fn is_sh(id: &str) -> bool {
    id.starts_with("shl")
}
fn is_sg(id: &str) -> bool {
    matches!(id, "sg" | "sgls" | "sglsa" | "sgnnls" | "sgra" | "sgnnra" | "sgpls" | "sgpnnls" | "sg9h" | "sg12h")
}
fn is_ad(id: &str) -> bool {
    matches!(id, "adrbf" | "adrbf-tangent" | "ad9" | "adpls" | "adpnnls")
}

/// Whether a mode reconstructs specular.
pub fn supported(id: &str) -> bool {
    is_sh(id) || is_sg(id) || is_ad(id)
}

/// Specular image of a mode for roughness `alpha`, or `None` for irradiance-only modes.
pub fn reconstruct(r: &ModeResult, ctx: &Context, alpha: f64) -> Option<Vec<[f64; 3]>> {
    if !supported(r.id) {
        return None;
    }
    let c = &r.coefficients;
    let chan = |k: usize| c.iter().map(|v| v[k]).collect::<Vec<f64>>();
    let chans = [chan(0), chan(1), chan(2)];
    let dfg = sbf::luts::committed::dfg();
    let lut = sbf::luts::committed::ad_specular_2d();
    let out = (0..ctx.dirs.len())
        .into_par_iter()
        .map(|k| {
            let Some((n, v)) = geometry(ctx, k) else { return [0.0; 3] };
            let nv = n.dot(v).clamp(0.0, 1.0);
            if is_sh(r.id) {
                let d = dfg.sample2(nv as f32, alpha as f32);
                [0, 1, 2].map(|ch| shr::specular_zonal(&chans[ch], n, v, alpha, 1.0, 1.0, [d[0] as f64, d[1] as f64]).unwrap_or(f64::NAN))
            } else if is_sg(r.id) {
                let warp = sgr::AsgWarp::new(n, v, alpha, 1.0, 1.0);
                let d = dfg.sample2(nv as f32, alpha as f32);
                [0, 1, 2].map(|ch| {
                    let lobes: f64 = r
                        .lobes
                        .iter()
                        .enumerate()
                        .map(|(i, (axis, lam))| chans[ch][i] * warp.lobe(&sbf::Sg { axis: *axis, sharpness: *lam, amplitude: 1.0 }))
                        .sum();
                    // An ambient (constant) function reflects its value times the albedo.
                    let ambient = if chans[ch].len() > r.lobes.len() { chans[ch][r.lobes.len()] * (d[0] + d[1]) as f64 } else { 0.0 };
                    lobes + ambient
                })
            } else {
                let axes: Vec<DVec3> = r.lobes.iter().map(|(a, _)| *a).collect();
                let l = lut.sample2(nv as f32, alpha as f32);
                [0, 1, 2].map(|ch| adr::specular(&axes, &chans[ch], n, v, alpha, 1.0, 1.0, [l[0] as f64, l[1] as f64]))
            }
        })
        .collect();
    Some(out)
}
