//! The lightmap in the directional formats engines ship (`--engine-formats`), repackaged
//! from the SH L1 bake ([`sbf::recon::engine`]: the encodes and the engines' decodes, each
//! format named for the engine version and decode it is for).
//!
//! Per texel, the SH L1 radiance coefficients (tangent frame, normal +Z) give the linear
//! L1 irradiance a₀ + a₁·n; a₁ is turned into world space with the texel's frame
//! ([`crate::scene::geometry::frame`] about its normal, as the bake used), then into the
//! engine's frame ([`EngineFrame`]: glTF's axes for Godot, x negated for Unity and Bakery —
//! or glTF's for every format with `--engine-frame gltf`). Enlighten's colour is the bake's
//! own E/π at the texel normal (`irradiance.exr`), its direction the radiance's mean over the
//! texel's hemisphere (the SH L1 fit holds it exactly: the bake projects with zero below the
//! surface, [`Moments::sphere`]), its rescaling factor from that normal. Files:
//!
//! | format | files |
//! |---|---|
//! | `godot-l1` | `godot_l1_0.exr` (L0), `godot_l1_1.exr` … `_3.exr` (the y, z, x layers), f16 values |
//! | `godot-l1-legacy` | `godot_l1_legacy_0.exr` … `_3.exr` (signed SH coefficients), f16 values |
//! | `monosh`, `monosh-linear` | `monosh_l0.exr` (f16 values), `monosh_dir.png` (RGBA8, alpha 255): one set for both decodes |
//! | `enlighten` | `enlighten_irradiance.exr` (f16 values), `enlighten_dir.png` (RGBA8, rescaling factor in alpha) |
//! | `enlighten-rgb` | `enlighten_rgb_irradiance.exr`, `enlighten_rgb_dir_r.png`, `_g.png`, `_b.png` |
//!
//! EXR files are 32-bit containers holding the values rounded to f16 (what the engine
//! keeps), RGB + the bake's validity alpha; PNG bytes are the 8-bit values themselves, tagged
//! linear (a gAMA chunk of 1.0: import them as linear data — Unity: sRGB (Color Texture) off;
//! Godot: no sRGB conversion). Texels without a normal (empty, never dilated) hold colour 0
//! and direction ½ (no direction).
//!
//! bake.json records per format the engine and decode, the frame, the files, the bytes per
//! texel the engine stores, the values clamped, and errors over the baked texels against the
//! bake: the decode at the texel normal against the bake's E/π there (what the format loses
//! at the baking normal); the decode at normals tilted [`TILT`] rad towards ±t and ±b (a
//! normal map's reach) against the bake's SH irradiance there (SH L2 where the bake has it,
//! else SH L1 — named in the record), next to what a lightmap without direction (E/π at the
//! texel normal used at any normal) loses there; and what storage alone loses. With
//! `--compress bc6h` each format is also written block-compressed as its engine ships it
//! ([`EngineFormat::compressed`]) and in any labelled variant
//! ([`EngineFormat::compressed_variants`]), `.dds` and `.ktx2` (the same blocks; the engine
//! and layout in its key/value data) beside each file, with the same errors.

use super::write_exr;
use crate::post::images::LightmapImages;
use crate::scene::geometry::frame;
use sbf::glam::{DVec3, Vec3};
use sbf::recon::engine::{self, BlockFormat, CompressedLayout, EngineFormat, EngineFrame, EnlightenInput, L1Irradiance, Moments, Texel};
use serde::Serialize;
use std::path::Path;

/// The tilt of the off-normal error (rad): a normal map's typical reach.
pub const TILT: f64 = 0.5;

/// One format's record in bake.json.
#[derive(Debug, Clone, Serialize)]
pub struct EngineFormatJson {
    pub format: &'static str,
    /// The engine and version whose default decode this is.
    pub engine: &'static str,
    /// The shader function the decode transcribes.
    pub decode: &'static str,
    /// The frame the directions are written in.
    pub frame: &'static str,
    pub files: Vec<String>,
    /// Bytes per texel as the engine stores the textures uncompressed.
    pub bytes_per_texel: usize,
    /// Stored values that were out of the format's range and clamped (all texels).
    pub clamped_values: usize,
    /// RMS over baked texels of (decode at the texel normal − the bake's E/π there),
    /// divided by the RMS of that E/π.
    pub error_at_normal_rel_rms: f64,
    /// RMS over baked texels and the four tilted normals of (decode − the bake's SH
    /// irradiance there) / the RMS of the latter.
    pub error_off_normal_rel_rms: f64,
    /// The same for a lightmap without direction (the bake's E/π at the texel normal).
    pub error_off_normal_without_direction_rel_rms: f64,
    /// The tilt of those normals (rad) and the reference there (`sh2` or `sh1` irradiance).
    pub off_normal_tilt_rad: f64,
    pub off_normal_reference: &'static str,
    /// RMS over baked texels of (decode of the stored values − decode at full precision) at
    /// the texel normal, divided by the RMS of the bake's E/π.
    pub storage_rel_rms: f64,
    /// The textures block-compressed as the engine ships them (`--compress bc6h`; absent:
    /// not asked).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compressed: Option<CompressedFormatJson>,
    /// Other labelled compressed layouts (Godot ≥ 4.4: the unshipped proposal).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub compressed_variants: Vec<CompressedFormatJson>,
}

/// An engine format's textures block-compressed in one layout.
#[derive(Debug, Clone, Serialize)]
pub struct CompressedFormatJson {
    /// What the layout is and who ships it.
    pub layout: &'static str,
    pub files: Vec<String>,
    /// The DXGI format of each file.
    pub dxgi_formats: Vec<&'static str>,
    pub bytes_per_texel: f64,
    /// As [`EngineFormatJson::error_at_normal_rel_rms`], decoded from the compressed files.
    pub error_at_normal_rel_rms: f64,
    /// RMS of (compressed decode − full-precision decode) at the normal / RMS of E/π.
    pub storage_rel_rms: f64,
    /// Values the block format cannot hold (negative colours in BC6H_UF16 — MC noise and LS
    /// fits can dip below 0 — or beyond ±65 504), clamped.
    pub clamped_values: usize,
}

impl EngineFormatJson {
    /// The record as log lines: the uncompressed format, then each compressed layout.
    pub fn log_lines(&self) -> Vec<String> {
        let clamped = if self.clamped_values > 0 { format!(", {} stored values clamped", self.clamped_values) } else { String::new() };
        let mut out = vec![format!(
            "engine format {} ({}): {} B/texel, error at the texel normal {:.2} % of the E/π RMS ({:.3} % from storage), {:.1} rad off it {:.2} % (no direction: {:.2} %; against the bake's {}){clamped}",
            self.format,
            self.engine,
            self.bytes_per_texel,
            100.0 * self.error_at_normal_rel_rms,
            100.0 * self.storage_rel_rms,
            self.off_normal_tilt_rad,
            100.0 * self.error_off_normal_rel_rms,
            100.0 * self.error_off_normal_without_direction_rel_rms,
            self.off_normal_reference,
        )];
        for c in self.compressed.iter().chain(&self.compressed_variants) {
            out.push(format!(
                "engine format {} block-compressed ({}): {:.2} B/texel, error at the texel normal {:.2} % ({:.2} % from storage)",
                self.format,
                c.layout,
                c.bytes_per_texel,
                100.0 * c.error_at_normal_rel_rms,
                100.0 * c.storage_rel_rms
            ));
        }
        out
    }
}

/// One texel encoded for a format: its normal and tangent frame in the engine's frame,
/// the texel at full precision and as stored, the values clamped.
struct EncodedTexel {
    n: DVec3,
    t: DVec3,
    b: DVec3,
    full: Texel,
    stored: Texel,
    clamped: usize,
}

/// Per texel the format's encode (None where the texel has no normal).
fn encode_texels(img: &LightmapImages, sh1: &[Vec<[f32; 3]>], format: EngineFormat, fr: EngineFrame) -> Vec<Option<EncodedTexel>> {
    (0..img.width * img.height)
        .map(|t| {
            let n = Vec3::from(img.normals[t]);
            if n.length_squared() < 0.5 {
                return None;
            }
            let rgb: [[f64; 4]; 3] = [0, 1, 2].map(|ch| [0, 1, 2, 3].map(|l| f64::from(sh1[l][t][ch])));
            let local = L1Irradiance::from_sh(&rgb);
            let (tn, bn) = frame(n);
            // The texel's frame in the engine's frame (a reflection keeps it orthonormal).
            let (tn, bn, nd) = (fr.from_gltf(tn.as_dvec3()), fr.from_gltf(bn.as_dvec3()), fr.from_gltf(n.as_dvec3()));
            let world = L1Irradiance { a0: local.a0, a1: local.a1.map(|a| tn * a.x + bn * a.y + nd * a.z) };
            let input = EnlightenInput {
                normal: nd,
                irradiance: img.irradiance[t].map(f64::from),
                moments: Moments::sphere(&rgb).to_frame(tn, bn, nd),
            };
            let enc = engine::encode(format, &world, Some(&input))?;
            Some(EncodedTexel { n: nd, t: tn, b: bn, full: enc.texel, stored: enc.texel.stored(format), clamped: enc.clamped })
        })
        .collect()
}

/// An RGBA8 PNG of one unit texture (`unit[k]`) of every texel, tagged linear (gAMA 1.0).
fn write_png(path: &Path, img: &LightmapImages, texels: &[Option<EncodedTexel>], k: usize, alpha: bool) -> Result<(), String> {
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let data: Vec<u8> = texels
        .iter()
        .flat_map(|t| match t {
            Some(e) => {
                let u = e.stored.unit[k];
                [byte(u[0]), byte(u[1]), byte(u[2]), if alpha { byte(u[3]) } else { 255 }]
            }
            None => [128, 128, 128, 255],
        })
        .collect();
    let err = |e: &dyn std::fmt::Display| format!("writing {}: {e}", path.display());
    let file = std::fs::File::create(path).map_err(|e| err(&e))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), img.width as u32, img.height as u32);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    // Linear data: gAMA 1.0 (PNG spec §11.3.3.2), so importers do not treat it as sRGB.
    enc.set_source_gamma(png::ScaledFloat::new(1.0));
    let mut w = enc.write_header().map_err(|e| err(&e))?;
    w.write_image_data(&data).map_err(|e| err(&e))?;
    w.finish().map_err(|e| err(&e))
}

/// The texture names of a format (colour first), without extension.
fn stems(format: EngineFormat) -> Vec<String> {
    match format {
        EngineFormat::GodotL1 => (0..4).map(|k| format!("godot_l1_{k}")).collect(),
        EngineFormat::GodotL1Legacy => (0..4).map(|k| format!("godot_l1_legacy_{k}")).collect(),
        EngineFormat::MonoSh | EngineFormat::MonoShLinear => vec!["monosh_l0".into(), "monosh_dir".into()],
        EngineFormat::Enlighten => vec!["enlighten_irradiance".into(), "enlighten_dir".into()],
        EngineFormat::EnlightenRgb => ["irradiance", "dir_r", "dir_g", "dir_b"].iter().map(|s| format!("enlighten_rgb_{s}")).collect(),
    }
}

/// Writes one format's files into `dir`; returns their names.
fn write_files(dir: &Path, img: &LightmapImages, texels: &[Option<EncodedTexel>], format: EngineFormat) -> Result<Vec<String>, String> {
    let rgb = |f: &dyn Fn(&Texel) -> [f64; 3]| -> Vec<[f32; 3]> {
        texels.iter().map(|t| t.as_ref().map_or([0.0; 3], |e| f(&e.stored).map(|v| v as f32))).collect()
    };
    let stems = stems(format);
    let mut names = Vec::new();
    let mut exr = |name: String, data: &[[f32; 3]]| -> Result<(), String> {
        write_exr(&dir.join(&name), img.width, img.height, data, &img.validity)?;
        names.push(name);
        Ok(())
    };
    exr(format!("{}.exr", stems[0]), &rgb(&|s| s.colour))?;
    if format.unit_storage() == engine::Channel::F16 {
        // Godot's layers: f16 values in EXR.
        for (layer, stem) in stems[1..].iter().enumerate() {
            exr(format!("{stem}.exr"), &rgb(&|s| [s.unit[layer][0], s.unit[layer][1], s.unit[layer][2]]))?;
        }
        return Ok(names);
    }
    for (k, stem) in stems[1..].iter().enumerate() {
        let name = format!("{stem}.png");
        write_png(&dir.join(&name), img, texels, k, format.unit_channels() == 4)?;
        names.push(name);
    }
    Ok(names)
}

/// DXGI name of a block format.
fn dxgi_name(f: BlockFormat) -> &'static str {
    match f {
        BlockFormat::Bc6hUf16 => "BC6H_UF16",
        BlockFormat::Bc6hSf16 => "BC6H_SF16",
        BlockFormat::Bc1 => "BC1_UNORM",
        BlockFormat::Bc7 => "BC7_UNORM",
    }
}

/// One RGB(A) texture through a block format: writes `dir/{stem}.dds` and the same blocks as
/// `{stem}.ktx2` (`keys` in its key/value data), returns the decode (RGBA; alpha 1 for BC6H),
/// the bytes and the values clamped.
fn compress_texture(
    dir: &Path,
    img: &LightmapImages,
    stem: &str,
    f: BlockFormat,
    rgba: &[[f64; 4]],
    keys: &[(String, String)],
) -> Result<(Vec<[f64; 4]>, usize, usize), String> {
    use sbf::bc;
    let (w, h) = (img.width, img.height);
    let path = dir.join(format!("{stem}.dds"));
    let ktx = dir.join(format!("{stem}.ktx2"));
    match f {
        BlockFormat::Bc6hUf16 | BlockFormat::Bc6hSf16 => {
            let rgb: Vec<[f32; 3]> = rgba.iter().map(|p| [p[0] as f32, p[1] as f32, p[2] as f32]).collect();
            let b = if f == BlockFormat::Bc6hSf16 { bc::encode_bc6h_signed(w, h, &rgb)? } else { bc::encode_bc6h_unsigned(w, h, &rgb) };
            let decoded = b.decode(w, h).iter().map(|p| [p[0] as f64, p[1] as f64, p[2] as f64, 1.0]).collect();
            let (bytes, clamped) = (b.blocks.len(), b.clamped);
            super::compress::write_ktx2(&ktx, [w, h], None, b.format, &b.blocks, keys.to_vec())?;
            bc::write_dds(&path, w, h, b.format, b.blocks)?;
            Ok((decoded, bytes, clamped))
        }
        BlockFormat::Bc1 | BlockFormat::Bc7 => {
            let (blocks, dxgi, decoded) = bc::encode_unorm(w, h, rgba, f == BlockFormat::Bc7);
            let bytes = blocks.len();
            super::compress::write_ktx2(&ktx, [w, h], None, dxgi, &blocks, keys.to_vec())?;
            bc::write_dds(&path, w, h, dxgi, blocks)?;
            Ok((decoded, bytes, 0))
        }
    }
}

/// The format's textures in one compressed layout (files `{stem}{suffix}.dds`; the colour
/// keeps its stem): returns the texels as the engine reads them back and the record's parts.
fn compress_layout(
    dir: &Path,
    img: &LightmapImages,
    texels: &[Option<EncodedTexel>],
    format: EngineFormat,
    layout: CompressedLayout,
    suffix: &str,
) -> Result<(Vec<Option<Texel>>, CompressedFormatJson), String> {
    let stems = stems(format);
    let colour: Vec<[f64; 4]> =
        texels.iter().map(|t| t.as_ref().map_or([0.0; 4], |e| [e.stored.colour[0], e.stored.colour[1], e.stored.colour[2], 1.0])).collect();
    // MonoSH's two decodes share their textures: the file names both.
    let engine = match format {
        EngineFormat::MonoSh | EngineFormat::MonoShLinear => {
            "Bakery for Unity, MonoSH: the same textures for SH non-linear mode on (Bakery's default) and off"
        }
        _ => format.engine(),
    };
    let keys = vec![("sbf.engine".to_string(), engine.to_string()), ("sbf.layout".to_string(), layout.label.to_string())];
    let (decoded_colour, mut bytes, clamped) = compress_texture(dir, img, &stems[0], layout.colour, &colour, &keys)?;
    let mut files = vec![format!("{}.dds", stems[0])];
    let mut formats = vec![dxgi_name(layout.colour)];
    let mut units = Vec::new();
    for k in 0..format.unit_textures() {
        let rgba: Vec<[f64; 4]> = texels.iter().map(|t| t.as_ref().map_or([0.5, 0.5, 0.5, 1.0], |e| e.stored.unit[k])).collect();
        let stem = format!("{}{suffix}", stems[k + 1]);
        let (decoded, b, _) = compress_texture(dir, img, &stem, layout.units, &rgba, &keys)?;
        bytes += b;
        files.push(format!("{stem}.dds"));
        formats.push(dxgi_name(layout.units));
        units.push(decoded);
    }
    let alpha = format.unit_channels() == 4;
    let read = texels
        .iter()
        .enumerate()
        .map(|(t, tx)| {
            tx.as_ref().map(|_| {
                let mut unit = [[1.0; 4]; 3];
                for (k, u) in units.iter().enumerate() {
                    unit[k] = if alpha { u[t] } else { [u[t][0], u[t][1], u[t][2], 1.0] };
                }
                Texel { colour: [decoded_colour[t][0], decoded_colour[t][1], decoded_colour[t][2]], unit }
            })
        })
        .collect();
    let json = CompressedFormatJson {
        layout: layout.label,
        files,
        dxgi_formats: formats,
        bytes_per_texel: bytes as f64 / (img.width * img.height).max(1) as f64,
        error_at_normal_rel_rms: 0.0,
        storage_rel_rms: 0.0,
        clamped_values: clamped,
    };
    Ok((read, json))
}

/// The bake's SH irradiance E/π at tangent-frame normal `nl` of texel `t`, from the
/// highest SH order it has.
fn sh_irradiance(reference: &[Vec<[f32; 3]>], t: usize, nl: DVec3) -> [f64; 3] {
    [0, 1, 2].map(|ch| {
        let c: Vec<f64> = reference.iter().map(|lobe| f64::from(lobe[t][ch])).collect();
        sbf::recon::sh::irradiance(&c, nl).unwrap_or(f64::NAN)
    })
}

/// The tilted normals of the off-normal error, in the tangent frame (x along t, y along b).
fn tilts() -> [DVec3; 4] {
    let s = TILT.tan();
    [DVec3::new(s, 0.0, 1.0), DVec3::new(-s, 0.0, 1.0), DVec3::new(0.0, s, 1.0), DVec3::new(0.0, -s, 1.0)].map(|v| v.normalize())
}

/// Encodes the SH L1 lightmap (`sh1[lobe][texel]`, 4 lobes) in every format of `formats`,
/// writes their files into `dir` (and block-compressed copies with `compress`) and returns
/// their bake.json records. `sh2`: the bake's SH L2 lobes, the off-normal reference where
/// present (else SH L1); `frame`: every format's directions in this frame instead of its
/// engine's.
pub fn write_engine_formats(
    dir: &Path,
    img: &LightmapImages,
    sh1: &[Vec<[f32; 3]>],
    sh2: Option<&[Vec<[f32; 3]>]>,
    formats: &[EngineFormat],
    frame_override: Option<EngineFrame>,
    compress: bool,
) -> Result<Vec<EngineFormatJson>, String> {
    if sh1.len() != 4 {
        return Err(format!("engine formats are encoded from SH L1 (4 lobes), got {} lobes", sh1.len()));
    }
    if let Some(s) = sh2 {
        if s.len() != 9 {
            return Err(format!("the off-normal reference is SH L2 (9 lobes), got {} lobes", s.len()));
        }
    }
    let (reference, reference_name) = match sh2 {
        Some(s) => (s, "sh2"),
        None => (sh1, "sh1"),
    };
    let tilts = tilts();
    let mut out = Vec::new();
    for &format in formats {
        let fr = frame_override.unwrap_or(format.frame());
        let texels = encode_texels(img, sh1, format, fr);
        let files = write_files(dir, img, &texels, format)?;
        let mut layouts = Vec::new();
        if compress {
            layouts.push(compress_layout(dir, img, &texels, format, format.compressed(), "")?);
            for (i, l) in format.compressed_variants().into_iter().enumerate() {
                let suffix = format!(
                    "_{}",
                    if i == 0 { dxgi_name(l.units).split('_').next().unwrap_or("v").to_lowercase() } else { format!("v{i}") }
                );
                layouts.push(compress_layout(dir, img, &texels, format, l, &suffix)?);
            }
        }
        let (mut err, mut storage, mut signal) = (0.0, 0.0, 0.0);
        let (mut off, mut off_plain, mut off_signal) = (0.0, 0.0, 0.0);
        let mut comp = vec![(0.0, 0.0); layouts.len()];
        for (t, tx) in texels.iter().enumerate() {
            let Some(e) = tx else { continue };
            if img.validity[t] <= 0.0 {
                continue;
            }
            let (df, ds) = (engine::decode(format, &e.full, e.n), engine::decode(format, &e.stored, e.n));
            let dc: Vec<Option<[f64; 3]>> =
                layouts.iter().map(|(read, _)| read[t].as_ref().map(|c| engine::decode(format, c, e.n))).collect();
            let bake = img.irradiance[t].map(f64::from);
            for k in 0..3 {
                err += (ds[k] - bake[k]).powi(2);
                storage += (ds[k] - df[k]).powi(2);
                signal += bake[k] * bake[k];
                for (c, d) in comp.iter_mut().zip(&dc) {
                    if let Some(d) = d {
                        c.0 += (d[k] - bake[k]).powi(2);
                        c.1 += (d[k] - df[k]).powi(2);
                    }
                }
            }
            for nl in tilts {
                let want = sh_irradiance(reference, t, nl);
                let got = engine::decode(format, &e.stored, e.t * nl.x + e.b * nl.y + e.n * nl.z);
                for k in 0..3 {
                    off += (got[k] - want[k]).powi(2);
                    off_plain += (bake[k] - want[k]).powi(2);
                    off_signal += want[k] * want[k];
                }
            }
        }
        let rel = |x: f64, s: f64| if s > 0.0 { (x / s).sqrt() } else { 0.0 };
        let mut compressed: Vec<CompressedFormatJson> = layouts
            .into_iter()
            .zip(comp)
            .map(|((_, mut j), (e, s))| {
                j.error_at_normal_rel_rms = rel(e, signal);
                j.storage_rel_rms = rel(s, signal);
                j
            })
            .collect();
        let shipped = if compressed.is_empty() { None } else { Some(compressed.remove(0)) };
        out.push(EngineFormatJson {
            format: format.id(),
            engine: format.engine(),
            decode: format.decode_source(),
            frame: fr.id(),
            files,
            bytes_per_texel: format.engine_bytes(),
            clamped_values: texels.iter().flatten().map(|e| e.clamped).sum(),
            error_at_normal_rel_rms: rel(err, signal),
            error_off_normal_rel_rms: rel(off, off_signal),
            error_off_normal_without_direction_rel_rms: rel(off_plain, off_signal),
            off_normal_tilt_rad: TILT,
            off_normal_reference: reference_name,
            storage_rel_rms: rel(storage, signal),
            compressed: shipped,
            compressed_variants: compressed,
        });
    }
    Ok(out)
}
