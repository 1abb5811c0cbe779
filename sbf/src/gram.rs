//! Gram matrices G_ij = ∫_S B_i B_j over the sphere or the upper hemisphere
//! ([Roughton19 eq. 7.3]), their condition numbers, and a Cholesky solve of G b = m.
//!
//! Closed forms where they exist ([`Basis`] types that know theirs: SH on the sphere
//! is I; SG lobes on the sphere use the SG inner product). Everything else uses the
//! Gauss–Legendre × trapezoid product rule of [`crate::quadrature`] at two
//! resolutions; the reported `quadrature_error` is the largest entrywise difference
//! between them (an over-estimate of the fine rule's error when it converges).

use crate::basis::Basis;
use crate::error::{check_len, SbfError};
use crate::quadrature::{estimate_error, Domain, SphereQuadrature};
use nalgebra::{DMatrix, DVector};

/// How a Gram matrix was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GramMethod {
    /// Exact closed form.
    ClosedForm,
    /// Product quadrature with `n_z` Gauss–Legendre nodes and `n_phi` φ nodes.
    Quadrature {
        /// Gauss–Legendre nodes in z.
        n_z: usize,
        /// Equally spaced nodes in φ.
        n_phi: usize,
    },
}

/// Options for [`gram_matrix`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GramOptions {
    /// Gauss–Legendre nodes in z for the fine rule (φ uses 2·n_z); the error
    /// estimate uses half of each.
    pub n_z: usize,
    /// Use quadrature even when a closed form exists (for cross-checks).
    pub force_quadrature: bool,
}

impl Default for GramOptions {
    /// 256 × 512 nodes: quadrature error below 1e-8 for the clamped-cosine bases
    /// (Ambient Dice, ambient cube) and at rounding level for smooth ones.
    fn default() -> Self {
        GramOptions { n_z: 256, force_quadrature: false }
    }
}

/// A Gram matrix with how it was computed and how well conditioned it is.
#[derive(Debug, Clone)]
pub struct Gram {
    /// G_ij = ∫ B_i B_j dω over `domain`.
    pub matrix: DMatrix<f64>,
    /// The domain integrated over.
    pub domain: Domain,
    /// How the entries were computed.
    pub method: GramMethod,
    /// Estimated max entrywise quadrature error (0 for closed forms).
    pub quadrature_error: f64,
    /// 2-norm condition number λ_max/λ_min (+∞ when singular).
    pub condition: f64,
}

/// Gram matrix by quadrature (for any basis), at the resolution in `opts`.
pub fn gram_by_quadrature(basis: &dyn Basis, domain: Domain, opts: GramOptions) -> Result<Gram, SbfError> {
    if opts.n_z < 2 {
        return Err(SbfError::InvalidParameter { name: "Gram n_z", value: opts.n_z as f64, reason: "must be >= 2" });
    }
    let fine = SphereQuadrature::gauss_product(domain, opts.n_z, 2 * opts.n_z);
    let coarse = SphereQuadrature::gauss_product(domain, opts.n_z / 2, opts.n_z);
    let gf = gram_with_rule(basis, &fine);
    let gc = gram_with_rule(basis, &coarse);
    let err = estimate_error(gc.as_slice(), gf.as_slice());
    Ok(finish(gf, domain, GramMethod::Quadrature { n_z: opts.n_z, n_phi: 2 * opts.n_z }, err))
}

/// Gram matrix: the basis's closed form when it has one on `domain` (and
/// `opts.force_quadrature` is off), quadrature otherwise.
pub fn gram_matrix(basis: &dyn Basis, domain: Domain, opts: GramOptions) -> Result<Gram, SbfError> {
    if !opts.force_quadrature {
        if let Some(m) = basis.closed_form_gram(domain) {
            return Ok(finish(m, domain, GramMethod::ClosedForm, 0.0));
        }
    }
    gram_by_quadrature(basis, domain, opts)
}

/// Σ_k w_k B(d_k) B(d_k)ᵀ over the nodes of `rule`, in node order.
pub fn gram_with_rule(basis: &dyn Basis, rule: &SphereQuadrature) -> DMatrix<f64> {
    let n = basis.len();
    let mut g = vec![0.0; n * n];
    let mut b = vec![0.0; n];
    for (d, w) in rule.directions.iter().zip(&rule.weights) {
        basis.eval_into(*d, &mut b);
        for i in 0..n {
            let wi = w * b[i];
            if wi == 0.0 {
                continue;
            }
            let row = &mut g[i * n..(i + 1) * n];
            for j in i..n {
                row[j] += wi * b[j];
            }
        }
    }
    for i in 0..n {
        for j in 0..i {
            g[i * n + j] = g[j * n + i];
        }
    }
    DMatrix::from_row_slice(n, n, &g)
}

fn finish(matrix: DMatrix<f64>, domain: Domain, method: GramMethod, quadrature_error: f64) -> Gram {
    let condition = condition_number(&matrix);
    Gram { matrix, domain, method, quadrature_error, condition }
}

/// 2-norm condition number of a symmetric matrix: max|λ|/min|λ| (+∞ if singular).
pub fn condition_number(m: &DMatrix<f64>) -> f64 {
    let ev = m.clone().symmetric_eigenvalues();
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for &e in ev.iter() {
        lo = lo.min(e.abs());
        hi = hi.max(e.abs());
    }
    if lo == 0.0 {
        f64::INFINITY
    } else {
        hi / lo
    }
}

impl Gram {
    /// Solves G b = m by Cholesky (G must be numerically SPD).
    pub fn solve(&self, moments: &[f64]) -> Result<Vec<f64>, SbfError> {
        check_len("moment vector", self.matrix.nrows(), moments.len())?;
        let chol = self.matrix.clone().cholesky().ok_or(SbfError::NotPositiveDefinite { what: "Gram matrix" })?;
        let x = chol.solve(&DVector::from_column_slice(moments));
        Ok(x.iter().copied().collect())
    }
}
