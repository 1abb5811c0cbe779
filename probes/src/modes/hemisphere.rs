//! The hemisphere layouts of [Roughton19 App. C] (`ad9`, `adrbf-tangent`, `sg9h`, `sg12h`: least
//! squares over the sphere, lobes in tangent space) and the H-basis (`h4`, `h6`, fitted to the
//! irradiance image over the upper hemisphere).

use super::common::*;
use super::context::*;
use crate::frame::{tangent_to_world, world_to_tangent};
use sbf::glam::DVec3;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::recon::{ambient_dice as adr, sg as sgr};
use sbf::solve::{moments, solve_gram, LsOptions, RadianceSample};
use sbf::{AmbientDiceSrbf, Basis, Domain, SgBasis};

/// Runs mode `id` of this family up to its cost measurement ([`super::prepare`]).
pub(super) fn prepare<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let _vogel = sbf::layout::vogel_sphere(12).map_err(err)?;
    let dirs = &ctx.dirs;
    match id {
        "ad9" | "sg9h" | "sg12h" | "adrbf-tangent" => {
            // Appendix C: lobes laid out in tangent space (normal +Z), rotated to world
            // (+Y up); least squares over the whole sphere.
            let world = |v: Vec<DVec3>| v.into_iter().map(tangent_to_world).collect::<Vec<_>>();
            let (basis, is_ad): (std::sync::Arc<dyn Basis + Send + Sync>, bool) = match id {
                "ad9" => (
                    std::sync::Arc::new(
                        AmbientDiceSrbf::from_axes(&world(sbf::layout::icosahedron_hemisphere()), Domain::Sphere).map_err(err)?,
                    ),
                    true,
                ),
                "adrbf-tangent" => (
                    std::sync::Arc::new(AmbientDiceSrbf::from_axes(&world(sbf::layout::icosahedron()), Domain::Sphere).map_err(err)?),
                    true,
                ),
                "sg9h" => (
                    std::sync::Arc::new(SgBasis::new(&world(sbf::layout::vogel_hemisphere(9).map_err(err)?), 6.0, false).map_err(err)?),
                    false,
                ),
                _ => (
                    std::sync::Arc::new(SgBasis::new(&world(sbf::layout::vogel_hemisphere(12).map_err(err)?), 6.0, false).map_err(err)?),
                    false,
                ),
            };
            let b = basis.clone();
            let (c, t) = if !is_ad && ctx.convention == sbf::ggx::Convention::AppendixC {
                // Roughton's SG fits: its point samples, their own Gram (see appendix_c).
                let samples = crate::appendix_c::sg_samples(&ctx.map)?;
                timed(repeats, move || {
                    solve_gram(&sbf::solve::sample_gram(b.as_ref(), &samples), &moments(b.as_ref(), &samples), LsOptions::default())
                        .map(|s| channels(&s.coeffs))
                })
            } else {
                let g = gram_matrix(basis.as_ref(), Domain::Sphere, GramOptions::default()).map_err(err)?;
                timed(repeats, move || {
                    solve_gram(&g.matrix, &moments(b.as_ref(), &ctx.samples), LsOptions::default()).map(|s| channels(&s.coeffs))
                })
            };
            let c = ctx.stored(c.map_err(err)?);
            let chans = [channel(&c, 0), channel(&c, 1), channel(&c, 2)];
            let (axes, lobes): (Vec<DVec3>, Vec<(DVec3, f64)>) = if is_ad {
                let ad = AmbientDiceSrbf::from_axes(
                    &match id {
                        "ad9" => world(sbf::layout::icosahedron_hemisphere()),
                        _ => world(sbf::layout::icosahedron()),
                    },
                    Domain::Sphere,
                )
                .map_err(err)?;
                (ad.lobes().to_vec(), ad.lobes().iter().map(|a| (*a, 0.0)).collect())
            } else {
                let n = if id == "sg9h" { 9 } else { 12 };
                let a = world(sbf::layout::vogel_hemisphere(n).map_err(err)?);
                (a.clone(), a.iter().map(|x| (*x, 6.0)).collect())
            };
            let sharpness = vec![6.0; axes.len()];
            let (irr, ns) = if is_ad {
                eval_cost(ctx, move |d| [0, 1, 2].map(|k| adr::irradiance_fit(&axes, &chans[k], d, &adr::DIFFUSE_FIT_EQ_8_14)))
            } else {
                let cc = c.clone();
                eval_cost(ctx, move |d| {
                    dot_rgb(
                        &cc,
                        axes.iter()
                            .zip(&sharpness)
                            .map(|(a, l)| sgr::irradiance_hill(&sbf::Sg { axis: *a, sharpness: *l, amplitude: 1.0 }, d)),
                    )
                })
            };
            let rad = reconstruct(basis.as_ref(), &c, dirs);
            Ok(mk!(id, ctx; basis.name(), "least squares over the sphere", c, lobes, Some(rad), irr, t, ns))
        }
        "h4" | "h6" => {
            // The H-basis lives on the upper hemisphere: fit the irradiance image there
            // (texels of the upper rows, equal weights as the peer's image fits), evaluate
            // in tangent space. The lower hemisphere is outside its domain (E/π = 0 there).
            let h = sbf::HBasis::new(if id == "h4" { 4 } else { 6 }).map_err(err)?;
            let upper = ctx.grid.width * (ctx.grid.height / 2);
            let s: Vec<RadianceSample> = ctx.dirs[..upper]
                .iter()
                .zip(&ctx.irradiance[..upper])
                .map(|(d, e)| RadianceSample { direction: world_to_tangent(*d), value: *e, weight: 1.0 })
                .collect();
            let (c, t) = timed(repeats, move || {
                solve_gram(&sbf::solve::sample_gram(&h, &s), &moments(&h, &s), LsOptions::default()).map(|x| channels(&x.coeffs))
            });
            let c = ctx.stored(c.map_err(err)?);
            let chans = [channel(&c, 0), channel(&c, 1), channel(&c, 2)];
            let mut sc = vec![0.0; h.len()];
            let (irr, ns) = eval_cost(ctx, move |d| {
                let tt = world_to_tangent(d);
                if tt.z < 0.0 {
                    [0.0; 3]
                } else {
                    [0, 1, 2].map(|k| h.reconstruct(&chans[k], tt, &mut sc))
                }
            });
            let mut r = mk!(id, ctx; h.name(), "least squares (irradiance image, upper hemisphere)", c, Vec::new(), None, irr, t, ns);
            r.result.needs_reference = true;
            Ok(r)
        }
        _ => Err(format!("mode '{id}' is not one of this family's")),
    }
}
