//! SH irradiance: band factors, constant radiance, Geomerics and ZH3, windowing.
use crate::common;

use sbf::basis::sh::sh_count;
use sbf::glam::DVec3;
use sbf::recon::sh::*;
use sbf::{Basis, ShBasis};
use std::f64::consts::PI;

/// A_l against the closed form's values (A₂ = π/4, A₄ = −π/24, A₆ = π/64) and
/// finiteness at high order; the projection-matrix test checks A_l/π numerically.
#[test]
fn band_factors() {
    assert_eq!(lambert_band_factor(0), PI);
    assert!((lambert_band_factor(1) - 2.0 * PI / 3.0).abs() < 1e-15);
    assert!((lambert_band_factor(2) - PI / 4.0).abs() < 1e-15);
    assert!((lambert_band_factor(4) + PI / 24.0).abs() < 1e-15);
    assert!((lambert_band_factor(6) - PI / 64.0).abs() < 1e-15);
    assert_eq!(lambert_band_factor(3), 0.0);
    for l in [100, 1000, 100_000] {
        let a = lambert_band_factor(l);
        assert!(a.is_finite() && a.abs() < 1e-3, "A_{l} = {a}");
    }
}

/// Constant radiance L projects to c₀₀ = 2√π·L and gives E/π = L at every normal,
/// for every order and for Geomerics and ZH3 (no L1 vector: both reduce to R₀).
#[test]
fn constant_radiance_gives_l() {
    let l = 1.7;
    for order in [0, 1, 2, 4, 8] {
        let mut c = vec![0.0; sh_count(order)];
        c[0] = 2.0 * PI.sqrt() * l;
        for n in common::random_directions(91, 50) {
            assert!((irradiance(&c, n).unwrap() - l).abs() < 1e-13);
        }
    }
    let c1 = [2.0 * PI.sqrt() * l, 0.0, 0.0, 0.0];
    assert!((irradiance_l1_geomerics(&c1, DVec3::Z) - l).abs() < 1e-13);
    let z = irradiance_l1_zh3(&[c1; 3], DVec3::Y).unwrap();
    assert!(z.iter().all(|v| (v - l).abs() < 1e-13), "{z:?}");
}

/// Geomerics reduces to the exact linear L1 irradiance as |R₁|/R₀ → 0, stays
/// non-negative for non-negative radiance, and handles R₀ ≤ 0 and |R₁| = 0.
#[test]
fn geomerics_limits() {
    let sh = ShBasis::new(1).unwrap();
    let dirs = common::random_directions(92, 200);
    // Radiance 1 + ε·(ω·a): nearly constant.
    let a = DVec3::new(0.2, -0.5, 0.3);
    let eps = 1e-4;
    let mut c = [0.0; 4];
    for (d, w) in sbf::quadrature::SphereQuadrature::exact_for_degree(sbf::Domain::Sphere, 4)
        .directions
        .iter()
        .zip(sbf::quadrature::SphereQuadrature::exact_for_degree(sbf::Domain::Sphere, 4).weights.iter())
    {
        let y = sh.eval(*d);
        for k in 0..4 {
            c[k] += w * y[k] * (1.0 + eps * d.dot(a));
        }
    }
    for n in &dirs {
        let g = irradiance_l1_geomerics(&c, *n);
        let lin = irradiance_l1_linear(&c, *n);
        // The difference is second order in ε.
        assert!((g - lin).abs() < 10.0 * eps * eps, "{n}: {g} vs {lin}");
    }
    // A single directional light: radiance is a delta along a, SH L1 coefficients Y(a).
    let y = sh.eval(DVec3::Y);
    let delta = [y[0], y[1], y[2], y[3]];
    // Closed form for a delta: r0 = Y00² = 1/4π, r1 = (Y1·a)·Y1/3 = a/4π, so the ratio is 1,
    // p = 3, a = 0 and E/π = r0·4q³ = q³/π with q = (1 + n·a)/2 — non-negative everywhere.
    for n in &dirs {
        let g = irradiance_l1_geomerics(&delta, *n);
        let q = 0.5 * (1.0 + n.dot(DVec3::Y));
        assert!((g - q * q * q / PI).abs() < 1e-14, "{n}: {g} vs q³/π = {}", q * q * q / PI);
    }
    // A negative DC term takes the linear branch: r0 + 2·r1·n = −Y00 + 2·(0.5·Y1/3)·n_y.
    let k00 = 0.5 / PI.sqrt();
    let k1 = (3.0 / (4.0 * PI)).sqrt();
    for n in &dirs {
        let g = irradiance_l1_geomerics(&[-1.0, 0.5, 0.0, 0.0], *n);
        let want = -k00 + 2.0 * (0.5 * k1 / 3.0) * n.y;
        assert!((g - want).abs() < 1e-14, "{n}: {g} vs {want}");
    }
    assert!(irradiance_l1_geomerics(&[0.0, 0.0, 0.0, 0.0], DVec3::Z) == 0.0);
}

/// ZH3: finite for extreme inputs, equals L1 + a zonal term, and for a single
/// direction (r = |L1|/L0 = √3) adds L0·(0.08√3 + 1.8) on Y₂₀ along the axis.
#[test]
fn zh3_behaviour() {
    let sh = ShBasis::new(1).unwrap();
    let y = sh.eval(DVec3::Z);
    let c = [y[0], y[1], y[2], y[3]];
    let out = irradiance_l1_zh3(&[c; 3], DVec3::Z).unwrap();
    let a2 = lambert_band_factor(2) / PI;
    let y20 = (5.0 / (4.0 * PI)).sqrt();
    let r = 3f64.sqrt();
    let want = irradiance_l1_linear(&c, DVec3::Z) + a2 * c[0] * (0.08 * r + 0.6 * r * r) * y20;
    assert!((out[0] - want).abs() < 1e-13, "{out:?} vs {want}");
    // Homogeneous of degree 1 (r is a ratio): scaling the coefficients by 1e300 scales the
    // result by 1e300, without overflow in the intermediate |L1|/L0.
    let unit = irradiance_l1_zh3(&[[1.0, -1.0, 1.0, 0.0]; 3], DVec3::X).unwrap();
    let huge = irradiance_l1_zh3(&[[1e300, -1e300, 1e300, 0.0]; 3], DVec3::X).unwrap();
    for c in 0..3 {
        assert!((huge[c] / 1e300 - unit[c]).abs() <= 1e-14 * unit[c].abs().max(1e-300), "{huge:?} vs 1e300 × {unit:?}");
    }
    assert!(irradiance_l1_zh3(&[[f64::NAN, 0.0, 0.0, 0.0]; 3], DVec3::X).is_err());
}

/// Laplacian window: Newton finds λ that hits the requested energy fraction; the
/// sinc⁴ deringing returns a non-negative reconstruction on the test directions
/// and never lowers the negative fraction below zero.
#[test]
fn windowing() {
    // SH L4 of a sharp light: ringing, negative lobes.
    let sh = ShBasis::new(4).unwrap();
    let c = sh.eval(DVec3::new(0.3, 0.8, 0.5).normalize());
    let dirs: Vec<DVec3> = (0..4096).map(|i| sbf::sampling::spherical_fibonacci(i, 4096)).collect();
    let neg = negative_fraction(&c, &dirs).unwrap();
    assert!(neg > 0.05, "a delta in L4 rings: negative fraction {neg}");
    for target in [0.5, 0.1, 1e-3] {
        let lam = laplacian_window_lambda(&c, target).unwrap();
        let w = apply_window(&c, |l| laplacian_window(l, lam)).unwrap();
        let e = |x: &[f64]| {
            (1..=4).map(|l| ((l * (l + 1)) as f64).powi(2) * (0..2 * l + 1).map(|m| x[l * l + m].powi(2)).sum::<f64>()).sum::<f64>()
        };
        assert!((e(&w) / e(&c) - target).abs() < 1e-10, "target {target}: got {}", e(&w) / e(&c));
    }
    let (width, windowed) = sinc4_deringing(&c, &dirs).unwrap().expect("DC alone is positive");
    assert!(minimum_over(&windowed, &dirs).unwrap() >= 0.0);
    assert!(width > 1.0 && width <= 5.0, "w = {width}");
    assert_eq!(negative_fraction(&windowed, &dirs).unwrap(), 0.0);
    assert!(laplacian_window_lambda(&c, 0.0).is_err());
    assert!(irradiance(&[1.0; 5], DVec3::Z).is_err(), "5 is not (L+1)²");
}

/// `dering_irradiance` on a sun (a delta at s: c_lm = Y_lm(s)) in SH L2: its E/π rings
/// negative (by the zonal closed form E/π(μ) = Σ_l (A_l/π)(2l+1)/(4π)·σ_l·P_l(μ) with
/// A = (π, 2π/3, π/4), μ = n·s — written here with Legendre polynomials, not SH
/// evaluation); the windowed radiance's E/π is ≥ 0 for all μ (dense grid), the window is
/// the widest on the 1/64 grid up to L + 1 that does it, and the DC is kept. A constant
/// (no ringing) is left alone. Mutation: the window applied to the E/π instead of the
/// radiance coefficients → the coefficient check fails.
#[test]
fn dering_irradiance_of_a_sun() {
    let dirs: Vec<DVec3> = (0..4096).map(|i| sbf::sampling::spherical_fibonacci(i, 4096)).collect();
    let s = DVec3::new(0.3, 0.8, 0.5).normalize();
    let c = ShBasis::new(2).unwrap().eval(s);
    let zonal = |w: f64, mu: f64| {
        let p = [1.0, mu, 0.5 * (3.0 * mu * mu - 1.0)];
        let a = [1.0, 2.0 / 3.0, 0.25];
        (0..3).map(|l| a[l] * (2 * l + 1) as f64 / (4.0 * PI) * sinc4_window(l, w) * p[l]).sum::<f64>()
    };
    let min_over_mu = |w: f64| (0..=20_000).map(|k| zonal(w, -1.0 + k as f64 / 10_000.0)).fold(f64::INFINITY, f64::min);
    assert!(min_over_mu(1e9) < -1e-3, "the sun's E/π rings: {}", min_over_mu(1e9));
    let (w, windowed) = dering_irradiance(&c, &dirs).unwrap().expect("it rings");
    // The spherical-Fibonacci set misses the exact minimum by at most its spacing: 1e-6.
    assert!(min_over_mu(w) >= -1e-6, "w {w}: min E/π {}", min_over_mu(w));
    // The scan starts at w = L + 1 = 3 (σ₃ = 0); below it, one step wider rings.
    assert!(w <= 3.0 && (w == 3.0 || min_over_mu(w + 1.0 / 64.0) < 0.0), "w {w} is not the widest");
    assert_eq!(windowed[0], c[0]);
    for l in 1..3 {
        for m in 0..2 * l + 1 {
            assert!((windowed[l * l + m] - c[l * l + m] * sinc4_window(l, w)).abs() < 1e-15);
        }
    }
    let mut constant = vec![0.0; 9];
    constant[0] = 1.0;
    assert!(dering_irradiance(&constant, &dirs).unwrap().is_none());
}

/// i_l(λ)/i_0(λ) from the all-positive power series i_l(λ) = λ^l Σ_k (λ²/2)^k/(k!(2l+2k+1)!!)
/// in log space (log-sum-exp over the terms until they fall 60 e-folds below the largest,
/// past the peak at k ≈ λ/2) — an independent oracle with no cancellation for any λ.
fn zonal_ratio_series(lambda: f64, l: usize) -> f64 {
    let log_sum = |l: usize| {
        let mut lt = -(1..=l).map(|j| ((2 * j + 1) as f64).ln()).sum::<f64>();
        let step = (lambda * lambda / 2.0).ln();
        let (mut terms, mut top) = (Vec::new(), f64::NEG_INFINITY);
        for k in 0.. {
            terms.push(lt);
            top = top.max(lt);
            if lt < top - 60.0 && k as f64 > lambda {
                break;
            }
            lt += step - ((k + 1) as f64).ln() - ((2 * l + 2 * k + 3) as f64).ln();
        }
        top + terms.iter().map(|t| (t - top).exp()).sum::<f64>().ln()
    };
    (l as f64 * lambda.ln() + log_sum(l) - log_sum(0)).exp()
}

/// The SG zonal ratios g_l/g_0 (sg_zonal_ratios, used by the SH specular path) match the
/// series oracle to 1e-6 relative for λ from 1e-4 to 1e5 (36 values, log-spaced, plus both
/// sides of the switch between the continued fraction and the finite form) and l ≤ 8, and
/// l ≤ 24 at a few λ — which covers every n·v ∈ [1e-4, 1] the path uses (λ = 1/(2α²·n·v)).
/// Values below 1e-200 (l ≥ 3 at λ = 1e-4) are compared to 1e-6 of themselves too: the
/// series is exact there. By value at the cases: α = 0.02, n·v = 1 (λ = 1250) band 1
/// ≈ 0.9992; α = 0.1, n·v = 0.01 (λ = 5000) band 1 ≈ 0.9998.
#[test]
fn sg_zonal_ratios_match_the_series() {
    let mut lambdas: Vec<f64> = (0..36).map(|k| 1e-4 * 10f64.powf(k as f64 / 4.0)).collect();
    lambdas.extend([63.9, 64.0, 64.1, 575.0, 576.0, 577.0, 1250.0, 5000.0]);
    let mut worst = 0.0f64;
    for &lambda in &lambdas {
        for lmax in [8usize, 24] {
            if lmax == 24 && !(lambda < 1e-2 || (50.0..=1e4).contains(&lambda)) {
                continue;
            }
            let g = sg_zonal_ratios(lambda, lmax);
            for l in 0..=lmax {
                let want = zonal_ratio_series(lambda, l);
                let e = (g[l] - want).abs() / want;
                worst = worst.max(e);
                assert!(e <= 1e-6, "λ {lambda} l {l} (lmax {lmax}): {} vs series {want}", g[l]);
            }
        }
    }
    println!("sg_zonal_ratios: worst relative error against the series {worst:.2e}");
    // The cases by value: band 1 = coth λ − 1/λ.
    for lambda in [1250.0f64, 5000.0] {
        let band1 = 1.0 / lambda.tanh() - 1.0 / lambda;
        assert!((sg_zonal_ratios(lambda, 4)[1] - band1).abs() <= 1e-12, "λ {lambda}");
    }
}
