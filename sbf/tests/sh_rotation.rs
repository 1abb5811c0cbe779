//! SH rotation (Ivanic–Ruedenberg recurrences) against oracles that do not use the
//! recurrence: projection of the rotated function by an exact quadrature rule (l ≤ 8), the
//! azimuthal closed form for rotations about z (any l), the band-2 matrix from the
//! traceless-tensor form of the quadratic harmonics, and the group identities
//! (composition, inverse = transpose).
use sbf::basis::sh::sh_count;
use sbf::basis::sh_rotation::{check_rotation, ShRotation};
use sbf::glam::{DMat3, DQuat, DVec3};
use sbf::quadrature::SphereQuadrature;
use sbf::sampling::{uniform_sphere, Pcg32};
use sbf::{Basis, Domain, SbfError, ShBasis};

fn random_rotation(r: &mut Pcg32) -> DMat3 {
    let axis = uniform_sphere(r.next_2d());
    let angle = 2.0 * std::f64::consts::PI * r.next_2d()[0];
    DMat3::from_quat(DQuat::from_axis_angle(axis, angle))
}

fn random_coeffs(r: &mut Pcg32, n: usize) -> Vec<f64> {
    (0..n).map(|_| 2.0 * r.next_2d()[0] - 1.0).collect()
}

/// g(v) = f(Rᵀv) projected by a product rule exact for degree 2L (the integrand
/// Y_i(v)·f(Rᵀv) is a polynomial of degree ≤ 2L on the sphere), for L = 1…8, random
/// rotations and rotations about each axis. Error model: exact rule, so only f64
/// rounding of ~(L+1)²·rule-size terms of size ≤ ‖c‖₁·max|Y|² ≈ 1e-13 relative; bar 1e-10
/// of ‖c‖₁. A transposed matrix, a wrong sign in V or W, or a wrong edge column gives
/// errors of order 0.1.
#[test]
fn rotation_equals_projection_of_the_rotated_function() {
    let mut r = Pcg32::new(11, 3);
    let mut rotations: Vec<(String, DMat3)> = (0..4).map(|k| (format!("random {k}"), random_rotation(&mut r))).collect();
    for (name, axis) in [("x", DVec3::X), ("y", DVec3::Y), ("z", DVec3::Z)] {
        rotations.push((format!("about {name} by 0.7"), DMat3::from_axis_angle(axis, 0.7)));
        rotations.push((format!("about {name} by π/2"), DMat3::from_axis_angle(axis, std::f64::consts::FRAC_PI_2)));
    }
    for order in 1..=8 {
        let sh = ShBasis::new(order).unwrap();
        let n = sh_count(order);
        let rule = SphereQuadrature::exact_for_degree(Domain::Sphere, 2 * order);
        for (name, rot) in &rotations {
            let c = random_coeffs(&mut r, n);
            let got = ShRotation::new(order, *rot).unwrap().apply(&c).unwrap();
            let (mut y, mut yr) = (vec![0.0; n], vec![0.0; n]);
            let mut want = vec![0.0; n];
            for (d, w) in rule.directions.iter().zip(&rule.weights) {
                sh.eval_into(*d, &mut y);
                sh.eval_into((rot.transpose() * *d).normalize(), &mut yr);
                let g: f64 = c.iter().zip(&yr).map(|(a, b)| a * b).sum();
                for i in 0..n {
                    want[i] += w * y[i] * g;
                }
            }
            let norm: f64 = c.iter().map(|x| x.abs()).sum();
            let worst = got.iter().zip(&want).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(worst <= 1e-10 * norm, "L{order} {name}: max |rotated − projected| = {worst:e}");
        }
    }
}

/// About z by θ, g(φ) = f(φ − θ): for each m > 0, (a, b) = (c_{l,m}, c_{l,−m}) become
/// (a cos mθ − b sin mθ, a sin mθ + b cos mθ), zonal terms unchanged — every band to L = 30.
/// Error model: the recurrence's rounding grows slowly with l (≈ l·1e-15 per entry); bar 1e-11.
#[test]
fn rotation_about_z_is_the_azimuthal_shift_at_every_order() {
    let order = 30;
    let theta = 0.83;
    let rot = ShRotation::new(order, DMat3::from_rotation_z(theta)).unwrap();
    let mut worst = 0.0f64;
    for l in 0..=order {
        let w = 2 * l + 1;
        let b = rot.band(l);
        for mi in 0..w {
            for ni in 0..w {
                let (m, n) = (mi as i64 - l as i64, ni as i64 - l as i64);
                let am = m.abs() as f64;
                let want = if m == 0 || n == 0 {
                    if m == n {
                        1.0
                    } else {
                        0.0
                    }
                } else if m == n {
                    (am * theta).cos()
                } else if m == -n {
                    // row +m, column −m: −sin mθ; row −m, column +m: +sin mθ.
                    if m > 0 {
                        -(am * theta).sin()
                    } else {
                        (am * theta).sin()
                    }
                } else {
                    0.0
                };
                worst = worst.max((b[mi * w + ni] - want).abs());
            }
        }
    }
    assert!(worst < 1e-11, "max deviation from the azimuthal closed form {worst:e}");
}

/// Band 2 in closed form: with Y_m(v) = vᵀQ_m v (Q_m symmetric traceless, the Cartesian
/// quadratics of the crate's convention), g(v) = Y_n(Rᵀv) = vᵀ(R Q_n Rᵀ)v and
/// ∫(vᵀAv)(vᵀBv)dω = (8π/15)·tr(AB) for traceless A, B, so M_mn = (8π/15)·tr(Q_m R Q_n Rᵀ).
/// Band 1 is R with rows and columns in (y, z, x) order. No recurrence involved; bar 1e-13.
#[test]
fn bands_one_and_two_equal_their_closed_forms() {
    use std::f64::consts::PI;
    let k = 0.5 * (15.0 / PI).sqrt();
    let sym = |i: usize, j: usize, s: f64| {
        let mut m = [[0.0; 3]; 3];
        m[i][j] += 0.5 * s;
        m[j][i] += 0.5 * s;
        DMat3::from_cols_array_2d(&m).transpose()
    };
    let k0 = 0.25 * (5.0 / PI).sqrt();
    let q = [
        sym(0, 1, k),                                             // xy
        sym(1, 2, k),                                             // yz
        DMat3::from_diagonal(DVec3::new(-k0, -k0, 2.0 * k0)),     // 3z² − 1 on the sphere
        sym(0, 2, k),                                             // xz
        DMat3::from_diagonal(DVec3::new(0.5 * k, -0.5 * k, 0.0)), // x² − y²
    ];
    // The tensors reproduce the basis (guards the oracle itself).
    let sh = ShBasis::new(2).unwrap();
    let mut y = vec![0.0; 9];
    for d in [DVec3::new(0.3, -0.5, 0.81).normalize(), DVec3::new(-0.9, 0.1, 0.2).normalize()] {
        sh.eval_into(d, &mut y);
        for (m, qm) in q.iter().enumerate() {
            assert!((d.dot(*qm * d) - y[4 + m]).abs() < 1e-14, "tensor {m}");
        }
    }
    let mut r = Pcg32::new(5, 9);
    for _ in 0..20 {
        let rm = random_rotation(&mut r);
        let rot = ShRotation::new(2, rm).unwrap();
        let b2 = rot.band(2);
        for m in 0..5 {
            for n in 0..5 {
                let a = q[m] * rm * q[n] * rm.transpose();
                let want = 8.0 * PI / 15.0 * (a.x_axis.x + a.y_axis.y + a.z_axis.z);
                assert!((b2[m * 5 + n] - want).abs() < 1e-13, "band 2 ({m}, {n}): {} vs {want}", b2[m * 5 + n]);
            }
        }
        let ax = [1usize, 2, 0];
        for m in 0..3 {
            for n in 0..3 {
                let want = rm.col(ax[n])[ax[m]];
                assert!((rot.band(1)[m * 3 + n] - want).abs() < 1e-15);
            }
        }
    }
}

/// Group identities to L = 40: rot(A)·rot(B) = rot(AB), rot(Rᵀ) = rot(R)ᵀ, each band
/// orthogonal. Bars from rounding of O(l) accumulated recurrence steps: 1e-11.
#[test]
fn composition_inverse_and_orthogonality_to_l40() {
    let order = 40;
    let mut r = Pcg32::new(21, 1);
    let (a, b) = (random_rotation(&mut r), random_rotation(&mut r));
    let ra = ShRotation::new(order, a).unwrap();
    let rb = ShRotation::new(order, b).unwrap();
    let rab = ShRotation::new(order, a * b).unwrap();
    let rat = ShRotation::new(order, a.transpose()).unwrap();
    let c = random_coeffs(&mut r, sh_count(order));
    let two = ra.apply(&rb.apply(&c).unwrap()).unwrap();
    let one = rab.apply(&c).unwrap();
    let back = rat.apply(&ra.apply(&c).unwrap()).unwrap();
    let norm = c.iter().map(|x| x * x).sum::<f64>().sqrt();
    let d1 = two.iter().zip(&one).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let d2 = back.iter().zip(&c).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(d1 < 1e-11 * norm, "composition {d1:e}");
    assert!(d2 < 1e-11 * norm, "inverse {d2:e}");
    // Orthogonality: ‖Mc‖ = ‖c‖ per band.
    let rc = ra.apply(&c).unwrap();
    for l in 0..=order {
        let s = l * l..(l + 1) * (l + 1);
        let (n0, n1) = (c[s.clone()].iter().map(|x| x * x).sum::<f64>(), rc[s].iter().map(|x| x * x).sum::<f64>());
        assert!((n0 - n1).abs() < 1e-11 * n0.max(1e-300), "band {l}: |c|² {n0} → {n1}");
    }
}

#[test]
fn bad_rotations_and_lengths_are_refused() {
    let reflect = DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0));
    assert!(matches!(ShRotation::new(2, reflect), Err(SbfError::InvalidParameter { name: "rotation", .. })));
    let scaled = DMat3::from_rotation_y(0.4) * 1.0001;
    assert!(matches!(check_rotation(scaled), Err(SbfError::InvalidParameter { name: "rotation", .. })));
    let mut nan = DMat3::IDENTITY;
    nan.x_axis.y = f64::NAN;
    assert!(ShRotation::new(1, nan).is_err());
    assert!(matches!(ShRotation::new(1000, DMat3::IDENTITY), Err(SbfError::OrderTooHigh { .. })));
    // An f32-assembled rotation is accepted.
    let f32rot = sbf::glam::Mat3::from_rotation_x(1.1).as_dmat3();
    assert!(ShRotation::new(3, f32rot).is_ok());
    let rot = ShRotation::new(2, DMat3::IDENTITY).unwrap();
    assert!(matches!(rot.apply(&[1.0; 4]), Err(SbfError::LengthMismatch { .. })));
    let mut out = vec![0.0; 4];
    assert!(rot.apply_into(&[1.0; 9], &mut out).is_err());
    // The identity leaves coefficients unchanged.
    let c: Vec<f64> = (0..9).map(|k| k as f64 - 4.0).collect();
    let same = rot.apply(&c).unwrap();
    assert!(same.iter().zip(&c).all(|(a, b)| (a - b).abs() < 1e-15));
}
