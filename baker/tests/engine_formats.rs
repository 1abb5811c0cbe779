//! `--engine-formats` export (`baker::output::engine`): the files written for texels whose
//! light has a closed form, read back as an engine would and decoded with the engines'
//! published equations (written out here, not the library's decoder).
//!
//! Each texel (normal n₀, its tangent frame t, b as the bake uses) sees radiance 1 uniform
//! over its upper hemisphere plus a delta light of intensity I from the world direction w
//! (above its surface). Its SH L1 radiance coefficients in the tangent frame (the bake's
//! storage, zero below the surface) are c = (√π, 0, √(3/4π)·π, 0) + I·Y(w_local). Closed
//! forms at a shading normal n: L1 irradiance (1 + n·n₀)/2 + I(1 + 2w·n)/(4π) (Godot and
//! MonoSH decode exactly this); Enlighten's direction d = (πn₀ + Iw)/(2π + I) and its
//! decode C·(1 + n·d)/(1 + n₀·d) with C = E/π at n₀ = 1 + I·w·n₀/π.
//!
//! Error model: values rounded to f16 (relative 2⁻¹¹ on the colour, absolute 2⁻¹² on
//! Godot's layers in [¼, ¾], × 8·L0·|n_k| each); 8-bit directions and rescaling factors
//! (1/510 each; Enlighten's relative to its rescaling factor w = ½(1 + n₀·d)).

use baker::output::engine::write_engine_formats;
use baker::post::images::LightmapImages;
use baker::scene::geometry::frame;
use sbf::glam::DVec3;
use sbf::recon::engine::EngineFormat;
use std::f64::consts::PI;
use std::path::Path;

const W: usize = 8;
const H: usize = 4;

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

/// The light of texel n₀: a delta light from w, tilted 0.6 rad from n₀ about t.
fn light_dir(n0: DVec3) -> DVec3 {
    let (t, _) = frame(n0.as_vec3());
    (n0 * 0.6f64.cos() + t.as_dvec3() * 0.6f64.sin()).normalize()
}

const I: f64 = 2.0;

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
        let w = light_dir(n0);
        let wl = DVec3::new(w.dot(t.as_dvec3()), w.dot(b.as_dvec3()), w.dot(n0));
        let c = [PI.sqrt() + I * 0.5 / PI.sqrt(), I * k1 * wl.y, k1 * PI + I * k1 * wl.z, I * k1 * wl.x];
        for (l, cl) in c.iter().enumerate() {
            img.coefficients[0][l][i] = [*cl as f32; 3];
        }
        img.normals[i] = n0.as_vec3().to_array();
        img.irradiance[i] = [(1.0 + I * w.dot(n0) / PI) as f32; 3];
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

#[test]
fn engine_files_decode_to_the_closed_form() {
    let dir = std::env::temp_dir().join(format!("sbf-engine-formats-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let img = images();
    let rec = write_engine_formats(&dir, &img, &img.coefficients[0], &EngineFormat::ALL, false).unwrap();
    assert_eq!(rec.len(), 4);
    assert!(rec.iter().all(|r| r.clamped_values == 0), "{rec:?}");
    let (l0, g1, g2, g3) =
        (exr(&dir, "godot_l1_0.exr"), exr(&dir, "godot_l1_1.exr"), exr(&dir, "godot_l1_2.exr"), exr(&dir, "godot_l1_3.exr"));
    let (m0, md) = (exr(&dir, "monosh_l0.exr"), png(&dir, "monosh_dir.png"));
    let (ec, ed) = (exr(&dir, "enlighten_irradiance.exr"), png(&dir, "enlighten_dir.png"));
    let (rc, rd) = (exr(&dir, "enlighten_rgb_irradiance.exr"), png(&dir, "enlighten_rgb_dir_g.png"));
    for (i, n0) in normals().into_iter().enumerate() {
        let w = light_dir(n0);
        let (t, b) = frame(n0.as_vec3());
        // Shading normals: n₀ and three tilts of 0.5 rad towards ±t and b (normal maps).
        let tilts = [DVec3::ZERO, t.as_dvec3(), -t.as_dvec3(), b.as_dvec3()];
        for tilt in tilts {
            let n = (n0 + tilt * 0.5f64.tan()).normalize();
            let lin = (1.0 + n.dot(n0)) / 2.0 + I * (1.0 + 2.0 * w.dot(n)) / (4.0 * PI);
            let nk = [n.y, n.z, n.x];
            // Godot: L0 + Σ (2s − 1)·n_k·4·L0 over the layers y, z, x.
            let godot =
                l0[i][0] + [g1[i][0], g2[i][0], g3[i][0]].iter().zip(nk).map(|(s, nk)| (s - 0.5) * 2.0 * nk * 4.0 * l0[i][0]).sum::<f64>();
            let tol = l0[i][0] * (3.0 * 2f64.powi(-11) + 8.0 * 2f64.powi(-12) * (n.x.abs() + n.y.abs() + n.z.abs()));
            assert!((godot - lin).abs() <= tol, "Godot texel {i} n {n}: {godot} vs {lin} (tol {tol:.2e})");
            // MonoSH: max(L0 + 2·L0·((2t − 1)·n), 0).
            let nl1 = DVec3::new(md[i][0], md[i][1], md[i][2]) * 2.0 - DVec3::ONE;
            let mono = (m0[i][0] + 2.0 * m0[i][0] * nl1.dot(n)).max(0.0);
            let tol = m0[i][0] * (3.0 * 2f64.powi(-11) + 4.0 / 510.0 * (n.x.abs() + n.y.abs() + n.z.abs()));
            assert!((mono - lin.max(0.0)).abs() <= tol, "MonoSH texel {i} n {n}: {mono} vs {lin} (tol {tol:.2e})");
            // Enlighten (both files, white light): C·(n·(t.xyz − ½) + ½)/t.w.
            let d = (n0 * PI + w * I) / (2.0 * PI + I);
            let c = 1.0 + I * w.dot(n0) / PI;
            let want = c * (1.0 + n.dot(d)) / (1.0 + n0.dot(d));
            // Half-Lambert h = ½(1 + n·d) over w = ½(1 + n₀·d): each of d's components off
            // by ≤ 1/510 moves h by ≤ √3/510·½·2 and w (8-bit) by 1/510.
            let (h, wr) = (0.5 * (1.0 + n.dot(d)), 0.5 * (1.0 + n0.dot(d)));
            let tol = c * (3.0 * 2f64.powi(-11) * h / wr + (3f64.sqrt() / 510.0) / wr + h / wr * (1.0 / 510.0) / wr);
            for (col, t) in [(&ec, &ed), (&rc, &rd)] {
                let u = t[i];
                let got = col[i][1] * (n.dot(DVec3::new(u[0], u[1], u[2]) - DVec3::splat(0.5)) + 0.5) / u[3].max(1e-4);
                assert!((got - want).abs() <= tol, "Enlighten texel {i} n {n}: {got} vs {want} (tol {tol:.2e})");
            }
        }
    }
    // At the texel normal, Enlighten keeps the bake's E/π; storage is all it loses.
    let e = rec.iter().find(|r| r.format == "enlighten").unwrap();
    assert!((e.error_at_normal_rel_rms - e.storage_rel_rms).abs() < 1e-12 && e.storage_rel_rms < 0.01, "{e:?}");
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
/// by the engines' equations, they give the error bake.json states (to 1e-6 relative: the
/// same blocks and decoder, summed in another order). (The texels here are unrelated
/// neighbours — every one a different normal — the worst case for 4 × 4 blocks, so the
/// errors themselves are large; a real lightmap's are in docs/baker.md.)
#[test]
fn compressed_engine_files_decode_to_the_stated_error() {
    let dir = std::env::temp_dir().join(format!("sbf-engine-formats-bc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let img = images();
    let rec = write_engine_formats(&dir, &img, &img.coefficients[0], &EngineFormat::ALL, true).unwrap();
    let read = |name: &str| -> Vec<[f64; 4]> {
        let dds = image_dds::ddsfile::Dds::read(std::fs::File::open(dir.join(name)).unwrap()).unwrap();
        let s = image_dds::Surface::from_dds(&dds).unwrap().decode_rgbaf32().unwrap();
        s.data.chunks_exact(4).map(|p| [p[0] as f64, p[1] as f64, p[2] as f64, p[3] as f64]).collect()
    };
    for r in &rec {
        let c = r.compressed.as_ref().unwrap();
        let tex: Vec<Vec<[f64; 4]>> = c.files.iter().map(|f| read(f)).collect();
        let (mut e, mut s) = (0.0, 0.0);
        for (i, n) in normals().into_iter().enumerate() {
            let col = tex[0][i];
            let half_lambert = |t: [f64; 4]| (n.dot(DVec3::new(t[0], t[1], t[2]) - DVec3::splat(0.5)) + 0.5) / t[3].max(1e-4);
            let got: [f64; 3] = match r.format {
                "godot-l1" => {
                    let nk = [n.y, n.z, n.x];
                    [0, 1, 2].map(|ch| col[ch] + (0..3).map(|l| (tex[l + 1][i][ch] - 0.5) * 2.0 * nk[l] * 4.0 * col[ch]).sum::<f64>())
                }
                "monosh" => {
                    let d = DVec3::new(tex[1][i][0], tex[1][i][1], tex[1][i][2]) * 2.0 - DVec3::ONE;
                    [0, 1, 2].map(|ch| (col[ch] + 2.0 * col[ch] * d.dot(n)).max(0.0))
                }
                "enlighten" => [0, 1, 2].map(|ch| col[ch] * half_lambert(tex[1][i])),
                _ => [0, 1, 2].map(|ch| col[ch] * half_lambert(tex[1 + ch][i])),
            };
            for ch in 0..3 {
                let want = img.irradiance[i][ch] as f64;
                e += (got[ch] - want).powi(2);
                s += want * want;
            }
        }
        let mine = (e / s).sqrt();
        println!("{}: {:.2} B/texel, stated {:.5}, recomputed {mine:.5}", r.format, c.bytes_per_texel, c.error_at_normal_rel_rms);
        assert!((mine - c.error_at_normal_rel_rms).abs() <= 1e-6 * mine.max(1e-9), "{}: {mine} vs {}", r.format, c.error_at_normal_rel_rms);
        let units = if matches!(r.format, "godot-l1" | "enlighten-rgb") { 3 } else { 1 };
        assert_eq!(c.files.len(), 1 + units, "{}: {:?}", r.format, c.files);
    }
    std::fs::remove_dir_all(&dir).ok();
}
