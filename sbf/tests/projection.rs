//! Projection matrices ([Roughton19 §7.4]) against closed forms and direct quadrature.
use crate::common;

use sbf::ggx;
use sbf::nalgebra::DMatrix;
use sbf::quadrature::SphereQuadrature;
use sbf::solve::{projection_matrix, Conversion, Kernel, ProjectionOptions};
use sbf::{Basis, Domain, HBasis, ShBasis};
use std::f64::consts::PI;

/// Lambert band factors from their closed form (math.md; Ramamoorthi & Hanrahan 2001).
fn a_l(l: usize) -> f64 {
    match l {
        0 => PI,
        1 => 2.0 * PI / 3.0,
        l if l % 2 == 1 => 0.0,
        l => {
            let fact = |k: usize| (1..=k).map(|x| x as f64).product::<f64>();
            let sign = if (l / 2 + 1) % 2 == 0 { 1.0 } else { -1.0 };
            2.0 * PI * sign / ((l + 2) as f64 * (l - 1) as f64) * fact(l) / (2f64.powi(l as i32) * fact(l / 2).powi(2))
        }
    }
}

/// P for the Lambert kernel on SH L6 is diag(A_l/π) to 1e-6 (the rules are exact for
/// these polynomial integrands, so the residual is rounding, ~1e-13).
#[test]
fn lambert_projection_of_sh_gives_band_factors() {
    assert!((a_l(2) - PI / 4.0).abs() < 1e-15 && (a_l(4) + PI / 24.0).abs() < 1e-15);
    let sh = ShBasis::new(6).unwrap();
    let p = projection_matrix(&sh, &sh, Kernel::Lambert, ProjectionOptions { outer_n_z: 16, inner_n_z: 8, ggx_samples: 1 }).unwrap();
    let mut worst = 0.0f64;
    for l in 0..=6usize {
        for m in -(l as i64)..=(l as i64) {
            let i = sbf::basis::sh::sh_index(l, m);
            for j in 0..sh.len() {
                let want = if i == j { a_l(l) / PI } else { 0.0 };
                worst = worst.max((p[(i, j)] - want).abs());
            }
        }
    }
    assert!(worst < 1e-6, "max |P − diag(A_l/π)| = {worst:e}");
}

/// Delta conversion SH L1 → H-basis 4 on the upper hemisphere is exact: {1, x, y, z}
/// restricted to z ≥ 0 is spanned by H0…H3.
#[test]
fn sh_to_hbasis_conversion_is_exact_for_l1() {
    let sh = ShBasis::new(1).unwrap();
    let h = HBasis::new(4).unwrap();
    let conv = Conversion::new(&h, &sh, Kernel::Delta, ProjectionOptions { outer_n_z: 16, inner_n_z: 4, ggx_samples: 1 }).unwrap();
    let a = DMatrix::from_column_slice(4, 1, &[0.7, -0.2, 0.4, 0.3]);
    let b = conv.apply(&a);
    let mut sb = vec![0.0; 4];
    let mut hb = vec![0.0; 4];
    for d in common::random_directions(61, 5000).into_iter().filter(|d| d.z >= 0.0) {
        let f_sh = sh.reconstruct(a.as_slice(), d, &mut sb);
        let f_h = h.reconstruct(b.as_slice(), d, &mut hb);
        assert!((f_sh - f_h).abs() < 1e-12, "{d}: SH {f_sh} vs H {f_h}");
    }
}

/// GGX kernel: P for a constant source against H-basis 4 equals a direct double
/// Gauss–Legendre quadrature of H_i(v)·Y₀₀·D·G2/(4 n·v) (Fresnel 1). α = 0.5 keeps
/// the integrand smooth enough for the direct rule; the VNDF estimate uses 4096
/// R2 samples per view (QMC error ~1e-4 relative), hence the 2e-3 bar.
#[test]
fn ggx_projection_matches_direct_quadrature() {
    let alpha = 0.5;
    let sh0 = ShBasis::new(0).unwrap();
    let h = HBasis::new(4).unwrap();
    let p =
        projection_matrix(&h, &sh0, Kernel::Ggx { alpha }, ProjectionOptions { outer_n_z: 24, inner_n_z: 2, ggx_samples: 4096 }).unwrap();
    let outer = SphereQuadrature::gauss_product(Domain::UpperHemisphere, 24, 48);
    let inner = SphereQuadrature::gauss_product(Domain::UpperHemisphere, 200, 200);
    let y00 = 0.5 / PI.sqrt();
    let mut direct = [0.0; 4];
    let mut hb = [0.0; 4];
    for (v, wv) in outer.directions.iter().zip(&outer.weights) {
        let e = inner.integrate(|l| {
            let hv = (*v + l).normalize();
            ggx::d(hv, alpha) * ggx::g2(*v, l, alpha) / (4.0 * v.z)
        });
        h.eval_into(*v, &mut hb);
        for i in 0..4 {
            direct[i] += wv * hb[i] * y00 * e;
        }
    }
    for i in 0..4 {
        let rel = (p[(i, 0)] - direct[i]).abs() / direct[0].abs();
        assert!(rel < 2e-3, "H{i}: projection {} vs direct {}", p[(i, 0)], direct[i]);
    }
    assert!(projection_matrix(&h, &sh0, Kernel::Ggx { alpha: 0.0 }, ProjectionOptions::default()).is_err());
}

/// Folding: applying G_B⁻¹PG_A⁻¹ to moments equals applying G_B⁻¹P to the LS
/// coefficients of the same signal (eq. 7.21 vs 7.22).
#[test]
fn folded_matrix_is_consistent() {
    let ad = sbf::AmbientDiceSrbf::twelve();
    let conv = Conversion::new(&ad, &ad, Kernel::Lambert, ProjectionOptions { outer_n_z: 24, inner_n_z: 16, ggx_samples: 1 }).unwrap();
    let m = DMatrix::from_fn(12, 3, |i, c| 0.1 + (i * 3 + c) as f64 * 0.01);
    let a = sbf::solve::solve_gram(&conv.source_gram.matrix, &m, Default::default()).unwrap().coeffs;
    let err = (conv.apply_moments(&m) - conv.apply(&a)).abs().max();
    assert!(err < 1e-9, "{err:e}");
    // Irradiance of the constant-1 radiance (AD coefficients all 1) is E/π = 1.
    let ones = DMatrix::from_element(12, 1, 1.0);
    let irr = conv.apply(&ones);
    let mut b = vec![0.0; 12];
    for d in common::random_directions(62, 200) {
        let e = ad.reconstruct(irr.as_slice(), d, &mut b);
        assert!((e - 1.0).abs() < 1e-3, "{d}: E/π = {e}");
    }
}
