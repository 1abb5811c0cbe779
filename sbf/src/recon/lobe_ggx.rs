//! GGX specular response of one radial lobe — exact by quadrature, and tabulated for the
//! runtime (a per-lobe path whose only approximation is interpolation).
//!
//! For a radiance lobe K(p·l) with unit axis p (an SG e^{λ(p·l − 1)}, an Ambient Dice
//! SRBF), the reflected radiance at normal n, view v and roughness α is
//!   R(v, α, p) = ∫ K(p·l)·f_GGX(v, l)·(n·l)₊ dl = f0·R₀ + f90·R₁,
//! R₀ and R₁ the integrals with (1 − F_c) and F_c (Schlick). The lobe and the BRDF are both
//! symmetric about their own axes, so R depends on four numbers only: θ_v (n·v = cos θ_v),
//! α, θ_p (n·p = cos θ_p) and φ, the azimuth of p about n measured from v's azimuth; R is
//! even in φ. A basis with fixed lobe shapes (all our SG bases share λ = 6; every AD lobe is
//! the same SRBF) needs one 4D table per shape, valid for any normal — normal-mapped
//! surfaces included — unlike a per-basis table in tangent space.
//!
//! Quadrature: [`crate::ggx::reflection_quadrature`] (Gauss–Legendre in the NDF's own CDF
//! and the half-vector azimuth, the horizon cut in closed form), both azimuth halves
//! evaluated since K breaks the y → −y symmetry. The table stores R on nodes (edges
//! included, so no extrapolation): θ_v on [0, π/2], √α on [0, 1], θ_p on [0, π], φ on
//! [0, π], uniform in each; sampling is multilinear. Angles, not cosines, because K is a
//! smooth function of the angle to its axis: uniform cosines would leave 0.3 rad gaps at
//! the poles. √α because the lobe's width is ~α and the mirror limit (α → 0) is a node.

use crate::ggx;
use glam::DVec3;
use std::f64::consts::PI;

/// The radial profile of a lobe, K(c) for c = cos of the angle to the lobe's axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RadialLobe {
    /// Spherical Gaussian e^{λ(c − 1)} (unit peak).
    Sg {
        /// λ.
        sharpness: f64,
    },
    /// The Ambient Dice cosine-lobe SRBF, 0.35c² + 0.25c⁴ for c > 0 ([Roughton19 §8.3.1]).
    #[cfg(feature = "ambient-dice")]
    AdSrbf,
}

impl RadialLobe {
    /// K(c).
    pub fn eval(&self, c: f64) -> f64 {
        match *self {
            RadialLobe::Sg { sharpness } => (sharpness * (c - 1.0)).exp(),
            #[cfg(feature = "ambient-dice")]
            RadialLobe::AdSrbf => crate::basis::ambient_dice::srbf_lobe(c),
        }
    }

    /// A short name for tables and reports (`sg6`, `ad`).
    pub fn name(&self) -> String {
        match *self {
            RadialLobe::Sg { sharpness } => format!("sg{}", fmt_sharpness(sharpness)),
            #[cfg(feature = "ambient-dice")]
            RadialLobe::AdSrbf => "ad".to_string(),
        }
    }
}

fn fmt_sharpness(l: f64) -> String {
    if l.fract() == 0.0 {
        format!("{}", l as i64)
    } else {
        format!("{l}").replace('.', "p")
    }
}

/// The lobe axis at (γ, ψ) for view angle θ_v in the quadrature's frame (normal +Z,
/// v = (sin θ_v, 0, cos θ_v)): p = cos γ·r + sin γ·(cos ψ·t + sin ψ·y) with r the mirror
/// direction (−sin θ_v, 0, cos θ_v) and t = (cos θ_v, 0, sin θ_v) ⟂ r towards the normal.
pub fn axis(theta_v: f64, gamma: f64, psi: f64) -> DVec3 {
    let (sv, cv) = theta_v.sin_cos();
    let r = DVec3::new(-sv, 0.0, cv);
    let t = DVec3::new(cv, 0.0, sv);
    gamma.cos() * r + gamma.sin() * (psi.cos() * t + psi.sin() * DVec3::Y)
}

/// Quadrature nodes of the GGX lobe for (n·v, α): (l, w·(1 − F_c), w·F_c) with both
/// azimuth halves listed, so Σ K(p·l)·w₀ ≈ R₀ for any axis p: `n` nodes in φ_h and n/2 in
/// ξ on each of 52 panels (26·n² nodes).
pub fn nodes(n_dot_v: f64, alpha: f64, n: usize) -> Vec<(DVec3, f64, f64)> {
    let mut out = Vec::new();
    // n/2 nodes in ξ per panel (the DFG uses n/8): K(p·l) varies across the first panel,
    // which spans θ_h up to atan(α) — 45° at α = 1, a 90° swing of l.
    ggx::reflection_quadrature(n_dot_v, alpha, n, (n / 2).max(4), |l, fc, wt, val| {
        let w = 0.5 * wt * val;
        for l in [l, DVec3::new(l.x, -l.y, l.z)] {
            out.push((l, w * (1.0 - fc), w * fc));
        }
    });
    out
}

/// R = (R₀, R₁) for the lobe axis `p` (frame of [`axis`]) from precomputed [`nodes`].
pub fn response_from_nodes(lobe: RadialLobe, nodes: &[(DVec3, f64, f64)], p: DVec3) -> [f64; 2] {
    let mut acc = [0.0; 2];
    for (l, w0, w1) in nodes {
        let k = lobe.eval(p.dot(*l));
        acc[0] += k * w0;
        acc[1] += k * w1;
    }
    acc
}

/// R = (R₀, R₁) by quadrature with `n` nodes per dimension (see
/// [`crate::ggx::reflection_quadrature`]; compare n and 2n for its error).
pub fn response(lobe: RadialLobe, n_dot_v: f64, alpha: f64, gamma: f64, psi: f64, n: usize) -> [f64; 2] {
    let nv = n_dot_v.clamp(0.0, 1.0);
    response_from_nodes(lobe, &nodes(nv, alpha, n), axis(nv.acos(), gamma, psi))
}

/// Node counts of a table: θ_v, √α, θ_p, φ (each ≥ 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Grid {
    /// Nodes in θ_v (as n·v from 0 to 1).
    pub theta_v: usize,
    /// Nodes in √α.
    pub alpha: usize,
    /// Nodes in γ, the lobe axis's angle to the mirror direction.
    pub gamma: usize,
    /// Nodes in ψ, the lobe axis's azimuth about the mirror direction.
    pub psi: usize,
}

impl Grid {
    /// Ranges of the four coordinates (node 0 at the low end, the last at the high end).
    pub const RANGES: [(f64, f64); 4] = [(0.0, 1.0), (0.0, 1.0), (0.0, PI), (0.0, PI)];

    /// The node counts in axis order (θ_v, √α, γ, ψ).
    pub fn sizes(&self) -> [usize; 4] {
        [self.theta_v, self.alpha, self.gamma, self.psi]
    }

    /// Coordinate of node k on axis d.
    pub fn node(&self, d: usize, k: usize) -> f64 {
        let (lo, hi) = Self::RANGES[d];
        lo + (hi - lo) * k as f64 / (self.sizes()[d] - 1) as f64
    }

    /// Values per table (two channels each).
    pub fn len(&self) -> usize {
        self.sizes().iter().product()
    }

    /// Whether some axis has no node.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Every (θ_p, φ) node of one (θ_v, √α) slab, θ_p-major: what a table builder computes in
/// parallel per slab.
pub fn slab(lobe: RadialLobe, grid: Grid, i_theta_v: usize, i_alpha: usize, n: usize) -> Vec<[f64; 2]> {
    let nv = grid.node(0, i_theta_v);
    let alpha = grid.node(1, i_alpha).powi(2);
    let nodes = nodes(nv, alpha, n);
    let mut out = Vec::with_capacity(grid.gamma * grid.psi);
    for i in 0..grid.gamma {
        for j in 0..grid.psi {
            out.push(response_from_nodes(lobe, &nodes, axis(nv.acos(), grid.node(2, i), grid.node(3, j))));
        }
    }
    out
}

/// A tabulated response: (R₀, R₁) on the nodes of `grid`, index
/// ((n·v·N_α + √α)·N_γ + γ)·N_ψ + ψ — the order of the `.sbflut` file, whose axes are
/// (ψ, γ, √α, n·v) fastest first with texel centres on the nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Its nodes.
    pub grid: Grid,
    /// Two values per node.
    pub values: Vec<f32>,
}

/// Linear interpolation position on a node axis: (lower node, fraction), clamped.
fn locate(x: f64, d: usize, size: usize) -> (usize, f64) {
    let (lo, hi) = Grid::RANGES[d];
    let t = ((x - lo) / (hi - lo)).clamp(0.0, 1.0) * (size - 1) as f64;
    let i = (t.floor() as usize).min(size - 2);
    (i, t - i as f64)
}

/// File axis names, fastest first.
const FILE_AXES: [(&str, usize); 4] = [("psi", 3), ("gamma", 2), ("sqrt_alpha", 1), ("n_dot_v", 0)];

impl Table {
    /// Builds a table serially (fitgen builds the slabs in parallel and calls [`Table::from_slabs`]).
    pub fn build(lobe: RadialLobe, grid: Grid, n: usize) -> Table {
        let slabs = (0..grid.theta_v).flat_map(|i| (0..grid.alpha).map(move |j| (i, j))).map(|(i, j)| slab(lobe, grid, i, j, n)).collect();
        Table::from_slabs(grid, slabs)
    }

    /// A table from its slabs in (n·v, √α) order.
    pub fn from_slabs(grid: Grid, slabs: Vec<Vec<[f64; 2]>>) -> Table {
        let values = slabs.into_iter().flatten().flat_map(|v| [v[0] as f32, v[1] as f32]).collect();
        Table { grid, values }
    }

    /// The table as an `.sbflut` file (axes (ψ, γ, √α, n·v), texel centres on the nodes).
    pub fn to_file(&self, format: crate::luts::ValueFormat, note: String) -> crate::luts::LutFile {
        let sizes = self.grid.sizes();
        let axes = FILE_AXES
            .iter()
            .map(|&(name, d)| {
                let (lo, hi) = Grid::RANGES[d];
                let h = (hi - lo) / (sizes[d] - 1) as f64;
                crate::luts::Axis { name: name.into(), size: sizes[d], lo: (lo - 0.5 * h) as f32, hi: (hi + 0.5 * h) as f32 }
            })
            .collect();
        crate::luts::LutFile { axes, channels: 2, format, note, values: self.values.clone() }
    }

    /// A table from an `.sbflut` file written by [`Table::to_file`].
    pub fn from_file(f: &crate::luts::LutFile) -> Result<Table, crate::SbfError> {
        let bad = |reason| crate::SbfError::InvalidParameter { name: "lobe GGX table", value: f.axes.len() as f64, reason };
        if f.axes.len() != 4 || f.channels != 2 || f.axes.iter().zip(FILE_AXES).any(|(a, (n, _))| a.name != n) {
            return Err(bad("expected 2 channels over axes (psi, gamma, sqrt_alpha, n_dot_v)"));
        }
        if f.axes.iter().any(|a| a.size < 2) {
            return Err(bad("every axis needs at least two nodes"));
        }
        let s = |k: usize| f.axes[k].size;
        Ok(Table { grid: Grid { theta_v: s(3), alpha: s(2), gamma: s(1), psi: s(0) }, values: f.values.clone() })
    }

    /// Per-pixel part: the (n·v, √α) corners and their weights.
    pub fn pixel(&self, n_dot_v: f64, alpha: f64) -> TablePixel {
        let g = self.grid;
        let (i, a) = locate(n_dot_v.clamp(0.0, 1.0), 0, g.theta_v);
        let (j, b) = locate(alpha.clamp(0.0, 1.0).sqrt(), 1, g.alpha);
        let slab = 2 * g.gamma * g.psi;
        let base = |di: usize, dj: usize| ((i + di) * g.alpha + j + dj) * slab;
        TablePixel {
            nodes: [i, j],
            corners: [base(0, 0), base(0, 1), base(1, 0), base(1, 1)],
            weights: [(1.0 - a) * (1.0 - b), (1.0 - a) * b, a * (1.0 - b), a * b],
        }
    }

    /// The most a texture unit's filter can change one lookup [`Table::lobe`] when the table
    /// is sampled as the runtime's `lobe_ggx_filtered_*` do — f16 texels in a 3D texture
    /// filtered along n·v, γ and ψ, two fetches blended along √α in the shader — by a
    /// sampler whose weights are within `weight_error` of the exact fractions on each axis
    /// and whose returned value is within `result_error` of the exact blend, relatively:
    /// per channel, `weight_error` × Σ over the three filtered axes of the largest
    /// difference of neighbouring nodes along that axis, plus `result_error` × the largest
    /// node value. A trilinear blend moves by at most its weight's change times that
    /// difference (it is linear in each weight); the two fetches' blend weighs them by
    /// weights summing to one. Along each filtered axis the window spans the cell and its
    /// two neighbours: an f32 position near a node may land in either cell.
    pub fn filter_error(&self, px: &TablePixel, gamma: f64, psi: f64, weight_error: f64, result_error: f64) -> [f64; 2] {
        let g = self.grid;
        let sizes = g.sizes();
        let base = [px.nodes[0], px.nodes[1], locate(gamma, 2, g.gamma).0, locate(psi, 3, g.psi).0];
        let window = |d: usize| if d == 1 { (base[d], base[d] + 1) } else { (base[d].saturating_sub(1), (base[d] + 2).min(sizes[d] - 1)) };
        let w = [window(0), window(1), window(2), window(3)];
        let at = |k: [usize; 4], c: usize| self.values[2 * (((k[0] * g.alpha + k[1]) * g.gamma + k[2]) * g.psi + k[3]) + c] as f64;
        let mut out = [0.0; 2];
        for (c, o) in out.iter_mut().enumerate() {
            let (mut spread, mut peak) = ([0.0f64; 4], 0.0f64);
            for k0 in w[0].0..=w[0].1 {
                for k1 in w[1].0..=w[1].1 {
                    for k2 in w[2].0..=w[2].1 {
                        for k3 in w[3].0..=w[3].1 {
                            let k = [k0, k1, k2, k3];
                            peak = peak.max(at(k, c).abs());
                            for (d, s) in spread.iter_mut().enumerate() {
                                if k[d] < w[d].1 {
                                    let mut up = k;
                                    up[d] += 1;
                                    *s = s.max((at(up, c) - at(k, c)).abs());
                                }
                            }
                        }
                    }
                }
            }
            // √α (axis 1) is blended by the shader in f32, not by the filter.
            *o = weight_error * (spread[0] + spread[2] + spread[3]) + result_error * peak;
        }
        out
    }

    /// R = (R₀, R₁) at (γ, ψ) for a pixel's corners.
    pub fn lobe(&self, px: &TablePixel, gamma: f64, psi: f64) -> [f64; 2] {
        let g = self.grid;
        let (k, c) = locate(gamma, 2, g.gamma);
        let (l, d) = locate(psi, 3, g.psi);
        let row = 2 * g.psi;
        let o = 2 * (k * g.psi + l);
        let taps = [(o, (1.0 - c) * (1.0 - d)), (o + 2, (1.0 - c) * d), (o + row, c * (1.0 - d)), (o + row + 2, c * d)];
        let mut acc = [0.0; 2];
        for (base, w) in px.corners.iter().zip(px.weights) {
            let v = &self.values[base + o..base + o + row + 4];
            for (t, tw) in taps {
                let (v0, v1) = (v[t - o], v[t - o + 1]);
                acc[0] += w * tw * v0 as f64;
                acc[1] += w * tw * v1 as f64;
            }
        }
        acc
    }

    /// R = (R₀, R₁) for unit normal n, unit view v, roughness α and unit lobe axis p.
    pub fn eval(&self, n: DVec3, v: DVec3, alpha: f64, p: DVec3) -> [f64; 2] {
        let px = self.pixel(n.dot(v), alpha);
        let (gamma, psi) = lobe_angles(n, v, p);
        self.lobe(&px, gamma, psi)
    }
}

/// A pixel's (θ_v, √α) corners in a [`Table`] and their bilinear weights.
#[derive(Debug, Clone, Copy)]
pub struct TablePixel {
    /// The lower (n·v, √α) nodes.
    nodes: [usize; 2],
    corners: [usize; 4],
    weights: [f64; 4],
}

/// The per-pixel frame of [`lobe_angles`]: the mirror direction r and the unit part of n
/// perpendicular to r (zero when n is along r, i.e. at normal incidence).
#[derive(Debug, Clone, Copy)]
pub struct MirrorFrame {
    r: DVec3,
    t: DVec3,
}

impl MirrorFrame {
    /// The frame of unit normal `n` and unit view `v`.
    pub fn new(n: DVec3, v: DVec3) -> Self {
        let r = 2.0 * n.dot(v) * n - v;
        let t = n - n.dot(r) * r;
        let l2 = t.length_squared();
        MirrorFrame { r, t: if l2 > 1e-24 { t / l2.sqrt() } else { DVec3::ZERO } }
    }

    /// (γ, ψ) of unit lobe axis p: γ the angle from r, ψ ∈ [0, π] the azimuth about r from
    /// the normal's side (0 when p or n is along r; R does not depend on ψ there).
    pub fn angles(&self, p: DVec3) -> (f64, f64) {
        let rp = self.r.dot(p).clamp(-1.0, 1.0);
        let st2 = (1.0 - rp * rp).max(0.0);
        let psi = if st2 > 1e-24 && self.t != DVec3::ZERO { (self.t.dot(p) / st2.sqrt()).clamp(-1.0, 1.0).acos() } else { 0.0 };
        (rp.acos(), psi)
    }
}

/// (γ, ψ) of lobe axis p for normal n and view v (see [`MirrorFrame::angles`]).
pub fn lobe_angles(n: DVec3, v: DVec3, p: DVec3) -> (f64, f64) {
    MirrorFrame::new(n, v).angles(p)
}

/// Specular of RGB lobe coefficients through a table: Σ_i b_i·(f0·R₀ + f90·R₁)(p_i).
pub fn specular_rgb(table: &Table, axes: &[DVec3], coeffs: &[[f64; 3]], n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64) -> [f64; 3] {
    specular_rgb_by(table, axes, coeffs, n, v, alpha, f0, f90, |px, gamma, psi| table.lobe(px, gamma, psi))
}

/// The most a texture unit's filter can change [`specular_rgb`] (the runtime's
/// `lobe_ggx_filtered_*` path): Σ_i |b_i|·(|f0|·ε₀ + |f90|·ε₁)(p_i), ε from
/// [`Table::filter_error`] with the sampler's `weight_error` and `result_error`.
pub fn specular_rgb_filter_error(
    table: &Table,
    axes: &[DVec3],
    coeffs: &[[f64; 3]],
    n: DVec3,
    v: DVec3,
    alpha: f64,
    f0: f64,
    f90: f64,
    weight_error: f64,
    result_error: f64,
) -> [f64; 3] {
    let magnitudes: Vec<[f64; 3]> = coeffs.iter().map(|b| b.map(f64::abs)).collect();
    specular_rgb_by(table, axes, &magnitudes, n, v, alpha, f0.abs(), f90.abs(), |px, gamma, psi| {
        table.filter_error(px, gamma, psi, weight_error, result_error)
    })
}

/// Σ_i b_i·(f0·R₀ + f90·R₁)(p_i) with R from `lookup` (pixel, γ, ψ).
fn specular_rgb_by(
    table: &Table,
    axes: &[DVec3],
    coeffs: &[[f64; 3]],
    n: DVec3,
    v: DVec3,
    alpha: f64,
    f0: f64,
    f90: f64,
    lookup: impl Fn(&TablePixel, f64, f64) -> [f64; 2],
) -> [f64; 3] {
    let px = table.pixel(n.dot(v), alpha);
    let frame = MirrorFrame::new(n, v);
    let mut e = [0.0; 3];
    for (p, b) in axes.iter().zip(coeffs) {
        let (gamma, psi) = frame.angles(*p);
        let r = lookup(&px, gamma, psi);
        let w = f0 * r[0] + f90 * r[1];
        for c in 0..3 {
            e[c] += w * b[c];
        }
    }
    e
}
