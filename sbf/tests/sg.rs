//! Spherical Gaussians and ASGs: closed forms against quadrature over the whole
//! stiff range λ ∈ [1e-4, 1e4], f32 finiteness, product identity.
use crate::common;

use common::rel;
use sbf::basis::sg::{sg_unit_inner_product_f32, sg_unit_integral, sg_unit_integral_f32};
use sbf::glam::DVec3;
use sbf::quadrature::gauss_legendre;
use sbf::{Asg, Basis, Sg, SgBasis};
use std::f64::consts::PI;

const LAMBDAS: [f64; 9] = [1e-4, 1e-2, 0.5, 1.0, 6.0, 50.0, 300.0, 2e3, 1e4];

/// Oracle: ∫ f over the sphere in polar coordinates about +Z, u = 1 − cos θ ∈ [0, 2]
/// (dΩ = du dφ). Composite 32-point Gauss–Legendre on geometric u-intervals
/// [0, 1e-10, …, 0.1, 1, 1.9, …, 2 − 1e-10, 2] resolves lobes down to width 1e-5
/// in u at either pole; the periodic
/// trapezoid rule in φ converges exponentially for smooth integrands.
fn polar_quadrature(f: impl Fn(DVec3) -> f64, n_phi: usize) -> f64 {
    let (gx, gw) = gauss_legendre(32);
    let mut edges = vec![0.0];
    let mut e = 1e-10;
    while e < 1.0 {
        edges.push(e);
        e *= 10.0;
    }
    // Mirror towards u = 2 (the antipode), where a product of opposite lobes peaks.
    let lower: Vec<f64> = edges.clone();
    edges.push(1.0);
    edges.extend(lower.iter().rev().map(|x| 2.0 - x));
    let mut total = 0.0;
    for w in edges.windows(2) {
        let (a, b) = (w[0], w[1]);
        for (x, wx) in gx.iter().zip(&gw) {
            let u = a + 0.5 * (b - a) * (x + 1.0);
            let s = (u * (2.0 - u)).max(0.0).sqrt();
            let mut ring = 0.0;
            for k in 0..n_phi {
                let p = 2.0 * PI * (k as f64 + 0.5) / n_phi as f64;
                ring += f(DVec3::new(s * p.cos(), s * p.sin(), 1.0 - u));
            }
            total += 0.5 * (b - a) * wx * ring * 2.0 * PI / n_phi as f64;
        }
    }
    total
}

/// Integral: relative 1e-6 (the oracle is accurate to ~1e-12; 1e-6 is the
/// acceptance bar and leaves room for exp() rounding at λ = 1e4).
#[test]
fn sg_integral_matches_quadrature() {
    for &l in &LAMBDAS {
        let sg = Sg::new(DVec3::Z, l, 1.7).unwrap();
        let q = polar_quadrature(|v| sg.eval(v), 8);
        let c = sg.integral();
        assert!(c.is_finite() && rel(c, q) < 1e-6, "λ={l}: closed {c} vs quadrature {q}");
        let f = sg_unit_integral_f32(l as f32) as f64 * 1.7;
        assert!(f.is_finite() && rel(f, c) < 1e-5, "λ={l}: f32 {f} vs f64 {c}");
    }
    assert_eq!(sg_unit_integral(0.0), 4.0 * PI);
    assert_eq!(sg_unit_integral_f32(0.0), 4.0 * std::f32::consts::PI);
}

/// Inner product for every pair of sharpness values and three separations
/// (0, a lobe-width apart, opposite), relative 1e-6 against the polar oracle.
#[test]
fn sg_inner_product_matches_quadrature() {
    for &la in &LAMBDAS {
        for &lb in &LAMBDAS {
            let width = 1.0 / la.max(lb).sqrt();
            for delta in [0.0, (2.0 * width).min(2.5), PI] {
                let pa = DVec3::Z;
                let pb = DVec3::new(delta.sin(), 0.0, delta.cos());
                let (a, b) = (Sg::new(pa, la, 1.0).unwrap(), Sg::new(pb, lb, 1.0).unwrap());
                let closed = a.inner_product(&b);
                assert!(closed.is_finite() && closed >= 0.0, "λ=({la},{lb}) δ={delta}: {closed}");
                if closed < 1e-250 {
                    continue; // true value underflows f64 (opposite sharp lobes)
                }
                let q = polar_quadrature(|v| a.eval(v) * b.eval(v), 2048);
                assert!(rel(closed, q) < 1e-6, "λ=({la},{lb}) δ={delta}: closed {closed} vs quadrature {q}");
                let f = sg_unit_inner_product_f32(pa.as_vec3(), la as f32, pb.as_vec3(), lb as f32) as f64;
                assert!(f.is_finite(), "f32 inner product not finite at λ=({la},{lb}) δ={delta}");
                if closed > 1e-30 {
                    // f32: exponent computed without cancellation, so ~1e-6 relative;
                    // 1e-4 allows for the f32 rounding of the axes themselves.
                    assert!(rel(f, closed) < 1e-4, "λ=({la},{lb}) δ={delta}: f32 {f} vs f64 {closed}");
                }
            }
        }
    }
}

/// f32 closed forms at extreme inputs well beyond the tested range (the sinh form would
/// overflow from λ ≈ 44), by value against the f64 closed forms (themselves checked
/// against quadrature above): relative 1e-4 (f32 rounding of the exponent argument λ·(1 −
/// cos) at λ = 1e6 is ~1e-7·λ·(1 − cos) — 0 for equal or opposite axes here, and the X
/// axis makes the value underflow), or both below f32's smallest normal.
#[test]
fn sg_f32_extremes_by_value() {
    use sbf::basis::sg::sg_unit_inner_product;
    for la in [0.0f32, 1e-4, 44.0, 89.0, 1e4, 1e6] {
        for lb in [0.0f32, 1e-4, 44.0, 89.0, 1e4, 1e6] {
            for pb in [sbf::glam::Vec3::Z, -sbf::glam::Vec3::Z, sbf::glam::Vec3::X] {
                let v = sg_unit_inner_product_f32(sbf::glam::Vec3::Z, la, pb, lb) as f64;
                let want = sg_unit_inner_product(DVec3::Z, la as f64, pb.as_dvec3(), lb as f64);
                let ok =
                    if want >= f32::MIN_POSITIVE as f64 { rel(v, want) < 1e-4 } else { v < f32::MIN_POSITIVE as f64 * 2.0 && v >= 0.0 };
                assert!(ok, "({la},{lb},{pb}): f32 {v} vs f64 {want}");
            }
            let (i32v, i64v) = (sg_unit_integral_f32(la) as f64, sg_unit_integral(la as f64));
            assert!(rel(i32v, i64v) < 1e-5, "integral λ={la}: f32 {i32v} vs f64 {i64v}");
        }
    }
}

/// The product of two SGs is an SG: pointwise identity at random directions.
#[test]
fn sg_product_identity() {
    let a = Sg::new(DVec3::new(0.2, 0.3, 0.9), 7.0, 2.0).unwrap();
    let b = Sg::new(DVec3::new(-0.5, 0.1, 0.4), 3.0, 0.5).unwrap();
    let p = a.product(&b);
    for v in common::random_directions(3, 2000) {
        let want = a.eval(v) * b.eval(v);
        assert!((p.eval(v) - want).abs() <= 1e-13 * want.max(1e-300) + 1e-300, "{v}");
    }
    // And its integral is the inner product.
    assert!(rel(p.integral(), a.inner_product(&b)) < 1e-13);
}

/// Closed-form Gram (with ambient lobe) equals quadrature of the basis products.
#[test]
fn sg_basis_gram_closed_form_matches_quadrature() {
    let axes = sbf::layout::vogel_sphere(12).unwrap();
    let basis = SgBasis::new(&axes, 6.0, true).unwrap();
    let closed = basis.closed_form_gram(sbf::Domain::Sphere).unwrap();
    let q =
        sbf::gram::gram_by_quadrature(&basis, sbf::Domain::Sphere, sbf::gram::GramOptions { n_z: 128, force_quadrature: true }).unwrap();
    let err = (closed - &q.matrix).abs().max();
    // Smooth integrands: the 128×256 rule is accurate to ~1e-12.
    assert!(err < 1e-10, "max |closed − quadrature| = {err:e}");
    assert!(basis.closed_form_gram(sbf::Domain::UpperHemisphere).is_none());
}

/// ASG evaluation stays finite and within [0, μ] for anisotropy up to 1e4 and
/// sharpness up to 1e4; for sharp lobes its integral approaches π/√(λxλy)
/// (Xu et al. 2013 §4), an independent check of the frame and exponent.
#[test]
fn asg_finite_and_normalised() {
    let dirs = common::random_directions(5, 5000);
    for (lx, ly) in [(1e4, 1.0), (1.0, 1e4), (1e4, 1e4), (1e-4, 1e4), (0.0, 0.0), (1.0, 1.0)] {
        let asg = Asg::new(DVec3::new(0.1, 0.2, 1.0), DVec3::X, lx, ly, 3.0).unwrap();
        for d in &dirs {
            let v = asg.eval(*d);
            assert!(v.is_finite() && (0.0..=3.0).contains(&v), "({lx},{ly}) {d}: {v}");
            let f = asg.eval_f32(d.as_vec3());
            assert!(f.is_finite() && (0.0..=3.0001).contains(&f));
        }
    }
    for (lx, ly) in [(200.0, 200.0), (400.0, 1600.0)] {
        let asg = Asg::new(DVec3::Z, DVec3::X, lx, ly, 1.0).unwrap();
        let q = polar_quadrature(|v| asg.eval(v), 512);
        let approx = PI / (lx * ly).sqrt();
        // The approximation drops O(1/λ) terms: 2% at λ ≥ 200.
        assert!(rel(q, approx) < 0.02, "({lx},{ly}): quadrature {q} vs π/√(λxλy) {approx}");
    }
    assert!(Asg::new(DVec3::Z, DVec3::Z, 1.0, 1.0, 1.0).is_err(), "degenerate frame must be an error");
    assert!(Asg::new(DVec3::Z, DVec3::X, -1.0, 1.0, 1.0).is_err());
}

#[test]
fn sg_bad_input_is_an_error() {
    assert!(Sg::new(DVec3::ZERO, 1.0, 1.0).is_err());
    assert!(Sg::new(DVec3::Z, f64::NAN, 1.0).is_err());
    assert!(Sg::new(DVec3::Z, -1.0, 1.0).is_err());
    assert!(SgBasis::new(&[DVec3::Z], 0.0, false).is_err());
    assert!(SgBasis::new(&[], 1.0, false).is_err());
    assert!(SgBasis::with_sharpness(&[DVec3::Z, DVec3::X], &[1.0], false).is_err());
    assert!(SgBasis::new(&[DVec3::Z, DVec3::new(f64::INFINITY, 0.0, 0.0)], 1.0, false).is_err());
}
