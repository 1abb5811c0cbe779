//! Compressed lightmaps (`--compress bc6h`): every lightmap image as a DDS file in BC6H
//! (DXGI_FORMAT_BC6H_UF16, 1 byte per texel), what the engines stream instead of f32 EXR,
//! with the error it adds measured by an independent decoder.
//!
//! Encoder: ISPC Texture Compressor's BC6H through `intel_tex_2` ("very slow": its highest
//! quality). Images are padded to whole 4 × 4 blocks by repeating the last row and column.
//! BC6H_UF16 holds non-negative half floats: an image with negative values (SH lobes, LS
//! lobes) is stored shifted by a per-channel offset (−its minimum, recorded in bake.json; the
//! runtime subtracts it), as engines store signed lightmap data in unsigned formats. Values
//! above the f16 maximum (65 504) are counted and clamped.
//!
//! Decoder: `bcdec_rs` (a port of bcdec, independent of the encoder). Per image, bake.json
//! records the offset, the bytes and the RMS of (decoded − source) over baked texels relative
//! to the source's RMS; per basis, the error each storage adds to E/π at the texel normal
//! (the basis's Lambert runtime on the lobes, [`BasisKind::irradiance_at_normal`]): f16
//! (each lobe rounded to half, as the renderer's f16 textures) and BC6H, relative to the
//! RMS of E/π from the f32 lobes; and each storage's total error at the normal against the
//! bake's own E/π (`irradiance.exr`).

use crate::accumulate::BasisKind;
use crate::post::images::LightmapImages;
use sbf::glam::DVec3;
use serde::Serialize;
use std::path::Path;

/// One compressed image in bake.json.
#[derive(Debug, Clone, Serialize)]
pub struct CompressedImageJson {
    pub file: String,
    /// The EXR it encodes.
    pub source: String,
    /// Added per channel before encoding (subtract after decoding).
    pub offset: [f32; 3],
    pub bytes: usize,
    /// RMS of (decoded − source) over baked texels / RMS of the source there.
    pub rel_rms: f64,
    /// Values above the f16 maximum, clamped to it.
    pub clamped_values: usize,
}

/// One basis's storage against its error in bake.json.
#[derive(Debug, Clone, Serialize)]
pub struct BasisStorageJson {
    pub basis: String,
    /// Bytes per texel as f32 RGB (the EXR data), f16 RGBA (GPU rgba16float) and BC6H.
    pub bytes_per_texel: [f64; 3],
    /// RMS over baked texels of the change in E/π at the texel normal, relative to the RMS
    /// of E/π from the f32 lobes: with every lobe rounded to f16, and through BC6H.
    pub irradiance_rel_rms_f16: f64,
    pub irradiance_rel_rms_bc6h: f64,
    /// RMS over baked texels of (E/π at the texel normal from the lobes − the bake's E/π
    /// there, `irradiance.exr`), relative to the latter's RMS, from the f32, f16 and BC6H
    /// lobes: the basis's own error at the normal plus what storage adds.
    pub error_at_normal_rel_rms: [f64; 3],
}

/// What `--compress bc6h` wrote and measured.
#[derive(Debug, Clone, Serialize)]
pub struct CompressionJson {
    pub format: &'static str,
    pub encoder: &'static str,
    pub decoder: &'static str,
    pub images: Vec<CompressedImageJson>,
    pub bases: Vec<BasisStorageJson>,
    pub seconds: f64,
}

const F16_MAX: f32 = 65504.0;

/// Encodes one RGB image as BC6H blocks; returns (blocks, offset, clamped count).
pub fn encode(width: usize, height: usize, rgb: &[[f32; 3]]) -> (Vec<u8>, [f32; 3], usize) {
    let mut offset = [0.0f32; 3];
    for p in rgb {
        for k in 0..3 {
            offset[k] = offset[k].max(-p[k]);
        }
    }
    let (pw, ph) = (width.div_ceil(4) * 4, height.div_ceil(4) * 4);
    let mut clamped = 0;
    let mut data = Vec::with_capacity(pw * ph * 8);
    for y in 0..ph {
        for x in 0..pw {
            let p = rgb[y.min(height - 1) * width + x.min(width - 1)];
            for k in 0..3 {
                let v = p[k] + offset[k];
                if v > F16_MAX && x < width && y < height {
                    clamped += 1;
                }
                data.extend_from_slice(&half::f16::from_f32(v.clamp(0.0, F16_MAX)).to_le_bytes());
            }
            data.extend_from_slice(&half::f16::ONE.to_le_bytes());
        }
    }
    let surface = intel_tex_2::RgbaSurface { data: &data, width: pw as u32, height: ph as u32, stride: (pw * 8) as u32 };
    (intel_tex_2::bc6h::compress_blocks(&intel_tex_2::bc6h::very_slow_settings(), &surface), offset, clamped)
}

/// Decodes BC6H blocks of a `width` × `height` image (bcdec) and removes the offset.
pub fn decode(width: usize, height: usize, blocks: &[u8], offset: [f32; 3]) -> Vec<[f32; 3]> {
    let bw = width.div_ceil(4);
    let mut out = vec![[0.0f32; 3]; width * height];
    let mut texels = [0.0f32; 48];
    for (b, block) in blocks.chunks_exact(16).enumerate() {
        bcdec_rs::bc6h_float(block, &mut texels, 12, false);
        let (bx, by) = (b % bw, b / bw);
        for j in 0..4 {
            for i in 0..4 {
                let (x, y) = (bx * 4 + i, by * 4 + j);
                if x < width && y < height {
                    let t = &texels[j * 12 + i * 3..j * 12 + i * 3 + 3];
                    out[y * width + x] = [t[0] - offset[0], t[1] - offset[1], t[2] - offset[2]];
                }
            }
        }
    }
    out
}

/// An 8-bit RGBA image (values in [0, 1], rounded to k/255) as BC1 (RGB, `alpha` false:
/// 8 bytes per 4 × 4 block) or BC7 (RGBA, 16 bytes per block; ISPC's "alpha slow" settings),
/// padded like [`encode`]; returns (blocks, DXGI format, the bcdec decode in [0, 1]).
pub fn encode_unorm(width: usize, height: usize, rgba: &[[f64; 4]], alpha: bool) -> (Vec<u8>, ddsfile::DxgiFormat, Vec<[f64; 4]>) {
    let (pw, ph) = (width.div_ceil(4) * 4, height.div_ceil(4) * 4);
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let mut data = Vec::with_capacity(pw * ph * 4);
    for y in 0..ph {
        for x in 0..pw {
            let p = rgba[y.min(height - 1) * width + x.min(width - 1)];
            data.extend_from_slice(&[byte(p[0]), byte(p[1]), byte(p[2]), if alpha { byte(p[3]) } else { 255 }]);
        }
    }
    let surface = intel_tex_2::RgbaSurface { data: &data, width: pw as u32, height: ph as u32, stride: (pw * 4) as u32 };
    let (blocks, format, block_bytes) = if alpha {
        (intel_tex_2::bc7::compress_blocks(&intel_tex_2::bc7::alpha_slow_settings(), &surface), ddsfile::DxgiFormat::BC7_UNorm, 16)
    } else {
        (intel_tex_2::bc1::compress_blocks(&surface), ddsfile::DxgiFormat::BC1_UNorm, 8)
    };
    let bw = width.div_ceil(4);
    let mut out = vec![[0.0; 4]; width * height];
    let mut texels = [0u8; 64];
    for (b, block) in blocks.chunks_exact(block_bytes).enumerate() {
        if alpha {
            bcdec_rs::bc7(block, &mut texels, 16);
        } else {
            bcdec_rs::bc1(block, &mut texels, 16);
        }
        let (bx, by) = (b % bw, b / bw);
        for j in 0..4 {
            for i in 0..4 {
                let (x, y) = (bx * 4 + i, by * 4 + j);
                if x < width && y < height {
                    let t = &texels[j * 16 + i * 4..j * 16 + i * 4 + 4];
                    out[y * width + x] = [0, 1, 2, 3].map(|k| t[k] as f64 / 255.0);
                }
            }
        }
    }
    (blocks, format, out)
}

/// Writes compressed blocks as a DDS file (DX10 header, `format`).
pub fn write_dds_as(path: &Path, width: usize, height: usize, format: ddsfile::DxgiFormat, blocks: Vec<u8>) -> Result<(), String> {
    let mut dds = ddsfile::Dds::new_dxgi(ddsfile::NewDxgiParams {
        height: height as u32,
        width: width as u32,
        depth: None,
        format,
        mipmap_levels: None,
        array_layers: None,
        caps2: None,
        is_cubemap: false,
        resource_dimension: ddsfile::D3D10ResourceDimension::Texture2D,
        alpha_mode: ddsfile::AlphaMode::Unknown,
    })
    .map_err(|e| format!("DDS header for {}: {e}", path.display()))?;
    dds.data = blocks;
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(|e| format!("creating {}: {e}", path.display()))?);
    dds.write(&mut f).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// RMS of (a − b) over valid texels and RMS of b there.
fn rms_pair(valid: &[f32], a: impl Iterator<Item = DVec3>, b: impl Iterator<Item = DVec3>) -> (f64, f64) {
    let (mut e, mut s, mut n) = (0.0, 0.0, 0usize);
    for ((v, x), y) in valid.iter().zip(a).zip(b) {
        if *v > 0.0 {
            e += (x - y).length_squared();
            s += y.length_squared();
            n += 1;
        }
    }
    let n = n.max(1) as f64;
    ((e / n).sqrt(), (s / n).sqrt())
}

fn rel(e: f64, s: f64) -> f64 {
    if s > 0.0 {
        e / s
    } else {
        0.0
    }
}

fn dv(p: [f32; 3]) -> DVec3 {
    DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
}

/// Compresses one image into `dir/{stem}.dds`; returns its record and the decoded image.
fn compress_image(dir: &Path, img: &LightmapImages, stem: &str, rgb: &[[f32; 3]]) -> Result<(CompressedImageJson, Vec<[f32; 3]>), String> {
    let (blocks, offset, clamped_values) = encode(img.width, img.height, rgb);
    let decoded = decode(img.width, img.height, &blocks, offset);
    let bytes = blocks.len();
    let file = format!("{stem}.dds");
    write_dds_as(&dir.join(&file), img.width, img.height, ddsfile::DxgiFormat::BC6H_UF16, blocks)?;
    let (e, s) = rms_pair(&img.validity, decoded.iter().map(|p| dv(*p)), rgb.iter().map(|p| dv(*p)));
    Ok((CompressedImageJson { file, source: format!("{stem}.exr"), offset, bytes, rel_rms: rel(e, s), clamped_values }, decoded))
}

/// Writes every lightmap image (E/π and each basis lobe) as BC6H DDS next to its EXR and
/// measures what f16 and BC6H storage do to each basis's E/π at the texel normal.
pub fn write_bc6h(dir: &Path, img: &LightmapImages, bases: &[BasisKind], sg_sharpness: f64) -> Result<CompressionJson, String> {
    let t0 = std::time::Instant::now();
    let n = img.width * img.height;
    let texels = (img.width.div_ceil(4) * img.height.div_ceil(4) * 16) as f64 / n.max(1) as f64;
    let mut images = Vec::new();
    let mut out_bases = Vec::new();
    let (rec, irr) = compress_image(dir, img, "irradiance", &img.irradiance)?;
    images.push(rec);
    let (e, s) = rms_pair(&img.validity, irr.iter().map(|p| dv(*p)), img.irradiance.iter().map(|p| dv(*p)));
    let f16 = |p: &[f32; 3]| p.map(|v| half::f16::from_f32(v).to_f32());
    let (e16, _) = rms_pair(&img.validity, img.irradiance.iter().map(|p| dv(f16(p))), img.irradiance.iter().map(|p| dv(*p)));
    out_bases.push(BasisStorageJson {
        basis: "irradiance".into(),
        bytes_per_texel: [12.0, 8.0, texels],
        irradiance_rel_rms_f16: rel(e16, s),
        irradiance_rel_rms_bc6h: rel(e, s),
        error_at_normal_rel_rms: [0.0, rel(e16, s), rel(e, s)],
    });
    let bake: Vec<DVec3> = img.irradiance.iter().map(|p| dv(*p)).collect();
    for (b, kind) in bases.iter().enumerate() {
        let lobes = &img.coefficients[b];
        let mut decoded = Vec::with_capacity(lobes.len());
        for (l, lobe) in lobes.iter().enumerate() {
            let (rec, d) = compress_image(dir, img, &format!("{}_{l:02}", kind.name()), lobe)?;
            images.push(rec);
            decoded.push(d);
        }
        let at = |src: &dyn Fn(usize, usize) -> DVec3, t: usize| -> DVec3 {
            let c: Vec<DVec3> = (0..lobes.len()).map(|l| src(l, t)).collect();
            kind.irradiance_at_normal(&c, sg_sharpness)
        };
        let full: Vec<DVec3> = (0..n).map(|t| at(&|l, t| dv(lobes[l][t]), t)).collect();
        let half: Vec<DVec3> = (0..n).map(|t| at(&|l, t| dv(f16(&lobes[l][t])), t)).collect();
        let bc: Vec<DVec3> = (0..n).map(|t| at(&|l, t| dv(decoded[l][t]), t)).collect();
        let (e16, s) = rms_pair(&img.validity, half.iter().copied(), full.iter().copied());
        let (ebc, _) = rms_pair(&img.validity, bc.iter().copied(), full.iter().copied());
        let vs_bake = |x: &[DVec3]| {
            let (e, s) = rms_pair(&img.validity, x.iter().copied(), bake.iter().copied());
            rel(e, s)
        };
        let k = lobes.len() as f64;
        out_bases.push(BasisStorageJson {
            basis: kind.name().into(),
            bytes_per_texel: [12.0 * k, 8.0 * k, texels * k],
            irradiance_rel_rms_f16: rel(e16, s),
            irradiance_rel_rms_bc6h: rel(ebc, s),
            error_at_normal_rel_rms: [vs_bake(&full), vs_bake(&half), vs_bake(&bc)],
        });
    }
    Ok(CompressionJson {
        format: "DDS, DXGI_FORMAT_BC6H_UF16 (one 16-byte block per 4 × 4 texels)",
        encoder: "ISPC Texture Compressor BC6H via intel_tex_2 0.5 (very slow settings)",
        decoder: "bcdec_rs 0.2 (bc6h_float)",
        images,
        bases: out_bases,
        seconds: t0.elapsed().as_secs_f64(),
    })
}
