//! The irradiance-pinned NNLS fit of the non-negative bases (`Solver::NnlsIrradiance`):
//! the bake encodes SG and Ambient Dice lobes by progressive least squares (an unbiased
//! estimate of the normal equations' solution b_LS, [Roughton19 §7.3]); per texel and channel
//! the moments are m = G b_LS (G the basis' Gram over the domain its samples cover: the
//! upper hemisphere, or the sphere for sphere bases with the lower half mirrored to zero),
//! and the non-negative fit of those moments is solved with its E/π at the texel's normal —
//! by the runtime the renderer uses ([`BakedBasis::irradiance_at_normal`]) — pinned to the
//! texel's own E/π estimate (`sbf::solve::nnls_gram_eq`). Plain NNLS of a small source
//! carries up to ~1.8× its irradiance (one non-negative lobe cannot cancel its excess);
//! the pin keeps the light the bake measured.
//!
//! The default (`Solver::NnlsRescaled`, [`rescale_irradiance`]) keeps the NNLS lobes' shape
//! and scales them per texel to the texel's E/π; [`irradiance_ratios`] measures what any
//! fit keeps (bake.json records it for every basis).

use super::images::LightmapImages;
use crate::accumulate::{BakedBasis, BasisId};
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
pub fn pin_irradiance(img: &mut LightmapImages, bases: &[BasisId], sg_sharpness: f64) -> Result<Vec<PinAccount>, String> {
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
        let row = constraint_row(*kind, sg_sharpness);
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

/// E/π at the texel's normal (+Z) of each lobe with unit coefficient, by the renderer's
/// runtime: the row c with E/π = c·x for lobes x (one channel).
pub fn constraint_row(kind: BasisId, sg_sharpness: f64) -> Vec<f64> {
    let n = kind.lobes();
    (0..n)
        .map(|i| {
            let mut e = vec![DVec3::ZERO; n];
            e[i] = DVec3::ONE;
            kind.irradiance_at_normal(&e, sg_sharpness).x
        })
        .collect()
}

/// What rescaling did to one basis.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RescaleAccount {
    pub basis: &'static str,
    /// Texel-channels rescaled (the fit's E/π > 0).
    pub rescaled: usize,
    /// Texel-channels with E/π > 0 whose fit had E/π = 0 at the normal: nothing to scale,
    /// left as they are (their light is lost; reported, never hidden).
    pub unscalable: usize,
    /// Mean over texel-channels with E/π > 0 of the fit's E/π at the normal over the
    /// texel's before the rescale.
    pub mean_ratio: f64,
    /// The largest and smallest scale applied (1 where nothing was rescaled).
    pub max_scale: f64,
    pub min_scale: f64,
}

/// Scales every non-negative basis' lobes of `img` per texel and channel so that their E/π
/// at the normal (the renderer's runtime, [`constraint_row`]) equals `img.irradiance`: the
/// NNLS fit's shape, the light the bake measured. A scale keeps the lobes non-negative.
pub fn rescale_irradiance(img: &mut LightmapImages, bases: &[BasisId], sg_sharpness: f64) -> Result<Vec<RescaleAccount>, String> {
    let mut out = Vec::new();
    for (bi, kind) in bases.iter().enumerate() {
        if !kind.non_negative() {
            continue;
        }
        let row = constraint_row(*kind, sg_sharpness);
        let (mut rescaled, mut unscalable, mut ratio) = (0usize, 0usize, 0.0f64);
        let (mut max_scale, mut min_scale) = (1.0f64, 1.0f64);
        for t in 0..img.validity.len() {
            if img.validity[t] <= 0.0 {
                continue;
            }
            for ch in 0..3 {
                let d = img.irradiance[t][ch] as f64;
                if !(d.is_finite() && d >= 0.0) {
                    return Err(format!("{}: texel {t} has E/π {d} in channel {ch}: nothing to rescale to", kind.name()));
                }
                let e: f64 = row.iter().enumerate().map(|(l, r)| r * img.coefficients[bi][l][t][ch] as f64).sum();
                if d == 0.0 {
                    continue;
                }
                if e > 0.0 {
                    ratio += e / d;
                    rescaled += 1;
                    let k = d / e;
                    max_scale = max_scale.max(k);
                    min_scale = min_scale.min(k);
                    for l in 0..row.len() {
                        let v = &mut img.coefficients[bi][l][t][ch];
                        *v = (*v as f64 * k) as f32;
                    }
                } else {
                    unscalable += 1;
                }
            }
        }
        out.push(RescaleAccount {
            basis: kind.name(),
            rescaled,
            unscalable,
            mean_ratio: if rescaled > 0 { ratio / rescaled as f64 } else { f64::NAN },
            max_scale,
            min_scale,
        });
    }
    Ok(out)
}

/// What a basis' lobes keep of the texels' E/π at the normal: Σ fit / Σ E/π over the valid
/// texels and channels, overall and for the chart furthest from 1.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IrradianceRatio {
    pub basis: &'static str,
    pub mean: f64,
    /// The chart (its id in the layout) whose ratio is furthest from 1, among charts with
    /// at least [`MIN_CHART_TEXELS`] valid texels and some light.
    pub worst_chart: Option<u32>,
    pub worst_chart_ratio: f64,
    pub worst_chart_texels: usize,
}

/// Charts smaller than this are left out of the worst chart (a chart of one or two texels
/// is all border).
pub const MIN_CHART_TEXELS: usize = 4;

/// [`IrradianceRatio`] of every basis of `img`; `texel_charts` gives each texel's chart
/// (`Lightmap::texel_charts`). NaN ratios where no valid texel has light.
pub fn irradiance_ratios(img: &LightmapImages, bases: &[BasisId], sg_sharpness: f64, texel_charts: &[u32]) -> Vec<IrradianceRatio> {
    bases
        .iter()
        .enumerate()
        .map(|(bi, kind)| {
            let row = constraint_row(*kind, sg_sharpness);
            let mut charts: std::collections::BTreeMap<u32, (f64, f64, usize)> = Default::default();
            let (mut fit, mut e) = (0.0f64, 0.0f64);
            for t in 0..img.validity.len() {
                if img.validity[t] <= 0.0 {
                    continue;
                }
                let (mut f_t, mut e_t) = (0.0, 0.0);
                for ch in 0..3 {
                    f_t += row.iter().enumerate().map(|(l, r)| r * img.coefficients[bi][l][t][ch] as f64).sum::<f64>();
                    e_t += img.irradiance[t][ch] as f64;
                }
                fit += f_t;
                e += e_t;
                let c = charts.entry(texel_charts.get(t).copied().unwrap_or(u32::MAX)).or_default();
                c.0 += f_t;
                c.1 += e_t;
                c.2 += 1;
            }
            let worst = charts
                .iter()
                .filter(|(_, (_, e, n))| *n >= MIN_CHART_TEXELS && *e > 0.0)
                .map(|(id, (f, e, n))| (*id, f / e, *n))
                .max_by(|a, b| (a.1 - 1.0).abs().total_cmp(&(b.1 - 1.0).abs()));
            IrradianceRatio {
                basis: kind.name(),
                mean: if e > 0.0 { fit / e } else { f64::NAN },
                worst_chart: worst.map(|w| w.0),
                worst_chart_ratio: worst.map_or(f64::NAN, |w| w.1),
                worst_chart_texels: worst.map_or(0, |w| w.2),
            }
        })
        .collect()
}

/// The solver's step on the finished lightmap (`Solver::NnlsIrradiance`: [`pin_irradiance`];
/// `Solver::NnlsRescaled`: [`rescale_irradiance`]; else none), logged. Returns every
/// basis' [`IrradianceRatio`] of the fit before the step.
pub fn solver_step(
    img: &mut LightmapImages,
    config: &crate::accumulate::BakeConfig,
    texel_charts: &[u32],
    log: &mut dyn FnMut(String),
) -> Result<Vec<IrradianceRatio>, String> {
    use crate::accumulate::config::Solver;
    let before = irradiance_ratios(img, &config.bases, config.sg_sharpness, texel_charts);
    let t = std::time::Instant::now();
    match config.solver {
        Solver::NnlsIrradiance => {
            for a in pin_irradiance(img, &config.bases, config.sg_sharpness)? {
                log(format!(
                    "solver: {} refitted as NNLS with E/π pinned ({} texel-channels, worst KKT residual {:.1e}; the LS estimate's E/π was {:.4}× the texel's on average) in {:.2} s",
                    a.basis,
                    a.fits,
                    a.worst_kkt,
                    a.mean_ls_ratio,
                    t.elapsed().as_secs_f64()
                ));
            }
        }
        Solver::NnlsRescaled => {
            for a in rescale_irradiance(img, &config.bases, config.sg_sharpness)? {
                log(format!(
                    "solver: {} NNLS lobes rescaled to the texel's E/π ({} texel-channels, scales {:.3}…{:.3}; their E/π was {:.4}× the texel's on average; {} with no light in the fit left as they are)",
                    a.basis, a.rescaled, a.min_scale, a.max_scale, a.mean_ratio, a.unscalable
                ));
            }
        }
        Solver::Ls | Solver::Nnls => {}
    }
    Ok(before)
}
