//! Batch least squares ([Roughton19 §7.2, eq. 7.3]).
//!
//! Gram form, G b = m: Cholesky when G is numerically positive definite, otherwise a
//! pseudo-inverse through the symmetric eigen-decomposition that drops eigenvalues
//! below `rank_tolerance`·λ_max and reports the numerical rank. Optional Tikhonov
//! regularisation solves (G + τ·mean(diag G)·I) b = m.
//!
//! Design-matrix form, min ‖W^½(A b − y)‖ (samples × lobes): Householder QR, with an
//! SVD fallback when R has a negligible diagonal entry (rank deficiency).

use crate::error::{check_len, SbfError};
use nalgebra::{DMatrix, SymmetricEigen};

/// Options for the batch least-squares solvers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LsOptions {
    /// Tikhonov factor τ, relative to the mean diagonal of G (0 = none).
    pub tikhonov: f64,
    /// Relative threshold below which eigen/singular values count as zero.
    pub rank_tolerance: f64,
}

impl Default for LsOptions {
    /// No regularisation; rank threshold 1e-13 (≈ 500·ε: keeps Gram condition
    /// numbers up to ~1e12 at full rank, drops exact duplicates).
    fn default() -> Self {
        LsOptions { tikhonov: 0.0, rank_tolerance: 1e-13 }
    }
}

/// Which factorisation produced a solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LsMethod {
    /// Cholesky factorisation of the Gram matrix (well conditioned, Gram form).
    Cholesky,
    /// Eigen-decomposition pseudo-inverse (Gram form).
    EigenPseudoInverse,
    /// QR factorisation of the design matrix (design form).
    Qr,
    /// SVD pseudo-inverse (design form).
    Svd,
}

/// A least-squares solution with the diagnostics a caller needs to judge it.
#[derive(Debug, Clone)]
pub struct LsSolution {
    /// Coefficients, n × channels.
    pub coeffs: DMatrix<f64>,
    /// The factorisation used.
    pub method: LsMethod,
    /// Numerical rank (n when full rank).
    pub rank: usize,
    /// 2-norm condition number of the (regularised) system matrix (+∞ if singular).
    pub condition: f64,
}

fn check_finite(what: &'static str, m: &DMatrix<f64>) -> Result<(), SbfError> {
    if let Some(v) = m.iter().find(|v| !v.is_finite()) {
        return Err(SbfError::InvalidParameter { name: what, value: *v, reason: "contains a non-finite entry" });
    }
    Ok(())
}

/// Solves G b = m for every column of `m` (n × channels).
pub fn solve_gram(g: &DMatrix<f64>, m: &DMatrix<f64>, opts: LsOptions) -> Result<LsSolution, SbfError> {
    let n = g.nrows();
    check_len("Gram matrix columns", n, g.ncols())?;
    check_len("moment rows", n, m.nrows())?;
    check_finite("Gram matrix", g)?;
    check_finite("moments", m)?;
    if !(opts.tikhonov.is_finite() && opts.tikhonov >= 0.0) {
        return Err(SbfError::InvalidParameter { name: "Tikhonov factor", value: opts.tikhonov, reason: "must be finite and >= 0" });
    }
    let mut a = g.clone();
    if opts.tikhonov > 0.0 {
        let mean_diag = g.diagonal().mean();
        for i in 0..n {
            a[(i, i)] += opts.tikhonov * mean_diag;
        }
    }
    let eig = SymmetricEigen::new(a.clone());
    let lmax = eig.eigenvalues.iter().fold(0.0f64, |x, v| x.max(v.abs()));
    let cut = opts.rank_tolerance * lmax;
    let rank = eig.eigenvalues.iter().filter(|v| **v > cut).count();
    let lmin = eig.eigenvalues.iter().fold(f64::INFINITY, |x, v| x.min(v.abs()));
    let condition = if lmin > 0.0 { lmax / lmin } else { f64::INFINITY };
    if rank == n {
        if let Some(ch) = a.clone().cholesky() {
            return Ok(LsSolution { coeffs: ch.solve(m), method: LsMethod::Cholesky, rank, condition });
        }
    }
    // Pseudo-inverse: b = V diag(1/λ for λ > cut) Vᵀ m.
    let v = &eig.eigenvectors;
    let mut vt_m = v.transpose() * m;
    for (k, lam) in eig.eigenvalues.iter().enumerate() {
        let s = if *lam > cut { 1.0 / lam } else { 0.0 };
        for c in 0..vt_m.ncols() {
            vt_m[(k, c)] *= s;
        }
    }
    Ok(LsSolution { coeffs: v * vt_m, method: LsMethod::EigenPseudoInverse, rank, condition })
}

/// Solves min Σ_k w_k (A_k· b − y_k)² for every column of `y` (samples × channels).
/// `weights` (one per row, ≥ 0) default to 1.
pub fn solve_design(a: &DMatrix<f64>, y: &DMatrix<f64>, weights: Option<&[f64]>, opts: LsOptions) -> Result<LsSolution, SbfError> {
    let (k, n) = (a.nrows(), a.ncols());
    check_len("design rows vs values", k, y.nrows())?;
    check_finite("design matrix", a)?;
    check_finite("sample values", y)?;
    if k < n {
        return Err(SbfError::InvalidParameter { name: "sample count", value: k as f64, reason: "fewer samples than unknowns" });
    }
    let (mut aw, mut yw) = (a.clone(), y.clone());
    if let Some(w) = weights {
        check_len("sample weights", k, w.len())?;
        for (r, wr) in w.iter().enumerate() {
            if !(wr.is_finite() && *wr >= 0.0) {
                return Err(SbfError::InvalidParameter { name: "sample weight", value: *wr, reason: "must be finite and >= 0" });
            }
            let s = wr.sqrt();
            aw.row_mut(r).scale_mut(s);
            yw.row_mut(r).scale_mut(s);
        }
    }
    if opts.tikhonov > 0.0 {
        // Append √(τ·mean diag(AᵀA))·I rows: the design-form twin of Gram Tikhonov.
        let mean_diag = (0..n).map(|j| aw.column(j).norm_squared()).sum::<f64>() / n as f64;
        let s = (opts.tikhonov * mean_diag).sqrt();
        let mut a2 = DMatrix::zeros(k + n, n);
        a2.rows_mut(0, k).copy_from(&aw);
        for j in 0..n {
            a2[(k + j, j)] = s;
        }
        let mut y2 = DMatrix::zeros(k + n, yw.ncols());
        y2.rows_mut(0, k).copy_from(&yw);
        aw = a2;
        yw = y2;
    }
    let qr = aw.clone().qr();
    let r = qr.r();
    let rmax = (0..n).map(|i| r[(i, i)].abs()).fold(0.0f64, f64::max);
    let full = (0..n).all(|i| r[(i, i)].abs() > opts.rank_tolerance.sqrt() * rmax);
    if full {
        let qty = qr.q().transpose() * &yw;
        if let Some(x) = r.solve_upper_triangular(&qty) {
            let sv = aw.singular_values();
            let cond = sv.max() / sv.min();
            return Ok(LsSolution { coeffs: x, method: LsMethod::Qr, rank: n, condition: cond * cond });
        }
    }
    let svd = aw.svd(true, true);
    let smax = svd.singular_values.max();
    let cut = opts.rank_tolerance.sqrt() * smax;
    let rank = svd.singular_values.iter().filter(|s| **s > cut).count();
    let smin = svd.singular_values.min();
    let condition = if smin > 0.0 { (smax / smin).powi(2) } else { f64::INFINITY };
    let x = svd.solve(&yw, cut).map_err(|_| SbfError::NotPositiveDefinite { what: "design matrix (SVD failed)" })?;
    Ok(LsSolution { coeffs: x, method: LsMethod::Svd, rank, condition })
}
