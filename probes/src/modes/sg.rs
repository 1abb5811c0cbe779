//! The SG 12 batch modes: the peer's naive projection (`sg`), least squares (`sgls`, `sglsa` with
//! an ambient lobe) and NNLS (`sgnnls`), with the run's SG irradiance reconstruction.

use super::common::*;
use super::context::*;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::solve::{moments, naive_projection, nnls_gram, solve_gram, LsOptions, NnlsOptions};
use sbf::{Basis, Domain, SgBasis};

/// Runs mode `id` of this family up to its cost measurement ([`super::prepare`]).
pub(super) fn prepare<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let vogel = sbf::layout::vogel_sphere(12).map_err(err)?;
    let dirs = &ctx.dirs;
    match id {
        "sg" | "sgls" | "sglsa" | "sgnnls" => {
            let basis = SgBasis::new(&vogel, 6.0, id == "sglsa").map_err(err)?;
            let g = gram_matrix(&basis, Domain::Sphere, GramOptions::default()).map_err(err)?;
            let basis_t = basis.clone();
            let fit = move || -> Result<Vec<[f64; 3]>, String> {
                let basis = &basis_t;
                let m = moments(basis, &ctx.samples);
                match id {
                    // The peer's naive projection: moments scaled by 4λ²/((1 − e^(−2λ))·N)/(4π)
                    // (Probulator's sgBasisNormalizationFactor), which maps a constant to
                    // about that constant for N well-spread lobes. Equivalent to
                    // naive_projection with "diagonal" ∫B_i·N/(2λ).
                    "sg" => {
                        let lam = 6.0;
                        let n = basis.lobe_count() as f64;
                        let d: Vec<f64> = (0..basis.len()).map(|i| basis.lobe(i).integral() * n / (2.0 * lam)).collect();
                        Ok(channels(&naive_projection(&m, &d)))
                    }
                    "sgnnls" => {
                        let mut out = vec![[0.0; 3]; basis.len()];
                        for k in 0..3 {
                            let col: Vec<f64> = m.column(k).iter().copied().collect();
                            let sol = nnls_gram(&g.matrix, &col, NnlsOptions::default()).map_err(err)?;
                            for i in 0..basis.len() {
                                out[i][k] = sol.coeffs[i];
                            }
                        }
                        Ok(out)
                    }
                    _ => solve_gram(&g.matrix, &m, LsOptions::default()).map(|s| channels(&s.coeffs)).map_err(err),
                }
            };
            let method = ctx.sg_irradiance.for_mode(id);
            let prior = if method == SgIrradiance::Prior { Some(PriorRgb::new(&basis).map_err(err)?) } else { None };
            // The encode: the fit, and for the prior estimate the per-probe transform c' = Σ⁻¹G·c.
            let prior_t = prior.clone();
            let (c, t) = timed(repeats, move || -> Result<(Rgb, Rgb), String> {
                let c = fit()?;
                let cp = match &prior_t {
                    Some(p) => p.coefficients(&c).map_err(err)?,
                    None => Vec::new(),
                };
                Ok((c, cp))
            });
            let (c, cp) = c?;
            // The prior estimate stores c′ (what its runtime reads); the radiance image reads c.
            let (c, cp) = (ctx.stored(c), ctx.stored(cp));
            let lobes = sg_lobes(&basis, id);
            let (irr, ns) = match prior {
                Some(mut p) => eval_cost(ctx, move |d| p.eval(&cp, d)),
                None => {
                    let (b, cc) = (basis.clone(), c.clone());
                    eval_cost(ctx, move |d| sg_irradiance_rgb(ctx.sg_irradiance, id, &b, &lobes, &cc, d))
                }
            };
            let rad = reconstruct(&basis, &c, dirs);
            let solver = match id {
                "sg" if method == SgIrradiance::Peer => "naive projection; irradiance by the peer's SG kernel (λ 8.5)",
                "sg" => "naive projection",
                "sgnnls" if method == SgIrradiance::Peer => "NNLS; irradiance by the peer's SG kernel (λ 3)",
                "sgnnls" => "NNLS",
                _ if method == SgIrradiance::Prior => {
                    "least squares; irradiance by the isotropic-prior estimate (C_l ∝ l⁻², sbf::recon::prior)"
                }
                _ if method == SgIrradiance::Peer => "least squares; irradiance by the peer's SG kernel (λ 3)",
                _ => "least squares",
            };
            let mut r = mk!(id, ctx; basis.name(), solver, c, vogel.iter().map(|a| (*a, 6.0)).collect(), Some(rad), irr, t, ns);
            r.result.wgsl_irradiance = method == SgIrradiance::Hill;
            r.result.irradiance_variant = method.name();
            Ok(r)
        }
        _ => Err(format!("mode '{id}' is not one of this family's")),
    }
}
