//! `--engine-formats` export (`baker::output::engine`): the files written for texels whose
//! light has a closed form, read back as an engine would and decoded with the engines'
//! shader functions transcribed in f32 (`sbf/tests/engine_formats/shader.rs`, written from
//! the shader sources, not the library's decoder), in each engine's frame.
//!
//! Each texel (normal n₀, its tangent frame t, b as the bake uses) sees radiance 1 uniform
//! over its upper hemisphere plus, per colour channel k, a delta light of its own intensity
//! I_k = I·(1, 0.6, 0.3) from its own world direction w_k (tilted 0.6 rad from n₀ towards t,
//! −t and b for red, green and blue): a channel swap, one direction file written three
//! times, or other luminance weights than Rec. 709's give another texture. Channel k's SH L1
//! radiance coefficients in the tangent frame (the bake's storage, zero below the surface)
//! are c = (√π, 0, √(3/4π)·π, 0) + I_k·Y(w_k local). Closed forms at a shading normal n: L1
//! irradiance (1 + n·n₀)/2 + I_k(1 + 2w_k·n)/(4π) (Godot decodes exactly this); MonoSH's
//! L0_k = a₀_k = ½ + I_k/(4π) and one luminance direction
//! d_Y = Σ Y_k(n₀/2 + I_k·w_k/(2π)) / (2·Σ Y_k·a₀_k); Enlighten's direction
//! d = Σ Y_k(πn₀ + I_k·w_k)/Σ Y_k(2π + I_k) (RGB: each channel's (πn₀ + I_k·w_k)/(2π + I_k))
//! and its decode C_k·(1 + n·d)/(1 + n₀·d) with C_k = E/π at n₀ = 1 + I_k·w_k·n₀/π. Y = (0.2126, 0.7152, 0.0722) typed here (ITU-R BT.709). Unity's and
//! Bakery's files are in Unity's frame: x negated (UnityGLTF's glTF import).
//!
//! Error model: values rounded to f16 (relative 2⁻¹¹ on the colour, absolute 2⁻¹² on
//! Godot's layers in [¼, ¾], × 8·L0·|n_k| each; 4.0–4.3's signed layers relative 2⁻¹¹);
//! 8-bit directions and rescaling factors (1/510 each; Enlighten's relative to its
//! rescaling factor w = ½(1 + n₀·d)); f32 arithmetic of the transcriptions (≤ 10⁻⁶).

#[path = "../../sbf/tests/engine_formats/shader.rs"]
mod shader;

use baker::output::engine::write_engine_formats;
use baker::post::images::LightmapImages;
use baker::scene::geometry::frame;
use sbf::glam::DVec3;
use sbf::recon::engine::{EngineFormat, EngineFrame};
use std::f64::consts::PI;
use std::path::Path;

const W: usize = 8;
const H: usize = 4;
const I: f64 = 2.0;
/// Each channel's light intensity.
const IK: [f64; 3] = [I, 0.6 * I, 0.3 * I];
const Y709: [f64; 3] = [0.2126, 0.7152, 0.0722];

fn normals() -> Vec<DVec3> {
    (0..W * H)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / (W * H) as f64;
            let phi = i as f64 * PI * (3.0 - 5f64.sqrt());
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// Channel k's light at texel n₀: tilted 0.6 rad from n₀ towards t, −t, b.
fn light_dirs(n0: DVec3) -> [DVec3; 3] {
    let (t, b) = frame(n0.as_vec3());
    let (t, b) = (t.as_dvec3(), b.as_dvec3());
    [t, -t, b].map(|a| (n0 * 0.6f64.cos() + a * 0.6f64.sin()).normalize())
}

fn images() -> LightmapImages {
    let n = W * H;
    let k1 = (3.0 / (4.0 * PI)).sqrt();
    let mut img = LightmapImages {
        width: W,
        height: H,
        validity: vec![1.0; n],
        irradiance: vec![[0.0; 3]; n],
        standard_error: vec![[0.0; 3]; n],
        coefficients: vec![vec![vec![[0.0; 3]; n]; 4]],
        normals: vec![[0.0; 3]; n],
    };
    for (i, n0) in normals().into_iter().enumerate() {
        let (t, b) = frame(n0.as_vec3());
        for (ch, w) in light_dirs(n0).into_iter().enumerate() {
            let wl = DVec3::new(w.dot(t.as_dvec3()), w.dot(b.as_dvec3()), w.dot(n0));
            let ik = IK[ch];
            let c = [PI.sqrt() + ik * 0.5 / PI.sqrt(), ik * k1 * wl.y, k1 * PI + ik * k1 * wl.z, ik * k1 * wl.x];
            for (l, cl) in c.iter().enumerate() {
                img.coefficients[0][l][i][ch] = *cl as f32;
            }
            img.irradiance[i][ch] = (1.0 + ik * w.dot(n0) / PI) as f32;
        }
        img.normals[i] = n0.as_vec3().to_array();
    }
    img
}

fn exr(dir: &Path, name: &str) -> Vec<[f64; 3]> {
    let im = image::open(dir.join(name)).unwrap().to_rgba32f();
    im.pixels().map(|p| [p[0] as f64, p[1] as f64, p[2] as f64]).collect()
}

fn png(dir: &Path, name: &str) -> Vec<[f64; 4]> {
    let im = image::open(dir.join(name)).unwrap().to_rgba8();
    im.pixels().map(|p| p.0.map(|v| v as f64 / 255.0)).collect()
}

/// The PNG's gAMA chunk value (×100 000), read from the chunk list (PNG spec §5.3).
fn png_gamma(dir: &Path, name: &str) -> Option<u32> {
    let raw = std::fs::read(dir.join(name)).unwrap();
    let mut at = 8;
    while at + 8 <= raw.len() {
        let len = u32::from_be_bytes(raw[at..at + 4].try_into().unwrap()) as usize;
        if &raw[at + 4..at + 8] == b"gAMA" {
            return Some(u32::from_be_bytes(raw[at + 8..at + 12].try_into().unwrap()));
        }
        at += 12 + len;
    }
    None
}

fn unity(v: DVec3) -> DVec3 {
    DVec3::new(-v.x, v.y, v.z)
}

fn f3(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

fn rgb32(c: [f64; 3]) -> [f32; 3] {
    c.map(|v| v as f32)
}

#[test]
fn engine_files_decode_to_the_closed_form_per_channel() {
    let dir = std::env::temp_dir().join(format!("sbf-engine-formats-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let img = images();
    let rec = write_engine_formats(&dir, &img, &img.coefficients[0], None, &EngineFormat::ALL, None, false).unwrap();
    assert_eq!(rec.len(), 6);
    assert!(rec.iter().all(|r| r.clamped_values == 0), "{rec:?}");
    let g: Vec<Vec<[f64; 3]>> = (0..4).map(|k| exr(&dir, &format!("godot_l1_{k}.exr"))).collect();
    let gl: Vec<Vec<[f64; 3]>> = (0..4).map(|k| exr(&dir, &format!("godot_l1_legacy_{k}.exr"))).collect();
    let (m0, md) = (exr(&dir, "monosh_l0.exr"), png(&dir, "monosh_dir.png"));
    let (ec, ed) = (exr(&dir, "enlighten_irradiance.exr"), png(&dir, "enlighten_dir.png"));
    let rc = exr(&dir, "enlighten_rgb_irradiance.exr");
    let rd: Vec<Vec<[f64; 4]>> = ["r", "g", "b"].iter().map(|c| png(&dir, &format!("enlighten_rgb_dir_{c}.png"))).collect();
    for name in ["monosh_dir.png", "enlighten_dir.png", "enlighten_rgb_dir_r.png"] {
        assert_eq!(png_gamma(&dir, name), Some(100_000), "{name}: linear data needs gAMA 1.0");
    }
    for (i, n0) in normals().into_iter().enumerate() {
        let ws = light_dirs(n0);
        let (t, b) = frame(n0.as_vec3());
        let layer = |tex: &Vec<Vec<[f64; 3]>>, l: usize| rgb32(tex[l][i]);
        // The MonoSH textures themselves: L0 per channel and the luminance direction.
        let a0 = IK.map(|ik| 0.5 + ik / (4.0 * PI));
        let y_a1: DVec3 = (0..3).map(|k| (n0 * 0.5 + ws[k] * (IK[k] / (2.0 * PI))) * Y709[k]).sum();
        let y_a0: f64 = (0..3).map(|k| Y709[k] * a0[k]).sum();
        let d_mono = unity(y_a1 / (2.0 * y_a0));
        for k in 0..3 {
            assert!((m0[i][k] - a0[k]).abs() <= a0[k] * 2f64.powi(-11), "MonoSH L0 texel {i} channel {k}: {} vs {}", m0[i][k], a0[k]);
        }
        let stored = DVec3::new(md[i][0], md[i][1], md[i][2]) * 2.0 - DVec3::ONE;
        assert!((stored - d_mono).abs().max_element() <= 1.0 / 255.0 + 1e-9, "MonoSH direction texel {i}: {stored} vs {d_mono}");
        // Shading normals: n₀ and three tilts of 0.5 rad towards ±t and b (normal maps).
        let tilts = [DVec3::ZERO, t.as_dvec3(), -t.as_dvec3(), b.as_dvec3()];
        for tilt in tilts {
            let n = (n0 + tilt * 0.5f64.tan()).normalize();
            let lin = [0, 1, 2].map(|k| (1.0 + n.dot(n0)) / 2.0 + IK[k] * (1.0 + 2.0 * ws[k].dot(n)) / (4.0 * PI));
            let godot = shader::godot_4_4(layer(&g, 0), layer(&g, 1), layer(&g, 2), layer(&g, 3), f3(n));
            let legacy = shader::godot_4_0(layer(&gl, 0), layer(&gl, 1), layer(&gl, 2), layer(&gl, 3), f3(n));
            let sum_n = n.x.abs() + n.y.abs() + n.z.abs();
            for k in 0..3 {
                let l0 = g[0][i][k];
                let tol = l0 * (3.0 * 2f64.powi(-11) + 8.0 * 2f64.powi(-12) * sum_n) + 1e-6;
                assert!(
                    (godot[k] as f64 - lin[k]).abs() <= tol,
                    "Godot ≥ 4.4 texel {i} n {n} channel {k}: {} vs {} (tol {tol:.2e})",
                    godot[k],
                    lin[k]
                );
                assert!((legacy[k] as f64 - lin[k]).abs() <= tol, "Godot 4.0–4.3 texel {i} n {n} channel {k}: {} vs {}", legacy[k], lin[k]);
            }
            // MonoSH linear through Bakery's shader, in Unity's frame: one luminance direction.
            let mono = shader::bakery_mono_sh(rgb32(m0[i]), [md[i][0] as f32, md[i][1] as f32, md[i][2] as f32], f3(unity(n)), false);
            for k in 0..3 {
                let want = (a0[k] + 2.0 * a0[k] * d_mono.dot(unity(n))).max(0.0);
                let tol = a0[k] * (3.0 * 2f64.powi(-11) + 4.0 / 510.0 * sum_n) + 1e-6;
                assert!((mono[k] as f64 - want).abs() <= tol, "MonoSH texel {i} n {n} channel {k}: {} vs {want}", mono[k]);
            }
            // Enlighten (luminance direction) and Enlighten RGB (each channel's), Unity's decode.
            let m1: DVec3 = (0..3).map(|k| (n0 * PI + ws[k] * IK[k]) * Y709[k]).sum();
            let m0: f64 = (0..3).map(|k| Y709[k] * (2.0 * PI + IK[k])).sum();
            let d_lum = unity(m1 / m0);
            for k in 0..3 {
                let c = 1.0 + IK[k] * ws[k].dot(n0) / PI;
                for (name, col, u, d) in [
                    ("Enlighten", &ec, ed[i], d_lum),
                    ("Enlighten RGB", &rc, rd[k][i], unity((n0 * PI + ws[k] * IK[k]) / (2.0 * PI + IK[k]))),
                ] {
                    let (ne, n0e) = (unity(n), unity(n0));
                    let want = c * (1.0 + ne.dot(d)) / (1.0 + n0e.dot(d));
                    // Half-Lambert h = ½(1 + n·d) over w = ½(1 + n₀·d): each of d's components off
                    // by ≤ 1/510 moves h by ≤ √3/510·½·2 and w (8-bit) by 1/510.
                    let (h, wr) = (0.5 * (1.0 + ne.dot(d)), 0.5 * (1.0 + n0e.dot(d)));
                    let tol = c * (3.0 * 2f64.powi(-11) * h / wr + (3f64.sqrt() / 510.0) / wr + h / wr * (1.0 / 510.0) / wr) + 1e-6;
                    let got = shader::unity_decode_directional_lightmap(rgb32(col[i]), u.map(|v| v as f32), f3(ne))[k] as f64;
                    assert!((got - want).abs() <= tol, "{name} texel {i} n {n} channel {k}: {got} vs {want} (tol {tol:.2e})");
                }
            }
        }
    }
    // At the texel normal, Enlighten keeps the bake's E/π; storage is all it loses. Godot
    // decodes the L1 irradiance, the reference off the normal here (no SH L2 given):
    // storage is all it loses there too; Enlighten's half contrast loses more.
    let by = |f: &str| rec.iter().find(|r| r.format == f).unwrap();
    let e = by("enlighten");
    assert!((e.error_at_normal_rel_rms - e.storage_rel_rms).abs() < 1e-12 && e.storage_rel_rms < 0.01, "{e:?}");
    let g = by("godot-l1");
    assert_eq!(g.off_normal_reference, "sh1");
    assert!(g.error_off_normal_rel_rms < 2e-3 && e.error_off_normal_rel_rms > 5.0 * g.error_off_normal_rel_rms, "{g:?} {e:?}");
    assert!(g.frame.starts_with("gltf") && by("monosh").frame.starts_with("unity"), "{rec:?}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `--engine-frame gltf`: Unity's formats keep the scene's axes (x not negated).
#[test]
fn gltf_frame_keeps_the_scene_axes() {
    let dir = std::env::temp_dir().join(format!("sbf-engine-formats-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let img = images();
    let rec =
        write_engine_formats(&dir, &img, &img.coefficients[0], None, &[EngineFormat::MonoSh], Some(EngineFrame::Gltf), false).unwrap();
    assert!(rec[0].frame.starts_with("gltf"), "{rec:?}");
    let md = png(&dir, "monosh_dir.png");
    for (i, n0) in normals().into_iter().enumerate() {
        let ws = light_dirs(n0);
        let y_a1: DVec3 = (0..3).map(|k| (n0 * 0.5 + ws[k] * (IK[k] / (2.0 * PI))) * Y709[k]).sum();
        let y_a0: f64 = (0..3).map(|k| Y709[k] * (0.5 + IK[k] / (4.0 * PI))).sum();
        let d = y_a1 / (2.0 * y_a0);
        let stored = DVec3::new(md[i][0], md[i][1], md[i][2]) * 2.0 - DVec3::ONE;
        assert!((stored - d).abs().max_element() <= 1.0 / 255.0 + 1e-9, "texel {i}: {stored} vs {d}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The CLI refuses engine formats without the SH L1 basis they are encoded from, and names
/// unknown ones.
#[test]
fn engine_formats_need_sh1_and_known_names() {
    let bin = env!("CARGO_BIN_EXE_baker");
    let run = |args: &[&str]| std::process::Command::new(bin).args(args).output().unwrap();
    let o = run(&["--bases", "sh2", "--engine-formats", "monosh", "--passes", "1"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("add sh1 to the bases"), "{err}");
    let o = run(&["--bases", "sh1", "--engine-formats", "unreal", "--passes", "1"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("unknown engine format 'unreal'"), "{err}");
}

/// The block-compressed copies (`--compress bc6h`): read back by an independent reader
/// (image_dds: its own DDS parser and block layout over bcdec), decoded at the texel normal
/// by the engines' shader functions, they give the error bake.json states (to 1e-6
/// relative: the same blocks and decoder, summed in another order). Godot's shipped layout
/// is four BC6H layers (4 B/texel, signed for 4.0–4.3); the proposal (BC6H + three BC1) is a
/// labelled variant at 2.5 B/texel. (The texels here are unrelated neighbours — every one a
/// different normal — the worst case for 4 × 4 blocks, so the errors themselves are large;
/// a real lightmap's are in docs/baker.md.)
#[test]
fn compressed_engine_files_decode_to_the_stated_error() {
    let dir = std::env::temp_dir().join(format!("sbf-engine-formats-bc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let img = images();
    let rec = write_engine_formats(&dir, &img, &img.coefficients[0], None, &EngineFormat::ALL, None, true).unwrap();
    let read = |name: &str| -> (String, Vec<[f64; 4]>) {
        let dds = image_dds::ddsfile::Dds::read(std::fs::File::open(dir.join(name)).unwrap()).unwrap();
        let f = format!("{:?}", dds.get_dxgi_format().unwrap());
        if f == "BC6H_SF16" {
            // image_dds 0.7 decodes BC6H_SF16 blocks as unsigned (its decoder passes
            // is_signed = false): its parsed blocks go to bcdec's signed decode instead.
            let d = sbf::bc::decode_bc6h(W, H, &dds.data, true);
            return (f, d.iter().map(|p| [p[0] as f64, p[1] as f64, p[2] as f64, 1.0]).collect());
        }
        let s = image_dds::Surface::from_dds(&dds).unwrap().decode_rgbaf32().unwrap();
        (f, s.data.chunks_exact(4).map(|p| [p[0] as f64, p[1] as f64, p[2] as f64, p[3] as f64]).collect())
    };
    let mut checked = 0;
    for r in &rec {
        for c in r.compressed.iter().chain(&r.compressed_variants) {
            let tex: Vec<(String, Vec<[f64; 4]>)> = c.files.iter().map(|f| read(f)).collect();
            for ((f, _), stated) in tex.iter().zip(&c.dxgi_formats) {
                assert!(f.eq_ignore_ascii_case(stated), "{}: {f} vs {stated} in {:?}", r.format, c.files);
            }
            // The KTX2 beside each DDS: the same blocks, the matching Vulkan format, and the
            // engine named in its key/value data.
            for (file, stated) in c.files.iter().zip(&c.dxgi_formats) {
                let dds = image_dds::ddsfile::Dds::read(std::fs::File::open(dir.join(file)).unwrap()).unwrap();
                let bytes = std::fs::read(dir.join(file.replace(".dds", ".ktx2"))).unwrap();
                let k = ktx2::Reader::new(bytes.as_slice()).unwrap();
                let want = match *stated {
                    "BC6H_UF16" => ktx2::Format::BC6H_UFLOAT_BLOCK,
                    "BC6H_SF16" => ktx2::Format::BC6H_SFLOAT_BLOCK,
                    "BC1_UNORM" => ktx2::Format::BC1_RGB_UNORM_BLOCK,
                    _ => ktx2::Format::BC7_UNORM_BLOCK,
                };
                assert_eq!((k.header().format, k.header().pixel_width as usize), (Some(want), W), "{file}");
                assert!(k.levels().next().unwrap().data == dds.data.as_slice(), "{file}: KTX2 blocks differ from the DDS's");
                assert!(
                    k.key_value_data().any(|(key, v)| key == "sbf.engine" && v.starts_with(r.engine.split(',').next().unwrap().as_bytes())),
                    "{file}"
                );
            }
            let (mut e, mut s) = (0.0, 0.0);
            for (i, n) in normals().into_iter().enumerate() {
                let col = rgb32([tex[0].1[i][0], tex[0].1[i][1], tex[0].1[i][2]]);
                let u = |l: usize| tex[l].1[i].map(|v| v as f32);
                let u3 = |l: usize| [u(l)[0], u(l)[1], u(l)[2]];
                let (nu, ng) = (f3(unity(n)), f3(n));
                let got: [f32; 3] = match r.format {
                    "godot-l1" => shader::godot_4_4(col, u3(1), u3(2), u3(3), ng),
                    "godot-l1-legacy" => shader::godot_4_0(col, u3(1), u3(2), u3(3), ng),
                    "monosh" => shader::bakery_mono_sh(col, u3(1), nu, true),
                    "monosh-linear" => shader::bakery_mono_sh(col, u3(1), nu, false),
                    "enlighten" => shader::unity_decode_directional_lightmap(col, u(1), nu),
                    _ => [0, 1, 2].map(|k| shader::unity_decode_directional_lightmap(col, u(1 + k), nu)[k]),
                };
                for ch in 0..3 {
                    let want = img.irradiance[i][ch] as f64;
                    e += (got[ch] as f64 - want).powi(2);
                    s += want * want;
                }
            }
            let mine = (e / s).sqrt();
            println!(
                "{} [{}]: {:.2} B/texel, stated {:.5}, recomputed {mine:.5}",
                r.format, c.layout, c.bytes_per_texel, c.error_at_normal_rel_rms
            );
            assert!(
                (mine - c.error_at_normal_rel_rms).abs() <= 1e-5 * mine.max(1e-9),
                "{}: {mine} vs {}",
                r.format,
                c.error_at_normal_rel_rms
            );
            checked += 1;
        }
        let units = if matches!(r.format, "godot-l1" | "godot-l1-legacy" | "enlighten-rgb") { 3 } else { 1 };
        assert_eq!(r.compressed.as_ref().unwrap().files.len(), 1 + units, "{}", r.format);
    }
    assert_eq!(checked, 7, "six shipped layouts and Godot's proposal");
    let g = rec.iter().find(|r| r.format == "godot-l1").unwrap();
    let (shipped, proposal) = (g.compressed.as_ref().unwrap(), &g.compressed_variants[0]);
    // W × H = 8 × 4 texels: whole blocks, so bytes per texel are the formats' own.
    assert_eq!((shipped.bytes_per_texel, proposal.bytes_per_texel), (4.0, 2.5));
    assert!(shipped.dxgi_formats.iter().all(|f| *f == "BC6H_UF16") && proposal.layout.starts_with("proposal"), "{g:?}");
    let l = rec.iter().find(|r| r.format == "godot-l1-legacy").unwrap();
    assert!(l.compressed.as_ref().unwrap().dxgi_formats.iter().all(|f| *f == "BC6H_SF16"), "{l:?}");
    std::fs::remove_dir_all(&dir).ok();
}
