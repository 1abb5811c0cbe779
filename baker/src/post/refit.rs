//! The irradiance-pinned NNLS fit of the non-negative bases (`Solver::NnlsIrradiance`):
//! the bake encodes SG and Ambient Dice lobes by progressive least squares (an unbiased
//! estimate of the normal equations' solution b_LS, seed 004 §7.3); per texel and channel
//! the moments are m = G b_LS (G the basis' Gram over the domain its samples cover: the
//! upper hemisphere, or the sphere for sphere bases with the lower half mirrored to zero),
//! and the non-negative fit of those moments is solved with its E/π at the texel's normal —
//! by the runtime the renderer uses ([`BasisKind::irradiance_at_normal`]) — pinned to the
//! texel's own E/π estimate (`sbf::solve::nnls_gram_eq`). Plain NNLS of a small source
//! carries up to ~1.8× its irradiance (one non-negative lobe cannot cancel its excess);
//! the pin keeps the light the bake measured.

use super::images::LightmapImages;
use crate::accumulate::BasisKind;
use rayon::prelude::*;
use sbf::glam::DVec3;
use sbf::solve::{nnls_gram_eq, NnlsOptions};

/// One texel's refitted lobes, worst KKT residual, Σ of the LS fit's E/π ratios and how
/// many channels that sums.
type TexelFit = (Vec<[f32; 3]>, f64, f64, usize);

/// What the pin did to one basis.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PinAccount {
    pub basis: &'static str,
    /// Texel-channels fitted.
    pub fits: usize,
    /// Worst relative KKT residual of the constrained fits.
    pub worst_kkt: f64,
    /// Mean over texel-channels with E/π > 0 of the plain LS fit's E/π at the normal over the
    /// texel's E/π (the progressive LS estimate's own bias, for the record).
    pub mean_ls_ratio: f64,
}

/// Refits every non-negative basis of `img` (its coefficients: the progressive LS estimate)
/// as NNLS with E/π at the normal pinned to `img.irradiance`, in place; SH is left as is.
/// Errors name the basis and texel whose fit failed (a non-finite or negative E/π, a Gram
/// matrix that is not positive definite).
pub fn pin_irradiance(img: &mut LightmapImages, bases: &[BasisKind], sg_sharpness: f64) -> Result<Vec<PinAccount>, String> {
    let mut out = Vec::new();
    for (bi, kind) in bases.iter().enumerate() {
        if !kind.non_negative() {
            continue;
        }
        let basis = kind.basis_with(sg_sharpness);
        let domain = if kind.is_sphere() { sbf::quadrature::Domain::Sphere } else { sbf::quadrature::Domain::UpperHemisphere };
        let gram =
            sbf::gram::gram_matrix(&*basis, domain, Default::default()).map_err(|e| format!("{}: Gram matrix: {e}", kind.name()))?.matrix;
        let n = gram.nrows();
        // E/π at +Z of each lobe with unit coefficient: the constraint row.
        let row: Vec<f64> = (0..n)
            .map(|i| {
                let mut e = vec![DVec3::ZERO; n];
                e[i] = DVec3::ONE;
                kind.irradiance_at_normal(&e, sg_sharpness).x
            })
            .collect();
        let c = sbf::nalgebra::DMatrix::from_row_slice(1, n, &row);
        let texels = img.validity.len();
        let lobes = &img.coefficients[bi];
        let fitted: Vec<Result<TexelFit, String>> = (0..texels)
            .into_par_iter()
            .map(|t| {
                let ls: Vec<[f32; 3]> = (0..n).map(|l| lobes[l][t]).collect();
                if img.validity[t] <= 0.0 {
                    return Ok((ls, 0.0, 0.0, 0));
                }
                let mut refit = ls.clone();
                let (mut kkt, mut ratio, mut counted) = (0.0f64, 0.0, 0);
                for ch in 0..3 {
                    let d = img.irradiance[t][ch] as f64;
                    if !(d.is_finite() && d >= 0.0) {
                        return Err(format!("{}: texel {t} has E/π {d} in channel {ch}: no fit can be pinned to it", kind.name()));
                    }
                    let b: Vec<f64> = ls.iter().map(|x| x[ch] as f64).collect();
                    let m: Vec<f64> = (0..n).map(|i| (0..n).map(|j| gram[(i, j)] * b[j]).sum()).collect();
                    let s = nnls_gram_eq(&gram, &m, &c, &[d], NnlsOptions::default())
                        .map_err(|e| format!("{}: texel {t}: {e}", kind.name()))?;
                    for (l, v) in s.coeffs.iter().enumerate() {
                        refit[l][ch] = *v as f32;
                    }
                    kkt = kkt.max(s.kkt_residual);
                    if d > 0.0 {
                        ratio += row.iter().zip(&b).map(|(r, x)| r * x).sum::<f64>() / d;
                        counted += 1;
                    }
                }
                Ok((refit, kkt, ratio, counted))
            })
            .collect();
        let (mut worst_kkt, mut ratio, mut counted) = (0.0f64, 0.0, 0usize);
        for (t, r) in fitted.into_iter().enumerate() {
            let (refit, kkt, rs, k) = r?;
            for (l, v) in refit.into_iter().enumerate() {
                img.coefficients[bi][l][t] = v;
            }
            worst_kkt = worst_kkt.max(kkt);
            ratio += rs;
            counted += k;
        }
        out.push(PinAccount {
            basis: kind.name(),
            fits: 3 * img.validity.iter().filter(|v| **v > 0.0).count(),
            worst_kkt,
            mean_ls_ratio: if counted > 0 { ratio / counted as f64 } else { f64::NAN },
        });
    }
    Ok(out)
}
