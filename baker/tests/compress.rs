//! `--compress bc6h`: the DDS files read back by an independent reader (image_dds: its own
//! DDS parser and block layout, decoding with bcdec) agree with what bake.json states, and
//! the error is what BC6H can do.
//!
//! Oracle: for every image bake.json lists, the RMS of (decoded − EXR source) over baked
//! texels, relative to the source's RMS, recomputed here from the two files — bake.json's
//! value must match it to f32 summation rounding (1e-4 relative; both sides decode the same
//! blocks). Bound on the error itself: BC6H_UF16 keeps 10–16-bit endpoints and 3–4-bit
//! indices per 4 × 4 block; a smooth lightmap stays within a few percent, and no image
//! loses more than 25 % of its RMS.

use serde_json::Value;
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sbf-compress-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The KTX2 file beside a DDS, read by the `ktx2` crate: its header's format and size, its
/// level data, and its key/value pairs.
fn ktx2_file(path: &std::path::Path) -> (ktx2::Header, Vec<u8>, Vec<(String, String)>) {
    let bytes = std::fs::read(path).unwrap();
    let r = ktx2::Reader::new(bytes.as_slice()).unwrap();
    let level = r.levels().next().unwrap().data.to_vec();
    let kv = r.key_value_data().map(|(k, v)| (k.to_string(), String::from_utf8_lossy(v).trim_end_matches('\0').to_string())).collect();
    (r.header(), level, kv)
}

/// The `sbf.offset` of a KTX2 file's key/value pairs.
fn ktx2_offset(kv: &[(String, String)]) -> Vec<f64> {
    let v = &kv.iter().find(|(k, _)| k == "sbf.offset").expect("sbf.offset in the KTX2").1;
    v.split_whitespace().map(|x| x.parse().unwrap()).collect()
}

fn exr(path: &std::path::Path) -> (Vec<[f64; 3]>, Vec<f64>) {
    let im = image::open(path).unwrap().to_rgba32f();
    (im.pixels().map(|p| [p[0] as f64, p[1] as f64, p[2] as f64]).collect(), im.pixels().map(|p| p[3] as f64).collect())
}

#[test]
fn bc6h_files_decode_to_the_error_bake_json_states() {
    let out = tmp("cornell");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_baker"))
        .args([
            "--device",
            "cpu",
            "--passes",
            "8",
            "--texels-per-unit",
            "6",
            "--bases",
            "sh1,ad9",
            "--probes",
            "0,0,0",
            "--compress",
            "bc6h",
            "--preview-width",
            "16",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta: Value = serde_json::from_str(&std::fs::read_to_string(out.join("bake.json")).unwrap()).unwrap();
    let c = &meta["compression"];
    let images = c["images"].as_array().unwrap();
    assert_eq!(images.len(), 1 + 4 + 9, "irradiance, sh1 ×4, ad9 ×9");
    for im in images {
        let file = im["file"].as_str().unwrap();
        let dds = image_dds::ddsfile::Dds::read(std::fs::File::open(out.join(file)).unwrap()).unwrap();
        assert_eq!(dds.get_dxgi_format(), Some(image_dds::ddsfile::DxgiFormat::BC6H_UF16), "{file}");
        let surf = image_dds::Surface::from_dds(&dds).unwrap().decode_rgbaf32().unwrap();
        let (src, alpha) = exr(&out.join(im["source"].as_str().unwrap()));
        assert_eq!((surf.width * surf.height) as usize, src.len(), "{file}: size");
        let offset: Vec<f64> = im["offset"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let (mut e, mut s) = (0.0, 0.0);
        for (t, (p, a)) in src.iter().zip(&alpha).enumerate() {
            if *a <= 0.0 {
                continue;
            }
            for k in 0..3 {
                let d = surf.data[4 * t + k] as f64 - offset[k];
                e += (d - p[k]).powi(2);
                s += p[k] * p[k];
            }
        }
        let mine = if s > 0.0 { (e / s).sqrt() } else { 0.0 };
        let stated = im["rel_rms"].as_f64().unwrap();
        println!("{file}: stated {stated:.5}, recomputed {mine:.5}");
        assert!((mine - stated).abs() <= 1e-4 * stated.max(1e-6), "{file}: bake.json says {stated}, the file gives {mine}");
        assert!(mine < 0.25, "{file}: BC6H lost {mine} of the RMS");
        assert_eq!(im["bytes"].as_u64().unwrap() as usize, dds.data.len());
        // The KTX2 beside it: the same blocks, BC6H_UFLOAT, the size, and the offset in the
        // file itself (so it decodes without bake.json).
        let (h, level, kv) = ktx2_file(&out.join(im["ktx2"].as_str().unwrap()));
        assert_eq!(h.format, Some(ktx2::Format::BC6H_UFLOAT_BLOCK), "{file}");
        assert_eq!((h.pixel_width, h.pixel_height), (surf.width, surf.height), "{file}");
        assert!(level == dds.data, "{file}: the KTX2's blocks differ from the DDS's");
        assert_eq!(ktx2_offset(&kv), offset, "{file}: the KTX2's offset");
    }
    let bases = c["bases"].as_array().unwrap();
    assert_eq!(bases.len(), 3);
    for b in bases {
        let bc = b["irradiance_rel_rms_bc6h"].as_f64().unwrap();
        let f16 = b["irradiance_rel_rms_f16"].as_f64().unwrap();
        // f16 rounds each value by ≤ 2⁻¹¹ relative; summed over lobes it stays far below BC6H.
        assert!(f16 < 2e-3 && f16 < bc && bc.is_finite(), "{b}");
    }
    std::fs::remove_dir_all(&out).ok();
}

/// The probe grid's BC6H volumes: each DDS is an NX × NY × NZ Texture3D, flagged a volume in
/// its header, whose texels, read
/// by image_dds (its own DDS parser and 3D block layout) minus the stated offset, give the
/// coefficient error bake.json states against probes.json's coefficients over valid probes
/// (same oracle and tolerance as the lightmap images); f16 rounds each coefficient by
/// ≤ 2⁻¹¹ relative, so its E/π change stays below 2e-3 and below BC6H's.
#[test]
fn probe_volumes_decode_to_the_error_bake_json_states() {
    let out = tmp("probes");
    let (nx, ny, nz) = (6usize, 5usize, 3usize);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_baker"))
        .args(["--device", "cpu", "--passes", "8", "--texels-per-unit", "4", "--bases", "sh1", "--probes", "6,5,3", "--compress", "bc6h"])
        .args(["--preview-width", "16", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta: Value = serde_json::from_str(&std::fs::read_to_string(out.join("bake.json")).unwrap()).unwrap();
    let probes: Value = serde_json::from_str(&std::fs::read_to_string(out.join("probes.json")).unwrap()).unwrap();
    let list = probes["probes"].as_array().unwrap();
    assert_eq!(list.len(), nx * ny * nz);
    let volumes = meta["compression"]["probes"].as_array().unwrap();
    assert_eq!(volumes.len(), probes["bases"].as_array().unwrap().len());
    for v in volumes {
        let basis = v["basis"].as_str().unwrap();
        let files = v["files"].as_array().unwrap();
        let (mut e, mut s, mut bytes) = (0.0, 0.0, 0usize);
        for (l, f) in files.iter().enumerate() {
            let file = f.as_str().unwrap();
            let dds = image_dds::ddsfile::Dds::read(std::fs::File::open(out.join(file)).unwrap()).unwrap();
            bytes += dds.data.len();
            assert_eq!(dds.get_dxgi_format(), Some(image_dds::ddsfile::DxgiFormat::BC6H_UF16), "{file}");
            // The header as bytes (DDS_HEADER after the 4-byte magic, Microsoft's
            // "DDS_HEADER structure"): dwFlags at 8 has DDSD_DEPTH (0x800000), dwDepth at 24,
            // dwCaps2 at 112 has DDSCAPS2_VOLUME (0x200000); the DX10 header's
            // resourceDimension at 132 is TEXTURE3D (4).
            let raw = std::fs::read(out.join(file)).unwrap();
            let u32_at = |o: usize| u32::from_le_bytes(raw[o..o + 4].try_into().unwrap());
            assert!(u32_at(8) & 0x80_0000 != 0 && u32_at(24) as usize == nz, "{file}: flags {:#x}, depth {}", u32_at(8), u32_at(24));
            assert!(u32_at(112) & 0x20_0000 != 0, "{file}: caps2 {:#x} lacks DDSCAPS2_VOLUME", u32_at(112));
            assert_eq!(u32_at(132), 4, "{file}: resource dimension");
            let surf = image_dds::Surface::from_dds(&dds).unwrap().decode_rgbaf32().unwrap();
            assert_eq!((surf.width as usize, surf.height as usize, surf.depth as usize), (nx, ny, nz), "{file}");
            let offset: Vec<f64> = v["offsets"][l].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
            let (h, level, kv) = ktx2_file(&out.join(file.replace(".dds", ".ktx2")));
            assert_eq!(
                (h.format, h.pixel_width as usize, h.pixel_height as usize, h.pixel_depth as usize),
                (Some(ktx2::Format::BC6H_UFLOAT_BLOCK), nx, ny, nz),
                "{file}"
            );
            assert!(level == dds.data && ktx2_offset(&kv) == offset, "{file}: KTX2 blocks or offset differ");
            for (k, p) in list.iter().enumerate() {
                if !p["valid"].as_bool().unwrap() {
                    continue;
                }
                let c = &p["coefficients"][basis][l];
                for ch in 0..3 {
                    let want = c[ch].as_f64().unwrap();
                    let got = surf.data[4 * k + ch] as f64 - offset[ch];
                    e += (got - want).powi(2);
                    s += want * want;
                }
            }
        }
        let mine = (e / s).sqrt();
        let stated = v["coefficient_rel_rms"].as_f64().unwrap();
        println!("{basis}: stated {stated:.5}, recomputed {mine:.5}");
        assert!((mine - stated).abs() <= 1e-4 * stated.max(1e-6), "{basis}: bake.json says {stated}, the files give {mine}");
        assert!(mine < 0.25, "{basis}: BC6H lost {mine} of the RMS");
        let (f16, bc) = (v["irradiance_rel_rms_f16"].as_f64().unwrap(), v["irradiance_rel_rms_bc6h"].as_f64().unwrap());
        assert!(f16 > 0.0 && f16 < 2e-3 && f16 < bc && bc.is_finite(), "{v}");
        let stated = v["bytes_per_probe"][2].as_f64().unwrap();
        assert_eq!(stated, bytes as f64 / (nx * ny * nz) as f64, "{basis}: BC6H bytes per probe");
    }
    std::fs::remove_dir_all(&out).ok();
}
