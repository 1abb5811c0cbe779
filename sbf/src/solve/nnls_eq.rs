//! Non-negative least squares under equality constraints, in f64:
//!   min ½bᵀGb − mᵀb  subject to  b ≥ 0,  C b = d
//! (G symmetric positive definite, C k × n of full row rank k < n) — a fit whose lobes stay
//! non-negative while it keeps linear functionals of the signal exactly, e.g. the
//! irradiance at a texel's normal equal to the bake's own estimate.
//!
//! Method (Lawson & Hanson 1974, "Solving Least Squares Problems"): the objective as a
//! least-squares norm ‖Lᵀb − L⁻¹m‖ (G = LLᵀ, Cholesky); the equalities eliminated through
//! the null space of C, b = b₀ + Z z with b₀ = Cᵀ(CCᵀ)⁻¹d and the columns of Z an orthonormal
//! basis of ker C (ch. 20, "LSE"); the remaining problem — least squares in z under the
//! inequalities Z z ≥ −b₀ ("LSI", ch. 23 §5) — reduced by the QR factors of LᵀZ to a
//! least-distance problem min ‖x‖ subject to Ẽx ≥ f̃ ("LDP", ch. 23 §3), which one NNLS
//! solves: u ≥ 0 minimising ‖[Ẽᵀ; f̃ᵀ]u − eₙ₊₁‖, residual r, x = −r₁..ₙ / rₙ₊₁; r = 0 means
//! no b ≥ 0 satisfies C b = d.
//!
//! The result carries its own check, independent of the path that found it: the
//! multipliers λ of the equalities by least squares over the positive coefficients, then
//! the KKT residual of G b − m + Cᵀλ = μ, μ ≥ 0, μᵢbᵢ = 0 (relative, as
//! [`super::nnls`]'s), and the equalities' residual |C b − d|.

use super::nnls::{nnls_design, NnlsOptions, NnlsStatus};
use crate::error::{check_len, SbfError};
use nalgebra::{DMatrix, DVector};

/// A solution of NNLS under equality constraints (one channel).
#[derive(Debug, Clone)]
pub struct NnlsEqSolution {
    /// Coefficients, all ≥ 0.
    pub coeffs: Vec<f64>,
    /// How the inner NNLS (of the least-distance problem) ended.
    pub status: NnlsStatus,
    /// Its passive-set solves.
    pub iterations: usize,
    /// Relative KKT residual of the constrained problem: max over i of |μᵢ| where bᵢ > 0,
    /// max(−μᵢ, 0) where bᵢ = 0, with μ = G b − m + Cᵀλ; over max(‖m‖∞, ‖G‖∞‖b‖∞).
    pub kkt_residual: f64,
    /// max |C b − d| over max(‖d‖∞, ‖C‖∞‖b‖∞).
    pub equality_residual: f64,
    /// The equalities' multipliers λ (∂ objective / ∂ d = −λ).
    pub multipliers: Vec<f64>,
}

/// min ½bᵀGb − mᵀb subject to b ≥ 0 and C b = d (one channel; `c` is k × n, k < n rows).
/// Errors: lengths that do not match, non-finite input, G not positive definite, C not of
/// full row rank, and constraints no non-negative b satisfies (named with the residual of
/// the least-distance problem).
pub fn nnls_gram_eq(g: &DMatrix<f64>, m: &[f64], c: &DMatrix<f64>, d: &[f64], opts: NnlsOptions) -> Result<NnlsEqSolution, SbfError> {
    let n = m.len();
    check_len("Gram matrix rows", n, g.nrows())?;
    check_len("Gram matrix columns", n, g.ncols())?;
    check_len("constraint matrix columns", n, c.ncols())?;
    check_len("constraint values", c.nrows(), d.len())?;
    if let Some(v) = g.iter().chain(m).chain(c.iter()).chain(d).find(|v| !v.is_finite()) {
        return Err(SbfError::InvalidParameter { name: "NNLS input", value: *v, reason: "contains a non-finite entry" });
    }
    let k = c.nrows();
    if k == 0 || k >= n {
        return Err(SbfError::InvalidParameter {
            name: "equality constraints",
            value: k as f64,
            reason: "need between 1 and n − 1 rows (without rows: nnls_gram)",
        });
    }
    let l = g.clone().cholesky().ok_or(SbfError::NotPositiveDefinite { what: "Gram matrix" })?.l();
    // Least-squares form: ½bᵀGb − mᵀb = ½‖Lᵀb − y‖² − ½‖y‖², L y = m.
    let a = l.transpose();
    let y = l.solve_lower_triangular(&DVector::from_column_slice(m)).expect("Cholesky factor is invertible");
    // The null space of C and the minimum-norm point of C b = d (eigenvectors of CᵀC).
    let eig = (c.transpose() * c).symmetric_eigen();
    let top = eig.eigenvalues.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|i, j| eig.eigenvalues[*i].total_cmp(&eig.eigenvalues[*j]));
    let rank = eig.eigenvalues.iter().filter(|v| **v > 1e-12 * top).count();
    if rank < k {
        return Err(SbfError::InvalidParameter {
            name: "equality constraints",
            value: rank as f64,
            reason: "the constraint rows are linearly dependent (the value is their rank)",
        });
    }
    let z = DMatrix::from_fn(n, n - k, |r, j| eig.eigenvectors[(r, order[j])]);
    let cct = c * c.transpose();
    let w = cct.cholesky().ok_or(SbfError::NotPositiveDefinite { what: "C Cᵀ" })?.solve(&DVector::from_column_slice(d));
    let b0 = c.transpose() * w;
    // LSI in z: min ‖E z − f‖ subject to Z z ≥ −b₀, with E = LᵀZ (full column rank).
    let e = &a * &z;
    let f = &y - &a * &b0;
    let qr = e.qr();
    let (q, r) = (qr.q(), qr.r());
    let qtf = q.transpose() * &f;
    // x = R z − Qᵀf: min ‖x‖ subject to Ẽ x ≥ f̃, Ẽ = Z R⁻¹, f̃ = −b₀ − Ẽ Qᵀf.
    let et = r.transpose().solve_lower_triangular(&z.transpose()).expect("R is invertible: E has full column rank");
    let e_tilde = et.transpose();
    let f_tilde = -&b0 - &e_tilde * &qtf;
    let p = n - k;
    let (x, status, iterations) = if f_tilde.iter().all(|v| *v <= 0.0) {
        // x = 0 satisfies every inequality: the unconstrained-in-sign solution is feasible.
        (DVector::zeros(p), NnlsStatus::Converged, 0)
    } else {
        let mat = DMatrix::from_fn(p + 1, n, |row, col| if row < p { e_tilde[(col, row)] } else { f_tilde[col] });
        let mut rhs = vec![0.0; p + 1];
        rhs[p] = 1.0;
        let u = nnls_design(&mat, &rhs, opts)?;
        let res = &mat * DVector::from_column_slice(&u.coeffs) - DVector::from_column_slice(&rhs);
        // r = 0 (to rounding): eₙ₊₁ lies in the cone of the constraints — infeasible.
        if res[p].abs() <= 1e-12 {
            return Err(SbfError::InvalidParameter {
                name: "equality constraints",
                value: res[p],
                reason: "no non-negative coefficients satisfy them (the value is the least-distance residual)",
            });
        }
        (DVector::from_fn(p, |i, _| -res[i] / res[p]), u.status, u.iterations)
    };
    // b = b₀ + Z R⁻¹x + Z R⁻¹Qᵀf: the last two cancel where the inequalities bind, so a
    // coefficient within rounding of their size (1e-10 of the largest term: ε times the
    // conditioning these fits meet, with room) is zero, of either sign.
    let inv_r = |v: DVector<f64>| r.solve_upper_triangular(&v).expect("R is invertible: E has full column rank");
    let (bx, bq) = (&z * inv_r(x), &z * inv_r(qtf));
    let norm = |v: &DVector<f64>| v.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    let floor = 1e-10 * norm(&b0).max(norm(&bx)).max(norm(&bq));
    let mut b: Vec<f64> = (b0 + bx + bq).iter().map(|v| if v.abs() <= floor { 0.0 } else { *v }).collect();
    let (refined, steps) = refine(g, m, c, d, &b, opts.max_iterations.unwrap_or(3 * n + 30));
    if let Some(exact) = refined {
        b = exact;
    }
    let iterations = iterations + steps;
    let (kkt_residual, multipliers) = kkt(g, m, c, &b);
    let cb = c * DVector::from_column_slice(&b);
    let cnorm = (0..k).map(|i| c.row(i).iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
    let dnorm = d.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let bnorm = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let equality_residual = (0..k).map(|i| (cb[i] - d[i]).abs()).fold(0.0, f64::max) / dnorm.max(cnorm * bnorm).max(f64::MIN_POSITIVE);
    Ok(NnlsEqSolution { coeffs: b, status, iterations, kkt_residual, equality_residual, multipliers })
}

/// The equality-constrained minimiser on the support `p` (the KKT system
/// [G_PP C_Pᵀ; C_P 0][b_P; λ] = [m_P; d] by LU): b (zero off p) and λ; None where the system
/// is singular (fewer or dependent constraint columns on p).
fn solve_on_support(g: &DMatrix<f64>, m: &[f64], c: &DMatrix<f64>, d: &[f64], p: &[usize]) -> Option<(Vec<f64>, DVector<f64>)> {
    let (q, k, n) = (p.len(), c.nrows(), m.len());
    if q < k {
        return None;
    }
    let kkt = DMatrix::from_fn(q + k, q + k, |r, s| match (r < q, s < q) {
        (true, true) => g[(p[r], p[s])],
        (true, false) => c[(s - q, p[r])],
        (false, true) => c[(r - q, p[s])],
        (false, false) => 0.0,
    });
    let rhs = DVector::from_fn(q + k, |r, _| if r < q { m[p[r]] } else { d[r - q] });
    let x = kkt.lu().solve(&rhs)?;
    if x.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut b = vec![0.0; n];
    for (a, &i) in p.iter().enumerate() {
        b[i] = x[a];
    }
    // The system's λ is the multiplier of −C b = −d in ½bᵀGb − mᵀb + λᵀ(C b − d)'s form used
    // by [`kkt`]: G b − m + Cᵀλ = 0 on p.
    Some((b, -x.rows(q, k).into_owned()))
}

/// The LDP's answer carries the rounding of the terms it cancels (≈ cond(G)·ε relative,
/// more where it squares the conditioning): a primal active-set iteration from it (Lawson
/// and Hanson's NNLS loop with the equality-constrained solve on the support; Nocedal and
/// Wright 2006, §16.5) ends on the exact minimiser of its support. From b (equalities met
/// to rounding, b ≥ 0 after the rounding-level negatives are dropped): solve on the support;
/// where that leaves a coefficient ≤ 0, step towards it until the first reaches zero and
/// drop it; else add the coefficient whose multiplier μᵢ = (G b − m + Cᵀλ)ᵢ is most negative,
/// until none is. Returns the refined b (None where the support's system is singular) and
/// the solves taken.
fn refine(g: &DMatrix<f64>, m: &[f64], c: &DMatrix<f64>, d: &[f64], start: &[f64], cap: usize) -> (Option<Vec<f64>>, usize) {
    let n = m.len();
    let mut b: Vec<f64> = start.iter().map(|v| v.max(0.0)).collect();
    let mut passive: Vec<bool> = b.iter().map(|v| *v > 0.0).collect();
    let scale = m.iter().fold(0.0f64, |s, v| s.max(v.abs())).max(f64::MIN_POSITIVE);
    for step in 1..=cap {
        let p: Vec<usize> = (0..n).filter(|i| passive[*i]).collect();
        let Some((z, lambda)) = solve_on_support(g, m, c, d, &p) else { return (None, step) };
        if p.iter().all(|&i| z[i] > 0.0) {
            b = z;
            let grad = g * DVector::from_column_slice(&b) - DVector::from_column_slice(m);
            let mu = grad - c.transpose() * &lambda;
            let enter = (0..n).filter(|i| !passive[*i] && mu[*i] < -1e-12 * scale).min_by(|a, c| mu[*a].total_cmp(&mu[*c]));
            match enter {
                Some(i) => passive[i] = true,
                None => return (Some(b), step),
            }
            continue;
        }
        // Step from b towards z until the first passive coefficient reaches zero.
        let mut alpha = 1.0f64;
        let mut leave = None;
        for &i in &p {
            if z[i] <= 0.0 {
                let t = if b[i] - z[i] > 0.0 { b[i] / (b[i] - z[i]) } else { 0.0 };
                if t < alpha {
                    alpha = t;
                    leave = Some(i);
                }
            }
        }
        for i in 0..n {
            b[i] += alpha * (z[i] - b[i]);
        }
        if let Some(i) = leave {
            b[i] = 0.0;
            passive[i] = false;
        }
        for &i in &p {
            if b[i] <= 0.0 {
                b[i] = 0.0;
                passive[i] = false;
            }
        }
    }
    (None, cap)
}

/// The KKT residual of b and the equalities' multipliers (see [`NnlsEqSolution`]): the
/// multipliers that best satisfy G b − m + Cᵀλ = μ with μᵢ ≥ 0 where bᵢ = 0 and μᵢ = 0 where
/// bᵢ > 0 — λ = λ⁺ − λ⁻ and those μᵢ as the non-negative unknowns of one NNLS (several λ fit
/// when fewer coefficients than rows are positive: the sign conditions pick among them) —
/// and what is left of the equation.
fn kkt(g: &DMatrix<f64>, m: &[f64], c: &DMatrix<f64>, b: &[f64]) -> (f64, Vec<f64>) {
    let (n, k) = (m.len(), c.nrows());
    let bv = DVector::from_column_slice(b);
    let grad = g * &bv - DVector::from_column_slice(m);
    let active: Vec<usize> = (0..n).filter(|i| b[*i] <= 0.0).collect();
    let cols = 2 * k + active.len();
    let a = DMatrix::from_fn(n, cols, |i, j| match j {
        j if j < k => c[(j, i)],
        j if j < 2 * k => -c[(j - k, i)],
        j => -f64::from(u8::from(active[j - 2 * k] == i)),
    });
    let rhs: Vec<f64> = grad.iter().map(|v| -v).collect();
    let (lambda, left) = match nnls_design(&a, &rhs, NnlsOptions::default()) {
        Ok(u) => {
            let r = &a * DVector::from_column_slice(&u.coeffs) + &grad;
            ((0..k).map(|j| u.coeffs[j] - u.coeffs[k + j]).collect(), r.iter().fold(0.0f64, |s, v| s.max(v.abs())))
        }
        Err(_) => (vec![0.0; k], f64::INFINITY),
    };
    let gnorm = (0..n).map(|i| g.row(i).iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
    let mnorm = m.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let bnorm = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let scale = mnorm.max(gnorm * bnorm).max(f64::MIN_POSITIVE);
    let negative = b.iter().fold(0.0f64, |s, v| s.max(-v)) * gnorm;
    (left.max(negative) / scale, lambda)
}
