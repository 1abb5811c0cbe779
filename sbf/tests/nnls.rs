//! NNLS (Lawson–Hanson) against brute-force enumeration of active sets.

use sbf::nalgebra::{DMatrix, DVector};
use sbf::sampling::Pcg32;
use sbf::solve::{nnls_design, nnls_gram, NnlsOptions, NnlsStatus};

fn gaussian(rng: &mut Pcg32) -> f64 {
    // Box–Muller.
    let u1 = rng.next_f64().max(1e-300);
    let u2 = rng.next_f64();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

fn random_orthogonal(rng: &mut Pcg32, n: usize) -> DMatrix<f64> {
    let a = DMatrix::from_fn(n, n, |_, _| gaussian(rng));
    a.qr().q()
}

/// ½bᵀGb − mᵀb
fn objective(g: &DMatrix<f64>, m: &[f64], b: &[f64]) -> f64 {
    let bv = DVector::from_column_slice(b);
    0.5 * bv.dot(&(g * &bv)) - DVector::from_column_slice(m).dot(&bv)
}

/// The oracle: for every subset P of indices, the unconstrained minimiser on P
/// (pseudo-inverse); keep the feasible ones (z ≥ 0) and return the best objective.
/// The NNLS optimum is among them (it is the unconstrained optimum on its support).
fn brute_force(g: &DMatrix<f64>, m: &[f64]) -> (f64, Vec<f64>) {
    let n = m.len();
    let mut best = (0.0, vec![0.0; n]); // P = ∅
    for mask in 1u32..(1 << n) {
        let p: Vec<usize> = (0..n).filter(|i| mask & (1 << i) != 0).collect();
        let gp = DMatrix::from_fn(p.len(), p.len(), |a, b| g[(p[a], p[b])]);
        let mp = DVector::from_fn(p.len(), |a, _| m[p[a]]);
        let eig = gp.clone().symmetric_eigen();
        let lmax = eig.eigenvalues.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut t = eig.eigenvectors.transpose() * &mp;
        for k in 0..p.len() {
            t[k] = if eig.eigenvalues[k] > 1e-13 * lmax { t[k] / eig.eigenvalues[k] } else { 0.0 };
        }
        let z = &eig.eigenvectors * t;
        let zmax = z.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if z.iter().any(|v| *v < -1e-9 * zmax) {
            continue;
        }
        let mut b = vec![0.0; n];
        for (k, &i) in p.iter().enumerate() {
            b[i] = z[k].max(0.0);
        }
        let f = objective(g, m, &b);
        if f < best.0 {
            best = (f, b);
        }
    }
    best
}

/// ≥ 1000 random problems, n ≤ 10: Gram matrices with condition numbers log-uniform
/// in [1, 1e10], and design problems with a duplicated column (singular G).
/// Tolerances: the optimum value agrees to 1e-8 relative plus the rounding floor of
/// evaluating ½bᵀGb − mᵀb itself (64·n·ε·(‖G‖‖b‖² + ‖m‖‖b‖)), the KKT residual of
/// every converged solve is ≤ 1e-9, and coefficients agree to 1e-7 relative where
/// cond ≤ 1e6 (unique solution, error ≤ cond·ε·‖b‖).
#[test]
fn nnls_matches_brute_force() {
    let mut rng = Pcg32::new(2024, 3);
    let (mut worst_kkt, mut worst_obj, mut max_iters, mut count) = (0.0f64, 0.0f64, 0usize, 0);
    for trial in 0..1200 {
        let n = 1 + (rng.next_u32() % 10) as usize;
        let duplicated = trial % 4 == 3 && n >= 2;
        let (g, m, cond) = if duplicated {
            let k = n + 5;
            let mut a = DMatrix::from_fn(k, n, |_, _| gaussian(&mut rng));
            let (i, j) = (0, 1 + (rng.next_u32() as usize % (n - 1)));
            let col = a.column(i).clone_owned();
            a.set_column(j, &col);
            let y = DVector::from_fn(k, |_, _| gaussian(&mut rng));
            let g = a.transpose() * &a;
            let m: Vec<f64> = (a.transpose() * &y).iter().copied().collect();
            // The design form on the same (rank-deficient) problem reaches the same
            // residual ‖Ab − y‖ as the Gram form: duplicated columns make b non-unique
            // but the fit unique.
            let yv: Vec<f64> = y.iter().copied().collect();
            let d = nnls_design(&a, &yv, NnlsOptions::default()).unwrap();
            let s = nnls_gram(&g, &m, NnlsOptions::default()).unwrap();
            let fit = |b: &[f64]| (&a * DVector::from_column_slice(b)).iter().copied().collect::<Vec<f64>>();
            let (fd, fs) = (fit(&d.coeffs), fit(&s.coeffs));
            let diff = fd.iter().zip(&fs).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
            assert!(d.status == NnlsStatus::Converged && diff < 1e-9, "trial {trial}: design vs Gram fit differ by {diff:e}");
            (g, m, f64::INFINITY)
        } else {
            let q = random_orthogonal(&mut rng, n);
            let c = 10f64.powf(10.0 * rng.next_f64());
            let lam = DVector::from_fn(n, |i, _| if n == 1 { 1.0 } else { c.powf(-(i as f64) / (n - 1) as f64) });
            let g = &q * DMatrix::from_diagonal(&lam) * q.transpose();
            let g = (&g + g.transpose()) * 0.5;
            let m: Vec<f64> = (0..n).map(|_| gaussian(&mut rng)).collect();
            (g, m, c)
        };
        let sol = nnls_gram(&g, &m, NnlsOptions::default()).unwrap();
        assert_eq!(sol.status, NnlsStatus::Converged, "trial {trial} (n={n}, cond={cond:e}) hit the cap");
        assert!(sol.coeffs.iter().all(|v| *v >= 0.0 && v.is_finite()), "trial {trial}: {:?}", sol.coeffs);
        assert!(sol.kkt_residual <= 1e-9, "trial {trial} (n={n}, cond={cond:e}): KKT residual {:e}", sol.kkt_residual);
        let (fb, bb) = brute_force(&g, &m);
        let fs = objective(&g, &m, &sol.coeffs);
        // Evaluating f in floating point cancels terms of size ‖G‖‖b‖² and ‖m‖‖b‖:
        // its own rounding error is ~n·ε times those, which dominates for cond ≳ 1e8.
        let bn = bb.iter().chain(&sol.coeffs).fold(0.0f64, |a, v| a.max(v.abs()));
        let mn = m.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let gn = g.abs().max();
        let eval_floor = 64.0 * f64::EPSILON * (n as f64) * (gn * bn * bn + mn * bn);
        let scale = fb.abs().max(1e-300);
        let rel_obj = (fs - fb) / scale;
        assert!((fs - fb).abs() <= 1e-8 * scale + eval_floor, "trial {trial} (n={n}, cond={cond:e}): objective {fs} vs brute force {fb}");
        if cond <= 1e6 {
            let bmax = bb.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-300);
            let diff = sol.coeffs.iter().zip(&bb).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(diff <= 1e-7 * bmax, "trial {trial}: coefficients {:?} vs brute force {bb:?}", sol.coeffs);
        }
        worst_kkt = worst_kkt.max(sol.kkt_residual);
        worst_obj = worst_obj.max(rel_obj.abs());
        max_iters = max_iters.max(sol.iterations);
        count += 1;
    }
    println!("{count} problems: worst KKT residual {worst_kkt:.2e}, worst objective gap {worst_obj:.2e}, most iterations {max_iters}");
    assert!(count >= 1000);
}

/// The design form agrees with the Gram form on the same problem (normal equations).
#[test]
fn nnls_design_matches_gram_form() {
    let mut rng = Pcg32::new(77, 1);
    for _ in 0..200 {
        let n = 2 + (rng.next_u32() % 8) as usize;
        let k = n + 10;
        let a = DMatrix::from_fn(k, n, |_, _| gaussian(&mut rng));
        let y: Vec<f64> = (0..k).map(|_| gaussian(&mut rng)).collect();
        let d = nnls_design(&a, &y, NnlsOptions::default()).unwrap();
        let g = a.transpose() * &a;
        let m: Vec<f64> = (a.transpose() * DVector::from_column_slice(&y)).iter().copied().collect();
        let s = nnls_gram(&g, &m, NnlsOptions::default()).unwrap();
        assert_eq!(d.status, NnlsStatus::Converged);
        assert!(d.kkt_residual <= 1e-9, "design KKT {:e}", d.kkt_residual);
        let diff = d.coeffs.iter().zip(&s.coeffs).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        // Random Gaussian designs have cond(A) ≲ 30: agreement to ~1e-13 expected.
        assert!(diff < 1e-9, "{:?} vs {:?}", d.coeffs, s.coeffs);
    }
}

/// An adversarial case built to need many steps: G = I with m_i decreasing and a
/// coupling that makes each entering index push the previous ones out again.
/// With a tiny cap the solver stops, says so, and returns a feasible point with
/// its KKT residual; with the default cap the same problem converges.
#[test]
fn nnls_iteration_cap_is_reported() {
    let n = 10;
    // Strongly coupled, all-positive-gradient problem: every index enters, several
    // leave again.
    let g = DMatrix::from_fn(n, n, |i, j| if i == j { 1.0 } else { 0.9f64.powi((i as i32 - j as i32).abs()) });
    let m: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 1.0 + 0.1 * i as f64 } else { 0.95 }).collect();
    let full = nnls_gram(&g, &m, NnlsOptions::default()).unwrap();
    assert_eq!(full.status, NnlsStatus::Converged);
    assert!(full.iterations > 3, "needs several steps ({})", full.iterations);
    let capped = nnls_gram(&g, &m, NnlsOptions { max_iterations: Some(2), ..NnlsOptions::default() }).unwrap();
    assert_eq!(capped.status, NnlsStatus::IterationCap);
    assert_eq!(capped.iterations, 2);
    assert!(capped.coeffs.iter().all(|v| *v >= 0.0 && v.is_finite()));
    assert!(capped.kkt_residual > 1e-6, "a capped solve must report how far it is from optimal: {:e}", capped.kkt_residual);
}

#[test]
fn nnls_bad_input() {
    let g = DMatrix::identity(3, 3);
    assert!(nnls_gram(&g, &[1.0, 2.0], NnlsOptions::default()).is_err());
    assert!(nnls_gram(&g, &[1.0, f64::NAN, 0.0], NnlsOptions::default()).is_err());
    let z = nnls_gram(&g, &[0.0; 3], NnlsOptions::default()).unwrap();
    assert_eq!(z.coeffs, vec![0.0; 3]);
    let neg = nnls_gram(&g, &[-1.0, -2.0, -3.0], NnlsOptions::default()).unwrap();
    assert_eq!(neg.coeffs, vec![0.0; 3]);
    assert_eq!(neg.status, NnlsStatus::Converged);
}
