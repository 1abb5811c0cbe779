//! Solvers that turn radiance samples (or whole maps) into basis coefficients.
//!
//! | what | function/type | module |
//! |---|---|---|
//! | moments and Monte-Carlo Gram from samples or maps | [`moments`], [`sample_gram`], [`map_samples`] | this file |
//! | batch least squares, Gram form (Cholesky → eigen pseudo-inverse, Tikhonov) | [`solve_gram`] | [`lsq`] |
//! | batch least squares, design-matrix form (QR → SVD) | [`solve_design`] | [`lsq`] |
//! | non-negative least squares (Lawson–Hanson, bounded, explicit status) | [`nnls_gram`], [`nnls_design`] | [`nnls`] |
//! | NNLS under equality constraints (null-space elimination, LSI → LDP → NNLS; KKT check) | [`nnls_gram_eq`] | [`nnls_eq`] |
//! | progressive per-sample LS/NNLS ([Roughton19 §7.3]), naive projection, running average | [`ProgressiveEncoder`], [`naive_projection`] | [`progressive`] |
//! | projection/convolution matrices and basis conversion ([Roughton19 §7.4]) | [`projection_matrix`], [`Conversion`] | [`projection`] |
//!
//! Samples carry a quadrature weight: the solid angle each represents (4π/N for N
//! uniform sphere samples, the texel solid angle for a map). Moments are then
//! m_i = Σ_k w_k f_k B_i(d_k) ≈ ∫ f B_i, and the sample Gram Σ_k w_k B(d_k)B(d_k)ᵀ ≈ G.

pub mod lsq;
pub mod nnls;
pub mod nnls_eq;
pub mod progressive;
pub mod projection;

pub use lsq::{solve_design, solve_gram, LsMethod, LsOptions, LsSolution};
pub use nnls::{nnls_design, nnls_gram, NnlsOptions, NnlsSolution, NnlsStatus};
pub use nnls_eq::{nnls_gram_eq, NnlsEqSolution};
pub use progressive::{naive_projection, Denominator, Iteration, ProgressiveEncoder, ProgressiveOptions, Real};
pub use projection::{projection_matrix, Conversion, Kernel, ProjectionOptions};

use crate::basis::Basis;
use crate::envmap::LatLongImage;
use glam::DVec3;
use nalgebra::DMatrix;

/// One radiance sample: unit direction, RGB radiance, and quadrature weight (sr).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadianceSample {
    /// Unit direction.
    pub direction: DVec3,
    /// RGB radiance.
    pub value: [f64; 3],
    /// Quadrature weight (sr).
    pub weight: f64,
}

/// Moments m (n × 3): m_ic = Σ_k w_k f_kc B_i(d_k).
pub fn moments(basis: &dyn Basis, samples: &[RadianceSample]) -> DMatrix<f64> {
    let n = basis.len();
    let mut m = DMatrix::zeros(n, 3);
    let (mut b, mut wb) = (vec![0.0; n], vec![0.0; n]);
    for s in samples {
        basis.eval_into(s.direction, &mut b);
        for (x, y) in wb.iter_mut().zip(&b) {
            *x = s.weight * y;
        }
        // Column-major storage: each channel's column is contiguous.
        for (c, col) in m.as_mut_slice().chunks_exact_mut(n).enumerate() {
            let v = s.value[c];
            for (o, x) in col.iter_mut().zip(&wb) {
                *o += x * v;
            }
        }
    }
    m
}

/// Gram matrix of the samples' own quadrature: Σ_k w_k B(d_k) B(d_k)ᵀ. Solving with
/// it instead of the exact G gives the least-squares fit *on the samples*.
pub fn sample_gram(basis: &dyn Basis, samples: &[RadianceSample]) -> DMatrix<f64> {
    let n = basis.len();
    let mut g = DMatrix::zeros(n, n);
    let (mut b, mut wb) = (vec![0.0; n], vec![0.0; n]);
    for s in samples {
        basis.eval_into(s.direction, &mut b);
        for (x, y) in wb.iter_mut().zip(&b) {
            *x = s.weight * y;
        }
        // Upper triangle, column by column (column-major: rows 0..=j of column j are
        // contiguous): g_ij += (w·b_i)·b_j, the same products in the same order per entry.
        for (j, col) in g.as_mut_slice().chunks_exact_mut(n).enumerate() {
            let bj = b[j];
            if bj == 0.0 {
                continue;
            }
            for (o, x) in col[..=j].iter_mut().zip(&wb) {
                *o += x * bj;
            }
        }
    }
    for i in 0..n {
        for j in 0..i {
            g[(i, j)] = g[(j, i)];
        }
    }
    g
}

/// Every texel of a lat-long map as a sample weighted by its exact solid angle.
pub fn map_samples(map: &LatLongImage) -> Vec<RadianceSample> {
    let g = map.geometry;
    let mut out = Vec::with_capacity(g.texel_count());
    for j in 0..g.height {
        let w = g.texel_solid_angle(j);
        for i in 0..g.width {
            let t = map.texel(i, j);
            out.push(RadianceSample { direction: g.texel_direction(i, j), value: [t[0] as f64, t[1] as f64, t[2] as f64], weight: w });
        }
    }
    out
}
