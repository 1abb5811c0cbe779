//! Lightmap denoiser (\[HWRTL\]'s post-process): joint non-local means
//! over the atlas, guided by position and normal, within a chart, over valid texels only.
//!
//! For a valid texel p, the output of every stored quantity — E/π and every coefficient of
//! every basis — is Σ_q w(p, q)·v(q) / Σ_q w(p, q) over the valid texels q of the same chart
//! in a (2R+1)² window, with one weight per pair, so the filtered coefficients still encode
//! one consistent function per texel. The weight is the product of
//! - a **patch distance** on E/π normalised by the texels' own variance (Rousselle, Knaus &
//!   Zwicker 2012, "Adaptive rendering with non-local means filtering", eq. 4–5, k = 0.45):
//!   d² = mean over the (2F+1)² patch offsets where both texels are valid and over channels
//!   of [(u_p − u_q)² − (σ²_p + min(σ²_p, σ²_q))] / (ε + k²(σ²_p + σ²_q)), weight exp(−max(0, d²)),
//!   with σ² the squared standard error the bake tracks — flat regions average over the
//!   whole window, real features (where the difference exceeds the noise) keep their edges;
//! - a **geometry** term exp(−|x_p − x_q|²/(2 s²)), s = R world texel sizes, and a **normal**
//!   term exp(−(1 − n_p·n_q)/0.1): texels adjacent in the atlas but not on the surface, or
//!   across a crease, do not mix.
//!
//! Invalid texels (validity 0: empty, inside geometry) are never read — not as q, not in a
//! patch — so whatever they hold (NaN included) cannot reach the output; they are not
//! written either (dilation fills them afterwards). Deterministic: every output is an
//! ordered sum over its window, independent of the thread count.

use crate::layout::lightmap::Lightmap;
use crate::post::images::LightmapImages;
use rayon::prelude::*;
use sbf::glam::Vec3;

/// Filter parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DenoiseOptions {
    /// Window radius R in texels.
    pub radius: usize,
    /// Patch radius F in texels.
    pub patch: usize,
    /// NLM strength k (Rousselle et al. 2012 use 0.45).
    pub strength: f32,
}

impl Default for DenoiseOptions {
    fn default() -> Self {
        DenoiseOptions { radius: 5, patch: 1, strength: 0.45 }
    }
}

/// What the filter did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DenoiseStats {
    /// Valid texels filtered.
    pub texels: usize,
    /// Mean effective number of neighbours, (Σw)²/Σw², over the filtered texels.
    pub mean_effective_neighbours: f64,
}

/// Per-texel guides: chart, world position and unit normal (mean over the texel's points).
struct Guides {
    chart: Vec<u32>,
    position: Vec<Vec3>,
    normal: Vec<Vec3>,
    valid: Vec<bool>,
}

fn guides(lm: &Lightmap, img: &LightmapImages) -> Guides {
    let n = img.width * img.height;
    let mut g = Guides { chart: vec![u32::MAX; n], position: vec![Vec3::ZERO; n], normal: vec![Vec3::ZERO; n], valid: vec![false; n] };
    for t in 0..n {
        let tx = &lm.texels[t];
        if img.validity[t] <= 0.0 || tx.points.is_empty() {
            continue;
        }
        g.valid[t] = true;
        g.chart[t] = tx.chart;
        g.position[t] = tx.points.iter().map(|p| p.position).sum::<Vec3>() / tx.points.len() as f32;
        g.normal[t] = Vec3::from(img.normals[t]);
    }
    g
}

/// Filters `img` in place (see the module docs) with the atlas geometry of `lm`. Errors
/// when the images and the lightmap disagree in size.
pub fn denoise(img: &mut LightmapImages, lm: &Lightmap, opts: DenoiseOptions) -> Result<DenoiseStats, String> {
    let (w, h) = (img.width, img.height);
    if lm.width != w || lm.height != h || lm.texels.len() != w * h {
        return Err(format!("denoise: images are {w}×{h}, the lightmap {}×{}", lm.width, lm.height));
    }
    let g = guides(lm, img);
    let (r, f) = (opts.radius as i64, opts.patch as i64);
    let texel_size = 1.0 / lm.texels_per_unit.max(1e-6);
    let inv_2s2 = 1.0 / (2.0 * (opts.radius.max(1) as f32 * texel_size).powi(2));
    let k2 = opts.strength * opts.strength;
    let var: Vec<[f32; 3]> = img.standard_error.iter().map(|s| s.map(|x| x * x)).collect();
    let u = &img.irradiance;
    let at = |x: i64, y: i64| -> Option<usize> {
        (x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h).then(|| y as usize * w + x as usize).filter(|t| g.valid[*t])
    };
    // Weights per valid texel: (neighbour, weight), in window order.
    let weights: Vec<Vec<(usize, f32)>> = (0..w * h)
        .into_par_iter()
        .map(|p| {
            if !g.valid[p] {
                return Vec::new();
            }
            let (px, py) = ((p % w) as i64, (p / w) as i64);
            let mut out = Vec::new();
            for dy in -r..=r {
                for dx in -r..=r {
                    let Some(q) = at(px + dx, py + dy) else { continue };
                    if g.chart[q] != g.chart[p] {
                        continue;
                    }
                    let geo =
                        (-(g.position[p] - g.position[q]).length_squared() * inv_2s2 - (1.0 - g.normal[p].dot(g.normal[q])) / 0.1).exp();
                    if q == p {
                        out.push((q, geo));
                        continue;
                    }
                    let (mut d2, mut count) = (0.0f32, 0usize);
                    for oy in -f..=f {
                        for ox in -f..=f {
                            let (Some(a), Some(b)) = (at(px + ox, py + oy), at(px + dx + ox, py + dy + oy)) else { continue };
                            for c in 0..3 {
                                let (va, vb) = (var[a][c], var[b][c]);
                                let num = (u[a][c] - u[b][c]).powi(2) - (va + va.min(vb));
                                d2 += num / (1e-10 + k2 * (va + vb));
                            }
                            count += 3;
                        }
                    }
                    let nlm = if count == 0 { 0.0 } else { (-(d2 / count as f32).max(0.0)).exp() };
                    let wq = geo * nlm;
                    if wq > 0.0 {
                        out.push((q, wq));
                    }
                }
            }
            out
        })
        .collect();
    let apply = |v: &mut Vec<[f32; 3]>| {
        let src = v.clone();
        for (p, ws) in weights.iter().enumerate() {
            if ws.is_empty() {
                continue;
            }
            let (mut acc, mut sum) = ([0.0f64; 3], 0.0f64);
            for &(q, wq) in ws {
                sum += wq as f64;
                for c in 0..3 {
                    acc[c] += wq as f64 * src[q][c] as f64;
                }
            }
            v[p] = acc.map(|a| (a / sum) as f32);
        }
    };
    apply(&mut img.irradiance);
    for basis in img.coefficients.iter_mut() {
        for lobe in basis.iter_mut() {
            apply(lobe);
        }
    }
    // The standard error of a weighted mean of independent texels: σ·√Σw²/Σw (an estimate:
    // neighbours are not independent of the weights).
    let se = img.standard_error.clone();
    for (p, ws) in weights.iter().enumerate() {
        if ws.is_empty() {
            continue;
        }
        let sum: f64 = ws.iter().map(|x| x.1 as f64).sum();
        let mut v = [0.0f64; 3];
        for &(q, wq) in ws {
            for c in 0..3 {
                v[c] += (wq as f64 * se[q][c] as f64).powi(2);
            }
        }
        img.standard_error[p] = v.map(|x| (x.sqrt() / sum) as f32);
    }
    let filtered: Vec<&Vec<(usize, f32)>> = weights.iter().filter(|w| !w.is_empty()).collect();
    let eff: f64 = filtered
        .iter()
        .map(|ws| {
            let (s, s2) = ws.iter().fold((0.0f64, 0.0f64), |(a, b), x| (a + x.1 as f64, b + (x.1 as f64).powi(2)));
            s * s / s2
        })
        .sum();
    Ok(DenoiseStats { texels: filtered.len(), mean_effective_neighbours: eff / filtered.len().max(1) as f64 })
}
