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
//! - [`stitch`]: least squares (Iwanicki, "Lighting Technology of The Last of Us", SIGGRAPH
//!   2013; Sylvan, "Fixing Texture Seams With Linear Least-Squares", 2015): minimise λ·Σ_samples (lookup_A − lookup_B)² + Σ_texels
//!   μ_t (x_t − x0_t)² over the taps' texels, per channel of E/π and of every coefficient —
//!   one matrix for all of them, so every texel's coefficients change by the same linear
//!   map. Valid texels keep their value with μ = 1; empty (padding) texels under a tap are
//!   unknowns too, anchored weakly (μ = 0.01) to what dilation would give them, and are then
//!   kept by dilation. Solved by Jacobi-preconditioned conjugate gradients.
//!   Sign: (λCᵀC + M)⁻¹M is not entrywise ≥ 0 (two taps on one side of a sample couple with
//!   +λ·w_i·w_j; a padding tap of small bilinear weight and weight μ = 0.01 is a lever that
//!   moves by several times the jump), so the free solve can take E/π below zero next to a
//!   seam (in the glTF room, 67 texels down to −913 where E/π's median is 276). Texels where
//!   it does are held at their anchors in every image of that colour channel and all are
//!   solved again until none is negative (an active set that only grows). Coefficient sets
//!   that are ≥ 0 under every tap (SG, Ambient Dice: NNLS lobes) are not solved: each
//!   texel's lobes are scaled by its stitched E/π over its E/π before, per channel — the
//!   default solver's rescale applied to the stitched E/π — so they stay ≥ 0 and keep their
//!   E/π at the normal (a texel with E/π = 0 — black, or empty where dilation never reached
//!   — takes the lobe shape of a texel with E/π under its samples). Where nothing goes
//!   negative, E/π and the signed sets (SH) are the free solution, unchanged.
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
    /// Texels held at their anchors in some colour channel: the free solve took a
    /// non-negative image below zero there, or (with a non-negative coefficient set) their
    /// E/π is 0 in that channel and no texel under their samples has E/π to lend a lobe shape.
    pub held: usize,
    /// Solves of the non-negative images, summed over the colour channels (3: none had to be
    /// held after the first).
    pub rounds: usize,
}

/// The stitch's linear system (λCᵀC + M)x = M·x0 over the unknown texels (module docs).
struct System {
    n: usize,
    /// Anchor weights μ (1 valid, [`EMPTY_WEIGHT`] empty).
    mu: Vec<f64>,
    /// Constraint rows c_s (A taps minus B taps, merged by unknown).
    rows: Vec<Vec<(usize, f64)>>,
    /// The diagonal of λCᵀC + M (the Jacobi preconditioner).
    diag: Vec<f64>,
    /// The rows each unknown appears in.
    incident: Vec<Vec<usize>>,
    /// The most CG iterations of any solve, and whether every solve converged.
    iterations: usize,
    converged: bool,
}

impl System {
    fn new(samples: &[SeamSample], index: &BTreeMap<usize, usize>, valid: &[bool]) -> Self {
        let n = valid.len();
        let mu: Vec<f64> = valid.iter().map(|v| if *v { 1.0 } else { EMPTY_WEIGHT }).collect();
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
        let mut incident: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, r) in rows.iter().enumerate() {
            for (i, w) in r {
                diag[*i] += SEAM_WEIGHT * w * w;
                incident[*i].push(k);
            }
        }
        System { n, mu, rows, diag, incident, iterations: 0, converged: true }
    }

    /// y = (λCᵀC + M)x.
    fn apply(&self, x: &[f64], y: &mut [f64]) {
        for i in 0..self.n {
            y[i] = self.mu[i] * x[i];
        }
        for r in &self.rows {
            let d: f64 = r.iter().map(|(i, w)| w * x[*i]).sum();
            for (i, w) in r {
                y[*i] += SEAM_WEIGHT * w * d;
            }
        }
    }

    /// Solves for one right-hand side M·x0 over the unknowns not `held` (they keep x0):
    /// Jacobi-preconditioned conjugate gradients restricted to the free unknowns — the plain
    /// solve when none is held.
    fn solve(&mut self, x0: &[f64], held: &[bool]) -> Vec<f64> {
        let n = self.n;
        let b: Vec<f64> = (0..n).map(|i| self.mu[i] * x0[i]).collect();
        let mut x = x0.to_vec();
        let mut ax = vec![0.0; n];
        self.apply(&x, &mut ax);
        let mut r: Vec<f64> = (0..n).map(|i| if held[i] { 0.0 } else { b[i] - ax[i] }).collect();
        let mut z: Vec<f64> = (0..n).map(|i| r[i] / self.diag[i]).collect();
        let mut p = z.clone();
        let mut rz: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
        let bnorm = b.iter().map(|v| v * v).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
        let mut ap = vec![0.0; n];
        for it in 0..MAX_CG_ITERATIONS {
            if r.iter().map(|v| v * v).sum::<f64>().sqrt() <= CG_TOLERANCE * bnorm {
                self.iterations = self.iterations.max(it);
                break;
            }
            self.apply(&p, &mut ap);
            for i in 0..n {
                if held[i] {
                    ap[i] = 0.0;
                }
            }
            let alpha = rz / p.iter().zip(&ap).map(|(a, b)| a * b).sum::<f64>();
            for i in 0..n {
                x[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
                z[i] = r[i] / self.diag[i];
            }
            let rz_new: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
            self.iterations = self.iterations.max(it + 1);
            if it + 1 == MAX_CG_ITERATIONS {
                self.converged = false;
            }
        }
        x
    }

    /// The donor of unknown `i` for one channel's E/π `e0`: of the texels with E/π > 0 under
    /// the samples `i` is a tap of, the one of largest tap weight on `i`'s side, else on the
    /// other side.
    fn donor(&self, e0: &[f64], i: usize) -> Option<usize> {
        let mut best: [Option<(f64, usize)>; 2] = [None, None];
        for k in &self.incident[i] {
            let wi = self.rows[*k].iter().find(|(j, _)| *j == i).map_or(0.0, |(_, w)| *w);
            for (j, w) in &self.rows[*k] {
                let side = usize::from(w * wi < 0.0);
                if *j != i && e0[*j] > 0.0 && best[side].is_none_or(|(b, _)| w.abs() > b) {
                    best[side] = Some((w.abs(), *j));
                }
            }
        }
        best[0].or(best[1]).map(|(_, j)| j)
    }

    /// Solves one colour channel's images (`channels`, anchors per unknown; the first E/π)
    /// with one held set: the non-negative ones are solved, the unknowns any of them takes
    /// below zero added to `held`, until none does; then the rest. Returns the solutions in
    /// `channels`' order and the rounds.
    fn solve_channel(&mut self, channels: &[&Vec<f64>], held: &mut [bool]) -> (Vec<Vec<f64>>, usize) {
        let non_negative: Vec<bool> = channels.iter().map(|x0| x0.iter().all(|v| *v >= 0.0)).collect();
        let mut solved: Vec<Option<Vec<f64>>> = vec![None; channels.len()];
        let mut rounds = 0;
        loop {
            rounds += 1;
            let mut negative = vec![false; self.n];
            for (k, x0) in channels.iter().enumerate().filter(|(k, _)| non_negative[*k]) {
                let x = self.solve(x0, held);
                for i in 0..self.n {
                    negative[i] |= (x[i] as f32) < 0.0;
                }
                solved[k] = Some(x);
            }
            if !negative.iter().any(|v| *v) {
                break;
            }
            for i in 0..self.n {
                held[i] |= negative[i];
            }
        }
        let out = channels.iter().zip(solved).map(|(x0, x)| x.unwrap_or_else(|| self.solve(x0, held))).collect();
        (out, rounds)
    }
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
    let mut sys = System::new(samples, &index, &valid);
    // Anchors (valid texels their value, empty ones the dilated value) of every channel:
    // E/π's three, then each coefficient set's lobes'.
    let anchors = |src: &[[f32; 3]], dil: &[[f32; 3]]| -> Vec<Vec<f64>> {
        (0..3).map(|c| texels.iter().zip(&valid).map(|(t, v)| if *v { src[*t][c] as f64 } else { dil[*t][c] as f64 }).collect()).collect()
    };
    let e0 = anchors(&img.irradiance, &dilated.irradiance);
    let sets: Vec<Vec<Vec<f64>>> = img
        .coefficients
        .iter()
        .enumerate()
        .map(|(b, basis)| basis.iter().enumerate().flat_map(|(l, lobe)| anchors(lobe, &dilated.coefficients[b][l])).collect())
        .collect();
    // A coefficient set ≥ 0 under every tap is a non-negative basis: rescaled, not solved.
    let scaled: Vec<bool> = sets.iter().map(|set| set.iter().flatten().all(|v| *v >= 0.0)).collect();
    // Per colour channel (each texel's E/π and lobes relate channel by channel): E/π's and the
    // signed sets' lobes' channel c share one held set and one matrix.
    let (mut held_any, mut rounds) = (vec![false; n], 0);
    let (mut e1, mut donor_of, mut signed) = (Vec::new(), Vec::new(), Vec::new());
    for c in 0..3 {
        let mut channels: Vec<&Vec<f64>> = vec![&e0[c]];
        for (set, s) in sets.iter().zip(&scaled) {
            if !s {
                channels.extend(set.iter().skip(c).step_by(3));
            }
        }
        // A texel whose E/π is 0 (black, or empty where dilation never reached: a chart with no
        // valid texel) has no scale for its lobes: it takes a donor's lobe shape, else is held.
        let donors: Vec<Option<usize>> = (0..n).map(|i| if e0[c][i] <= 0.0 { sys.donor(&e0[c], i) } else { None }).collect();
        let mut held: Vec<bool> = (0..n).map(|i| scaled.iter().any(|s| *s) && e0[c][i] <= 0.0 && donors[i].is_none()).collect();
        let (solved, r) = sys.solve_channel(&channels, &mut held);
        rounds += r;
        let mut solved = solved.into_iter();
        e1.push(solved.next().expect("E/π"));
        signed.push(solved);
        donor_of.push(donors);
        for i in 0..n {
            held_any[i] |= held[i];
        }
    }
    let write = |dst: &mut Vec<[f32; 3]>, c: usize, x: &[f64]| {
        for (i, t) in texels.iter().enumerate() {
            dst[*t][c] = x[i] as f32;
        }
    };
    for (c, x) in e1.iter().enumerate() {
        write(&mut img.irradiance, c, x);
    }
    for ((basis, set), s) in img.coefficients.iter_mut().zip(&sets).zip(&scaled) {
        for (l, lobe) in basis.iter_mut().enumerate() {
            for c in 0..3 {
                let x = if *s {
                    let x0 = &set[3 * l + c];
                    (0..n)
                        .map(|i| match donor_of[c][i] {
                            Some(j) => x0[j] * (e1[c][i] / e0[c][j]),
                            None if e0[c][i] > 0.0 => x0[i] * (e1[c][i] / e0[c][i]),
                            None => x0[i],
                        })
                        .collect()
                } else {
                    signed[c].next().expect("coefficient")
                };
                write(lobe, c, &x);
            }
        }
    }
    // Empty texels written: their normal and standard error as dilation would give them.
    let written_empty: Vec<usize> = texels.iter().zip(&valid).filter(|(_, v)| !**v).map(|(t, _)| *t).collect();
    for t in &written_empty {
        img.normals[*t] = dilated.normals[*t];
        img.standard_error[*t] = dilated.standard_error[*t];
    }
    let held = held_any.iter().filter(|h| **h).count();
    StitchStats { samples: samples.len(), texels: n, written_empty, iterations: sys.iterations, converged: sys.converged, held, rounds }
}
