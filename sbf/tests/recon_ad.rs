//! Ambient Dice SRBF irradiance: [Roughton19 eq. 8.11]/8.13 against an independent
//! quadrature, the quadratic fit (8.14), continuity, and the constant-radiance identity.
use crate::common;

use sbf::basis::ambient_dice::srbf_lobe;
use sbf::quadrature::gauss_legendre;
use sbf::recon::ambient_dice::*;
use sbf::{AmbientDiceSrbf, Basis};
use std::f64::consts::PI;

/// Oracle: E/π = (1/π)∫ B(ω·p)·max(0, ω·n) dω in polar coordinates (t, φ) about the
/// lobe axis p. The φ-integral of max(0, A + B cos φ), A = cos t cos θ,
/// B = sin t sin θ, has the closed form 2πA (A ≥ |B|), 0 (A ≤ −|B|), else
/// 2(A·acos(−A/B) + √(B² − A²)). The remaining t-integral over [0, π/2] (the lobe's
/// support) is split at its kinks (t = |π/2 − θ| and π/2 − |θ − π/2|…) and integrated
/// with 40-point Gauss–Legendre per piece: accurate to ~1e-13.
fn oracle(theta: f64) -> f64 {
    let (st, ct) = theta.sin_cos();
    let ring = |t: f64| {
        let a = t.cos() * ct;
        let b = (t.sin() * st).abs();
        if a >= b {
            2.0 * PI * a
        } else if a <= -b {
            0.0
        } else {
            2.0 * (a * (-a / b).acos() + (b * b - a * a).sqrt())
        }
    };
    let f = |t: f64| srbf_lobe(t.cos()) * t.sin() * ring(t) / PI;
    let mut cuts = vec![0.0, 0.5 * PI];
    for k in [(0.5 * PI - theta).abs(), theta - 0.5 * PI, 1.5 * PI - theta] {
        if k > 0.0 && k < 0.5 * PI {
            cuts.push(k);
        }
    }
    cuts.sort_by(f64::total_cmp);
    let (x, w) = gauss_legendre(40);
    let mut total = 0.0;
    for c in cuts.windows(2) {
        let (a, b) = (c[0], c[1]);
        for (xi, wi) in x.iter().zip(&w) {
            total += 0.5 * (b - a) * wi * f(a + 0.5 * (b - a) * (xi + 1.0));
        }
    }
    total
}

/// Roughton's eq. 8.13 (θ < π/2) and eq. 8.11 (θ ≥ π/2) exactly as printed in our
/// copy of the seed (the arctangent simplified to π/4 − θ/2, an identity).
fn seed_as_printed(t: f64) -> f64 {
    let (s, c) = t.sin_cos();
    if t < 0.5 * PI {
        let c2 = c * c;
        3.0 * c2 / 40.0 + 41.0 * c2.powi(2) / 192.0 + 63.0 * c2.powi(3) / 320.0 - 15.0 * c2.powi(4) / 32.0
            + 35.0 * c2.powi(5) / 192.0
            + (31.0 * c2 / 120.0 - 23.0 * c2.powi(2) / 45.0 - 73.0 * c2.powi(3) / 120.0 + 17.0 * c2.powi(4) / 12.0 - 5.0 * c2.powi(5) / 9.0)
                / PI
            + (31.0 * t * c * s / 120.0 + t * c2 * c * s / 24.0) / PI
            + 19.0 / 320.0
    } else {
        let at = 0.25 * PI - 0.5 * t;
        let cs = |k: f64| (k * t).cos();
        let sn = |k: f64| (k * t).sin();
        1167.0 * cs(6.0) / 163840.0 - 313.0 * cs(4.0) / 61440.0 - 8959.0 * cs(2.0) / 245760.0 + 5.0 * cs(8.0) / 49152.0
            - 35.0 * cs(10.0) / 98304.0
            + 67.0 * sn(2.0) / 960.0
            + sn(4.0) / 384.0
            + (113.0 * cs(2.0) / 5760.0 - cs(4.0) / 576.0 - 53.0 * cs(6.0) / 2560.0 - cs(8.0) / 4608.0
                + 5.0 * cs(10.0) / 4608.0
                + 1.0 / 512.0)
                / PI
            + (67.0 * at * sn(2.0) / 240.0 + at * sn(4.0) / 96.0) / PI
            + 2841.0 / 81920.0
    }
}

/// The analytic lobe irradiance equals the independent quadrature to 1e-6
/// (acceptance) across θ ∈ [0, π]; measured agreement is ~1e-16. Roughton's printed
/// closed forms are measured too: they deviate by ~2.0e-3 between the anchors
/// θ = 0, π/2, π (documented in `sbf::recon::ambient_dice`).
#[test]
fn analytic_lobe_irradiance_matches_quadrature() {
    let (mut worst, mut seed_worst) = (0.0f64, 0.0f64);
    for k in 0..=2000 {
        let theta = PI * k as f64 / 2000.0;
        let q = oracle(theta);
        worst = worst.max((lobe_irradiance(theta) - q).abs());
        seed_worst = seed_worst.max((seed_as_printed(theta) - q).abs());
    }
    println!("max |quartic − quadrature| = {worst:.2e}; max |[Roughton19 eq. 8.11]/8.13 as printed − quadrature| = {seed_worst:.2e}");
    assert!(worst < 1e-6, "{worst:e}");
    assert!(seed_worst > 1e-3 && seed_worst < 3e-3, "the printed formula's known deviation changed: {seed_worst:e}");
    for theta in [0.0, 0.5 * PI, PI] {
        assert!((seed_as_printed(theta) - lobe_irradiance(theta)).abs() < 1e-12, "anchors agree at θ = {theta}");
    }
    // Closed-form anchors: θ = 0 gives 2∫(0.35c² + 0.25c⁴)c dc = 0.258333…, θ = π gives 0.
    assert!((lobe_irradiance(0.0) - (0.35 / 2.0 + 0.25 / 3.0)).abs() < 1e-15);
    assert!(lobe_irradiance(PI).abs() < 1e-15);
}

/// θ = π/2 is where Roughton's two printed closed forms (eq. 8.13 below, 8.11 above) hand
/// over: they must meet there in value and slope — an identity of Roughton's formulas that
/// a transcription error breaks. And the quartic's slope there, dE/dθ = −sinθ·dE/dc =
/// −31/240 at c = 0, must equal the central difference of the independent quadrature
/// (error model: O(h²·E‴) ≈ 1e-9 at h = 1e-4, plus 2·1e-13/h of quadrature noise; bar 1e-7).
#[test]
fn closed_forms_hand_over_at_half_pi() {
    let e = 1e-9;
    let (lo, hi) = (seed_as_printed(0.5 * PI - e), seed_as_printed(0.5 * PI + e));
    assert!((lo - hi).abs() < 1e-8, "seed branches jump by {:e}", (lo - hi).abs());
    let h = 1e-5;
    let slope_lo = (seed_as_printed(0.5 * PI - e) - seed_as_printed(0.5 * PI - e - h)) / h;
    let slope_hi = (seed_as_printed(0.5 * PI + e + h) - seed_as_printed(0.5 * PI + e)) / h;
    assert!((slope_lo - slope_hi).abs() < 1e-4, "seed branch slopes {slope_lo} vs {slope_hi}");
    let h = 1e-4;
    let oracle_slope = (oracle(0.5 * PI + h) - oracle(0.5 * PI - h)) / (2.0 * h);
    let quartic_slope = (lobe_irradiance(0.5 * PI + h) - lobe_irradiance(0.5 * PI - h)) / (2.0 * h);
    assert!((oracle_slope + 31.0 / 240.0).abs() < 1e-7, "quadrature slope {oracle_slope} vs −31/240");
    assert!((quartic_slope - oracle_slope).abs() < 1e-7, "quartic slope {quartic_slope} vs quadrature {oracle_slope}");
}

/// Quadratic fit error vs the analytic integral over c = cos θ ∈ [−1, 1]: Roughton's
/// minimax quadratic (our default) and Listing 8.1's constants stay within 1e-3
/// (acceptance); eq. 8.14 as printed reaches 1.22e-3; and a
/// least-squares quadratic on a uniform c grid is printed for comparison (fitgen will
/// own the committed re-fits).
#[test]
fn quadratic_fit_error() {
    let grid: Vec<f64> = (0..=4000).map(|k| -1.0 + 2.0 * k as f64 / 4000.0).collect();
    let exact: Vec<f64> = grid.iter().map(|c| lobe_irradiance(c.acos())).collect();
    let max_err = |p: &[f64; 3]| grid.iter().zip(&exact).map(|(c, e)| (lobe_irradiance_fit(p, *c) - e).abs()).fold(0.0, f64::max);
    let seed = max_err(&DIFFUSE_FIT_EQ_8_14);
    let listing = max_err(&DIFFUSE_FIT_LISTING_8_1);
    let minimax = max_err(&DIFFUSE_FIT_MINIMAX);
    // Least-squares quadratic in c on the same grid (normal equations, 3×3).
    let mut ata = [[0.0f64; 3]; 3];
    let mut aty = [0.0f64; 3];
    for (c, e) in grid.iter().zip(&exact) {
        let row = [1.0, *c, c * c];
        for i in 0..3 {
            aty[i] += row[i] * e;
            for j in 0..3 {
                ata[i][j] += row[i] * row[j];
            }
        }
    }
    let m = sbf::nalgebra::Matrix3::from_fn(|i, j| ata[i][j]);
    let p = m.lu().solve(&sbf::nalgebra::Vector3::from(aty)).unwrap();
    let refit = [p[0], p[1], p[2]];
    let ours = max_err(&refit);
    println!(
        "max abs error (E/π): eq. 8.14 {seed:.2e}, Listing 8.1 {listing:.2e}, minimax {minimax:.2e}, LS re-fit {ours:.2e} with {refit:.5?}"
    );
    // The minimax quadratic's error is exactly 1/1536 (equioscillation of T₄/8).
    assert!((minimax - 1.0 / 1536.0).abs() < 1e-12, "minimax error {minimax:e}");
    assert!(listing <= 1e-3, "Listing 8.1 max error {listing:e}");
    // Eq. 8.14 as printed overshoots at c = 1 by 1.22e-3 (0.25955 vs 0.25833): above
    // the 1e-3 bar, so the library's default fit is the minimax one; pinned here.
    assert!(seed > 1e-3 && seed < 1.3e-3, "eq. 8.14 max error {seed:e}");
    // LS in c weights the ends less than minimax: ~1.2e-3 is expected (quartic term
    // 1/192 times the max of c⁴'s degree-4 Legendre residual, 8/35).
    assert!(ours < 1.3e-3, "LS quadratic fit max error {ours:e}");
}

/// Constant radiance L (all 12 coefficients = L, a partition of unity) gives E/π = L
/// at every normal, exactly with the analytic integral (the 12 lobe integrals sum to
/// 1: icosahedral symmetry) and within the fit's error with eq. 8.14.
#[test]
fn constant_radiance_gives_e_over_pi_equal_l() {
    let ad = AmbientDiceSrbf::twelve();
    for n in common::random_directions(71, 2000) {
        let e = irradiance(ad.lobes(), &[2.5; 12], n);
        assert!((e - 2.5).abs() < 1e-12, "{n}: {e}");
        let f = irradiance_fit(ad.lobes(), &[2.5; 12], n, &DIFFUSE_FIT_EQ_8_14);
        assert!((f - 2.5).abs() < 2.5 * 12.0 * 1e-3, "{n}: {f}");
    }
    assert_eq!(ad.len(), 12);
}
