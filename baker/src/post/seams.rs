//! Seam stitching: where one surface is cut into two UV islands (two
//! charts, or two meshes), the texels on either side of the cut are filtered bilinearly
//! from different places of the atlas, so a lookup just left of the seam and one just right
//! of it disagree by the two sides' noise and filtering. Here:
//!
//! - [`find_seams`]: edges whose world-space endpoints coincide (welded to 1e-5 of the
//!   scene's extent) on two triangles with different atlas UVs and nearly parallel faces
//!   (cos > [`MAX_CREASE_COS`]): a crease, such as a box's corner, is a real discontinuity
//!   of the lighting and is left alone.
//! - [`samples`]: points along each seam edge (two per texel of its longer side), each with
//!   the four bilinear taps of both sides (texel centres at +½, as `LightmapImages::sample`).
//! - [`stitch`]: least squares (the approach of Sloan's "Stitching lightmap seams" and the
//!   lightmappers that followed): minimise λ·Σ_samples (lookup_A − lookup_B)² + Σ_texels
//!   μ_t (x_t − x0_t)² over the taps' texels, per channel of E/π and of every coefficient —
//!   one matrix for all of them, so every texel's coefficients change by the same linear
//!   map. Valid texels keep their value with μ = 1; empty (padding) texels under a tap are
//!   unknowns too, anchored weakly (μ = 0.01) to what dilation would give them, and are then
//!   kept by dilation. Solved by Jacobi-preconditioned conjugate gradients.
//! - [`seam_metric`]: the mean absolute difference of E/π lookups across the seams (over
//!   samples and channels) — reported before and after, next to the texels' noise.
//!
//! Runs after the denoiser and before dilation. Deterministic (fixed orders throughout).

use crate::layout::lightmap::Lightmap;
use crate::post::images::LightmapImages;
use crate::scene::Scene;
use sbf::glam::{Vec2, Vec3};
use std::collections::BTreeMap;

/// Faces meeting at a larger angle than acos(this) form a crease, not a seam.
pub const MAX_CREASE_COS: f32 = 0.9;
/// Weight of the seam term against a valid texel's data term.
pub const SEAM_WEIGHT: f64 = 100.0;
/// Data weight of an empty (padding) texel under a seam tap.
pub const EMPTY_WEIGHT: f64 = 0.01;
/// Relative residual at which a solve stops: below the f32 the images store (6e-8) would
/// buy nothing; 1e-7 of the right-hand side.
pub const CG_TOLERANCE: f64 = 1e-7;
/// Iteration cap (the system's condition is ≲ λ/μ_empty = 1e4: CG needs ~√1e4·ln(1e7)/2 ≈
/// 800 iterations in the worst case).
pub const MAX_CG_ITERATIONS: usize = 5000;

/// One seam edge: the atlas UVs (texels) of its two endpoints on side A and on side B, in
/// the same world order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeamEdge {
    pub a: [Vec2; 2],
    pub b: [Vec2; 2],
}

/// A point on a seam: the bilinear taps (texel, weight) on side A and on side B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeamSample {
    pub a: [(usize, f32); 4],
    pub b: [(usize, f32); 4],
}

/// An edge by its two welded endpoints (grid coordinates), lower first.
type EdgeKey = ([i64; 3], [i64; 3]);

/// The seam edges of a lightmapped scene (see the module docs).
pub fn find_seams(scene: &Scene, lm: &Lightmap) -> Vec<SeamEdge> {
    let (lo, hi) = scene
        .meshes
        .iter()
        .flat_map(|m| m.positions.iter())
        .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(a, b), p| (a.min(*p), b.max(*p)));
    let quantum = ((hi - lo).max_element() * 1e-5).max(f32::MIN_POSITIVE);
    let key = |p: Vec3| ((p - lo) / quantum).round().to_array().map(|v| v as i64);
    // Edge (welded endpoints, ordered) → (uv of the lower endpoint, uv of the other, face normal).
    let mut edges: BTreeMap<EdgeKey, Vec<(Vec2, Vec2, Vec3)>> = BTreeMap::new();
    for (mi, mesh) in scene.meshes.iter().enumerate() {
        let Some(uvs) = lm.triangle_uv.get(mi).filter(|u| !u.is_empty()) else { continue };
        for (tri, idx) in mesh.indices.iter().enumerate() {
            let p = idx.map(|i| mesh.positions[i as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            if n == Vec3::ZERO {
                continue;
            }
            for e in 0..3 {
                let (i, j) = (e, (e + 1) % 3);
                let (ki, kj) = (key(p[i]), key(p[j]));
                if ki == kj {
                    continue;
                }
                let (k, uv) = if ki < kj { ((ki, kj), (uvs[tri][i], uvs[tri][j])) } else { ((kj, ki), (uvs[tri][j], uvs[tri][i])) };
                edges.entry(k).or_default().push((uv.0, uv.1, n));
            }
        }
    }
    let mut out = Vec::new();
    for sides in edges.values() {
        for i in 0..sides.len() {
            for j in i + 1..sides.len() {
                let (a, b) = (sides[i], sides[j]);
                let same_uv = (a.0 - b.0).length() + (a.1 - b.1).length() < 1e-2;
                if !same_uv && a.2.dot(b.2) > MAX_CREASE_COS {
                    out.push(SeamEdge { a: [a.0, a.1], b: [b.0, b.1] });
                }
            }
        }
    }
    out
}

/// The four bilinear taps of atlas position `uv` (texels; centres at +½), clamped.
fn taps(width: usize, height: usize, uv: Vec2) -> [(usize, f32); 4] {
    let p = uv - Vec2::splat(0.5);
    let (x0, y0) = (p.x.floor(), p.y.floor());
    let (fx, fy) = (p.x - x0, p.y - y0);
    let at = |x: f32, y: f32| (y.clamp(0.0, (height - 1) as f32) as usize) * width + x.clamp(0.0, (width - 1) as f32) as usize;
    [
        (at(x0, y0), (1.0 - fx) * (1.0 - fy)),
        (at(x0 + 1.0, y0), fx * (1.0 - fy)),
        (at(x0, y0 + 1.0), (1.0 - fx) * fy),
        (at(x0 + 1.0, y0 + 1.0), fx * fy),
    ]
}

/// Sample points along every seam: two per texel of the longer side, at the centres of
/// equal steps.
pub fn samples(seams: &[SeamEdge], width: usize, height: usize) -> Vec<SeamSample> {
    let mut out = Vec::new();
    for s in seams {
        let len = (s.a[1] - s.a[0]).length().max((s.b[1] - s.b[0]).length());
        let n = ((2.0 * len).ceil() as usize).max(2);
        for k in 0..n {
            let t = (k as f32 + 0.5) / n as f32;
            out.push(SeamSample { a: taps(width, height, s.a[0].lerp(s.a[1], t)), b: taps(width, height, s.b[0].lerp(s.b[1], t)) });
        }
    }
    out
}

/// Mean |lookup_A − lookup_B| of E/π over the samples and channels (0 without samples).
pub fn seam_metric(img: &LightmapImages, samples: &[SeamSample]) -> f64 {
    if samples.is_empty() {
        return 0.0;
    }
    let look = |t: &[(usize, f32); 4], c: usize| t.iter().map(|(i, w)| *w as f64 * img.irradiance[*i][c] as f64).sum::<f64>();
    let s: f64 = samples.iter().map(|x| (0..3).map(|c| (look(&x.a, c) - look(&x.b, c)).abs()).sum::<f64>()).sum();
    s / (3 * samples.len()) as f64
}

/// What [`stitch`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StitchStats {
    pub samples: usize,
    /// Texels the solve changed (valid and empty).
    pub texels: usize,
    /// Empty texels it wrote (dilation keeps them).
    pub written_empty: Vec<usize>,
    /// Largest conjugate-gradient iteration count over the right-hand sides.
    pub iterations: usize,
    /// Whether every solve reached [`CG_TOLERANCE`] within [`MAX_CG_ITERATIONS`].
    pub converged: bool,
}

/// Stitches `img` along `samples` (see the module docs). `dilated` is the same images after
/// dilation: the anchors of empty texels under a tap.
pub fn stitch(img: &mut LightmapImages, dilated: &LightmapImages, samples: &[SeamSample]) -> StitchStats {
    // Unknowns: every texel under a tap, in first-seen order.
    let mut index: BTreeMap<usize, usize> = BTreeMap::new();
    let mut texels = Vec::new();
    for s in samples {
        for (t, _) in s.a.iter().chain(&s.b) {
            index.entry(*t).or_insert_with(|| {
                texels.push(*t);
                texels.len() - 1
            });
        }
    }
    if texels.is_empty() {
        return StitchStats::default();
    }
    let n = texels.len();
    let valid: Vec<bool> = texels.iter().map(|t| img.validity[*t] > 0.0).collect();
    let mu: Vec<f64> = valid.iter().map(|v| if *v { 1.0 } else { EMPTY_WEIGHT }).collect();
    // Constraint rows c_s (A taps minus B taps, merged by unknown).
    let rows: Vec<Vec<(usize, f64)>> = samples
        .iter()
        .map(|s| {
            let mut r: BTreeMap<usize, f64> = BTreeMap::new();
            for (t, w) in &s.a {
                *r.entry(index[t]).or_default() += *w as f64;
            }
            for (t, w) in &s.b {
                *r.entry(index[t]).or_default() -= *w as f64;
            }
            r.into_iter().filter(|(_, w)| *w != 0.0).collect()
        })
        .collect();
    let mut diag = mu.clone();
    for r in &rows {
        for (i, w) in r {
            diag[*i] += SEAM_WEIGHT * w * w;
        }
    }
    let apply = |x: &[f64], y: &mut [f64]| {
        for i in 0..n {
            y[i] = mu[i] * x[i];
        }
        for r in &rows {
            let d: f64 = r.iter().map(|(i, w)| w * x[*i]).sum();
            for (i, w) in r {
                y[*i] += SEAM_WEIGHT * w * d;
            }
        }
    };
    let mut iterations = 0;
    let mut converged = true;
    // Solve (λCᵀC + M)x = M·x0 for one right-hand side; returns x.
    let mut solve = |x0: &[f64]| -> Vec<f64> {
        let b: Vec<f64> = (0..n).map(|i| mu[i] * x0[i]).collect();
        let mut x = x0.to_vec();
        let mut ax = vec![0.0; n];
        apply(&x, &mut ax);
        let mut r: Vec<f64> = (0..n).map(|i| b[i] - ax[i]).collect();
        let mut z: Vec<f64> = (0..n).map(|i| r[i] / diag[i]).collect();
        let mut p = z.clone();
        let mut rz: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
        let bnorm = b.iter().map(|v| v * v).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
        let mut ap = vec![0.0; n];
        for it in 0..MAX_CG_ITERATIONS {
            if r.iter().map(|v| v * v).sum::<f64>().sqrt() <= CG_TOLERANCE * bnorm {
                iterations = iterations.max(it);
                break;
            }
            apply(&p, &mut ap);
            let alpha = rz / p.iter().zip(&ap).map(|(a, b)| a * b).sum::<f64>();
            for i in 0..n {
                x[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
                z[i] = r[i] / diag[i];
            }
            let rz_new: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
            iterations = iterations.max(it + 1);
            if it + 1 == MAX_CG_ITERATIONS {
                converged = false;
            }
        }
        x
    };
    // Anchors: valid texels their value, empty ones the dilated value.
    let mut run = |src: &mut Vec<[f32; 3]>, anchor: &[[f32; 3]]| {
        for c in 0..3 {
            let x0: Vec<f64> = texels.iter().zip(&valid).map(|(t, v)| if *v { src[*t][c] as f64 } else { anchor[*t][c] as f64 }).collect();
            let x = solve(&x0);
            for (i, t) in texels.iter().enumerate() {
                src[*t][c] = x[i] as f32;
            }
        }
    };
    run(&mut img.irradiance, &dilated.irradiance);
    for (b, basis) in img.coefficients.iter_mut().enumerate() {
        for (l, lobe) in basis.iter_mut().enumerate() {
            run(lobe, &dilated.coefficients[b][l]);
        }
    }
    // Empty texels written: their normal and standard error as dilation would give them.
    let written_empty: Vec<usize> = texels.iter().zip(&valid).filter(|(_, v)| !**v).map(|(t, _)| *t).collect();
    for t in &written_empty {
        img.normals[*t] = dilated.normals[*t];
        img.standard_error[*t] = dilated.standard_error[*t];
    }
    StitchStats { samples: samples.len(), texels: n, written_empty, iterations, converged }
}
