//! NNLS under equality constraints (`sbf::solve::nnls_gram_eq`) against a closed form (one
//! source between two SG lobes, the irradiance at the normal pinned), against an
//! independent exact method (every support set's equality-constrained KKT system), against
//! scipy (values pinned by `tests/generators/nnls_eq_scipy.py`), and on bad input.
//!
//! Mutations tried (2026-12-06; each fails at least one test here): the equality dropped
//! (d taken as 0: all three tests), its sign flipped (all three), the least-distance
//! solution's sign flipped (x = +r/rₙ₊₁: enumeration and bad input), the active-set
//! refinement left out (the LDP's rounding: enumeration), the refinement's multiplier sign
//! flipped (enumeration). The refinement's right-hand side d scaled by 1.02 fails
//! `matches_scipy`; the elimination's particular point b₀ scaled by 1.02 passes every test,
//! as it should: the refinement re-solves the support's KKT system from the true d.

use sbf::nalgebra::{DMatrix, DVector};
use sbf::sampling::Pcg32;
use sbf::solve::{nnls_gram, nnls_gram_eq, NnlsOptions, NnlsStatus};
use std::f64::consts::PI;

fn gaussian(rng: &mut Pcg32) -> f64 {
    let u1 = rng.next_f64().max(1e-300);
    let u2 = rng.next_f64();
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

/// ½bᵀGb − mᵀb
fn objective(g: &DMatrix<f64>, m: &[f64], b: &[f64]) -> f64 {
    let bv = DVector::from_column_slice(b);
    0.5 * bv.dot(&(g * &bv)) - DVector::from_column_slice(m).dot(&bv)
}

/// The SG lobe e^{λ(μ·ω − 1)}.
fn sg(axis: [f64; 3], lambda: f64, w: [f64; 3]) -> f64 {
    (lambda * (axis[0] * w[0] + axis[1] * w[1] + axis[2] * w[2] - 1.0)).exp()
}

/// One delta source between two SG lobes (λ 6, axes 35° either side of the normal +Z in
/// the xz plane), the source 20° from the normal towards the first lobe, power Φ = 2.
/// Gram and moments in closed form: ∫G_iG_j dω = 4π e^{−2λ} sinh‖λ(μ_i + μ_j)‖ / ‖λ(μ_i + μ_j)‖,
/// m_i = Φ G_i(ω_s). The constraint: the fit's E/π at the normal equals the source's,
/// Φ cos 20° / π, with c_i = (1/π)∫_H G_i cos θ dω by a midpoint rule (400 × 800 cells; its
/// error only changes the problem, not the oracle). On the line c·b = d the objective is a
/// parabola in b₁: its vertex, clamped to the segment where both b ≥ 0, is the solution —
/// written here. Tolerance: cond(G) ≈ 3 and the LDP's Cholesky and QR in f64: 1e-10
/// relative (ε × cond × a few hundred flops).
#[test]
fn one_source_between_two_lobes_keeps_its_irradiance() {
    let lambda = 6.0;
    let t = 35f64.to_radians();
    let axes = [[t.sin(), 0.0, t.cos()], [-t.sin(), 0.0, t.cos()]];
    let s = 20f64.to_radians();
    let ws = [s.sin(), 0.0, s.cos()];
    let phi = 2.0;
    let gram = |i: usize, j: usize| {
        let v: Vec<f64> = (0..3).map(|c| lambda * (axes[i][c] + axes[j][c])).collect();
        let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        4.0 * PI * (-2.0 * lambda).exp() * r.sinh() / r
    };
    let g = DMatrix::from_fn(2, 2, gram);
    let m: Vec<f64> = (0..2).map(|i| phi * sg(axes[i], lambda, ws)).collect();
    let (nt, np) = (400, 800);
    let mut c = [0.0; 2];
    for it in 0..nt {
        let th = (it as f64 + 0.5) * 0.5 * PI / nt as f64;
        for ip in 0..np {
            let ph = (ip as f64 + 0.5) * 2.0 * PI / np as f64;
            let w = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
            let dw = th.sin() * (0.5 * PI / nt as f64) * (2.0 * PI / np as f64);
            for (i, ci) in c.iter_mut().enumerate() {
                *ci += sg(axes[i], lambda, w) * th.cos() * dw / PI;
            }
        }
    }
    let d = phi * s.cos() / PI;
    // The closed form on the line b(s) = (s, (d − c₁s)/c₂), direction v = (1, −c₁/c₂).
    let v = [1.0, -c[0] / c[1]];
    let at0 = [0.0, d / c[1]];
    let grad0: Vec<f64> = (0..2).map(|i| g[(i, 0)] * at0[0] + g[(i, 1)] * at0[1] - m[i]).collect();
    let gv: Vec<f64> = (0..2).map(|i| g[(i, 0)] * v[0] + g[(i, 1)] * v[1]).collect();
    let vertex = -(v[0] * grad0[0] + v[1] * grad0[1]) / (v[0] * gv[0] + v[1] * gv[1]);
    let s_star = vertex.clamp(0.0, d / c[0]);
    let want = [s_star, (d - c[0] * s_star) / c[1]];

    let cm = DMatrix::from_row_slice(1, 2, &c);
    let sol = nnls_gram_eq(&g, &m, &cm, &[d], NnlsOptions::default()).unwrap();
    let plain = nnls_gram(&g, &m, NnlsOptions::default()).unwrap();
    let irr = |b: &[f64]| c[0] * b[0] + c[1] * b[1];
    println!(
        "E/π of the source {d:.6}; plain NNLS {:.6} (×{:.4}); constrained {:.6}; b = {:?} (closed form {want:?}); KKT {:.2e}, equality {:.2e}",
        irr(&plain.coeffs),
        irr(&plain.coeffs) / d,
        irr(&sol.coeffs),
        sol.coeffs,
        sol.kkt_residual,
        sol.equality_residual
    );
    // The case is one the constraint changes: plain NNLS misses the source's irradiance.
    assert!((irr(&plain.coeffs) / d - 1.0).abs() > 0.01, "plain NNLS already keeps E/π: the test would not see the constraint");
    let scale = want[0].abs().max(want[1].abs());
    for i in 0..2 {
        assert!((sol.coeffs[i] - want[i]).abs() <= 1e-10 * scale, "b{i} = {} vs closed form {}", sol.coeffs[i], want[i]);
    }
    assert!((irr(&sol.coeffs) - d).abs() <= 1e-12 * d);
    assert_eq!(sol.status, NnlsStatus::Converged);
    assert!(sol.kkt_residual <= 1e-12 && sol.equality_residual <= 1e-14);
}

/// The oracle: for every support set P, the equality-constrained minimiser on P — the KKT
/// system [G_PP C_Pᵀ; C_P 0][b_P; λ] = [m_P; d] by SVD (pseudo-inverse) — kept where it
/// satisfies C b = d and b_P ≥ 0; the best objective among those. The problem is convex and
/// its optimum is the equality-constrained minimiser on its own support, so it is among them.
fn enumerate(g: &DMatrix<f64>, m: &[f64], c: &DMatrix<f64>, d: &[f64]) -> Option<(f64, Vec<f64>)> {
    let (n, k) = (m.len(), c.nrows());
    let mut best: Option<(f64, Vec<f64>)> = None;
    for mask in 1u32..(1 << n) {
        let p: Vec<usize> = (0..n).filter(|i| mask & (1 << i) != 0).collect();
        let q = p.len();
        let kkt = DMatrix::from_fn(q + k, q + k, |r, s| match (r < q, s < q) {
            (true, true) => g[(p[r], p[s])],
            (true, false) => c[(s - q, p[r])],
            (false, true) => c[(r - q, p[s])],
            (false, false) => 0.0,
        });
        let rhs = DVector::from_fn(q + k, |r, _| if r < q { m[p[r]] } else { d[r - q] });
        let Ok(x) = kkt.clone().svd(true, true).solve(&rhs, 1e-12) else { continue };
        let mut b = vec![0.0; n];
        for (a, &i) in p.iter().enumerate() {
            b[i] = x[a];
        }
        let bmax = b.iter().fold(0.0f64, |s, v| s.max(v.abs())).max(1e-300);
        let cb = c * DVector::from_column_slice(&b);
        let eq = (0..k).map(|i| (cb[i] - d[i]).abs()).fold(0.0, f64::max);
        if b.iter().any(|v| *v < -1e-9 * bmax) || eq > 1e-9 * (1.0 + d.iter().fold(0.0f64, |s, v| s.max(v.abs()))) {
            continue;
        }
        let b: Vec<f64> = b.into_iter().map(|v| v.max(0.0)).collect();
        let f = objective(g, m, &b);
        if best.as_ref().is_none_or(|(bf, _)| f < *bf) {
            best = Some((f, b));
        }
    }
    best
}

/// ≥ 600 random problems, n from 3 to 9, one or two equality rows, G with condition
/// numbers log-uniform in [1, 1e6], m Gaussian, C Gaussian, d = C b_f for a non-negative
/// b_f with random zeros (feasible by construction). Against the enumeration: the optimum
/// value to 1e-8 relative plus the rounding floor of evaluating ½bᵀGb − mᵀb
/// (64·n·ε·(‖G‖‖b‖² + ‖m‖‖b‖), ‖b‖ at least b_f's unit scale); the coefficients to 1e-6 of
/// their largest, at least 1 (the solution
/// is unique: G is positive definite; both paths lose ≈ cond(G)·ε·(n² flops) ≤ 1e-8 relative,
/// the KKT system's SVD up to cond(KKT)·ε); every solve converged with KKT residual ≤ 1e-8
/// and equality residual within 16·n·ε·cond(G) relative (the solver restores C b = d on the
/// positive coefficients to the rounding of evaluating C b; where fewer coefficients than
/// rows are positive it cannot, and the rounding of the cancelled terms, ≈ cond(G)·ε, stays).
#[test]
fn matches_enumeration_of_support_sets() {
    let mut rng = Pcg32::new(61, 7);
    let (mut worst_kkt, mut worst_eq, mut worst_coef, mut count) = (0.0f64, 0.0f64, 0.0f64, 0);
    for trial in 0..640 {
        let n = 3 + (rng.next_u32() % 7) as usize;
        let k = 1 + (rng.next_u32() % 2) as usize;
        let q = DMatrix::from_fn(n, n, |_, _| gaussian(&mut rng)).qr().q();
        let cond = 10f64.powf(6.0 * rng.next_f64());
        let lam = DVector::from_fn(n, |i, _| cond.powf(-(i as f64) / (n - 1) as f64));
        let g = &q * DMatrix::from_diagonal(&lam) * q.transpose();
        let g = (&g + g.transpose()) * 0.5;
        let m: Vec<f64> = (0..n).map(|_| gaussian(&mut rng)).collect();
        let c = DMatrix::from_fn(k, n, |_, _| gaussian(&mut rng));
        let bf: Vec<f64> = (0..n).map(|_| if rng.next_f64() < 0.4 { 0.0 } else { rng.next_f64() }).collect();
        let d: Vec<f64> = (c.clone() * DVector::from_column_slice(&bf)).iter().copied().collect();
        let sol = nnls_gram_eq(&g, &m, &c, &d, NnlsOptions::default()).unwrap();
        let (fb, bb) = enumerate(&g, &m, &c, &d).expect("feasible by construction");
        let fs = objective(&g, &m, &sol.coeffs);
        let bn = bb.iter().chain(&sol.coeffs).fold(0.0f64, |a, v| a.max(v.abs()));
        let mn = m.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        // At least unit coefficients (b_f's scale): where the optimum is b = 0 the oracle's
        // own solve leaves rounding-level coefficients.
        let bn = bn.max(1.0);
        let eval_floor = 64.0 * f64::EPSILON * (n as f64) * (g.abs().max() * bn * bn + mn * bn);
        let what = format!("trial {trial} (n {n}, k {k}, cond {cond:.1e})");
        assert_eq!(sol.status, NnlsStatus::Converged, "{what}");
        assert!(sol.coeffs.iter().all(|v| *v >= 0.0 && v.is_finite()), "{what}: {:?}", sol.coeffs);
        assert!((fs - fb).abs() <= 1e-8 * fb.abs() + eval_floor, "{what}: objective {fs} vs enumeration {fb}");
        let coef = sol.coeffs.iter().zip(&bb).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / bn;
        assert!(
            coef <= 1e-6,
            "{what}: coefficients {:?} vs enumeration {bb:?}; objectives {fs:e} vs {fb:e}; KKT {:e}",
            sol.coeffs,
            sol.kkt_residual
        );
        assert!(sol.kkt_residual <= 1e-8, "{what}: KKT residual {:e}", sol.kkt_residual);
        let eq_tol = 16.0 * n as f64 * f64::EPSILON * cond.max(1.0);
        assert!(sol.equality_residual <= eq_tol, "{what}: equality residual {:e}", sol.equality_residual);
        worst_kkt = worst_kkt.max(sol.kkt_residual);
        worst_eq = worst_eq.max(sol.equality_residual);
        worst_coef = worst_coef.max(coef);
        count += 1;
    }
    println!("{count} problems: worst KKT residual {worst_kkt:.2e}, equality residual {worst_eq:.2e}, coefficient gap {worst_coef:.2e}");
    assert!(count >= 600);
}

/// Constraints no b ≥ 0 meets, dependent rows, k ≥ n, mismatched lengths, non-finite
/// entries and a Gram matrix that is not positive definite are errors naming the cause.
#[test]
fn bad_constraints_are_named() {
    let g = DMatrix::<f64>::identity(3, 3);
    let m = [1.0, 0.5, -0.2];
    let row = |v: &[f64]| DMatrix::from_row_slice(v.len() / 3, 3, v);
    let err = |c: &DMatrix<f64>, d: &[f64]| nnls_gram_eq(&g, &m, c, d, NnlsOptions::default()).unwrap_err().to_string();
    assert!(err(&row(&[1.0, 1.0, 1.0]), &[-1.0]).contains("no non-negative coefficients"));
    assert!(err(&row(&[1.0, -1.0, 0.0, -1.0, 1.0, 0.0]), &[1.0, -1.0]).contains("linearly dependent"));
    assert!(err(&row(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]), &[1.0, 1.0, 1.0]).contains("between 1 and n − 1 rows"));
    assert!(err(&row(&[1.0, 1.0, 1.0]), &[1.0, 2.0]).contains("constraint values"));
    assert!(err(&row(&[1.0, f64::NAN, 1.0]), &[1.0]).contains("non-finite"));
    let not_pd = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0]);
    let e = nnls_gram_eq(&not_pd, &m, &row(&[1.0, 1.0, 1.0]), &[1.0], NnlsOptions::default()).unwrap_err().to_string();
    assert!(e.contains("positive definite"), "{e}");
    // On the boundary: d = 0 with non-negative rows leaves only b = 0.
    let s = nnls_gram_eq(&g, &m, &row(&[1.0, 2.0, 0.5]), &[0.0], NnlsOptions::default()).unwrap();
    assert_eq!(s.coeffs, vec![0.0; 3]);
}

/// Four fixed problems (G = AᵀA + ridge·I) against scipy 1.17.1, pinned by
/// `sbf/tests/generators/nnls_eq_scipy.py`: Lawson & Hanson's weighting method
/// (`scipy.optimize.nnls` on [Lᵀ; wC] for w = 1e3, 1e4, 1e5, extrapolated to 1/w² → 0),
/// which the script checks against `scipy.optimize.minimize(method="SLSQP")` before printing.
/// The oracle's error: the extrapolation's remainder O(w⁻⁶) is negligible; the weighted
/// NNLS' rounding is ε · cond([Lᵀ; wC]) ≈ ε · w_max · √cond(G) relative — allowed ×4 here, plus
/// this solver's own 1e-10 (the closed-form test's bound). Plain NNLS (no row) misses every
/// problem's constraint, so a dropped equality fails.
#[test]
fn matches_scipy() {
    struct P {
        a: &'static [&'static [f64]],
        ridge: f64,
        m: &'static [f64],
        c: &'static [&'static [f64]],
        d: &'static [f64],
        scipy: &'static [f64],
    }
    let problems = [
        P {
            a: &[&[1.0, 0.6, 0.2, 0.0], &[0.0, 1.0, 0.5, 0.1], &[0.0, 0.0, 1.0, 0.4], &[0.0, 0.0, 0.0, 1.0], &[0.3, 0.3, 0.3, 0.3]],
            ridge: 0.0,
            m: &[2.0, 0.5, -0.3, 1.4],
            c: &[&[1.0, 1.0, 1.0, 1.0]],
            d: &[1.5],
            scipy: &[1.085253456215692e+00, 0.0, 0.0, 4.147465437843079e-01],
        },
        P {
            a: &[
                &[2.0, 0.1, 0.0, 0.3, 0.0],
                &[0.0, 1.5, 0.2, 0.0, 0.1],
                &[0.1, 0.0, 1.0, 0.2, 0.0],
                &[0.0, 0.3, 0.0, 0.8, 0.2],
                &[0.0, 0.0, 0.4, 0.0, 1.2],
                &[0.5, 0.5, 0.5, 0.5, 0.5],
            ],
            ridge: 0.0,
            m: &[1.0, -0.5, 0.8, 0.2, -0.1],
            c: &[&[0.2, 0.4, 0.6, 0.8, 1.0], &[1.0, -1.0, 0.5, 0.0, 0.3]],
            d: &[0.9, 0.1],
            scipy: &[0.0, 8.823998364633774e-02, 3.745546059787275e-01, 7.959528842887272e-01, 3.208935523246517e-03],
        },
        P {
            a: &[
                &[1.0, 0.98, 0.9, 0.7, 0.45, 0.2],
                &[0.2, 0.45, 0.7, 0.9, 0.98, 1.0],
                &[0.5, 0.6, 0.7, 0.7, 0.6, 0.5],
                &[0.0, 0.1, 0.0, 0.1, 0.0, 0.1],
                &[0.1, 0.0, 0.1, 0.0, 0.1, 0.0],
                &[0.3, 0.2, 0.1, 0.1, 0.2, 0.3],
                &[0.05, 0.0, 0.0, 0.0, 0.0, 0.05],
            ],
            ridge: 1e-4,
            m: &[1.2, 0.3, 1.3, 0.4, -0.2, 1.1],
            c: &[&[0.9, 0.7, 0.4, 0.4, 0.7, 0.9]],
            d: &[1.8],
            scipy: &[1.076911244430764e+00, 0.0, 0.0, 0.0, 0.0, 9.230887555692364e-01],
        },
        P {
            a: &[&[1.0, 0.5, 0.0], &[0.0, 1.0, 0.5], &[0.2, 0.0, 1.0]],
            ridge: 0.0,
            m: &[1.0, 1.0, -1.0],
            c: &[&[0.0, 0.0, 1.0]],
            d: &[0.25],
            scipy: &[7.142857142826560e-01, 4.142857142857145e-01, 2.499999999999999e-01],
        },
    ];
    for (i, p) in problems.iter().enumerate() {
        let n = p.m.len();
        let a = DMatrix::from_fn(p.a.len(), n, |r, c| p.a[r][c]);
        let g = a.transpose() * &a + DMatrix::identity(n, n) * p.ridge;
        let c = DMatrix::from_fn(p.c.len(), n, |r, k| p.c[r][k]);
        let sol = nnls_gram_eq(&g, p.m, &c, p.d, NnlsOptions::default()).unwrap();
        let sv = g.clone().svd(false, false).singular_values;
        let cond = sv.max() / sv.min();
        let scale = p.scipy.iter().fold(1.0f64, |s, v| s.max(v.abs()));
        let tol = 1e-10 + 4.0 * f64::EPSILON * 1e5 * cond.sqrt();
        let gap = sol.coeffs.iter().zip(p.scipy).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale;
        println!("problem {i}: cond(G) {cond:.2e}, gap to scipy {gap:.1e} (allowed {tol:.1e}), KKT {:.1e}", sol.kkt_residual);
        assert_eq!(sol.status, NnlsStatus::Converged, "problem {i}");
        assert!(gap <= tol, "problem {i}: {:?} vs scipy {:?}", sol.coeffs, p.scipy);
        assert!(sol.kkt_residual <= 1e-8, "problem {i}: KKT residual {:e}", sol.kkt_residual);
        // The equality matters: plain NNLS misses it by far more than the tolerance.
        let plain = nnls_gram(&g, p.m, NnlsOptions::default()).unwrap();
        let miss = (&c * DVector::from_column_slice(&plain.coeffs) - DVector::from_column_slice(p.d)).amax();
        assert!(miss > 0.1, "problem {i}: plain NNLS already meets the rows ({miss:e})");
    }
}
