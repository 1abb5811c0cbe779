//! The ambient cube: `ac` (NNLS fit to the irradiance image, as the peer) and `acproj` (the exact
//! irradiance at the six axes).

use super::common::*;
use super::context::*;
use crate::reference;
use sbf::glam::DVec3;
use sbf::solve::{moments, nnls_gram, NnlsOptions};
use sbf::{AmbientCube, Basis};

/// Runs mode `id` of this family up to its cost measurement ([`super::prepare`]).
pub(super) fn prepare<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    match id {
        "ac" | "acproj" => {
            let ac = AmbientCube;
            let (c, t) = if id == "ac" {
                let s = irradiance_samples(ctx);
                timed(repeats, move || -> Result<Vec<[f64; 3]>, String> {
                    let g = sbf::solve::sample_gram(&ac, &s);
                    let m = moments(&ac, &s);
                    let mut out = vec![[0.0; 3]; 6];
                    for k in 0..3 {
                        let col: Vec<f64> = m.column(k).iter().copied().collect();
                        let sol = nnls_gram(&g, &col, NnlsOptions::default()).map_err(err)?;
                        for i in 0..6 {
                            out[i][k] = sol.coeffs[i];
                        }
                    }
                    Ok(out)
                })
            } else {
                timed(repeats, move || -> Result<Vec<[f64; 3]>, String> {
                    // The exact quadrature over every texel at each axis (serial: a timed section).
                    let axes = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];
                    Ok(axes.iter().map(|a| reference::irradiance_at(&ctx.map, *a)).collect())
                })
            };
            let c = ctx.stored(c?);
            let cc = c.clone();
            let (irr, ns) = eval_cost(ctx, move |d| {
                let mut w = [0.0; 6];
                ac.eval_into(d, &mut w);
                [0, 1, 2].map(|k| (0..6).map(|i| w[i] * cc[i][k]).sum())
            });
            let mut r = mk!(id, ctx;
                ac.name(),
                if id == "ac" { "NNLS on the irradiance image" } else { "projection (six axes)" },
                c,
                Vec::new(),
                None,
                irr,
                t,
                ns,
            );
            r.result.needs_reference = id == "ac";
            Ok(r)
        }
        _ => Err(format!("mode '{id}' is not one of this family's")),
    }
}
