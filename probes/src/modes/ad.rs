//! Ambient Dice: the SRBF 12 fits (`adrbf` radiance LS with exact lobe irradiance, `adrbf-irr`
//! fitted to the irradiance image) and the hybrid Bézier forms (`ad`, `adycocg`) fitted to the
//! irradiance image, as the peer.

use super::common::*;
use super::context::*;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::recon::ambient_dice as adr;
use sbf::solve::{moments, solve_gram, LsOptions, RadianceSample};
use sbf::{AmbientDiceSrbf, Basis, Domain};

/// Runs mode `id` of this family up to its cost measurement ([`super::prepare`]).
pub(super) fn prepare<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let dirs = &ctx.dirs;
    match id {
        "adrbf" | "adrbf-irr" => {
            let ad = AmbientDiceSrbf::twelve();
            let g = gram_matrix(&ad, Domain::Sphere, GramOptions::default()).map_err(err)?;
            if id == "adrbf" {
                let ad_t = ad.clone();
                let (c, t) = timed(repeats, move || {
                    solve_gram(&g.matrix, &moments(&ad_t, &ctx.samples), LsOptions::default()).map(|s| channels(&s.coeffs))
                });
                let c = ctx.stored(c.map_err(err)?);
                let (cc, adc) = (c.clone(), ad.clone());
                let (irr, ns) = eval_cost(ctx, move |d| dot_rgb(&cc, adc.lobes().iter().map(|a| adr::lobe_irradiance_cos(a.dot(d)))));
                let rad = reconstruct(&ad, &c, dirs);
                Ok(
                    mk!(id, ctx; ad.name(), "least squares (radiance)", c, ad.lobes().iter().map(|l| (*l, 0.0)).collect(), Some(rad), irr, t, ns),
                )
            } else {
                let s = irradiance_samples(ctx);
                let ad_t = ad.clone();
                let (c, t) = timed(repeats, move || {
                    solve_gram(&sbf::solve::sample_gram(&ad_t, &s), &moments(&ad_t, &s), LsOptions::default()).map(|s| channels(&s.coeffs))
                });
                let c = ctx.stored(c.map_err(err)?);
                let (irr, ns) = eval_basis(ctx, ad.clone(), c.clone());
                let mut r = mk!(id, ctx; ad.name(), "least squares (irradiance image)", c, ad.lobes().iter().map(|l| (*l, 0.0)).collect(), None, irr, t, ns);
                r.result.needs_reference = true;
                Ok(r)
            }
        }
        "ad" | "adycocg" => {
            // Fitted to the irradiance image (as the peer), unweighted texels.
            let s = irradiance_samples(ctx);
            let bz = sbf::AmbientDiceBezier::new();
            if id == "ad" {
                let bz_t = bz.clone();
                let (c, t) = timed(repeats, move || {
                    solve_gram(&sbf::solve::sample_gram(&bz_t, &s), &moments(&bz_t, &s), LsOptions::default()).map(|x| channels(&x.coeffs))
                });
                let c = ctx.stored(c.map_err(err)?);
                let (irr, ns) = eval_basis(ctx, bz.clone(), c.clone());
                let mut r = mk!(id, ctx; bz.name(), "least squares (irradiance image)", c, Vec::new(), None, irr, t, ns);
                r.result.needs_reference = true;
                Ok(r)
            } else {
                let lin = sbf::AmbientDiceLinear::new();
                let ys: Vec<RadianceSample> =
                    s.iter().map(|x| RadianceSample { value: sbf::basis::ambient_dice_bezier::rgb_to_ycocg(x.value), ..*x }).collect();
                let (c, t) = timed(repeats, move || -> Result<YCoCgCoeffs, String> {
                    let y = solve_gram(&sbf::solve::sample_gram(&bz, &ys), &moments(&bz, &ys), LsOptions::default()).map_err(err)?.coeffs;
                    let cc =
                        solve_gram(&sbf::solve::sample_gram(&lin, &ys), &moments(&lin, &ys), LsOptions::default()).map_err(err)?.coeffs;
                    Ok((
                        y.column(0).iter().copied().collect(),
                        cc.column(1).iter().copied().collect(),
                        cc.column(2).iter().copied().collect(),
                    ))
                });
                let (y, co, cg) = c?;
                let (y, co, cg) = (ctx.storage.store_scalars(&y), ctx.storage.store_scalars(&co), ctx.storage.store_scalars(&cg));
                let yc = sbf::AmbientDiceYCoCg::new();
                let (ya, coa, cga): ([f64; 36], [f64; 12], [f64; 12]) =
                    (y.clone().try_into().unwrap(), co.clone().try_into().unwrap(), cg.clone().try_into().unwrap());
                let (irr, ns) = eval_cost(ctx, move |d| yc.eval_rgb(&ya, &coa, &cga, d));
                // Coefficients as written: Y (36) then Co (12) then Cg (12), one value each.
                let coeffs: Vec<[f64; 3]> = y.iter().chain(&co).chain(&cg).map(|v| [*v, *v, *v]).collect();
                let mut r = mk!(id, ctx;
                    "AD YCoCg (Bézier Y 36 + linear Co, Cg 12+12)".into(),
                    "least squares (irradiance image, per YCoCg channel)",
                    coeffs,
                    Vec::new(),
                    None,
                    irr,
                    t,
                    ns,
                );
                r.result.needs_reference = true;
                r.result.stored_scalars = 60;
                Ok(r)
            }
        }
        _ => Err(format!("mode '{id}' is not one of this family's")),
    }
}
