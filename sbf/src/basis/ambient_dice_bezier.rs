//! Ambient Dice hybrid cubic Bézier variant (Iwanicki & Sloan 2017) and its YCoCg
//! form (Y by Bézier, Co/Cg piecewise-linear).
//!
//! Per icosahedron vertex i, three coefficients: the value f_i and the directional
//! derivatives (D_u, D_v) along the vertex's tangent frame (T_i, B_i), laid out as
//! `[f_0, Du_0, Dv_0, f_1, …]` (36 per channel).
//!
//! On the face containing d, with unnormalised gnomonic barycentrics b_k (d = Σ b_k v_k),
//! the value is the homogeneous cubic Bézier triangle
//!   Σ b_k³ f_k + Σ_{i≠j} 3 b_i² b_j c_{i→j} + 6 b₀b₁b₂ c₁₁₁.
//! Edge control points (derived here; they agree with math.md's −β/α = 1/√5):
//!   c_{i→j} = cos θ·f_i + (sin θ / 3)·∇f_i·t_ij,
//! with θ the edge angle (cos θ = 1/√5) and t_ij the unit tangent at v_i towards v_j.
//! These match the value and first derivative at each vertex along each edge and
//! reproduce every linear function a·d exactly on the edges. The interior point is
//! split Gregory-style, c₁₁₁ = Σ w_k c₁₁₁⁽ᵏ⁾, w₀ = b₁b₂/D (D = b₁b₂ + b₀b₂ + b₀b₁), where
//!   c₁₁₁⁽⁰⁾ = a₀(f₁ + f₂) + a₁(c_{1→2} + c_{2→1}) + a₂(c_{1→0} + c_{2→0})
//! uses only data on the edge opposite v₀, so the patch is C⁰ across all 30 edges.
//! a₀ = (√5 − 5)/40, a₁ = (11√5 − 15)/40, a₂ = √5/10 (math.md); they satisfy the two
//! conditions for c₁₁₁⁽ᵏ⁾ to reproduce linear functions exactly (a test), so the whole
//! patch reproduces a·d. Value weights are not a partition of unity (sum ∈ [0.93, 1]).

use super::ambient_dice::{AmbientDiceLinear, Icosahedron, ICOSAHEDRON_EDGE_COS};
use super::Basis;
use crate::quadrature::Domain;
use glam::DVec3;

/// Redistribution weights of the interior control point (math.md, Ambient Dice): the
/// weight of the triangle's own vertex, (√5 − 5)/40.
pub const BEZIER_A0: f64 = -0.069_098_300_562_505_26; // (√5 − 5)/40
/// The weight of each of the two other vertices of the triangle, (11√5 − 15)/40.
pub const BEZIER_A1: f64 = 0.239_918_693_812_442_1; // (11√5 − 15)/40
/// The weight of the neighbouring vertices, √5/10.
pub const BEZIER_A2: f64 = 0.223_606_797_749_979; // √5/10

pub use crate::frame::tangent_frame;

/// Per-face precomputed data: for each corner k and each of its two edges, the
/// derivative factors (sinθ/3)·(T·t, B·t).
#[derive(Debug, Clone, Copy)]
struct FaceEdges {
    // deriv[k][e] = (factor on Du_k, factor on Dv_k) for edge from corner k to corner (k+1+e)%3.
    deriv: [[[f64; 2]; 2]; 3],
}

/// Hybrid cubic Bézier Ambient Dice, 36 functions per channel.
#[derive(Debug, Clone)]
pub struct AmbientDiceBezier {
    ico: Icosahedron,
    frames: [(DVec3, DVec3); 12],
    faces: [FaceEdges; 20],
}

impl AmbientDiceBezier {
    /// On the standard icosahedron with [`tangent_frame`] frames at each vertex.
    pub fn new() -> Self {
        let ico = Icosahedron::standard();
        let frames = ico.vertices().map(tangent_frame);
        let cos_t = ICOSAHEDRON_EDGE_COS;
        let sin_t = (1.0 - cos_t * cos_t).sqrt();
        let mut faces = [FaceEdges { deriv: [[[0.0; 2]; 2]; 3] }; 20];
        for (f, face) in ico.faces().iter().enumerate() {
            for k in 0..3 {
                let vi = ico.vertices()[face[k]];
                let (t, b) = frames[face[k]];
                for e in 0..2 {
                    let vj = ico.vertices()[face[(k + 1 + e) % 3]];
                    let tij = (vj - cos_t * vi) / sin_t;
                    faces[f].deriv[k][e] = [sin_t / 3.0 * t.dot(tij), sin_t / 3.0 * b.dot(tij)];
                }
            }
        }
        AmbientDiceBezier { ico, frames, faces }
    }

    /// The underlying geometry.
    pub fn icosahedron(&self) -> &Icosahedron {
        &self.ico
    }
    /// Tangent frame (T, B) of vertex i: the directions of the stored derivatives.
    pub fn frame(&self, i: usize) -> (DVec3, DVec3) {
        self.frames[i]
    }

    /// Derivative factors of face `f`: `[k][e]` = (sinθ/3)·(T_k·t, B_k·t) for the edge
    /// from corner k to corner (k + 1 + e) % 3 (t its unit tangent at corner k). The GPU
    /// twin reads them as a table.
    pub fn edge_factors(&self, f: usize) -> [[[f64; 2]; 2]; 3] {
        self.faces[f].deriv
    }

    /// Weights of the 9 non-zero coefficients at `dir`: the face's vertex indices
    /// and, per corner, (value, Du, Dv) weights.
    pub fn weights(&self, dir: DVec3) -> ([usize; 3], [[f64; 3]; 3]) {
        let (f, b) = self.ico.locate(dir);
        let fe = &self.faces[f];
        let cos_t = ICOSAHEDRON_EDGE_COS;
        // Bernstein weights of the edge control points: ew[k][e] for c_{k→(k+1+e)%3}
        // = 3 b_k² b_j.
        let mut cw = [b[0] * b[0] * b[0], b[1] * b[1] * b[1], b[2] * b[2] * b[2]];
        let mut ew = [[0.0; 2]; 3];
        for k in 0..3 {
            for e in 0..2 {
                let j = (k + 1 + e) % 3;
                ew[k][e] = 3.0 * b[k] * b[k] * b[j];
            }
        }
        // Interior point, split Gregory-style. Where D = 0 (at a vertex) the
        // interior Bernstein weight 6 b0 b1 b2 is 0 as well.
        let d = b[1] * b[2] + b[0] * b[2] + b[0] * b[1];
        if d > 0.0 {
            let c111 = 6.0 * b[0] * b[1] * b[2];
            for k in 0..3 {
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                let wk = c111 * b[i] * b[j] / d;
                // a0 on the opposite vertices' values
                cw[i] += BEZIER_A0 * wk;
                cw[j] += BEZIER_A0 * wk;
                // a1 on c_{i→j} and c_{j→i}; a2 on c_{i→k} and c_{j→k}.
                ew[i][edge_slot(i, j)] += BEZIER_A1 * wk;
                ew[j][edge_slot(j, i)] += BEZIER_A1 * wk;
                ew[i][edge_slot(i, k)] += BEZIER_A2 * wk;
                ew[j][edge_slot(j, k)] += BEZIER_A2 * wk;
            }
        }
        let mut w = [[0.0; 3]; 3];
        for k in 0..3 {
            w[k][0] = cw[k] + cos_t * (ew[k][0] + ew[k][1]);
            for e in 0..2 {
                w[k][1] += ew[k][e] * fe.deriv[k][e][0];
                w[k][2] += ew[k][e] * fe.deriv[k][e][1];
            }
        }
        (self.ico.faces()[f], w)
    }
}

/// Slot e of edge k→j in `FaceEdges::deriv[k]` (j = (k + 1 + e) % 3).
#[inline]
fn edge_slot(k: usize, j: usize) -> usize {
    if (k + 1) % 3 == j {
        0
    } else {
        1
    }
}

impl Default for AmbientDiceBezier {
    fn default() -> Self {
        Self::new()
    }
}

impl Basis for AmbientDiceBezier {
    fn name(&self) -> String {
        "AD Bézier 36".into()
    }
    fn len(&self) -> usize {
        36
    }
    fn domain(&self) -> Domain {
        Domain::Sphere
    }
    fn eval_into(&self, dir: DVec3, out: &mut [f64]) {
        debug_assert!(super::is_unit(dir), "direction must be unit length: {dir:?}");
        out.fill(0.0);
        let (idx, w) = self.weights(dir);
        for k in 0..3 {
            out[3 * idx[k]..3 * idx[k] + 3].copy_from_slice(&w[k]);
        }
    }
}

/// RGB → YCoCg (Malvar & Sullivan 2003): Y = R/4 + G/2 + B/4, Co = (R − B)/2,
/// Cg = −R/4 + G/2 − B/4.
pub fn rgb_to_ycocg(rgb: [f64; 3]) -> [f64; 3] {
    let [r, g, b] = rgb;
    [0.25 * r + 0.5 * g + 0.25 * b, 0.5 * (r - b), -0.25 * r + 0.5 * g - 0.25 * b]
}

/// YCoCg → RGB, the exact inverse of [`rgb_to_ycocg`].
pub fn ycocg_to_rgb(ycocg: [f64; 3]) -> [f64; 3] {
    let [y, co, cg] = ycocg;
    let t = y - cg;
    [t + co, y + cg, t - co]
}

/// Ambient Dice YCoCg: luma through the Bézier basis (36 coefficients), chroma Co
/// and Cg through the piecewise-linear basis (12 each): 60 coefficients for RGB
/// instead of 108. A colour representation, so it is not itself a [`Basis`]; its
/// two channel bases are.
#[derive(Debug, Clone, Default)]
pub struct AmbientDiceYCoCg {
    /// The basis of Y (hybrid Bézier, 36 coefficients).
    pub luma: AmbientDiceBezier,
    /// The basis of Co and Cg (piecewise linear, 12 each).
    pub chroma: AmbientDiceLinear,
}

impl AmbientDiceYCoCg {
    /// Roughton's pairing: Bézier luma, linear chroma.
    pub fn new() -> Self {
        Self::default()
    }
    /// Total coefficients for RGB.
    pub const COEFFICIENTS: usize = 60;

    /// RGB at `dir` from Y (36), Co (12), Cg (12) coefficients.
    pub fn eval_rgb(&self, y: &[f64; 36], co: &[f64; 12], cg: &[f64; 12], dir: DVec3) -> [f64; 3] {
        let (idx, w) = self.luma.weights(dir);
        let mut yv = 0.0;
        for k in 0..3 {
            for c in 0..3 {
                yv += w[k][c] * y[3 * idx[k] + c];
            }
        }
        let mut lw = [0.0; 12];
        self.chroma.eval_into(dir, &mut lw);
        let cov: f64 = lw.iter().zip(co).map(|(a, b)| a * b).sum();
        let cgv: f64 = lw.iter().zip(cg).map(|(a, b)| a * b).sum();
        ycocg_to_rgb([yv, cov, cgv])
    }
}
