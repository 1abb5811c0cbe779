//! The engine lightmap formats (`sbf::recon::engine`) against their published decodes and
//! closed forms.
//!
//! Oracles: (1) vectors worked by hand here from each engine's shader equation (cited in
//! the module docs) — the texture values and the expected E/π are typed in, not computed by
//! the library; (2) the engines' shader functions transcribed line by line in f32
//! ([`shader`]), run on the same texels as the library's f64 decode; (3) closed forms of a
//! delta light (E/π = (1 + 2w·n)/(4π) in L1; Geomerics' curve (1 + w·n)³/2 per unit L0 —
//! exact Lambert at the light's direction; Enlighten's half-Lambert law
//! C·(1 + n·w)/(1 + n₀·w)) and of a uniform hemisphere (Enlighten's SDK: directionality ½);
//! (4) coloured light — red, green and blue from different directions — with the Rec. 709
//! weights typed in here, so a channel swap or other luminance weights change a stored value.

#[path = "engine_formats/shader.rs"]
mod shader;

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
    let got = decode(EngineFormat::MonoShLinear, &m, DVec3::new(0.0, 0.6, 0.8));
    assert!(close(got, [2.6, 1.3, 0.52], 1e-14), "MonoSH linear: {got:?}");
    assert_eq!(decode(EngineFormat::MonoShLinear, &m, DVec3::NEG_Z), [0.0; 3]);

    // Bakery MonoSH non-linear (#if BAKERY_SHNONLINEAR), the same texel at n = (0, 0.6, 0.8):
    // luma L0 = 1.7, luma L1 = 2·1.7·nL1 = (1.7, 0, 3.4); R₀ = 1.7, R₁ = (0.85, 0, 1.7),
    // |R₁| = 0.85·√5, |R₁|/R₀ = √5/2; q = ½ + ½·(0.8·2/√5) = ½ + 0.8/√5;
    // p = 1 + √5, a = (1 − √5/2)/(1 + √5/2); lumaSH = R₀(a + (1 − a)(p + 1)q^p);
    // regular = 2.6·1.7 = 4.42 (weight saturate(16·4.42) = 1) → sh·lumaSH/4.42.
    let r5 = 5f64.sqrt();
    let (q, p, a) = (0.5 + 0.8 / r5, 1.0 + r5, (1.0 - r5 / 2.0) / (1.0 + r5 / 2.0));
    let luma = 1.7 * (a + (1.0 - a) * (p + 1.0) * q.powf(p));
    let got = decode(EngineFormat::MonoSh, &m, DVec3::new(0.0, 0.6, 0.8));
    assert!(close(got, [2.6, 1.3, 0.52].map(|v| v * luma / 4.42), 1e-13), "MonoSH: {got:?}");

    // Godot 4.0–4.3: 0.282095·L0 + 0.32573·(l_y·n.y + l_z·n.z + l_x·n.x), signed layers.
    // L0 = 1, l_y = −0.5, l_z = 2, l_x = 0.25 (every channel); n = (0.6, 0, 0.8):
    // 0.282095 + 0.32573·(0 + 1.6 + 0.15) = 0.282095 + 0.5700275 = 0.8521225.
    let l = texel([1.0; 3], &[[-0.5, -0.5, -0.5, 1.0], [2.0, 2.0, 2.0, 1.0], [0.25, 0.25, 0.25, 1.0]]);
    let got = decode(EngineFormat::GodotL1Legacy, &l, DVec3::new(0.6, 0.0, 0.8));
    assert!(close(got, [0.8521225; 3], 1e-14), "Godot 4.0–4.3: {got:?}");

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
    for f in [EngineFormat::GodotL1, EngineFormat::GodotL1Legacy, EngineFormat::MonoShLinear] {
        let enc = encode(f, &l1, None).unwrap();
        assert_eq!(enc.clamped, 0, "{f:?}: nothing to clamp for a physical input");
        let stored = enc.texel.stored(f);
        for n in normals() {
            // Closed form: E/π = tint·(1 + 2w·n)/(4π); MonoSH clamps at 0 as its shader.
            let lin = (1.0 + 2.0 * w.dot(n)) / (4.0 * PI);
            let want = tint.map(|s| if f == EngineFormat::MonoShLinear { (s * lin).max(0.0) } else { s * lin });
            let got = decode(f, &enc.texel, n);
            assert!(close(got, want, 1e-15), "{f:?} at {n}: {got:?} vs {want:?}");
            // Stored precision. Error model: the colour in f16 (relative 2⁻¹¹) times a
            // decode factor |1 + 2w·n| ≤ 3; Godot's layers in f16 (values in [¼, ¾]: absolute
            // 2⁻¹²) times 8·L0·|n_k| each; 4.0–4.3's raw layers (|l| ≤ 2·L0/0.32573·…: relative
            // 2⁻¹¹ of a term ≤ 2·L0) — within the same 8·2⁻¹²·L0; MonoSH's direction in 8 bits
            // (absolute 1/510) times 4·L0·|n_k| each.
            let l0 = tint[0] / (4.0 * PI);
            let unit_err = if f == EngineFormat::MonoShLinear { 4.0 / 510.0 } else { 8.0 * 2f64.powi(-12) };
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
        if f.signed_units() {
            // Godot 4.0–4.3 stores the coefficients as they are: nothing to clamp.
            assert_eq!(enc.clamped, 0, "{f:?}");
            assert!((enc.texel.unit[2][0] - 0.5 / 0.32573).abs() < 1e-12, "{:?}", enc.texel.unit);
            continue;
        }
        assert!(enc.clamped > 0, "{f:?}");
        assert!(enc.texel.unit.iter().flatten().all(|v| (0.0..=1.0).contains(v)));
    }
    let nan = L1Irradiance { a0: [f64::NAN; 3], a1: [DVec3::ZERO; 3] };
    let enc = encode(EngineFormat::GodotL1, &nan, None).unwrap();
    assert!(enc.clamped > 0);
}

/// A small deterministic generator (64-bit LCG, top bits) for test inputs.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn f32x3(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

#[test]
fn library_decodes_equal_the_shader_transcriptions() {
    // Texels as textures hold them (colours 0.01…3, Godot layers and directions as 8-bit or
    // f16 values in [0, 1], Godot 4.0–4.3's signed layers in ±L0·3) at 200 normals. Error
    // model: each transcription is ≲ 30 f32 operations of relative 2⁻²⁴ on terms ≤ 4·max L0;
    // Bakery's non-linear rescale multiplies by lumaSH/regular ≤ 4R₀/(R₀/4) = 16 where
    // regular ≥ ΣL0/4 (compared only there: below, the 0/0-like ratio is ill-conditioned in
    // f32 itself) → |f64 − f32| ≤ 30·2⁻²⁴·4·16·max L0 ≈ 1.2·10⁻⁴·max L0.
    let mut rng = Lcg(7);
    let mut compared = [0usize; 6];
    for _ in 0..300 {
        let colour = [0, 1, 2].map(|_| 0.01 + 3.0 * rng.next() * rng.next());
        let max_l0 = colour.iter().cloned().fold(0.0, f64::max);
        let byte = |r: &mut Lcg| (r.next() * 255.0).round() / 255.0;
        let mut unit = [[1.0; 4]; 3];
        for u in &mut unit {
            *u = [byte(&mut rng), byte(&mut rng), byte(&mut rng), byte(&mut rng).max(1.0 / 255.0)];
        }
        let signed: [[f64; 4]; 3] =
            [0, 1, 2].map(|_| [0, 1, 2, 3].map(|k| if k < 3 { (rng.next() * 2.0 - 1.0) * 3.0 * colour[k] } else { 1.0 }));
        for n in normals() {
            let nf = f32x3(n);
            let c32 = colour.map(|v| v as f32);
            let u32_ = |k: usize| [unit[k][0] as f32, unit[k][1] as f32, unit[k][2] as f32];
            let channel = |k: usize, u: &[[f64; 4]; 3]| [u[0][k] as f32, u[1][k] as f32, u[2][k] as f32];
            for f in EngineFormat::ALL {
                let t = Texel { colour, unit: if f.signed_units() { signed } else { unit } };
                let lib = decode(f, &t, n);
                let tr: [f32; 3] = match f {
                    EngineFormat::GodotL1 => shader::godot_4_4(c32, u32_(0), u32_(1), u32_(2), nf),
                    EngineFormat::GodotL1Legacy => {
                        // Layer k of the texel holds channel values (R, G, B) of one coefficient.
                        let layer = |l: usize| [signed[l][0] as f32, signed[l][1] as f32, signed[l][2] as f32];
                        let _ = channel;
                        shader::godot_4_0(c32, layer(0), layer(1), layer(2), nf)
                    }
                    EngineFormat::MonoSh | EngineFormat::MonoShLinear => {
                        let nl1 = DVec3::new(unit[0][0], unit[0][1], unit[0][2]) * 2.0 - DVec3::ONE;
                        let sum: f64 = colour.iter().sum();
                        let regular: f64 = colour.iter().map(|l0| l0 + 2.0 * l0 * nl1.dot(n)).sum();
                        if f == EngineFormat::MonoSh && (regular < sum / 4.0 || nl1.length() < 0.01) {
                            continue;
                        }
                        shader::bakery_mono_sh(c32, u32_(0), nf, f == EngineFormat::MonoSh)
                    }
                    EngineFormat::Enlighten => shader::unity_decode_directional_lightmap(c32, unit[0].map(|v| v as f32), nf),
                    EngineFormat::EnlightenRgb => {
                        [0, 1, 2].map(|k| shader::unity_decode_directional_lightmap(c32, unit[k].map(|v| v as f32), nf)[k])
                    }
                };
                let tol = 1.2e-4 * max_l0 * if f.signed_units() { 3.0 } else { 1.0 };
                for k in 0..3 {
                    assert!(
                        (lib[k] - tr[k] as f64).abs() <= tol,
                        "{f:?} channel {k} at {n}: library {} vs shader {} (tol {tol:e})",
                        lib[k],
                        tr[k]
                    );
                }
                compared[EngineFormat::ALL.iter().position(|g| *g == f).unwrap()] += 1;
            }
        }
    }
    // Every format compared on most of its inputs (MonoSH non-linear skips the ill-conditioned).
    assert!(compared.iter().all(|c| *c > 20_000), "{compared:?}");
}

#[test]
fn monosh_nonlinear_follows_geomerics_closed_form_for_one_light() {
    // One delta light from w, tinted: L0_k = s_k/(4π), direction t = (w + 1)/2. With c = w·n
    // the linear value is L0_k(1 + 2c); Geomerics' curve of the channel sum has R₁/R₀ = 1
    // (p = 3, a = 0): ΣL0·4q³ = ΣL0·(1 + c)³/2. BakeryMonoSH rescales the linear value by
    // lerp(1, (1 + c)³/(2(1 + 2c)), saturate(16·ΣL0·(1 + c·2))) and clamps at 0. At n = w that
    // is 4·L0_k = s_k/π: the exact Lambert irradiance of the light (the linear decode: 3/4 of
    // it) wherever the rescale's weight is 1.
    let w = DVec3::new(0.2, 0.9, -0.3).normalize();
    for tint in [[1.0, 0.5, 0.25], [0.02, 0.01, 0.03]] {
        let l1 = L1Irradiance::from_sh(&delta_sh(w, tint));
        let t = encode(EngineFormat::MonoSh, &l1, None).unwrap().texel;
        let sum: f64 = tint.iter().sum::<f64>() / (4.0 * PI);
        for n in normals().into_iter().chain([w]) {
            let c = w.dot(n);
            let lin = 1.0 + 2.0 * c;
            let weight = (16.0 * sum * lin).clamp(0.0, 1.0);
            let factor = if weight > 0.0 { 1.0 + weight * ((1.0 + c).powi(3) / (2.0 * lin) - 1.0) } else { 1.0 };
            let want = tint.map(|s| (s / (4.0 * PI) * lin * factor).max(0.0));
            let got = decode(EngineFormat::MonoSh, &t, n);
            assert!(close(got, want, 1e-12 * (1.0 + want[0])), "tint {tint:?} at {n}: {got:?} vs {want:?}");
        }
        // Exact at the light where the rescale is whole (16·ΣL0·3 ≥ 1; the dim tint's is not:
        // Bakery fades it out below luma 1/16).
        if 48.0 * sum >= 1.0 {
            let at_light = decode(EngineFormat::MonoSh, &t, w);
            assert!(close(at_light, tint.map(|s| s / PI), 1e-12), "{at_light:?}");
        }
    }
}

/// SH L1 radiance of three delta lights, one per channel: channel k gets intensity s_k from
/// w_k (c₀ = s_k/(2√π), (c₁, c₂, c₃) = s_k·√(3/4π)·(w_y, w_z, w_x)).
fn coloured_sh(ws: [DVec3; 3], s: [f64; 3]) -> [[f64; 4]; 3] {
    let k1 = (3.0 / (4.0 * PI)).sqrt();
    [0, 1, 2].map(|k| [0.5 / PI.sqrt() * s[k], k1 * ws[k].y * s[k], k1 * ws[k].z * s[k], k1 * ws[k].x * s[k]])
}

#[test]
fn coloured_light_reaches_each_channel_with_rec709_luminance() {
    // Red from +x-ish, green from +y-ish, blue from +z-ish: any channel swap, repeated
    // direction or other luminance weights changes a stored value below.
    let ws = [DVec3::new(0.9, 0.3, 0.1).normalize(), DVec3::new(-0.2, 0.95, 0.1).normalize(), DVec3::new(0.1, -0.3, 0.9).normalize()];
    let s = [1.0, 0.6, 1.4];
    // Rec. 709 luminance, typed here (ITU-R BT.709).
    let y709 = [0.2126, 0.7152, 0.0722];
    let sh = coloured_sh(ws, s);
    let l1 = L1Irradiance::from_sh(&sh);
    let a0 = s.map(|v| v / (4.0 * PI));
    // The luminance-weighted direction of the three lights (MonoSH's L1 over 2·L0, and
    // Enlighten's mean direction: the moments of a delta light are s and s·w).
    let d: DVec3 = (0..3).map(|k| ws[k] * (y709[k] * s[k])).sum::<DVec3>() / (0..3).map(|k| y709[k] * s[k]).sum::<f64>();
    let axes = [1usize, 2, 0];

    let g = encode(EngineFormat::GodotL1, &l1, None).unwrap().texel;
    let gl = encode(EngineFormat::GodotL1Legacy, &l1, None).unwrap().texel;
    for k in 0..3 {
        assert!((g.colour[k] - a0[k]).abs() < 1e-15, "Godot L0 channel {k}");
        assert!((gl.colour[k] - a0[k] / 0.282095).abs() < 1e-14, "Godot 4.0–4.3 L0 channel {k}");
        for (layer, axis) in axes.into_iter().enumerate() {
            // s = a₁/(8a₀) + ½ = w/4 + ½ for a₁ = 2·s·w/(4π); 4.0–4.3: a₁/0.32573.
            let wa = ws[k].to_array()[axis];
            assert!((g.unit[layer][k] - (wa / 4.0 + 0.5)).abs() < 1e-14, "Godot layer {layer} channel {k}");
            assert!((gl.unit[layer][k] - 2.0 * s[k] * wa / (4.0 * PI) / 0.32573).abs() < 1e-14, "Godot 4.0–4.3 layer {layer} channel {k}");
        }
    }
    // Through the shaders: each channel's own light (E/π = s_k(1 + 2w_k·n)/(4π)).
    for n in normals() {
        let nf = f32x3(n);
        let lay = |t: &Texel, l: usize| [t.unit[l][0] as f32, t.unit[l][1] as f32, t.unit[l][2] as f32];
        let got44 = shader::godot_4_4(g.colour.map(|v| v as f32), lay(&g, 0), lay(&g, 1), lay(&g, 2), nf);
        let got40 = shader::godot_4_0(gl.colour.map(|v| v as f32), lay(&gl, 0), lay(&gl, 1), lay(&gl, 2), nf);
        for k in 0..3 {
            let want = s[k] * (1.0 + 2.0 * ws[k].dot(n)) / (4.0 * PI);
            assert!((got44[k] as f64 - want).abs() < 1e-6, "Godot ≥ 4.4 channel {k} at {n}: {} vs {want}", got44[k]);
            assert!((got40[k] as f64 - want).abs() < 1e-6, "Godot 4.0–4.3 channel {k} at {n}: {} vs {want}", got40[k]);
        }
    }

    for f in [EngineFormat::MonoSh, EngineFormat::MonoShLinear] {
        let t = encode(f, &l1, None).unwrap().texel;
        assert!(close(t.colour, a0, 1e-15), "{f:?} L0");
        let want = (d + DVec3::ONE) * 0.5;
        assert!(
            (DVec3::new(t.unit[0][0], t.unit[0][1], t.unit[0][2]) - want).length() < 1e-14,
            "{f:?} direction {:?} vs {want}",
            t.unit[0]
        );
    }

    let n0 = DVec3::new(0.0, 0.6, 0.8);
    let input = EnlightenInput { normal: n0, irradiance: [0.3, 0.2, 0.1], moments: Moments::sphere(&sh) };
    let e = encode(EngineFormat::Enlighten, &l1, Some(&input)).unwrap().texel;
    let want = (d + DVec3::ONE) * 0.5;
    assert!(
        (DVec3::new(e.unit[0][0], e.unit[0][1], e.unit[0][2]) - want).length() < 1e-14,
        "Enlighten direction {:?} vs {want}",
        e.unit[0]
    );
    assert!((e.unit[0][3] - 0.5 * (1.0 + n0.dot(d))).abs() < 1e-14, "Enlighten rescaling factor");
    assert_eq!(e.colour, [0.3, 0.2, 0.1]);
    let r = encode(EngineFormat::EnlightenRgb, &l1, Some(&input)).unwrap().texel;
    for k in 0..3 {
        let want = (ws[k] + DVec3::ONE) * 0.5;
        assert!(
            (DVec3::new(r.unit[k][0], r.unit[k][1], r.unit[k][2]) - want).length() < 1e-14,
            "Enlighten RGB channel {k}: {:?} vs {want}",
            r.unit[k]
        );
        assert!((r.unit[k][3] - 0.5 * (1.0 + n0.dot(ws[k]))).abs() < 1e-14);
    }
}
