//! Spherical harmonics: orthonormality, fast paths, constants, bad input.
use crate::common;

use sbf::basis::sh::{sh_count, SH_CONSTANT_C00};
use sbf::basis::sh_fast::{eval_sh_f32, eval_sh_l2};
use sbf::glam::{DVec3, Vec3};
use sbf::gram::{gram_by_quadrature, gram_with_rule, GramOptions};
use sbf::quadrature::SphereQuadrature;
use sbf::{Basis, Domain, SbfError, ShBasis};

/// Gram = I to 1e-10 for every order up to 12, with a rule exact for degree 2L
/// (products of two band-L polynomials). The tolerance covers f64 rounding in
/// ~10³ summed terms (≈1e-13) with margin; a wrong constant (the historical l = 3
/// bug) or sign gives errors of order 1e-2.
#[test]
fn sh_gram_is_identity_up_to_l12() {
    for order in 0..=12 {
        let sh = ShBasis::new(order).unwrap();
        let rule = SphereQuadrature::exact_for_degree(Domain::Sphere, 2 * order);
        let g = gram_with_rule(&sh, &rule);
        let n = sh_count(order);
        let mut worst = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let e = if i == j { 1.0 } else { 0.0 };
                worst = worst.max((g[(i, j)] - e).abs());
            }
        }
        assert!(worst < 1e-10, "L{order}: max |G − I| = {worst:e}");
    }
}

/// High order stays orthonormal (recurrence stability): L = 40 on an exact rule.
#[test]
fn sh_gram_is_identity_at_l40() {
    let sh = ShBasis::new(40).unwrap();
    let rule = SphereQuadrature::exact_for_degree(Domain::Sphere, 80);
    let g = gram_with_rule(&sh, &rule);
    let mut worst = 0.0f64;
    for i in 0..g.nrows() {
        for j in 0..g.ncols() {
            worst = worst.max((g[(i, j)] - if i == j { 1.0 } else { 0.0 }).abs());
        }
    }
    // 1681 functions, ~3300-node rule: rounding grows ~linearly with L; 1e-9 is loose.
    assert!(worst < 1e-9, "L40: max |G − I| = {worst:e}");
}

/// The closed form (identity) agrees with the generic quadrature path too.
#[test]
fn sh_gram_quadrature_path_matches_closed_form() {
    let sh = ShBasis::new(3).unwrap();
    let g = gram_by_quadrature(&sh, Domain::Sphere, GramOptions { n_z: 16, force_quadrature: true }).unwrap();
    assert!((g.condition - 1.0).abs() < 1e-10, "cond {}", g.condition);
    assert!(g.quadrature_error < 1e-12, "degree-6 integrands are exact at both resolutions");
}

/// f32 fast paths equal the f64 recurrence to 1e-6 at the same (f32) input
/// (f32 has ~6e-8 relative precision; values are ≤ 2.5 in magnitude and degree-4
/// polynomials accumulate a few ulps, so ~5e-7 is the expected worst case).
#[test]
fn sh_fast_paths_match_recurrence() {
    let sh = ShBasis::new(4).unwrap();
    let mut slow = vec![0.0; 25];
    let mut fast = [0.0f32; 25];
    let mut worst = 0.0f64;
    for d in common::random_directions(1, 20_000) {
        // Compare at the same input: the f32 direction, widened exactly to f64.
        let d32 = d.as_vec3().normalize();
        sh.eval_into(d32.as_dvec3(), &mut slow);
        eval_sh_f32(4, d32, &mut fast).unwrap();
        for i in 0..25 {
            worst = worst.max((fast[i] as f64 - slow[i]).abs());
        }
    }
    assert!(worst < 1e-6, "max |fast − recurrence| = {worst:e}");
    // Lower orders write exactly the prefix.
    let d = Vec3::new(0.3, -0.5, 0.7).normalize();
    let l2 = eval_sh_l2(d);
    eval_sh_f32(4, d, &mut fast).unwrap();
    assert_eq!(&fast[..9], &l2[..]);
}

/// Band 1 is √(3/4π)(y, z, x) with positive signs (no Condon–Shortley phase).
#[test]
fn sh_band1_convention() {
    let sh = ShBasis::new(1).unwrap();
    let k = (3.0 / (4.0 * std::f64::consts::PI)).sqrt();
    let d = DVec3::new(0.48, -0.6, 0.64);
    let v = sh.eval(d);
    for (got, want) in v[1..].iter().zip([k * d.y, k * d.z, k * d.x]) {
        assert!((got - want).abs() < 1e-15, "{got} vs {want}");
    }
}

/// Projection of f ≡ 1 gives c₀₀ = 2√π and zero elsewhere (quadrature exact for degree 8).
#[test]
fn sh_of_constant_one() {
    let sh = ShBasis::new(4).unwrap();
    let rule = SphereQuadrature::exact_for_degree(Domain::Sphere, 8);
    let mut c = vec![0.0; 25];
    let mut b = vec![0.0; 25];
    for (d, w) in rule.directions.iter().zip(&rule.weights) {
        sh.eval_into(*d, &mut b);
        for i in 0..25 {
            c[i] += w * b[i];
        }
    }
    assert!((c[0] - 2.0 * std::f64::consts::PI.sqrt()).abs() < 1e-13, "c00 = {}", c[0]);
    assert!((SH_CONSTANT_C00 - 2.0 * std::f64::consts::PI.sqrt()).abs() < 1e-15);
    assert!(c[1..].iter().all(|x| x.abs() < 1e-13), "{c:?}");
}

#[test]
fn sh_bad_input_is_an_error() {
    assert!(matches!(ShBasis::new(100_000), Err(SbfError::OrderTooHigh { .. })));
    let mut out = [0.0f32; 36];
    assert!(matches!(eval_sh_f32(5, Vec3::Z, &mut out), Err(SbfError::OrderTooHigh { order: 5, max: 4, .. })));
    let mut short = [0.0f32; 8];
    assert!(matches!(eval_sh_f32(2, Vec3::Z, &mut short), Err(SbfError::LengthMismatch { .. })));
    let sh = ShBasis::new(2).unwrap();
    let mut o = vec![0.0; 9];
    assert!(matches!(sh.try_eval_into(DVec3::ZERO, &mut o), Err(SbfError::InvalidDirection { .. })));
    assert!(matches!(sh.try_eval_into(DVec3::new(f64::NAN, 0.0, 1.0), &mut o), Err(SbfError::InvalidDirection { .. })));
    let mut wrong = vec![0.0; 4];
    assert!(matches!(sh.try_eval_into(DVec3::Z, &mut wrong), Err(SbfError::LengthMismatch { .. })));
    // try_eval normalises a non-unit direction.
    sh.try_eval_into(DVec3::new(0.0, 0.0, 5.0), &mut o).unwrap();
    assert!((o[2] - (3.0 / (4.0 * std::f64::consts::PI)).sqrt()).abs() < 1e-15);
}
