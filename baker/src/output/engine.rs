//! The lightmap in the directional formats engines ship (`--engine-formats`), repackaged
//! from the SH L1 bake ([`sbf::recon::engine`]: the encodes and the engines' published
//! decodes).
//!
//! Per texel, the SH L1 radiance coefficients (tangent frame, normal +Z) give the linear
//! L1 irradiance a₀ + a₁·n; a₁ is turned into world space with the texel's frame
//! ([`crate::scene::geometry::frame`] about its normal, as the bake used), since the engines'
//! directions are world-space. Enlighten's colour is the bake's own E/π at the texel normal
//! (`irradiance.exr`), its direction the radiance's mean over the texel's hemisphere (the
//! SH L1 fit holds it exactly: the bake projects with zero below the surface,
//! [`Moments::sphere`]), its rescaling factor from that normal. Files:
//!
//! | format | files |
//! |---|---|
//! | `godot-l1` | `godot_l1_0.exr` (L0), `godot_l1_1.exr` … `_3.exr` (the y, z, x layers), f16 values |
//! | `monosh` | `monosh_l0.exr` (f16 values), `monosh_dir.png` (RGBA8, alpha 255) |
//! | `enlighten` | `enlighten_irradiance.exr` (f16 values), `enlighten_dir.png` (RGBA8, rescaling factor in alpha) |
//! | `enlighten-rgb` | `enlighten_rgb_irradiance.exr`, `enlighten_rgb_dir_r.png`, `_g.png`, `_b.png` |
//!
//! EXR files are 32-bit containers holding the values rounded to f16 (what the engine
//! keeps), RGB + the bake's validity alpha; PNG bytes are the 8-bit values themselves.
//! Texels without a normal (empty, never dilated) hold colour 0 and direction ½ (no
//! direction). bake.json records, per format, the files, the bytes per texel the engine
//! stores, the values clamped, and two errors over the baked texels: the decode at the texel
//! normal against the bake's E/π there (what the format loses at the baking normal), and
//! the decode from the stored values against the same decode at full precision (what
//! storage alone loses). With `--compress bc6h` each format is also written block-compressed
//! ([`CompressedFormatJson`]: `.dds` beside each file), with the same two errors.

use super::write_exr;
use crate::post::images::LightmapImages;
use crate::scene::geometry::frame;
use sbf::glam::{DVec3, Vec3};
use sbf::recon::engine::{self, EngineFormat, EnlightenInput, L1Irradiance, Moments, Texel};
use serde::Serialize;
use std::path::Path;

/// One format's record in bake.json.
#[derive(Debug, Clone, Serialize)]
pub struct EngineFormatJson {
    pub format: &'static str,
    pub files: Vec<String>,
    /// Bytes per texel as the engine stores the textures uncompressed.
    pub bytes_per_texel: usize,
    /// Stored values that were out of the format's range and clamped (all texels).
    pub clamped_values: usize,
    /// RMS over baked texels of (decode at the texel normal − the bake's E/π there),
    /// divided by the RMS of that E/π.
    pub error_at_normal_rel_rms: f64,
    /// RMS over baked texels of (decode of the stored values − decode at full precision) at
    /// the texel normal, divided by the RMS of the bake's E/π.
    pub storage_rel_rms: f64,
    /// The same textures block-compressed (`--compress bc6h`; absent: not asked).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compressed: Option<CompressedFormatJson>,
}

/// An engine format's textures block-compressed: the colour as BC6H, RGB unit textures as
/// BC1 (Godot's layers, as its proposal for SH lightmaps; MonoSH's direction), RGBA ones
/// (Enlighten's direction + rescaling factor) as BC7.
#[derive(Debug, Clone, Serialize)]
pub struct CompressedFormatJson {
    pub files: Vec<String>,
    pub bytes_per_texel: f64,
    /// As [`EngineFormatJson::error_at_normal_rel_rms`], decoded from the compressed files.
    pub error_at_normal_rel_rms: f64,
    /// RMS of (compressed decode − full-precision decode) at the normal / RMS of E/π.
    pub storage_rel_rms: f64,
    /// Colour values below 0 (BC6H_UF16 holds none; engines' colours are ≥ 0 but MC noise
    /// and LS fits can dip below), clamped to 0.
    pub clamped_values: usize,
}

/// Per texel: (normal, full-precision texel, stored texel, clamped count); None where the
/// texel has no normal.
fn encode_texels(img: &LightmapImages, sh1: &[Vec<[f32; 3]>], format: EngineFormat) -> Vec<Option<(DVec3, Texel, Texel, usize)>> {
    (0..img.width * img.height)
        .map(|t| {
            let n = Vec3::from(img.normals[t]);
            if n.length_squared() < 0.5 {
                return None;
            }
            let rgb: [[f64; 4]; 3] = [0, 1, 2].map(|ch| [0, 1, 2, 3].map(|l| f64::from(sh1[l][t][ch])));
            let local = L1Irradiance::from_sh(&rgb);
            let (tn, bn) = frame(n);
            let (tn, bn, nd) = (tn.as_dvec3(), bn.as_dvec3(), n.as_dvec3());
            let world = L1Irradiance { a0: local.a0, a1: local.a1.map(|a| tn * a.x + bn * a.y + nd * a.z) };
            let input = EnlightenInput {
                normal: nd,
                irradiance: img.irradiance[t].map(f64::from),
                moments: Moments::sphere(&rgb).to_frame(tn, bn, nd),
            };
            let enc = engine::encode(format, &world, Some(&input))?;
            Some((nd, enc.texel, enc.texel.stored(format), enc.clamped))
        })
        .collect()
}

/// An RGBA8 PNG of one unit texture (`unit[k]`) of every texel.
fn write_png(
    path: &Path,
    img: &LightmapImages,
    texels: &[Option<(DVec3, Texel, Texel, usize)>],
    k: usize,
    alpha: bool,
) -> Result<(), String> {
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let data: Vec<u8> = texels
        .iter()
        .flat_map(|t| match t {
            Some((_, _, s, _)) => {
                let u = s.unit[k];
                [byte(u[0]), byte(u[1]), byte(u[2]), if alpha { byte(u[3]) } else { 255 }]
            }
            None => [128, 128, 128, 255],
        })
        .collect();
    let png = image::RgbaImage::from_raw(img.width as u32, img.height as u32, data).ok_or("PNG size mismatch")?;
    png.save_with_format(path, image::ImageFormat::Png).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// Writes one format's files into `dir`; returns their names.
fn write_files(
    dir: &Path,
    img: &LightmapImages,
    texels: &[Option<(DVec3, Texel, Texel, usize)>],
    format: EngineFormat,
) -> Result<Vec<String>, String> {
    let rgb = |f: &dyn Fn(&Texel) -> [f64; 3]| -> Vec<[f32; 3]> {
        texels.iter().map(|t| t.as_ref().map_or([0.0; 3], |(_, _, s, _)| f(s).map(|v| v as f32))).collect()
    };
    let colour = rgb(&|s| s.colour);
    let mut names = Vec::new();
    let mut exr = |name: String, data: &[[f32; 3]]| -> Result<(), String> {
        write_exr(&dir.join(&name), img.width, img.height, data, &img.validity)?;
        names.push(name);
        Ok(())
    };
    match format {
        EngineFormat::GodotL1 => {
            exr("godot_l1_0.exr".into(), &colour)?;
            for layer in 0..3 {
                exr(format!("godot_l1_{}.exr", layer + 1), &rgb(&|s| [s.unit[layer][0], s.unit[layer][1], s.unit[layer][2]]))?;
            }
        }
        EngineFormat::MonoSh => exr("monosh_l0.exr".into(), &colour)?,
        EngineFormat::Enlighten => exr("enlighten_irradiance.exr".into(), &colour)?,
        EngineFormat::EnlightenRgb => exr("enlighten_rgb_irradiance.exr".into(), &colour)?,
    }
    let pngs: Vec<(String, usize)> = match format {
        EngineFormat::GodotL1 => Vec::new(),
        EngineFormat::MonoSh => vec![("monosh_dir.png".into(), 0)],
        EngineFormat::Enlighten => vec![("enlighten_dir.png".into(), 0)],
        EngineFormat::EnlightenRgb => ["r", "g", "b"].iter().enumerate().map(|(k, c)| (format!("enlighten_rgb_dir_{c}.png"), k)).collect(),
    };
    for (name, k) in pngs {
        write_png(&dir.join(&name), img, texels, k, format.unit_channels() == 4)?;
        names.push(name);
    }
    Ok(names)
}

/// The texture names of a format (colour first), without extension.
fn stems(format: EngineFormat) -> Vec<String> {
    match format {
        EngineFormat::GodotL1 => (0..4).map(|k| format!("godot_l1_{k}")).collect(),
        EngineFormat::MonoSh => vec!["monosh_l0".into(), "monosh_dir".into()],
        EngineFormat::Enlighten => vec!["enlighten_irradiance".into(), "enlighten_dir".into()],
        EngineFormat::EnlightenRgb => ["irradiance", "dir_r", "dir_g", "dir_b"].iter().map(|s| format!("enlighten_rgb_{s}")).collect(),
    }
}

/// Writes the format's textures block-compressed (see [`CompressedFormatJson`]) and returns
/// the texels as the engine would read them back, with the files and bytes per texel.
#[allow(clippy::type_complexity)]
fn compress_format(
    dir: &Path,
    img: &LightmapImages,
    texels: &[Option<(DVec3, Texel, Texel, usize)>],
    format: EngineFormat,
) -> Result<(Vec<Option<Texel>>, Vec<String>, f64, usize), String> {
    use sbf::bc::{decode_bc6h as bc6h_decode, encode_bc6h as bc6h_encode, encode_unorm, write_dds as write_dds_as};
    let (w, h) = (img.width, img.height);
    let names = stems(format);
    let colour: Vec<[f32; 3]> = texels.iter().map(|t| t.as_ref().map_or([0.0; 3], |(_, _, s, _)| s.colour.map(|v| v as f32))).collect();
    let negative = colour.iter().flatten().filter(|v| **v < 0.0).count();
    let colour: Vec<[f32; 3]> = colour.iter().map(|c| c.map(|v| v.max(0.0))).collect();
    let (blocks, offset, _) = bc6h_encode(w, h, &colour);
    debug_assert_eq!(offset, [0.0; 3]);
    let mut bytes = blocks.len();
    let decoded_colour = bc6h_decode(w, h, &blocks, offset);
    write_dds_as(&dir.join(format!("{}.dds", names[0])), w, h, sbf::bc::ddsfile::DxgiFormat::BC6H_UF16, blocks)?;
    let alpha = format.unit_channels() == 4;
    let mut units = Vec::new();
    for k in 0..format.unit_textures() {
        let rgba: Vec<[f64; 4]> = texels.iter().map(|t| t.as_ref().map_or([0.5, 0.5, 0.5, 1.0], |(_, _, s, _)| s.unit[k])).collect();
        let (blocks, dxgi, decoded) = encode_unorm(w, h, &rgba, alpha);
        bytes += blocks.len();
        write_dds_as(&dir.join(format!("{}.dds", names[k + 1])), w, h, dxgi, blocks)?;
        units.push(decoded);
    }
    let read: Vec<Option<Texel>> = texels
        .iter()
        .enumerate()
        .map(|(t, tx)| {
            tx.as_ref().map(|_| {
                let mut unit = [[1.0; 4]; 3];
                for (k, u) in units.iter().enumerate() {
                    unit[k] = if alpha { u[t] } else { [u[t][0], u[t][1], u[t][2], 1.0] };
                }
                Texel { colour: decoded_colour[t].map(f64::from), unit }
            })
        })
        .collect();
    let files = names.iter().map(|n| format!("{n}.dds")).collect();
    Ok((read, files, bytes as f64 / (w * h).max(1) as f64, negative))
}

/// Encodes the SH L1 lightmap (`sh1[lobe][texel]`, 4 lobes) in every format of `formats`,
/// writes their files into `dir` (and block-compressed copies with `compress`) and returns
/// their bake.json records.
pub fn write_engine_formats(
    dir: &Path,
    img: &LightmapImages,
    sh1: &[Vec<[f32; 3]>],
    formats: &[EngineFormat],
    compress: bool,
) -> Result<Vec<EngineFormatJson>, String> {
    if sh1.len() != 4 {
        return Err(format!("engine formats are encoded from SH L1 (4 lobes), got {} lobes", sh1.len()));
    }
    let mut out = Vec::new();
    for &format in formats {
        let texels = encode_texels(img, sh1, format);
        let files = write_files(dir, img, &texels, format)?;
        let read = if compress { Some(compress_format(dir, img, &texels, format)?) } else { None };
        let (mut err, mut storage, mut signal, mut err_c, mut storage_c) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (t, tx) in texels.iter().enumerate() {
            let Some((n, full, stored, _)) = tx else { continue };
            if img.validity[t] <= 0.0 {
                continue;
            }
            let (df, ds) = (engine::decode(format, full, *n), engine::decode(format, stored, *n));
            let dc = read.as_ref().and_then(|r| r.0[t].as_ref()).map(|c| engine::decode(format, c, *n));
            for k in 0..3 {
                let e = f64::from(img.irradiance[t][k]);
                err += (ds[k] - e).powi(2);
                storage += (ds[k] - df[k]).powi(2);
                signal += e * e;
                if let Some(dc) = dc {
                    err_c += (dc[k] - e).powi(2);
                    storage_c += (dc[k] - df[k]).powi(2);
                }
            }
        }
        let rel = |x: f64| if signal > 0.0 { (x / signal).sqrt() } else { 0.0 };
        let compressed = read.map(|(_, files, bytes_per_texel, clamped_values)| CompressedFormatJson {
            files,
            bytes_per_texel,
            error_at_normal_rel_rms: rel(err_c),
            storage_rel_rms: rel(storage_c),
            clamped_values,
        });
        out.push(EngineFormatJson {
            format: format.id(),
            files,
            bytes_per_texel: format.engine_bytes(),
            clamped_values: texels.iter().flatten().map(|t| t.3).sum(),
            error_at_normal_rel_rms: rel(err),
            storage_rel_rms: rel(storage),
            compressed,
        });
    }
    Ok(out)
}
