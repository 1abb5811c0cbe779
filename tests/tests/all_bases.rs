//! Properties every basis exposed by `sbf` must have, checked on all of them
//! together: finite values on random and extreme directions, `try_eval_into`
//! rejecting bad input, and reconstruction of a constant where the basis can
//! represent one.

use sbf::glam::DVec3;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::quadrature::SphereQuadrature;
use sbf::sampling::{uniform_sphere, Pcg32};
use sbf::{AmbientCube, AmbientDiceBezier, AmbientDiceLinear, AmbientDiceSrbf, Basis, HBasis, SbfError, SgBasis, ShBasis};

fn all_bases() -> Vec<Box<dyn Basis>> {
    let vogel = sbf::layout::vogel_sphere(12).unwrap();
    let hemi = sbf::layout::vogel_hemisphere(9).unwrap();
    vec![
        Box::new(ShBasis::new(0).unwrap()),
        Box::new(ShBasis::new(3).unwrap()),
        Box::new(SgBasis::new(&vogel, 6.0, true).unwrap()),
        Box::new(SgBasis::new(&vogel, 1e-4, false).unwrap()),
        Box::new(SgBasis::new(&vogel, 1e4, false).unwrap()),
        Box::new(SgBasis::new(&hemi, 6.0, false).unwrap()),
        Box::new(AmbientDiceSrbf::twelve()),
        Box::new(AmbientDiceSrbf::nine_hemisphere()),
        Box::new(AmbientDiceBezier::new()),
        Box::new(AmbientDiceLinear::new()),
        Box::new(HBasis::new(4).unwrap()),
        Box::new(HBasis::new(6).unwrap()),
        Box::new(AmbientCube),
    ]
}

#[test]
fn every_basis_is_finite_everywhere() {
    let mut rng = Pcg32::new(99, 0);
    let mut dirs: Vec<DVec3> = (0..20_000).map(|_| uniform_sphere(rng.next_2d())).collect();
    // Poles, axes and the icosahedron vertices (ties in face lookup).
    dirs.extend([DVec3::X, DVec3::Y, DVec3::Z, DVec3::NEG_X, DVec3::NEG_Y, DVec3::NEG_Z]);
    dirs.extend(sbf::layout::icosahedron());
    for b in all_bases() {
        let mut out = vec![0.0; b.len()];
        for d in &dirs {
            b.eval_into(*d, &mut out);
            assert!(out.iter().all(|x| x.is_finite()), "{}: non-finite at {d}", b.name());
        }
    }
}

#[test]
fn every_basis_rejects_bad_directions() {
    for b in all_bases() {
        let mut out = vec![0.0; b.len()];
        for bad in [DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 1.0), DVec3::new(f64::INFINITY, 0.0, 0.0), DVec3::splat(1e-200)] {
            assert!(matches!(b.try_eval_into(bad, &mut out), Err(SbfError::InvalidDirection { .. })), "{} accepted {bad}", b.name());
        }
        let mut short = vec![0.0; b.len() + 1];
        assert!(matches!(b.try_eval_into(DVec3::Z, &mut short), Err(SbfError::LengthMismatch { .. })), "{}", b.name());
    }
}

/// Least-squares fit of f ≡ 1 on each basis' own domain: moments m_i = ∫B_i by a
/// Gauss–Legendre product rule, Gram matrix from `gram_matrix` (closed form where
/// one exists). Bases that contain constants (SH, SG + ambient, AD SRBF 12 and
/// linear, H-basis, ambient cube) must give their known coefficients to 1e-6: the
/// moments' quadrature error (≤ ~1e-8 for the kinked bases at 256×512 nodes) times
/// cond(G) ≤ 1e3 stays well below that; a wrong Gram, lobe or normalisation is
/// off by far more.
#[test]
fn bases_with_constants_reproduce_them() {
    for b in all_bases() {
        let Some(want) = constant_coeffs(b.as_ref()) else { continue };
        let rule = SphereQuadrature::gauss_product(b.domain(), 256, 512);
        let mut m = vec![0.0; b.len()];
        let mut v = vec![0.0; b.len()];
        for (d, w) in rule.directions.iter().zip(&rule.weights) {
            b.eval_into(*d, &mut v);
            for i in 0..b.len() {
                m[i] += w * v[i];
            }
        }
        let g = gram_matrix(b.as_ref(), b.domain(), GramOptions::default()).unwrap();
        let got = g.solve(&m).unwrap();
        let err = got.iter().zip(&want).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(err < 1e-6, "{}: max coefficient error {err:e}", b.name());
    }
}

/// Known exact coefficients of f ≡ 1, where the basis represents constants.
fn constant_coeffs(b: &dyn Basis) -> Option<Vec<f64>> {
    let name = b.name();
    let n = b.len();
    let mut c = vec![0.0; n];
    if name.starts_with("SH") {
        c[0] = 2.0 * std::f64::consts::PI.sqrt();
    } else if name.starts_with("H-basis") {
        c[0] = (2.0 * std::f64::consts::PI).sqrt();
    } else if name.ends_with("+ ambient") {
        c[n - 1] = 1.0;
    } else if name == "AD SRBF 12" || name == "AD linear 12" || name == "ambient cube" {
        c.fill(1.0);
    } else {
        return None;
    }
    Some(c)
}
