//! The engine lightmap formats (`sbf::recon::engine`) against their published decodes and
//! closed forms.
//!
//! Oracles: (1) vectors worked by hand here from each engine's shader equation (cited in
//! the module docs) — the texture values and the expected E/π are typed in, not computed by
//! the library; (2) closed forms of a delta light (E/π = (1 + 2w·n)/(4π) in L1; Enlighten's
//! half-Lambert law C·(1 + n·w)/(1 + n₀·w)) and of a uniform hemisphere (Enlighten's SDK:
//! directionality ½).

use sbf::glam::DVec3;
use sbf::recon::engine::{decode, encode, EngineFormat, EnlightenInput, L1Irradiance, Moments, Texel};
use std::f64::consts::PI;

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
}

/// Texel with unit textures `u` (missing ones 1).
fn texel(colour: [f64; 3], u: &[[f64; 4]]) -> Texel {
    let mut unit = [[1.0; 4]; 3];
    unit[..u.len()].copy_from_slice(u);
    Texel { colour, unit }
}

#[test]
fn decodes_match_vectors_worked_from_the_published_shaders() {
    // Godot (scene_forward_clustered.glsl): ambient = L0 + Σ (2s − 1)·n_k·4·L0 over the
    // layers y, z, x. n = (0.6, 0.8, 0):
    //   R: 0.5 + 0.5·0.8·2 + 0 + (−0.5)·0.6·2 = 0.7;  G: 0.25 + 0.2·0·1 = 0.25;
    //   B: 2 + (−0.5)·0.8·8 + 0 + 1·0.6·8 = 3.6.
    let g = texel([0.5, 0.25, 2.0], &[[0.75, 0.5, 0.25, 1.0], [0.5, 0.6, 0.5, 1.0], [0.25, 0.5, 1.0, 1.0]]);
    let got = decode(EngineFormat::GodotL1, &g, DVec3::new(0.6, 0.8, 0.0));
    assert!(close(got, [0.7, 0.25, 3.6], 1e-14), "Godot: {got:?}");

    // Bakery MonoSH (Bakery.cginc): nL1 = 2t − 1 = (0.5, 0, 1); n = (0, 0.6, 0.8):
    // nL1·n = 0.8, sh = L0·(1 + 2·0.8) = 2.6·L0; n = −z: 1 − 2 < 0 → max(…, 0) = 0.
    let m = texel([1.0, 0.5, 0.2], &[[0.75, 0.5, 1.0, 1.0]]);
    let got = decode(EngineFormat::MonoSh, &m, DVec3::new(0.0, 0.6, 0.8));
    assert!(close(got, [2.6, 1.3, 0.52], 1e-14), "MonoSH: {got:?}");
    assert_eq!(decode(EngineFormat::MonoSh, &m, DVec3::NEG_Z), [0.0; 3]);

    // Enlighten (UnityCG.cginc DecodeDirectionalLightmap): halfLambert = n·(t.xyz − ½) + ½,
    // C·halfLambert/t.w. t = (1, ½, ½, 0.8): n = +x → 1/0.8; n = −x → 0; n = +y → 0.5/0.8.
    let e = texel([0.4, 0.2, 0.1], &[[1.0, 0.5, 0.5, 0.8]]);
    assert!(close(decode(EngineFormat::Enlighten, &e, DVec3::X), [0.5, 0.25, 0.125], 1e-15));
    assert!(close(decode(EngineFormat::Enlighten, &e, DVec3::NEG_X), [0.0; 3], 1e-15));
    assert!(close(decode(EngineFormat::Enlighten, &e, DVec3::Y), [0.25, 0.125, 0.0625], 1e-15));

    // Enlighten RGB: one t per channel. n = +y: R 0.5/1, G (0.5 + 0.5)/0.5, B 0.5/0.5.
    let r = texel([1.0; 3], &[[1.0, 0.5, 0.5, 1.0], [0.5, 1.0, 0.5, 0.5], [0.5, 0.5, 0.5, 0.5]]);
    assert!(close(decode(EngineFormat::EnlightenRgb, &r, DVec3::Y), [0.5, 2.0, 1.0], 1e-15));
}

/// SH L1 radiance coefficients of a delta light of unit integral from `w`, tinted `rgb`:
/// c₀ = 1/(2√π), (c₁, c₂, c₃) = √(3/4π)·(w_y, w_z, w_x) (the real SH at w).
fn delta_sh(w: DVec3, rgb: [f64; 3]) -> [[f64; 4]; 3] {
    let k1 = (3.0 / (4.0 * PI)).sqrt();
    rgb.map(|s| [0.5 / PI.sqrt() * s, k1 * w.y * s, k1 * w.z * s, k1 * w.x * s])
}

fn normals() -> Vec<DVec3> {
    // A Fibonacci sphere of 200 normals.
    let n = 200;
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let phi = i as f64 * PI * (3.0 - 5f64.sqrt());
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

#[test]
fn godot_and_monosh_round_trip_the_l1_irradiance_of_a_delta_light() {
    let w = DVec3::new(-0.4, 0.7, 0.59).normalize();
    let tint = [1.0, 0.5, 0.25];
    let l1 = L1Irradiance::from_sh(&delta_sh(w, tint));
    for f in [EngineFormat::GodotL1, EngineFormat::MonoSh] {
        let enc = encode(f, &l1, None).unwrap();
        assert_eq!(enc.clamped, 0, "{f:?}: nothing to clamp for a physical input");
        let stored = enc.texel.stored(f);
        for n in normals() {
            // Closed form: E/π = tint·(1 + 2w·n)/(4π); MonoSH clamps at 0 as its shader.
            let lin = (1.0 + 2.0 * w.dot(n)) / (4.0 * PI);
            let want = tint.map(|s| if f == EngineFormat::MonoSh { (s * lin).max(0.0) } else { s * lin });
            let got = decode(f, &enc.texel, n);
            assert!(close(got, want, 1e-15), "{f:?} at {n}: {got:?} vs {want:?}");
            // Stored precision. Error model: the colour in f16 (relative 2⁻¹¹) times a
            // decode factor |1 + 2w·n| ≤ 3; Godot's layers in f16 (values in [¼, ¾]: absolute
            // 2⁻¹²) times 8·L0·|n_k| each; MonoSH's direction in 8 bits (absolute 1/510) times
            // 4·L0·|n_k| each.
            let l0 = tint[0] / (4.0 * PI);
            let unit_err = if f == EngineFormat::GodotL1 { 8.0 * 2f64.powi(-12) } else { 4.0 / 510.0 };
            let tol = l0 * (3.0 * 2f64.powi(-11) + unit_err * (n.x.abs() + n.y.abs() + n.z.abs())) + 1e-15;
            let got = decode(f, &stored, n);
            assert!(close(got, want, tol), "{f:?} stored at {n}: {got:?} vs {want:?} (tol {tol:e})");
        }
    }
}

#[test]
fn enlighten_keeps_the_colour_at_the_baking_normal_and_follows_half_lambert_elsewhere() {
    let w = DVec3::new(0.3, -0.2, 0.93).normalize();
    let n0 = DVec3::Z;
    let tint = [0.8, 1.0, 0.3];
    let sh = delta_sh(w, tint);
    let l1 = L1Irradiance::from_sh(&sh);
    // The exact E/π at n₀ of the delta light: tint·max(0, w·n₀)/π.
    let exact = tint.map(|s| s * w.dot(n0).max(0.0) / PI);
    // Its mean direction over the sphere is w (SH L1 holds a delta light's moments exactly).
    let d = Moments::sphere(&sh).luminance_direction();
    assert!((d - w).length() < 1e-14, "{d} vs {w}");
    let input = EnlightenInput { normal: n0, irradiance: exact, moments: Moments::sphere(&sh) };
    assert!(encode(EngineFormat::Enlighten, &l1, None).is_none(), "Enlighten needs its input");
    for f in [EngineFormat::Enlighten, EngineFormat::EnlightenRgb] {
        let enc = encode(f, &l1, Some(&input)).unwrap();
        assert_eq!(enc.clamped, 0);
        for n in normals() {
            let want = exact.map(|c| c * (1.0 + n.dot(w)) / (1.0 + n0.dot(w)));
            let got = decode(f, &enc.texel, n);
            assert!(close(got, want, 1e-14), "{f:?} at {n}: {got:?} vs {want:?}");
        }
        assert!(close(decode(f, &enc.texel, n0), exact, 1e-15));
    }
}

#[test]
fn enlighten_directionality_of_a_uniform_hemisphere_is_one_half() {
    // The SDK: light uniform over the hemisphere has directionality ½. L = 1 over z > 0 and
    // 0 below (a texel's light, zero below its surface), projected on SH L1: c₀ = ∫Y₀₀ =
    // 2π/(2√π) = √π, c_z = √(3/4π)·∫cosθ = √(3/4π)·π.
    let k1 = (3.0 / (4.0 * PI)).sqrt();
    let sh = [[PI.sqrt(), 0.0, k1 * PI, 0.0]; 3];
    let d = Moments::sphere(&sh).luminance_direction();
    assert!((d - DVec3::new(0.0, 0.0, 0.5)).length() < 1e-15, "{d}");
    // Stored: (d + 1)/2 = (½, ½, ¾), rescaling factor ½(1 + n₀·d) = ¾ at n₀ = z.
    let input = EnlightenInput { normal: DVec3::Z, irradiance: [1.0; 3], moments: Moments::sphere(&sh) };
    let t = encode(EngineFormat::Enlighten, &L1Irradiance::from_sh(&sh), Some(&input)).unwrap().texel;
    assert!((t.unit[0][2] - 0.75).abs() < 1e-15 && (t.unit[0][3] - 0.75).abs() < 1e-15, "{:?}", t.unit[0]);
}

#[test]
fn out_of_range_inputs_are_clamped_and_counted() {
    // L1 longer than the Lambert bound (|a₁| > 2a₀: not a non-negative radiance).
    let l1 = L1Irradiance { a0: [0.1; 3], a1: [DVec3::new(0.5, 0.0, 0.0); 3] };
    let input =
        EnlightenInput { normal: DVec3::Y, irradiance: [0.1; 3], moments: Moments { m0: [0.1; 3], m1: [DVec3::new(0.5, 0.0, 0.0); 3] } };
    for f in EngineFormat::ALL {
        let enc = encode(f, &l1, Some(&input)).unwrap();
        assert!(enc.clamped > 0, "{f:?}");
        assert!(enc.texel.unit.iter().flatten().all(|v| (0.0..=1.0).contains(v)));
    }
    let nan = L1Irradiance { a0: [f64::NAN; 3], a1: [DVec3::ZERO; 3] };
    let enc = encode(EngineFormat::GodotL1, &nan, None).unwrap();
    assert!(enc.clamped > 0);
}
