//! Non-negative least squares by the Lawson–Hanson active-set method
//! (Lawson & Hanson 1974, "Solving Least Squares Problems", ch. 23), in f64, for
//! the Gram form (min ½bᵀGb − mᵀb, b ≥ 0) and the design form (min ‖Ab − y‖, b ≥ 0).
//!
//! Guarantees: the number of passive-set solves is bounded by
//! [`NnlsOptions::max_iterations`] (an unbounded loop is a known defect of one public
//! tool), and the result says whether it converged, with the KKT residual
//!   r = max( max_{i∈P} |w_i|, max_{i∉P} max(w_i, 0), max_i max(−b_i, 0)·‖G‖ ) / scale,
//! w = m − Gb (the negative gradient), scale = max(‖m‖∞, ‖G‖∞·‖b‖∞).
//!
//! Degeneracy: an index whose passive solve comes back non-positive right after it
//! entered is barred until the next successful step (the classic anti-cycling guard
//! for rounding-level gradients, e.g. duplicated columns).

use crate::error::{check_len, SbfError};
use nalgebra::{DMatrix, DVector};

/// Options for NNLS.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NnlsOptions {
    /// Cap on passive-set solves (outer + inner iterations). `None` = 3n + 30.
    pub max_iterations: Option<usize>,
    /// Relative gradient tolerance for an index to enter the passive set.
    pub tolerance: f64,
}

impl Default for NnlsOptions {
    /// Cap 3n + 30 (Lawson–Hanson typically needs ≤ n outer steps; we have not seen
    /// more than ~2n on random problems up to cond 1e10), tolerance 1e-12.
    fn default() -> Self {
        NnlsOptions { max_iterations: None, tolerance: 1e-12 }
    }
}

/// How an NNLS solve ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NnlsStatus {
    /// KKT conditions hold to the tolerance.
    Converged,
    /// Stopped at the iteration cap; `kkt_residual` says how far from optimal.
    IterationCap,
    /// No index can enter, but an index barred by the anti-cycling guard still has a
    /// gradient above the entry tolerance and the KKT residual exceeds
    /// [`BARRED_KKT_LIMIT`]: the solve stalled; `kkt_residual` says how far from optimal.
    Stalled,
}

/// Largest relative KKT residual accepted as convergence when the only indices left
/// with a positive gradient are barred (their gradients are rounding-level in the
/// degenerate cases the guard exists for: duplicated columns, singular G).
pub const BARRED_KKT_LIMIT: f64 = 1e-9;

/// How a solve that finds no entering index ends: converged, unless a barred index's
/// gradient exceeds `tol` and the KKT residual exceeds [`BARRED_KKT_LIMIT`].
fn termination_status(barred: &[bool], w: &[f64], tol: f64, kkt: f64) -> NnlsStatus {
    let barred_open = barred.iter().zip(w).any(|(b, wi)| *b && *wi > tol);
    if barred_open && kkt > BARRED_KKT_LIMIT {
        NnlsStatus::Stalled
    } else {
        NnlsStatus::Converged
    }
}

/// An NNLS solution (one channel).
#[derive(Debug, Clone)]
pub struct NnlsSolution {
    /// Coefficients, all ≥ 0.
    pub coeffs: Vec<f64>,
    /// How the iteration ended.
    pub status: NnlsStatus,
    /// Passive-set solves performed.
    pub iterations: usize,
    /// Relative KKT residual (see module docs).
    pub kkt_residual: f64,
    /// Indices with b_i > 0 at exit (the passive set).
    pub passive: Vec<usize>,
}

/// The two problem forms share the active-set driver through this interface.
trait Problem {
    fn n(&self) -> usize;
    /// w = −∇f(b) (m − Gb, or Aᵀ(y − Ab)).
    fn neg_gradient(&self, b: &[f64]) -> Vec<f64>;
    /// Unconstrained minimiser over the passive indices (others 0).
    fn solve_passive(&self, passive: &[usize]) -> Vec<f64>;
    /// ‖G‖∞ (design form: ‖AᵀA‖∞) and ‖m‖∞ for the KKT scale.
    fn scales(&self) -> (f64, f64);
}

struct GramProblem<'a> {
    g: &'a DMatrix<f64>,
    m: &'a [f64],
}

impl Problem for GramProblem<'_> {
    fn n(&self) -> usize {
        self.m.len()
    }
    fn neg_gradient(&self, b: &[f64]) -> Vec<f64> {
        (0..self.n()).map(|i| self.m[i] - (0..self.n()).map(|j| self.g[(i, j)] * b[j]).sum::<f64>()).collect()
    }
    fn solve_passive(&self, p: &[usize]) -> Vec<f64> {
        let k = p.len();
        let gp = DMatrix::from_fn(k, k, |a, b| self.g[(p[a], p[b])]);
        let mp = DVector::from_fn(k, |a, _| self.m[p[a]]);
        let z = match gp.clone().cholesky() {
            Some(ch) => ch.solve(&mp),
            None => pinv_solve(&gp, &mp),
        };
        scatter(self.n(), p, &z)
    }
    fn scales(&self) -> (f64, f64) {
        (inf_norm(self.g), self.m.iter().fold(0.0, |a: f64, v| a.max(v.abs())))
    }
}

struct DesignProblem<'a> {
    a: &'a DMatrix<f64>,
    y: &'a DVector<f64>,
    aty: Vec<f64>,
}

impl Problem for DesignProblem<'_> {
    fn n(&self) -> usize {
        self.a.ncols()
    }
    fn neg_gradient(&self, b: &[f64]) -> Vec<f64> {
        let r = self.y - self.a * DVector::from_column_slice(b);
        (self.a.transpose() * r).iter().copied().collect()
    }
    fn solve_passive(&self, p: &[usize]) -> Vec<f64> {
        let ap = DMatrix::from_fn(self.a.nrows(), p.len(), |r, c| self.a[(r, p[c])]);
        // SVD handles rank-deficient passive sets (duplicated columns) gracefully.
        let svd = ap.svd(true, true);
        let cut = 1e-13 * svd.singular_values.max();
        let z = svd.solve(self.y, cut).unwrap_or_else(|_| DVector::zeros(p.len()));
        scatter(self.n(), p, &z)
    }
    fn scales(&self) -> (f64, f64) {
        (inf_norm(&(self.a.transpose() * self.a)), self.aty.iter().fold(0.0, |a: f64, v| a.max(v.abs())))
    }
}

fn inf_norm(g: &DMatrix<f64>) -> f64 {
    (0..g.nrows()).map(|i| g.row(i).iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max)
}

fn scatter(n: usize, p: &[usize], z: &DVector<f64>) -> Vec<f64> {
    let mut out = vec![0.0; n];
    for (k, &i) in p.iter().enumerate() {
        out[i] = z[k];
    }
    out
}

/// Pseudo-inverse solve of a small symmetric PSD system (rank-deficient passive sets).
fn pinv_solve(g: &DMatrix<f64>, m: &DVector<f64>) -> DVector<f64> {
    let eig = g.clone().symmetric_eigen();
    let lmax = eig.eigenvalues.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut t = eig.eigenvectors.transpose() * m;
    for (k, lam) in eig.eigenvalues.iter().enumerate() {
        t[k] = if *lam > 1e-13 * lmax { t[k] / lam } else { 0.0 };
    }
    &eig.eigenvectors * t
}

fn kkt_residual(b: &[f64], w: &[f64], passive: &[bool], gnorm: f64, mnorm: f64) -> f64 {
    let bnorm = b.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let scale = mnorm.max(gnorm * bnorm).max(f64::MIN_POSITIVE);
    let mut r = 0.0f64;
    for i in 0..b.len() {
        r = r.max(if passive[i] { w[i].abs() } else { w[i].max(0.0) });
        r = r.max((-b[i]).max(0.0) * gnorm);
    }
    r / scale
}

fn lawson_hanson(prob: &dyn Problem, opts: NnlsOptions) -> NnlsSolution {
    let n = prob.n();
    let cap = opts.max_iterations.unwrap_or(3 * n + 30);
    let (gnorm, mnorm) = prob.scales();
    let mut b = vec![0.0; n];
    let mut passive = vec![false; n];
    let mut barred = vec![false; n];
    let mut iterations = 0;
    let finish = |b: Vec<f64>, passive: &[bool], status, iterations| {
        let w = prob.neg_gradient(&b);
        let kkt = kkt_residual(&b, &w, passive, gnorm, mnorm);
        let p = (0..n).filter(|i| passive[*i]).collect();
        NnlsSolution { coeffs: b, status, iterations, kkt_residual: kkt, passive: p }
    };
    if mnorm == 0.0 {
        return finish(b, &passive, NnlsStatus::Converged, 0);
    }
    loop {
        let w = prob.neg_gradient(&b);
        let bnorm = b.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let tol = opts.tolerance * mnorm.max(gnorm * bnorm);
        // Entering index: largest positive negative-gradient among active, non-barred.
        let t = (0..n).filter(|i| !passive[*i] && !barred[*i] && w[*i] > tol).max_by(|a, c| w[*a].total_cmp(&w[*c]));
        let Some(t) = t else {
            let kkt = kkt_residual(&b, &w, &passive, gnorm, mnorm);
            return finish(b, &passive, termination_status(&barred, &w, tol, kkt), iterations);
        };
        passive[t] = true;
        // Inner loop: restore feasibility.
        loop {
            if iterations >= cap {
                return finish(b, &passive, NnlsStatus::IterationCap, iterations);
            }
            iterations += 1;
            let p: Vec<usize> = (0..n).filter(|i| passive[*i]).collect();
            let z = prob.solve_passive(&p);
            if p.iter().all(|&i| z[i] > 0.0) {
                b = z;
                barred.iter_mut().for_each(|x| *x = false);
                break;
            }
            // Step from b towards z until the first passive coefficient hits zero.
            let mut alpha = 1.0f64;
            for &i in &p {
                if z[i] <= 0.0 {
                    let denom = b[i] - z[i];
                    if denom > 0.0 {
                        alpha = alpha.min(b[i] / denom);
                    } else {
                        alpha = 0.0;
                    }
                }
            }
            for i in 0..n {
                b[i] += alpha * (z[i] - b[i]);
            }
            for &i in &p {
                if b[i] <= 0.0 || (z[i] <= 0.0 && b[i] <= f64::EPSILON * bnorm.max(f64::MIN_POSITIVE)) {
                    b[i] = 0.0;
                    passive[i] = false;
                }
            }
            if alpha == 0.0 && !passive[t] {
                // The entering index cannot grow (its gradient was rounding-level):
                // bar it until the next successful step, and pick another.
                barred[t] = true;
                break;
            }
        }
    }
}

/// NNLS on the Gram form: min ½bᵀGb − mᵀb subject to b ≥ 0 (one channel).
pub fn nnls_gram(g: &DMatrix<f64>, m: &[f64], opts: NnlsOptions) -> Result<NnlsSolution, SbfError> {
    check_len("Gram matrix rows", m.len(), g.nrows())?;
    check_len("Gram matrix columns", m.len(), g.ncols())?;
    if let Some(v) = g.iter().chain(m.iter()).find(|v| !v.is_finite()) {
        return Err(SbfError::InvalidParameter { name: "NNLS input", value: *v, reason: "contains a non-finite entry" });
    }
    Ok(lawson_hanson(&GramProblem { g, m }, opts))
}

/// NNLS on the design form: min ‖A b − y‖² subject to b ≥ 0 (one channel).
pub fn nnls_design(a: &DMatrix<f64>, y: &[f64], opts: NnlsOptions) -> Result<NnlsSolution, SbfError> {
    check_len("design rows vs values", a.nrows(), y.len())?;
    if let Some(v) = a.iter().chain(y.iter()).find(|v| !v.is_finite()) {
        return Err(SbfError::InvalidParameter { name: "NNLS input", value: *v, reason: "contains a non-finite entry" });
    }
    let yv = DVector::from_column_slice(y);
    let aty = (a.transpose() * &yv).iter().copied().collect();
    Ok(lawson_hanson(&DesignProblem { a, y: &yv, aty }, opts))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Converged is said only when every barred index's gradient is within the entry
    /// tolerance or the KKT residual is within BARRED_KKT_LIMIT.
    #[test]
    fn barred_indices_must_pass_the_kkt_check() {
        let tol = 1e-12;
        // Nothing barred: converged whatever the residual (the active set is exhausted).
        assert_eq!(termination_status(&[false, false], &[1.0, -1.0], tol, 0.5), NnlsStatus::Converged);
        // Barred with a rounding-level gradient: converged.
        assert_eq!(termination_status(&[true, false], &[5e-13, 0.0], tol, 1e-12), NnlsStatus::Converged);
        // Barred with a real gradient but a tiny residual (scale): converged.
        assert_eq!(termination_status(&[true, false], &[1e-6, 0.0], tol, 1e-10), NnlsStatus::Converged);
        // Barred with a real gradient and a residual above the limit: stalled.
        assert_eq!(termination_status(&[true, false], &[1e-3, 0.0], tol, 1e-3), NnlsStatus::Stalled);
        assert_eq!(termination_status(&[false, true], &[0.0, 2e-9], tol, 2e-9), NnlsStatus::Stalled);
    }
}
