//! `--compress bc6h` and `bc6h-offset`: the DDS files read back by an independent reader
//! (image_dds: its own DDS parser and block layout, decoding with bcdec; BC6H_SF16 blocks,
//! which image_dds 0.7 decodes as unsigned, through `bcdec_rs` with the block layout written
//! here) agree with what bake.json states, and the error is what BC6H can do.
//!
//! Oracle: for every image bake.json lists, the RMS of (decoded − EXR source) over baked
//! texels, relative to the source's RMS, recomputed here from the two files — bake.json's
//! value must match it to f32 summation rounding (1e-4 relative; both sides decode the same
//! blocks). A BC6H_SF16 file is decoded with no offset at all (the file alone must give the
//! values). Bound on the error itself: BC6H keeps 10–16-bit endpoints and 3–4-bit indices
//! per 4 × 4 block; a smooth lightmap stays within a few percent, and no image loses more
//! than 25 % of its RMS (the per-block bound of the signed encoder is
//! `sbf/tests/bc6h_signed.rs`'s).

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

/// A DDS's texels as RGBA f32, row-major, slice after slice: image_dds for BC6H_UF16;
/// BC6H_SF16 decoded block by block with bcdec (signed), the blocks of each slice row-major.
fn dds_texels(dds: &image_dds::ddsfile::Dds, signed: bool) -> (u32, u32, u32, Vec<f32>) {
    if !signed {
        let s = image_dds::Surface::from_dds(dds).unwrap().decode_rgbaf32().unwrap();
        return (s.width, s.height, s.depth, s.data);
    }
    let (w, h, d) = (dds.get_width() as usize, dds.get_height() as usize, dds.get_depth() as usize);
    let (bw, bh) = (w.div_ceil(4), h.div_ceil(4));
    assert_eq!(dds.data.len(), bw * bh * d * 16, "BC6H_SF16 data size");
    let mut out = vec![0.0f32; w * h * d * 4];
    let mut t = [0.0f32; 48];
    for (b, block) in dds.data.chunks_exact(16).enumerate() {
        bcdec_rs::bc6h_float(block, &mut t, 12, true);
        let (z, r) = (b / (bw * bh), b % (bw * bh));
        let (bx, by) = (r % bw, r / bw);
        for k in 0..16 {
            let (x, y) = (bx * 4 + k % 4, by * 4 + k / 4);
            if x < w && y < h {
                let o = ((z * h + y) * w + x) * 4;
                out[o..o + 3].copy_from_slice(&t[(k / 4) * 12 + (k % 4) * 3..][..3]);
                out[o + 3] = 1.0;
            }
        }
    }
    (w as u32, h as u32, d as u32, out)
}

/// The DXGI format bake.json names, checked against the DDS header and the KTX2's format:
/// whether it is BC6H_SF16.
fn check_format(file: &str, stated: &str, dds: &image_dds::ddsfile::Dds, ktx: Option<ktx2::Format>) -> bool {
    use image_dds::ddsfile::DxgiFormat as D;
    let (dxgi, vk, signed) = match stated {
        "BC6H_UF16" => (D::BC6H_UF16, ktx2::Format::BC6H_UFLOAT_BLOCK, false),
        "BC6H_SF16" => (D::BC6H_SF16, ktx2::Format::BC6H_SFLOAT_BLOCK, true),
        other => panic!("{file}: format {other}"),
    };
    assert_eq!(dds.get_dxgi_format(), Some(dxgi), "{file}");
    assert_eq!(ktx, Some(vk), "{file}: KTX2 format");
    signed
}

fn exr(path: &std::path::Path) -> (Vec<[f64; 3]>, Vec<f64>) {
    let im = image::open(path).unwrap().to_rgba32f();
    (im.pixels().map(|p| [p[0] as f64, p[1] as f64, p[2] as f64]).collect(), im.pixels().map(|p| p[3] as f64).collect())
}

#[test]
fn bc6h_files_decode_to_the_error_bake_json_states() {
    for mode in ["bc6h", "bc6h-offset"] {
        bc6h_files_decode(mode);
    }
}

fn bc6h_files_decode(mode: &str) {
    let out = tmp(&format!("cornell-{mode}"));
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_baker"))
        .args(["--device", "cpu", "--passes", "8", "--texels-per-unit", "6", "--bases", "sh1,ad9", "--probes", "0,0,0", "--compress", mode])
        .args(["--preview-width", "16", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta: Value = serde_json::from_str(&std::fs::read_to_string(out.join("bake.json")).unwrap()).unwrap();
    let c = &meta["compression"];
    let images = c["images"].as_array().unwrap();
    assert_eq!(images.len(), 1 + 4 + 9, "irradiance, sh1 ×4, ad9 ×9");
    let mut sf16 = 0;
    for im in images {
        let file = im["file"].as_str().unwrap();
        let dds = image_dds::ddsfile::Dds::read(std::fs::File::open(out.join(file)).unwrap()).unwrap();
        let (h, level, kv) = ktx2_file(&out.join(im["ktx2"].as_str().unwrap()));
        let signed = check_format(file, im["dxgi_format"].as_str().unwrap(), &dds, h.format);
        let (width, height, _, data) = dds_texels(&dds, signed);
        let (src, alpha) = exr(&out.join(im["source"].as_str().unwrap()));
        assert_eq!((width * height) as usize, src.len(), "{file}: size");
        // Under `bc6h` exactly the images with a negative value are SF16.
        let negative = src.iter().flatten().any(|v| *v < 0.0);
        assert_eq!(signed, mode == "bc6h" && negative, "{file}: {} with negative values {negative}", im["dxgi_format"]);
        // SF16: the values themselves, no offset anywhere (neither read nor written).
        let offset: Vec<f64> = if signed {
            sf16 += 1;
            assert_eq!(mode, "bc6h", "{file}: SF16 only under --compress bc6h");
            assert!(kv.iter().all(|(k, _)| k != "sbf.offset"), "{file}: an SF16 KTX2 carries no offset");
            vec![0.0; 3]
        } else {
            let o: Vec<f64> = im["offset"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
            if o.iter().any(|v| *v != 0.0) {
                assert_eq!(ktx2_offset(&kv), o, "{file}: the KTX2's offset");
            }
            o
        };
        let (mut e, mut s) = (0.0, 0.0);
        for (t, (p, a)) in src.iter().zip(&alpha).enumerate() {
            if *a <= 0.0 {
                continue;
            }
            for k in 0..3 {
                let d = data[4 * t + k] as f64 - offset[k];
                e += (d - p[k]).powi(2);
                s += p[k] * p[k];
            }
        }
        let mine = if s > 0.0 { (e / s).sqrt() } else { 0.0 };
        let stated = im["rel_rms"].as_f64().unwrap();
        println!("{mode} {file} ({}): stated {stated:.5}, recomputed {mine:.5}", im["dxgi_format"]);
        assert!((mine - stated).abs() <= 1e-4 * stated.max(1e-6), "{file}: bake.json says {stated}, the file gives {mine}");
        assert!(mine < 0.25, "{file}: BC6H lost {mine} of the RMS");
        assert_eq!(im["bytes"].as_u64().unwrap() as usize, dds.data.len());
        // The KTX2 beside it: the same blocks and size.
        assert_eq!((h.pixel_width, h.pixel_height), (width, height), "{file}");
        assert!(level == dds.data, "{file}: the KTX2's blocks differ from the DDS's");
    }
    // SH L1's band-1 lobes are signed.
    assert!(if mode == "bc6h" { sf16 >= 2 } else { sf16 == 0 }, "{mode}: {sf16} BC6H_SF16 files");
    let bases = c["bases"].as_array().unwrap();
    assert_eq!(bases.len(), 3);
    for b in bases {
        let bc = b["irradiance_rel_rms_bc6h"].as_f64().unwrap();
        let f16 = b["irradiance_rel_rms_f16"].as_f64().unwrap();
        // f16 rounds each value by ≤ 2⁻¹¹ relative; summed over lobes it stays far below BC6H.
        assert!(f16 < 2e-3 && f16 < bc && bc.is_finite(), "{b}");
        if b["basis"] == "sh1" {
            let alt = &b["signed_alternative"];
            let other = if mode == "bc6h" { "bc6h-offset" } else { "bc6h" };
            assert!(alt["compress"] == other && alt["irradiance_rel_rms_bc6h"].as_f64().unwrap().is_finite(), "{b}");
        }
    }
    std::fs::remove_dir_all(&out).ok();
}

/// The probe grid's BC6H volumes: each DDS is an NX × NY × NZ Texture3D, flagged a volume in
/// its header, whose texels, read
/// by image_dds (its own DDS parser and 3D block layout; BC6H_SF16 through bcdec), give the
/// coefficient error bake.json states against probes.json's coefficients over valid probes
/// (same oracle and tolerance as the lightmap images); f16 rounds each coefficient by
/// ≤ 2⁻¹¹ relative, so its E/π change stays below 2e-3 and below BC6H's.
#[test]
fn probe_volumes_decode_to_the_error_bake_json_states() {
    for mode in ["bc6h", "bc6h-offset"] {
        probe_volumes_decode(mode);
    }
}

fn probe_volumes_decode(mode: &str) {
    let out = tmp(&format!("probes-{mode}"));
    let (nx, ny, nz) = (6usize, 5usize, 3usize);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_baker"))
        .args(["--device", "cpu", "--passes", "8", "--texels-per-unit", "4", "--bases", "sh1", "--probes", "6,5,3", "--compress", mode])
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
        let (mut e, mut s, mut bytes, mut sf16) = (0.0, 0.0, 0usize, 0);
        for (l, f) in files.iter().enumerate() {
            let file = f.as_str().unwrap();
            let dds = image_dds::ddsfile::Dds::read(std::fs::File::open(out.join(file)).unwrap()).unwrap();
            bytes += dds.data.len();
            let (h, level, kv) = ktx2_file(&out.join(file.replace(".dds", ".ktx2")));
            let signed = check_format(file, v["dxgi_formats"][l].as_str().unwrap(), &dds, h.format);
            assert!(!signed || mode == "bc6h", "{file}: SF16 under {mode}");
            sf16 += usize::from(signed);
            // The header as bytes (DDS_HEADER after the 4-byte magic, Microsoft's
            // "DDS_HEADER structure"): dwFlags at 8 has DDSD_DEPTH (0x800000), dwDepth at 24,
            // dwCaps2 at 112 has DDSCAPS2_VOLUME (0x200000); the DX10 header's
            // resourceDimension at 132 is TEXTURE3D (4).
            let raw = std::fs::read(out.join(file)).unwrap();
            let u32_at = |o: usize| u32::from_le_bytes(raw[o..o + 4].try_into().unwrap());
            assert!(u32_at(8) & 0x80_0000 != 0 && u32_at(24) as usize == nz, "{file}: flags {:#x}, depth {}", u32_at(8), u32_at(24));
            assert!(u32_at(112) & 0x20_0000 != 0, "{file}: caps2 {:#x} lacks DDSCAPS2_VOLUME", u32_at(112));
            assert_eq!(u32_at(132), 4, "{file}: resource dimension");
            let (width, height, depth, data) = dds_texels(&dds, signed);
            assert_eq!((width as usize, height as usize, depth as usize), (nx, ny, nz), "{file}");
            // SF16 volumes decode with no offset; a UF16 one of signed values names its offset
            // in bake.json and the KTX2 (only under `bc6h-offset`).
            let offset: Vec<f64> = v["offsets"][l].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
            let offset = if signed {
                assert!(kv.iter().all(|(k, _)| k != "sbf.offset"), "{file}: an SF16 KTX2 carries no offset");
                vec![0.0; 3]
            } else {
                assert!(mode == "bc6h-offset" || offset.iter().all(|x| *x == 0.0), "{file}: an offset under --compress bc6h");
                if offset.iter().any(|x| *x != 0.0) {
                    assert_eq!(ktx2_offset(&kv), offset, "{file}: the KTX2's offset");
                }
                offset
            };
            assert_eq!((h.pixel_width as usize, h.pixel_height as usize, h.pixel_depth as usize), (nx, ny, nz), "{file}");
            assert!(level == dds.data, "{file}: KTX2 blocks differ");
            for (k, p) in list.iter().enumerate() {
                if !p["valid"].as_bool().unwrap() {
                    continue;
                }
                let c = &p["coefficients"][basis][l];
                for ch in 0..3 {
                    let want = c[ch].as_f64().unwrap();
                    let got = data[4 * k + ch] as f64 - offset[ch];
                    e += (got - want).powi(2);
                    s += want * want;
                }
            }
        }
        let mine = (e / s).sqrt();
        let stated = v["coefficient_rel_rms"].as_f64().unwrap();
        println!("{basis}: stated {stated:.5}, recomputed {mine:.5}");
        assert!((mine - stated).abs() <= 1e-4 * stated.max(1e-6), "{basis}: bake.json says {stated}, the files give {mine}");
        // The 25 % bound holds for UF16 (linear in value); SF16 interpolates half-float bit
        // patterns across zero, and neighbouring probes' coefficients change sign within a
        // block: what it loses is stated (and checked above), its per-block bound is
        // sbf/tests/bc6h_signed.rs's.
        assert!(sf16 > 0 || mine < 0.25, "{basis}: BC6H lost {mine} of the RMS");
        let (f16, bc) = (v["irradiance_rel_rms_f16"].as_f64().unwrap(), v["irradiance_rel_rms_bc6h"].as_f64().unwrap());
        assert!(f16 > 0.0 && f16 < 2e-3 && f16 < bc && bc.is_finite(), "{v}");
        // SH L2 bands 1–2 are signed.
        assert!(basis != "sh2" || (sf16 >= 3) == (mode == "bc6h"), "{basis}: {sf16} BC6H_SF16 volumes under {mode}");
        let stated = v["bytes_per_probe"][2].as_f64().unwrap();
        assert_eq!(stated, bytes as f64 / (nx * ny * nz) as f64, "{basis}: BC6H bytes per probe");
    }
    std::fs::remove_dir_all(&out).ok();
}
