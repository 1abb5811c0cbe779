//! The per-sample encoders: the peer's running averages (`sgra`, `sgnnra`) and [Roughton19 §7.3]'s
//! progressive LS/NNLS (`sgpls`, `sgpnnls`, `adpls`, `adpnnls`), with their error against sample
//! count.

use super::common::*;
use super::context::*;
use sbf::glam::DVec3;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::recon::ambient_dice as adr;
use sbf::solve::RadianceSample;
use sbf::{AmbientDiceSrbf, Basis, Domain, SgBasis};

/// Runs mode `id` of this family up to its cost measurement ([`super::prepare`]).
pub(super) fn prepare<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let vogel = sbf::layout::vogel_sphere(12).map_err(err)?;
    let dirs = &ctx.dirs;
    match id {
        "sgra" | "sgnnra" | "sgpls" | "sgpnnls" | "adpls" | "adpnnls" => {
            let vogel12 = vogel.clone();
            let (basis, lobes): (std::sync::Arc<dyn Basis + Send + Sync>, Vec<(DVec3, f64)>) = if id.starts_with("sg") {
                (std::sync::Arc::new(SgBasis::new(&vogel12, 6.0, false).map_err(err)?), vogel12.iter().map(|a| (*a, 6.0)).collect())
            } else {
                let ad = AmbientDiceSrbf::twelve();
                let l = ad.lobes().iter().map(|a| (*a, 0.0)).collect();
                (std::sync::Arc::new(ad), l)
            };
            let opts = match id {
                "sgra" | "sgnnra" => {
                    let g = gram_matrix(basis.as_ref(), Domain::Sphere, GramOptions::default()).map_err(err)?;
                    let diag: Vec<f64> = (0..basis.len()).map(|i| g.matrix[(i, i)]).collect();
                    sbf::solve::ProgressiveOptions::running_average(&diag, 4.0 * std::f64::consts::PI, id == "sgnnra")
                }
                "sgpnnls" | "adpnnls" => sbf::solve::ProgressiveOptions::non_negative(),
                _ => sbf::solve::ProgressiveOptions::default(),
            };
            // Samples: the running averages take every texel once in a fixed shuffled
            // order (as the peer); the progressive modes take PROGRESSIVE_SAMPLES Halton
            // directions with bilinear radiance. Equal weights: only ratios matter.
            let samples: std::sync::Arc<Vec<RadianceSample>> = std::sync::Arc::new(if id.ends_with("ra") {
                let mut order: Vec<usize> = (0..ctx.samples.len()).collect();
                let mut rng = sbf::sampling::Pcg32::new(17, 3);
                for i in (1..order.len()).rev() {
                    order.swap(i, (rng.next_u32() as usize) % (i + 1));
                }
                order.iter().map(|&k| ctx.samples[k]).collect()
            } else {
                (0..PROGRESSIVE_SAMPLES)
                    .map(|i| {
                        let d = sbf::sampling::uniform_sphere(sbf::sampling::halton2(i));
                        RadianceSample { direction: d, value: ctx.map.bilinear(d), weight: 1.0 }
                    })
                    .collect()
            });
            let (b, smp, o) = (basis.clone(), samples.clone(), opts.clone());
            let (c, t) = timed(repeats, move || -> Result<Vec<[f64; 3]>, String> {
                let mut enc = sbf::solve::ProgressiveEncoder::<f32>::new(b.len(), o.clone());
                for s in smp.iter() {
                    enc.add(b.as_ref(), s).map_err(err)?;
                }
                Ok(channels(&enc.coefficients()))
            });
            let c = ctx.stored(c?);
            let sgb = SgBasis::new(&vogel12, 6.0, false).map_err(err)?;
            let ad = AmbientDiceSrbf::twelve();
            // Irradiance of one direction from RGB coefficients. The peer's running
            // averages use Hill's fit too (their figures match it).
            let sgb_lobes = sg_lobes(&sgb, id);
            let (irr, ns) = if id.starts_with("sg") {
                let (b, l, cc) = (sgb.clone(), sg_lobes(&sgb, id), c.clone());
                eval_cost(ctx, move |d| sg_irradiance_rgb(SgIrradiance::Hill, id, &b, &l, &cc, d))
            } else {
                let (a, cc) = (ad.clone(), c.clone());
                eval_cost(ctx, move |d| dot_rgb(&cc, a.lobes().iter().map(|x| adr::lobe_irradiance_cos(x.dot(d)))))
            };
            // Error against sample count: an untimed second pass with snapshots. The
            // irradiance is linear in the coefficients, so each snapshot is a product with
            // the per-lobe irradiance K[d][i] (same functions as above, one lobe at a time).
            let nb = basis.len();
            let kmat: Vec<f64> = dirs
                .iter()
                .flat_map(|d| {
                    (0..nb).map(|i| {
                        if id.starts_with("sg") {
                            sgb_lobes.hill[i].eval(*d)
                        } else {
                            adr::lobe_irradiance_cos(ad.lobes()[i].dot(*d))
                        }
                    })
                })
                .collect();
            let mut enc = sbf::solve::ProgressiveEncoder::<f32>::new(basis.len(), opts.clone());
            let mut convergence = Vec::new();
            let mut next = 16usize;
            for (i, s) in samples.iter().enumerate() {
                enc.add(basis.as_ref(), s).map_err(err)?;
                let n = i + 1;
                if n == next || n == samples.len() {
                    let cc = channels(&enc.coefficients());
                    let img: Vec<[f64; 3]> = {
                        use rayon::prelude::*;
                        kmat.par_chunks_exact(nb).map(|k| dot_rgb(&cc, k.iter().copied())).collect()
                    };
                    convergence.push((n as u64, crate::metrics::rms_rows(ctx.grid, &img, &ctx.irradiance, ctx.metric_rows())));
                    while next <= n {
                        next *= 2;
                    }
                }
            }
            let rad = reconstruct(basis.as_ref(), &c, dirs);
            let solver = match id {
                "sgra" => "running average (per-sample, Jacobi, α = 1, clamped denominators)",
                "sgnnra" => "non-negative running average",
                "sgpls" | "adpls" => "progressive LS, f32 state, 4096 Halton samples ([Roughton19 §7.3])",
                _ => "progressive NNLS, f32 state, 4096 Halton samples ([Roughton19 §7.3])",
            };
            let mut r = mk!(id, ctx; basis.name(), solver, c, lobes, Some(rad), irr, t, ns);
            r.result.convergence = convergence;
            Ok(r)
        }
        _ => Err(format!("mode '{id}' is not one of this family's")),
    }
}
