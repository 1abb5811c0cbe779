//! Environment-map geometry: solid angles, conventions, lookups, quadrature.
use crate::common;

use sbf::envmap::{CubeMap, LatLong, LatLongImage, ProceduralSky};
use sbf::glam::DVec3;
use std::f64::consts::PI;

/// Texel solid angles sum to 4π within 1e-12 (compensated sum; the per-texel
/// formulas are exact up to rounding).
#[test]
fn solid_angles_sum_to_4pi() {
    for (w, h) in [(256, 128), (1, 1), (7, 3), (4096, 2048)] {
        let g = LatLong::new(w, h).unwrap();
        let s = g.integrate(|_| 1.0);
        assert!((s - 4.0 * PI).abs() < 1e-12, "{w}×{h}: {s}");
    }
    for n in [1, 3, 64, 512] {
        let c = CubeMap::new(n).unwrap();
        let s = c.integrate(|_| 1.0);
        assert!((s - 4.0 * PI).abs() < 1e-12, "cube {n}: {s}");
    }
}

/// The convention of design.md: +Y up at row 0, image centre facing −Z, +X at u = ¾.
#[test]
fn latlong_convention() {
    let at = |u: f64, v: f64| LatLong::uv_to_direction(u, v);
    assert!((at(0.5, 0.0) - DVec3::Y).length() < 1e-15);
    assert!((at(0.5, 0.5) - DVec3::NEG_Z).length() < 1e-15);
    assert!((at(0.75, 0.5) - DVec3::X).length() < 1e-15);
    assert!((at(0.25, 0.5) - DVec3::NEG_X).length() < 1e-15);
    for d in common::random_directions(41, 10_000) {
        let (u, v) = LatLong::direction_to_uv(d);
        assert!((0.0..1.0).contains(&u) && (0.0..=1.0).contains(&v));
        // The formula in design.md, literally.
        let u_ref = (1.0 + d.x.atan2(-d.z) / PI) / 2.0;
        assert!((u - u_ref).abs() < 1e-15 || (u - u_ref).abs() > 1.0 - 1e-15);
        assert!((LatLong::uv_to_direction(u, v) - d).length() < 1e-12);
    }
}

#[test]
fn cubemap_round_trip_and_faces() {
    for d in common::random_directions(42, 10_000) {
        let (f, s, t) = CubeMap::vector_to_face_st(d);
        assert!(s.abs() <= 1.0 && t.abs() <= 1.0);
        let back = CubeMap::face_st_to_vector(f, s, t).normalize();
        assert!((back - d).length() < 1e-12, "{d} -> face {f} ({s}, {t}) -> {back}");
    }
    let c = CubeMap::new(8).unwrap();
    for f in 0..6 {
        let centre = (c.texel_direction(f, 3, 3) + c.texel_direction(f, 4, 4)).normalize();
        assert_eq!(CubeMap::vector_to_face_st(centre).0, f);
    }
}

/// Map quadrature integrates smooth functions to O(h²): ∫ z² = 4π/3 and ∫ y = 0.
#[test]
fn map_quadrature_accuracy() {
    let g = LatLong::new(1024, 512).unwrap();
    let z2 = g.integrate(|d| d.z * d.z);
    assert!((z2 - 4.0 * PI / 3.0).abs() < 1e-5, "{z2}");
    assert!(g.integrate(|d| d.y).abs() < 1e-12);
    let c = CubeMap::new(256).unwrap();
    assert!((c.integrate(|d| d.z * d.z) - 4.0 * PI / 3.0).abs() < 1e-4);
}

/// Bilinear lookup returns texel values at texel centres and blends linearly between.
#[test]
fn bilinear_lookup() {
    let img = LatLongImage::from_fn(16, 8, |d| [d.x, d.y, d.z]).unwrap();
    for j in 0..8 {
        for i in 0..16 {
            let v = img.bilinear(img.geometry.texel_direction(i, j));
            let t = img.texel(i, j);
            for c in 0..3 {
                assert!((v[c] - t[c] as f64).abs() < 1e-6, "({i},{j}) {v:?} vs {t:?}");
            }
        }
    }
    // Seam: u just below 1 blends the last and first columns.
    let d = LatLong::uv_to_direction(0.9999, 0.5);
    let v = img.bilinear(d);
    let (a, b) = (img.texel(15, 4)[0] as f64, img.texel(0, 4)[0] as f64);
    assert!(v[0] >= a.min(b) - 1e-6 && v[0] <= a.max(b) + 1e-6);
    assert!(LatLongImage::new(4, 2, vec![[0.0; 3]; 7]).is_err());
    assert!(LatLong::new(0, 4).is_err());
}

/// The built-in sky is finite, non-negative, bright at the sun and dark at the nadir.
#[test]
fn procedural_sky() {
    let sky = ProceduralSky::default();
    for d in common::random_directions(43, 5000) {
        assert!(sky.radiance(d).iter().all(|c| c.is_finite() && *c >= 0.0));
    }
    assert!(sky.radiance(sky.sun_direction)[0] > 100.0);
    assert!(sky.radiance(DVec3::NEG_Y)[0] < 1.0);
}
