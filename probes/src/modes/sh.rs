//! Spherical harmonics: `shlN` (N = 1…16), `shl1g` and `shl1zh3` (L1 variants), and `shl2w` (L2
//! deringed where its irradiance would be negative).

use super::common::*;
use super::context::*;
use super::sh_order;
use sbf::glam::DVec3;
use sbf::recon::sh as shr;
use sbf::solve::moments;
use sbf::{Basis, ShBasis};

/// Runs mode `id` of this family up to its cost measurement ([`super::prepare`]).
pub(super) fn prepare<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let dirs = &ctx.dirs;
    match id {
        _ if sh_order(id).is_some() => {
            let order = sh_order(id).expect("guarded");
            let sh = ShBasis::new(order).map_err(err)?;
            let sh_t = sh.clone();
            let (m, t) = timed(repeats, move || moments(&sh_t, &ctx.samples));
            let c = ctx.stored(channels(&m));
            let chans = [channel(&c, 0), channel(&c, 1), channel(&c, 2)];
            let (irr, ns) = match id {
                "shl1g" => {
                    let rgb: [[f64; 4]; 3] = [0, 1, 2].map(|k| chans[k].clone().try_into().expect("4 coefficients"));
                    eval_cost(ctx, move |d| [0, 1, 2].map(|k| shr::irradiance_l1_geomerics(&rgb[k], d)))
                }
                "shl1zh3" => {
                    let rgb: [[f64; 4]; 3] = [0, 1, 2].map(|k| chans[k].clone().try_into().unwrap());
                    eval_cost(ctx, move |d| shr::irradiance_l1_zh3(&rgb, d).unwrap_or([f64::NAN; 3]))
                }
                _ => {
                    let e = [0, 1, 2].map(|k| shr::irradiance_coefficients(&chans[k]).expect("(L+1)² coefficients"));
                    let mut y = vec![0.0; sh.len()];
                    let sh = sh.clone();
                    eval_cost(ctx, move |d| {
                        sh.eval_into(d, &mut y);
                        [0, 1, 2].map(|k| e[k].iter().zip(&y).map(|(a, b)| a * b).sum())
                    })
                }
            };
            let (mut irr, rad) = (irr, reconstruct(&sh, &c, dirs));
            let neg = clamp_negative(&mut irr);
            let mut r =
                mk!(id, ctx; sh.name(), "projection (orthonormal LS); irradiance clamped at 0", c, Vec::new(), Some(rad), irr, t, ns);
            r.result.clamped_negative_fraction = Some(neg);
            Ok(r)
        }
        "shl2w" => {
            // SH L2 deringed with the sinc⁴ window (Sloan 2017) where the signal it
            // reconstructs rings: per channel, if the irradiance (E/π) is negative on any
            // of 4096 spherical-Fibonacci directions, the largest window width that makes
            // it non-negative is applied to the coefficients; otherwise nothing changes.
            // (The peer's Laplacian window sums each band from m = −1, a bug.)
            let sh = ShBasis::new(2).map_err(err)?;
            let fib: Vec<DVec3> = (0..4096).map(|i| sbf::sampling::spherical_fibonacci(i, 4096)).collect();
            let sh_t = sh.clone();
            let (c, t) = timed(repeats, move || -> Result<Vec<[f64; 3]>, String> {
                let c = channels(&moments(&sh_t, &ctx.samples));
                let mut out = c.clone();
                for k in 0..3 {
                    if let Some((_, windowed)) = shr::dering_irradiance(&channel(&c, k), &fib).map_err(err)? {
                        for i in 0..9 {
                            out[i][k] = windowed[i];
                        }
                    }
                }
                Ok(out)
            });
            let c = ctx.stored(c?);
            let chans = [channel(&c, 0), channel(&c, 1), channel(&c, 2)];
            let e = [0, 1, 2].map(|k| shr::irradiance_coefficients(&chans[k]).expect("9 coefficients"));
            let mut y = vec![0.0; sh.len()];
            let shc = sh.clone();
            let (mut irr, ns) = eval_cost(ctx, move |d| {
                let sh = &shc;
                sh.eval_into(d, &mut y);
                [0, 1, 2].map(|k| e[k].iter().zip(&y).map(|(a, b)| a * b).sum())
            });
            let neg = clamp_negative(&mut irr);
            let rad = reconstruct(&sh, &c, dirs);
            let mut r =
                mk!(id, ctx; sh.name(), "projection + sinc⁴ deringing; irradiance clamped at 0", c, Vec::new(), Some(rad), irr, t, ns);
            r.result.clamped_negative_fraction = Some(neg);
            Ok(r)
        }
        _ => Err(format!("mode '{id}' is not one of this family's")),
    }
}
