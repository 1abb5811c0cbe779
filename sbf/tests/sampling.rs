//! Samplers: pdfs integrate to 1, χ² goodness of fit at fixed seeds, inverse round trips.
use crate::common;

use common::{chi2_directions, chi2_z};
use sbf::ggx;
use sbf::glam::{DVec2, DVec3};
use sbf::quadrature::SphereQuadrature;
use sbf::sampling::*;
use sbf::Domain;
use std::f64::consts::PI;

const N: usize = 200_000;
/// z-score above which χ² rejects (p ≈ 5e-4). Fixed seeds make each test
/// deterministic; a wrong warp or pdf gives z in the tens or hundreds.
const Z_MAX: f64 = 3.3;

fn chi2_unit_square(points: &[[f64; 2]], bins: usize) -> f64 {
    let mut obs = vec![0.0; bins * bins];
    for p in points {
        assert!((0.0..1.0).contains(&p[0]) && (0.0..1.0).contains(&p[1]), "{p:?} outside [0,1)²");
        obs[(p[1] * bins as f64) as usize * bins + (p[0] * bins as f64) as usize] += 1.0;
    }
    let e = points.len() as f64 / (bins * bins) as f64;
    chi2_z(&obs, &vec![e; bins * bins]).0
}

#[test]
fn sequences_are_uniform() {
    let r2 = R2::with_seed(3);
    let r3 = R3::with_seed(3);
    // R3: every pair of its three coordinates, and the first two restricted to points
    // whose third is below ½ (a mixture choice keeps both halves stratified).
    let r3p: Vec<[f64; 3]> = (0..2 * N as u64).map(|i| r3.point(i)).collect();
    let sets: [(&str, Vec<[f64; 2]>); 8] = [
        ("halton", (0..N as u64).map(halton2).collect()),
        ("hammersley", (0..N as u64).map(|i| hammersley2(i, N as u64)).collect()),
        ("r2", (0..N as u64).map(|i| r2.point(i)).collect()),
        ("r3 (0, 1)", r3p[..N].iter().map(|p| [p[0], p[1]]).collect()),
        ("r3 (0, 2)", r3p[..N].iter().map(|p| [p[0], p[2]]).collect()),
        ("r3 (1, 2)", r3p[..N].iter().map(|p| [p[1], p[2]]).collect()),
        ("r3 (0, 1) | x2 < 1/2", r3p.iter().filter(|p| p[2] < 0.5).map(|p| [p[0], p[1]]).collect()),
        ("pcg32", {
            let mut rng = Pcg32::new(1, 2);
            (0..N).map(|_| rng.next_2d()).collect()
        }),
    ];
    for (name, pts) in &sets {
        let z = chi2_unit_square(pts, 16);
        assert!(z < Z_MAX, "{name}: χ² z = {z}");
    }
    // Radical inverse: exact digit reversal.
    assert_eq!(radical_inverse(2, 0b1011), 0.5 + 0.25 + 0.0625);
    assert!((radical_inverse(3, 5) - (2.0 / 3.0 + 1.0 / 9.0)).abs() < 1e-15);
}

/// Hammersley in index order is a set, not a sequence: its first half covers only
/// half of the first coordinate's range (why it breaks progressive encoding).
#[test]
fn hammersley_prefix_is_not_uniform() {
    let pts: Vec<[f64; 2]> = (0..N as u64 / 2).map(|i| hammersley2(i, N as u64)).collect();
    assert!(pts.iter().all(|p| p[0] < 0.5));
    let halton: Vec<[f64; 2]> = (0..N as u64 / 2).map(halton2).collect();
    assert!(chi2_unit_square(&halton, 16) < Z_MAX);
}

#[test]
fn sphere_and_hemisphere_warps() {
    let mut rng = Pcg32::new(21, 0);
    let us: Vec<[f64; 2]> = (0..N).map(|_| rng.next_2d()).collect();
    let s: Vec<DVec3> = us.iter().map(|u| uniform_sphere(*u)).collect();
    assert!(chi2_directions(&s, |_| UNIFORM_SPHERE_PDF, -1.0, 12, 24) < Z_MAX);
    let h: Vec<DVec3> = us.iter().map(|u| uniform_hemisphere(*u)).collect();
    assert!(chi2_directions(&h, |_| UNIFORM_HEMISPHERE_PDF, 0.0, 12, 24) < Z_MAX);
    let hc: Vec<DVec3> = us.iter().map(|u| uniform_hemisphere_concentric(*u)).collect();
    assert!(hc.iter().all(|d| (d.length() - 1.0).abs() < 1e-14 && d.z >= 0.0));
    assert!(chi2_directions(&hc, |_| UNIFORM_HEMISPHERE_PDF, 0.0, 12, 24) < Z_MAX);
    let c: Vec<DVec3> = us.iter().map(|u| cosine_hemisphere(*u)).collect();
    assert!(chi2_directions(&c, cosine_hemisphere_pdf, 0.0, 12, 24) < Z_MAX);
    // A wrong pdf is rejected (the test has power).
    assert!(chi2_directions(&c, |_| UNIFORM_HEMISPHERE_PDF, 0.0, 12, 24) > 10.0);
    // Pdfs integrate to 1 (rules exact for these polynomial pdfs).
    let sph = SphereQuadrature::exact_for_degree(Domain::Sphere, 2);
    let hem = SphereQuadrature::exact_for_degree(Domain::UpperHemisphere, 2);
    assert!((sph.integrate(|_| UNIFORM_SPHERE_PDF) - 1.0).abs() < 1e-14);
    assert!((hem.integrate(|_| UNIFORM_HEMISPHERE_PDF) - 1.0).abs() < 1e-14);
    assert!((hem.integrate(cosine_hemisphere_pdf) - 1.0).abs() < 1e-14);
}

#[test]
fn warp_inverses_round_trip() {
    let mut rng = Pcg32::new(22, 0);
    for _ in 0..20_000 {
        let u = rng.next_2d();
        for (name, back) in [
            ("sphere", uniform_sphere_inv(uniform_sphere(u))),
            ("hemisphere", uniform_hemisphere_inv(uniform_hemisphere(u))),
            ("cosine", cosine_hemisphere_inv(cosine_hemisphere(u))),
            ("disk", concentric_disk_inv(concentric_disk(u))),
            ("concentric hemisphere", uniform_hemisphere_concentric_inv(uniform_hemisphere_concentric(u))),
        ] {
            // Round trips lose a few ulps through acos/atan2/sqrt; 1e-9 is generous
            // except for φ at the seam, handled by comparing on the circle.
            let du = (back[0] - u[0]).abs();
            let dv = (back[1] - u[1]).abs().min(1.0 - (back[1] - u[1]).abs());
            assert!(du < 1e-9 && dv < 1e-9, "{name}: {u:?} -> {back:?}");
        }
    }
}

#[test]
fn concentric_disk_is_uniform() {
    let mut rng = Pcg32::new(23, 0);
    let pts: Vec<DVec2> = (0..N).map(|_| concentric_disk(rng.next_2d())).collect();
    // Equal-area cells: 10 rings in r², 16 sectors.
    let mut obs = vec![0.0; 160];
    for p in &pts {
        assert!(p.length() <= 1.0 + 1e-15);
        let ring = ((p.length_squared() * 10.0) as usize).min(9);
        let mut a = p.y.atan2(p.x);
        if a < 0.0 {
            a += 2.0 * PI;
        }
        obs[ring * 16 + ((a / (2.0 * PI) * 16.0) as usize).min(15)] += 1.0;
    }
    assert!(chi2_z(&obs, &vec![N as f64 / 160.0; 160]).0 < Z_MAX);
    // ∫ pdf dA over the unit disk, in polar coordinates with Gauss–Legendre in r.
    let (gx, gw) = sbf::quadrature::gauss_legendre(8);
    let integral: f64 = gx.iter().zip(&gw).map(|(x, w)| 0.5 * w * CONCENTRIC_DISK_PDF * 0.5 * (x + 1.0) * 2.0 * PI).sum();
    assert!((integral - 1.0).abs() < 1e-14, "{integral}");
}

#[test]
fn spherical_fibonacci_points_and_inverse() {
    let n = 50_000u64;
    let pts: Vec<DVec3> = (0..n).map(|i| spherical_fibonacci(i, n)).collect();
    assert!(chi2_directions(&pts, |_| UNIFORM_SPHERE_PDF, -1.0, 12, 24) < Z_MAX);
    for (i, p) in pts.iter().enumerate().step_by(97) {
        assert_eq!(spherical_fibonacci_nearest(*p, n), i as u64);
    }
    // Nearest-point inverse agrees with brute force on random queries.
    let m = 2000u64;
    let set: Vec<DVec3> = (0..m).map(|i| spherical_fibonacci(i, m)).collect();
    for d in common::random_directions(24, 500) {
        let brute = (0..m as usize).min_by(|a, b| (set[*a] - d).length_squared().total_cmp(&(set[*b] - d).length_squared())).unwrap();
        assert_eq!(spherical_fibonacci_nearest(d, m), brute as u64, "{d}");
    }
}

/// GGX VNDF: the visible-normal pdf integrates to 1 for any view, and samples
/// follow it (χ² on the half-vector hemisphere).
#[test]
fn ggx_vndf_pdf_and_chi2() {
    let rule = SphereQuadrature::gauss_product(Domain::UpperHemisphere, 600, 400);
    for alpha in [0.2, 0.5, 1.0] {
        for theta in [0.0f64, 0.7, 1.4, 1.55] {
            let v = DVec3::new(theta.sin(), 0.0, theta.cos());
            let integral = rule.integrate(|h| ggx::vndf_pdf(v, h, alpha));
            // Peaked but smooth integrand on a 600-node GL rule: ~1e-6 accurate.
            assert!((integral - 1.0).abs() < 1e-4, "α={alpha} θ={theta}: ∫pdf = {integral}");
            let mut rng = Pcg32::new(31, (alpha * 10.0) as u64);
            let hs: Vec<DVec3> = (0..N).map(|_| ggx::sample_vndf(v, alpha, rng.next_2d())).collect();
            let z = chi2_directions(&hs, |h| ggx::vndf_pdf(v, h, alpha), 0.0, 16, 24);
            assert!(z < Z_MAX, "α={alpha} θ={theta}: χ² z = {z}");
        }
    }
}

/// Stiff cases: α down to 1e-4 and grazing views give finite D, G1, G2, pdfs and samples.
#[test]
fn ggx_extremes_are_finite() {
    let mut rng = Pcg32::new(32, 0);
    for alpha in [1e-4, 1e-3, 0.05, 1.0] {
        for cos_v in [1e-4f64, 1e-2, 0.5, 1.0] {
            let v = DVec3::new((1.0 - cos_v * cos_v).sqrt(), 0.0, cos_v);
            for _ in 0..1000 {
                let h = ggx::sample_vndf(v, alpha, rng.next_2d());
                let l = ggx::reflect(v, h);
                let vals = [
                    ggx::d(h, alpha),
                    ggx::g1(v, alpha),
                    ggx::g2(v, l, alpha),
                    ggx::vndf_pdf(v, h, alpha),
                    ggx::vndf_reflected_pdf(v, l, alpha),
                ];
                assert!(h.is_finite() && (h.length() - 1.0).abs() < 1e-9, "α={alpha} cos={cos_v}: h={h}");
                assert!(vals.iter().all(|x| x.is_finite() && *x >= 0.0), "α={alpha} cos={cos_v}: {vals:?}");
            }
        }
    }
    assert_eq!(ggx::g1(DVec3::new(1.0, 0.0, 0.0), 0.5), 0.0);
    assert_eq!(ggx::g1(DVec3::new(0.0, 0.0, -1.0), 0.5), 0.0);
}
