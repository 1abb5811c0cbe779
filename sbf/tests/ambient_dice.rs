//! Ambient Dice (SRBF 12/9, Bézier, YCoCg, linear) identities.
use crate::common;

use sbf::basis::ambient_dice::{srbf_lobe, ICOSAHEDRON_EDGE_COS};
use sbf::basis::ambient_dice_bezier::{rgb_to_ycocg, ycocg_to_rgb, BEZIER_A0, BEZIER_A1, BEZIER_A2};
use sbf::glam::DVec3;
use sbf::gram::GramOptions;
use sbf::{AmbientDiceBezier, AmbientDiceLinear, AmbientDiceSrbf, AmbientDiceYCoCg, Basis, Domain, Icosahedron};

fn check_regular(ico: &Icosahedron) {
    for (i, a) in ico.vertices().iter().enumerate() {
        assert!((a.length() - 1.0).abs() < 1e-15);
        let n = ico.vertices().iter().filter(|b| (a.dot(**b) - ICOSAHEDRON_EDGE_COS).abs() < 1e-12).count();
        assert_eq!(n, 5, "vertex {i} has {n} neighbours");
    }
    assert_eq!(ico.faces().len(), 20);
}

#[test]
fn icosahedra_are_regular() {
    check_regular(&Icosahedron::standard());
    check_regular(&Icosahedron::face_up());
    assert!((ICOSAHEDRON_EDGE_COS - 1.0 / 5f64.sqrt()).abs() < 1e-16);
}

/// The 12 SRBF lobes sum to 1 everywhere (icosahedron = spherical 5-design), to
/// 1e-12 (rounding of a 12-term sum of O(1) values), and exactly six lobes are
/// non-zero away from the lobes' zero sets.
#[test]
fn srbf12_is_partition_of_unity() {
    let ad = AmbientDiceSrbf::twelve();
    let mut w = [0.0; 12];
    for d in common::random_directions(11, 100_000) {
        ad.eval_into(d, &mut w);
        let s: f64 = w.iter().sum();
        assert!((s - 1.0).abs() < 1e-12, "sum {s} at {d}");
        assert_eq!(w.iter().filter(|x| **x > 0.0).count(), 6, "at {d}");
    }
}

/// The 9-lobe hemisphere set reproduces Roughton's table (4 decimals printed,
/// so 1e-4) and its sum over the upper hemisphere lies in [0.837, 1] (math.md).
#[test]
fn srbf9_matches_seed_table() {
    let seed = [
        [0.5257, -0.3035, 0.7947],
        [-0.5257, -0.3035, 0.7947],
        [0.0, 0.6071, 0.7947],
        [0.8507, 0.4911, 0.1876],
        [-0.8507, 0.4911, 0.1876],
        [0.0, -0.9822, 0.1876],
        [-0.8507, -0.4911, -0.1876],
        [0.8507, -0.4911, -0.1876],
        [0.0, 0.9822, -0.1876],
    ];
    let ad9 = AmbientDiceSrbf::nine_hemisphere();
    for (p, s) in ad9.lobes().iter().zip(seed) {
        let d = (*p - DVec3::from_array(s)).abs().max_element();
        assert!(d < 1e-4, "{p} vs {s:?}");
    }
    let mean: DVec3 = ad9.lobes().iter().copied().sum::<DVec3>() / 9.0;
    assert!(mean.x.abs() < 1e-12 && mean.y.abs() < 1e-12 && mean.z > 0.0, "mean axis {mean}");
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    let mut w = [0.0; 9];
    for d in common::random_directions(12, 50_000).into_iter().filter(|d| d.z >= 0.0) {
        ad9.eval_into(d, &mut w);
        let s: f64 = w.iter().sum();
        lo = lo.min(s);
        hi = hi.max(s);
    }
    assert!(lo > 0.83 && hi <= 1.0 + 1e-12, "sum range [{lo}, {hi}]");
}

#[test]
fn srbf_lobe_profile() {
    // 0.7·½c² + 0.3·⅚c⁴ ([Roughton19 eq. 8.3]), zero below the horizon.
    for c in [0.0, 0.3, 0.7, 1.0] {
        assert!((srbf_lobe(c) - (0.7 * 0.5 * c * c + 0.3 * 5.0 / 6.0 * c.powi(4))).abs() < 1e-15);
    }
    assert_eq!(srbf_lobe(-0.5), 0.0);
}

/// Bézier value weights sum within [0.93, 1] (math.md: [0.938, 1]); derivative
/// weights are finite; at a vertex the value weight is exactly that vertex's.
#[test]
fn bezier_value_weights_sum() {
    let bz = AmbientDiceBezier::new();
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    let mut w = [0.0; 36];
    for d in common::random_directions(13, 100_000) {
        bz.eval_into(d, &mut w);
        assert!(w.iter().all(|x| x.is_finite()));
        let s: f64 = (0..12).map(|i| w[3 * i]).sum();
        lo = lo.min(s);
        hi = hi.max(s);
    }
    assert!(lo >= 0.93 && hi <= 1.0 + 1e-12, "value-weight sum in [{lo}, {hi}]");
    for (i, v) in bz.icosahedron().vertices().iter().enumerate() {
        bz.eval_into(*v, &mut w);
        assert!((w[3 * i] - 1.0).abs() < 1e-12 && (w[3 * i + 1]).abs() < 1e-12, "vertex {i}: {:?}", &w[3 * i..3 * i + 3]);
    }
}

/// The patch reproduces linear functions a·d exactly (values f_i = a·v_i,
/// derivatives (a·T_i, a·B_i)): the derivation's defining identity, which pins the
/// edge factors, the tangent projections and a₀…a₂ together.
#[test]
fn bezier_reproduces_linear_functions() {
    // a₂ = cos θ/2 and a₀ + a₁(2cos θ + 1)/3 + 2cos θ·a₂/3 = cos θ/3 (derivation in the module docs).
    let c = ICOSAHEDRON_EDGE_COS;
    assert!((BEZIER_A2 - c / 2.0).abs() < 1e-15);
    assert!((BEZIER_A0 + BEZIER_A1 * (2.0 * c + 1.0) / 3.0 + 2.0 * c * BEZIER_A2 / 3.0 - c / 3.0).abs() < 1e-15);
    let bz = AmbientDiceBezier::new();
    let a = DVec3::new(0.3, -1.2, 0.7);
    let mut coeffs = [0.0; 36];
    for i in 0..12 {
        let (t, b) = bz.frame(i);
        coeffs[3 * i] = a.dot(bz.icosahedron().vertices()[i]);
        coeffs[3 * i + 1] = a.dot(t);
        coeffs[3 * i + 2] = a.dot(b);
    }
    let mut s = [0.0; 36];
    let mut worst = 0.0f64;
    for d in common::random_directions(14, 50_000) {
        worst = worst.max((bz.reconstruct(&coeffs, d, &mut s) - a.dot(d)).abs());
    }
    assert!(worst < 1e-12, "max error {worst:e}");
}

/// C⁰ across all 30 edges: points on each edge arc, nudged 1e-9 into each adjacent
/// face, reconstruct the same value for random coefficients (max jump ≤ 1e-6;
/// the nudge alone moves a value by ~1e-8 for O(1) coefficients).
#[test]
fn bezier_continuous_across_edges() {
    let bz = AmbientDiceBezier::new();
    let ico = bz.icosahedron();
    let mut rng = sbf::sampling::Pcg32::new(15, 1);
    let coeffs: Vec<f64> = (0..36).map(|_| 2.0 * rng.next_f64() - 1.0).collect();
    let mut edges = std::collections::BTreeSet::new();
    for f in ico.faces() {
        for k in 0..3 {
            let (a, b) = (f[k].min(f[(k + 1) % 3]), f[k].max(f[(k + 1) % 3]));
            edges.insert((a, b));
        }
    }
    assert_eq!(edges.len(), 30);
    let mut s = [0.0; 36];
    let mut worst = 0.0f64;
    for &(a, b) in &edges {
        let (va, vb) = (ico.vertices()[a], ico.vertices()[b]);
        let normal = va.cross(vb).normalize();
        for k in 1..20 {
            let t = k as f64 / 20.0;
            let p = (va * (1.0 - t) + vb * t).normalize();
            let v1 = bz.reconstruct(&coeffs, (p + 1e-9 * normal).normalize(), &mut s);
            let v2 = bz.reconstruct(&coeffs, (p - 1e-9 * normal).normalize(), &mut s);
            worst = worst.max((v1 - v2).abs());
        }
    }
    assert!(worst <= 1e-6, "max jump across edges {worst:e}");
}

/// YCoCg: colour transform round trip; a constant colour is reproduced by the
/// linear chroma exactly and by the Bézier luma to within its value-weight sum.
#[test]
fn ycocg_round_trip_and_constants() {
    for rgb in [[1.0, 0.0, 0.0], [0.2, 0.5, 0.9], [3.0, 1e-3, 1e4]] {
        let back = ycocg_to_rgb(rgb_to_ycocg(rgb));
        // Channels mix, so rounding is relative to the largest channel (a few ulps).
        let scale = rgb.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        for k in 0..3 {
            assert!((back[k] - rgb[k]).abs() <= 4.0 * f64::EPSILON * scale, "{rgb:?} -> {back:?}");
        }
    }
    let lin = AmbientDiceLinear::new();
    let mut w = [0.0; 12];
    for d in common::random_directions(16, 10_000) {
        lin.eval_into(d, &mut w);
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-13);
        assert!(w.iter().all(|x| *x >= -1e-15));
    }
    let yc = AmbientDiceYCoCg::new();
    let col = rgb_to_ycocg([0.8, 0.4, 0.2]);
    let mut y = [0.0; 36];
    for i in 0..12 {
        y[3 * i] = col[0];
    }
    // By value: chroma is linear (partition of unity, exact), luma is the Bézier value
    // weights' sum S(d) ∈ [0.938, 1] times Y (derivatives 0), and RGB follows from Malvar &
    // Sullivan's inverse written out here: R = Y − Cg + Co, G = Y + Cg, B = Y − Cg − Co.
    let bz = AmbientDiceBezier::new();
    let mut w = [0.0; 36];
    for d in common::random_directions(19, 2_000) {
        let rgb = yc.eval_rgb(&y, &[col[1]; 12], &[col[2]; 12], d);
        bz.eval_into(d, &mut w);
        let luma = col[0] * (0..12).map(|i| w[3 * i]).sum::<f64>();
        let want = [luma - col[2] + col[1], luma + col[2], luma - col[2] - col[1]];
        for c in 0..3 {
            assert!((rgb[c] - want[c]).abs() < 1e-14, "{d}: {rgb:?} vs {want:?}");
        }
    }
    // The colour itself round-trips through the transform pair to rounding.
    let back = ycocg_to_rgb(col);
    assert!(back.iter().zip([0.8, 0.4, 0.2]).all(|(a, b)| (a - b).abs() < 1e-15), "{back:?}");
    assert_eq!(AmbientDiceYCoCg::COEFFICIENTS, 36 + 12 + 12);
}

/// Quadrature error of the default Gram resolution is small for kinked bases.
#[test]
fn ad_gram_quadrature_error_is_reported() {
    let g = sbf::gram::gram_matrix(&AmbientDiceSrbf::twelve(), Domain::Sphere, GramOptions::default()).unwrap();
    assert!(g.quadrature_error < 1e-7, "estimated error {:e}", g.quadrature_error);
    // math.md: diagonal ≈ 0.35465.
    assert!((g.matrix[(0, 0)] - 0.35465).abs() < 5e-5, "G00 = {}", g.matrix[(0, 0)]);
}

/// Appendix C's Listing 8.2 table weighs each sample by G2·G1(v) instead of G2/G1(v); v is
/// fixed per entry, so each of its entries is the physical entry times G1(v)² (an identity:
/// the same samples, the same horizon test). Tolerance 1e-12 relative: the per-sample
/// weights are computed by different products (rounding ~1e-16 each) and summed over 512
/// samples. Mutations tried: Roughton's weight's G1 dropped (G2 only) — fails at every n·v < 1.
#[test]
fn appendix_c_lut_entries_are_the_physical_ones_times_g1_squared() {
    use sbf::ggx::{self, Convention};
    use sbf::recon::ambient_dice::specular_lut_entry_with;
    for alpha in [0.05, 0.2, 0.5, 0.8, 1.0] {
        for nv in [0.02, 0.1, 0.3, 0.6, 0.9, 1.0] {
            let v = DVec3::new(0.0, (1.0f64 - nv * nv).max(0.0).sqrt(), nv);
            let g1 = ggx::g1(v, alpha);
            let phys = specular_lut_entry_with(nv, alpha, 512, Convention::Physical);
            let seed = specular_lut_entry_with(nv, alpha, 512, Convention::AppendixC);
            for c in 0..2 {
                let want = phys[c] * g1 * g1;
                assert!((seed[c] - want).abs() <= 1e-12 * want.abs() + 1e-300, "α {alpha} n·v {nv} channel {c}: {} vs {want}", seed[c]);
            }
        }
    }
}
