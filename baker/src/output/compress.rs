//! Compressed lightmaps (`--compress bc6h`): every lightmap image as a DDS file in BC6H (1
//! byte per texel) and the same blocks as KTX 2.0 beside it, what the engines stream instead
//! of f32 EXR, with the error it adds measured by an independent decoder. Probe volumes are
//! DDS volumes (`DDSCAPS2_VOLUME`, DX10 `TEXTURE3D`).
//!
//! The codec is `sbf::bc`, decoded by `bcdec_rs`. Non-negative images are BC6H_UF16 (ISPC
//! Texture Compressor). Signed ones (SH and least-squares lobes, probe coefficients) are
//! BC6H_SF16 (DirectXTex), so the file alone decodes to the values; `--compress bc6h-offset`
//! stores them as UF16 shifted by a per-channel offset instead (bake.json and the KTX2's
//! key/value data carry it; the runtime subtracts it), which loses less of a lobe that
//! changes sign within blocks ([`SignedStorage`]).
//!
//! Per image, bake.json records the offset, the bytes and the RMS of (decoded − source) over baked texels relative
//! to the source's RMS; per basis, the error each storage adds to E/π at the texel normal
//! (the basis's Lambert runtime on the lobes, [`BakedBasis::irradiance_at_normal`]): f16
//! (each lobe rounded to half, as the renderer's f16 textures) and BC6H, relative to the
//! RMS of E/π from the f32 lobes; and each storage's total error at the normal against the
//! bake's own E/π (`irradiance.exr`).

use crate::accumulate::{BakedBasis, BasisId};
use crate::post::images::LightmapImages;
use sbf::bc;
use sbf::glam::DVec3;
use serde::Serialize;
use std::path::Path;

/// How `--compress` stores an image with negative values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SignedStorage {
    /// BC6H_SF16: the file decodes to the values in any reader (`--compress bc6h`).
    Sf16,
    /// BC6H_UF16 of the values plus a per-channel offset the reader subtracts
    /// (`--compress bc6h-offset`).
    Offset,
}

impl SignedStorage {
    /// Its `--compress` value.
    pub fn name(self) -> &'static str {
        match self {
            Self::Sf16 => "bc6h",
            Self::Offset => "bc6h-offset",
        }
    }

    /// The other one.
    pub fn other(self) -> Self {
        match self {
            Self::Sf16 => Self::Offset,
            Self::Offset => Self::Sf16,
        }
    }
}

impl SignedAlternativeJson {
    /// " (--compress X: Y %)" for a log line, empty without an alternative.
    pub fn note(a: Option<&Self>) -> String {
        a.map_or(String::new(), |a| format!(" (--compress {}: {:.3} %)", a.compress, 100.0 * a.irradiance_rel_rms_bc6h))
    }
}

/// One compressed image in bake.json.
#[derive(Debug, Clone, Serialize)]
pub struct CompressedImageJson {
    pub file: String,
    /// `BC6H_UF16` or `BC6H_SF16` (the DDS's DXGI format).
    pub dxgi_format: &'static str,
    /// The same blocks as KTX 2.0 (`{stem}.ktx2`), the offset in its key/value data
    /// (`sbf.offset`).
    pub ktx2: String,
    /// The EXR it encodes.
    pub source: String,
    /// Added per channel before encoding (subtract after decoding); zero for BC6H_SF16 and
    /// non-negative images.
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
    /// Where an image of the basis is signed: what the other signed storage would have given
    /// (`bc6h-offset` under `--compress bc6h` and vice versa), measured the same way.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub signed_alternative: Option<SignedAlternativeJson>,
}

/// The other signed storage's figures for one basis (not written to files).
#[derive(Debug, Clone, Serialize)]
pub struct SignedAlternativeJson {
    /// `bc6h` (BC6H_SF16) or `bc6h-offset` (BC6H_UF16 + offset).
    pub compress: &'static str,
    /// As [`BasisStorageJson::irradiance_rel_rms_bc6h`] (or the probes' figure of that name)
    /// and the BC6H entry of [`BasisStorageJson::error_at_normal_rel_rms`] (lightmaps only).
    pub irradiance_rel_rms_bc6h: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_at_normal_rel_rms_bc6h: Option<f64>,
}

/// One probe basis's volumes against their error in bake.json.
#[derive(Debug, Clone, Serialize)]
pub struct ProbeStorageJson {
    pub basis: String,
    /// One DDS volume per coefficient (`probes_{basis}_{lobe}.dds`): NX × NY × NZ texels in
    /// the grid's order (x fastest, then y, then z), BC6H per slice; the same blocks as a
    /// KTX 2.0 3D texture beside each (`.ktx2`, the offset under `sbf.offset`).
    pub files: Vec<String>,
    /// Per file, its DXGI format (`BC6H_SF16` for a signed coefficient unless
    /// `--compress bc6h-offset`) and what was added per channel before encoding (subtract
    /// after decoding; zero but for `bc6h-offset`).
    pub dxgi_formats: Vec<&'static str>,
    pub offsets: Vec<[f32; 3]>,
    /// Bytes per probe: f32 RGB, f16 RGBA (a GPU volume's rgba16float) and BC6H (the
    /// files' blocks over the probes: slices padded to whole 4 × 4 blocks).
    pub bytes_per_probe: [f64; 3],
    /// RMS over valid probes of (decoded − baked) coefficients relative to the
    /// coefficients' RMS there.
    pub coefficient_rel_rms: f64,
    /// RMS over valid probes and 64 spherical-Fibonacci normals of the change in E/π
    /// (the basis's Lambert runtime, [`BakedBasis::irradiance_at`]) relative to its RMS:
    /// every coefficient rounded to f16, and through BC6H.
    pub irradiance_rel_rms_f16: f64,
    pub irradiance_rel_rms_bc6h: f64,
    /// Values above the f16 maximum, clamped to it.
    pub clamped_values: usize,
    /// Where a coefficient is signed: what the other signed storage would have given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub signed_alternative: Option<SignedAlternativeJson>,
}

/// What `--compress bc6h` wrote and measured.
#[derive(Debug, Clone, Serialize)]
pub struct CompressionJson {
    /// The containers and formats written (`--compress bc6h` or `bc6h-offset`).
    pub format: &'static str,
    pub encoder: &'static str,
    pub decoder: &'static str,
    pub images: Vec<CompressedImageJson>,
    pub bases: Vec<BasisStorageJson>,
    /// The probe grid's volumes (absent without probes).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub probes: Vec<ProbeStorageJson>,
    pub seconds: f64,
}

/// The probe grid of a bake as `--compress bc6h` stores it.
#[derive(Debug)]
pub struct ProbeGrid<'a> {
    /// NX, NY, NZ (probe k at x = k mod NX, y = (k / NX) mod NY, z = k / (NX·NY)).
    pub n: [usize; 3],
    pub bases: &'a [BasisId],
    /// `coefficients[basis][probe][lobe]`, world frame.
    pub coefficients: Vec<Vec<Vec<[f64; 3]>>>,
    pub valid: &'a [bool],
    pub sg_sharpness: f64,
    pub signed: SignedStorage,
}

/// Writes every probe basis's coefficients as BC6H DDS volumes (one per coefficient) and
/// measures what f16 and BC6H storage do to the probes' E/π.
pub fn write_probe_volumes(dir: &Path, g: &ProbeGrid) -> Result<Vec<ProbeStorageJson>, String> {
    let [nx, ny, nz] = g.n;
    let slice = nx * ny;
    let count = slice * nz;
    let normals: Vec<DVec3> = (0..64).map(|i| sbf::sampling::spherical_fibonacci(i, 64)).collect();
    let mut out = Vec::new();
    for (b, kind) in g.bases.iter().enumerate() {
        let c = &g.coefficients[b];
        if c.len() != count {
            return Err(format!("probe grid {nx}×{ny}×{nz} holds {count} probes, the bake {}", c.len()));
        }
        let lobes = c.first().map_or(0, Vec::len);
        let (mut files, mut offsets, mut dxgi_formats, mut clamped_values, mut block_bytes) = (Vec::new(), Vec::new(), Vec::new(), 0, 0);
        // decoded[probe][lobe], and through the other signed storage
        let mut decoded = vec![vec![DVec3::ZERO; lobes]; count];
        let (mut alternative, mut any_signed) = (vec![vec![DVec3::ZERO; lobes]; count], false);
        for l in 0..lobes {
            let volume: Vec<[f32; 3]> = c.iter().map(|p| p[l].map(|v| v as f32)).collect();
            let mut blocks = Vec::new();
            let enc = Encoding::choose(&volume, g.signed);
            let alt = match enc {
                Encoding::Unsigned => None,
                Encoding::Signed | Encoding::Offset(_) => Some(Encoding::choose(&volume, g.signed.other())),
            };
            any_signed |= alt.is_some();
            for z in 0..nz {
                let texels = &volume[z * slice..(z + 1) * slice];
                let (bl, dec, clamped) = enc.encode(nx, ny, texels)?;
                clamped_values += clamped;
                let dec_alt = match alt {
                    Some(a) => a.encode(nx, ny, texels)?.1,
                    None => dec.clone(),
                };
                for (i, (t, a)) in dec.iter().zip(&dec_alt).enumerate() {
                    decoded[z * slice + i][l] = dv(*t);
                    alternative[z * slice + i][l] = dv(*a);
                }
                blocks.extend(bl);
            }
            let file = format!("probes_{}_{l:02}.dds", kind.name());
            block_bytes += blocks.len();
            let ktx = dir.join(format!("probes_{}_{l:02}.ktx2", kind.name()));
            write_ktx2(&ktx, [nx, ny], Some(nz), enc.dxgi(), &blocks, enc.key_values())?;
            bc::write_dds_volume(&dir.join(&file), nx, ny, Some(nz), enc.dxgi(), blocks)?;
            dxgi_formats.push(enc.dxgi_name());
            files.push(file);
            offsets.push(enc.offset());
        }
        let valid = || (0..count).filter(|p| g.valid[*p]);
        let (mut e, mut s) = (0.0, 0.0);
        for p in valid() {
            for l in 0..lobes {
                let x = DVec3::from(c[p][l]);
                e += (decoded[p][l] - x).length_squared();
                s += x.length_squared();
            }
        }
        let irr = |src: &dyn Fn(usize) -> DVec3| -> Vec<DVec3> {
            let cs: Vec<DVec3> = (0..lobes).map(src).collect();
            normals.iter().map(|n| kind.irradiance_at(&cs, *n, g.sg_sharpness)).collect()
        };
        let (mut e16, mut ebc, mut ealt, mut sirr) = (0.0, 0.0, 0.0, 0.0);
        for p in valid() {
            let full = irr(&|l| DVec3::from(c[p][l]));
            let half = irr(&|l| DVec3::from(c[p][l].map(|v| half::f16::from_f64(v).to_f64())));
            let bc = irr(&|l| decoded[p][l]);
            let alt = irr(&|l| alternative[p][l]);
            for (((f, h), d), a) in full.iter().zip(&half).zip(&bc).zip(&alt) {
                e16 += (*h - *f).length_squared();
                ebc += (*d - *f).length_squared();
                ealt += (*a - *f).length_squared();
                sirr += f.length_squared();
            }
        }
        let k = lobes as f64;
        out.push(ProbeStorageJson {
            basis: kind.name().into(),
            files,
            dxgi_formats,
            offsets,
            bytes_per_probe: [12.0 * k, 8.0 * k, block_bytes as f64 / count as f64],
            coefficient_rel_rms: rel(e.sqrt(), s.sqrt()),
            irradiance_rel_rms_f16: rel(e16.sqrt(), sirr.sqrt()),
            irradiance_rel_rms_bc6h: rel(ebc.sqrt(), sirr.sqrt()),
            clamped_values,
            signed_alternative: any_signed.then(|| SignedAlternativeJson {
                compress: g.signed.other().name(),
                irradiance_rel_rms_bc6h: rel(ealt.sqrt(), sirr.sqrt()),
                error_at_normal_rel_rms_bc6h: None,
            }),
        });
    }
    Ok(out)
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

/// The same blocks as a KTX 2.0 file (`sbf::ktx`) beside the DDS — Godot, Bevy and three.js
/// read KTX2 — with `key_values` (e.g. the offset to subtract) in the file itself.
pub fn write_ktx2(
    path: &Path,
    size: [usize; 2],
    depth: Option<usize>,
    dxgi: bc::ddsfile::DxgiFormat,
    blocks: &[u8],
    key_values: Vec<(String, String)>,
) -> Result<(), String> {
    let format = bc::ktx2_format(dxgi).ok_or_else(|| format!("{}: no KTX2 format for {dxgi:?}", path.display()))?;
    let dimension = depth.map_or(sbf::ktx::Dimension::D2, |d| sbf::ktx::Dimension::D3 { depth: d as u32 });
    sbf::ktx::Ktx2Image { format, size: [size[0] as u32, size[1] as u32], dimension, key_values, data: blocks }.write(path)
}

/// An image's blocks, their bcdec decode (offset removed) and the values clamped.
type Encoded = (Vec<u8>, Vec<[f32; 3]>, usize);

/// An image's record, its decode and, for a signed image, its decode through the other
/// [`SignedStorage`].
type CompressedImage = (CompressedImageJson, Vec<[f32; 3]>, Option<Vec<[f32; 3]>>);

/// How one image (or volume) is stored: chosen from its values and [`SignedStorage`].
#[derive(Debug, Clone, Copy)]
enum Encoding {
    /// No negative value: BC6H_UF16.
    Unsigned,
    /// BC6H_SF16.
    Signed,
    /// BC6H_UF16 of the values plus this per-channel offset (−the minimum where negative).
    Offset([f32; 3]),
}

impl Encoding {
    fn choose(values: &[[f32; 3]], storage: SignedStorage) -> Self {
        if !values.iter().flatten().any(|v| *v < 0.0) {
            return Self::Unsigned;
        }
        match storage {
            SignedStorage::Sf16 => Self::Signed,
            SignedStorage::Offset => {
                let mut offset = [0.0f32; 3];
                for p in values {
                    for k in 0..3 {
                        offset[k] = offset[k].max(-p[k]);
                    }
                }
                Self::Offset(offset)
            }
        }
    }

    /// Blocks, their bcdec decode (offset removed) and the values clamped.
    fn encode(self, w: usize, h: usize, rgb: &[[f32; 3]]) -> Result<Encoded, String> {
        Ok(match self {
            Self::Unsigned => {
                let b = bc::encode_bc6h_unsigned(w, h, rgb);
                let d = b.decode(w, h);
                (b.blocks, d, b.clamped)
            }
            Self::Signed => {
                let b = bc::encode_bc6h_signed(w, h, rgb)?;
                let d = b.decode(w, h);
                (b.blocks, d, b.clamped)
            }
            Self::Offset(o) => {
                let shifted: Vec<[f32; 3]> = rgb.iter().map(|p| [0, 1, 2].map(|k| p[k] + o[k])).collect();
                let b = bc::encode_bc6h_unsigned(w, h, &shifted);
                let d = bc::decode_bc6h_offset(w, h, &b.blocks, o);
                (b.blocks, d, b.clamped)
            }
        })
    }

    fn dxgi(self) -> bc::ddsfile::DxgiFormat {
        match self {
            Self::Signed => bc::ddsfile::DxgiFormat::BC6H_SF16,
            Self::Unsigned | Self::Offset(_) => bc::ddsfile::DxgiFormat::BC6H_UF16,
        }
    }

    fn dxgi_name(self) -> &'static str {
        match self {
            Self::Signed => "BC6H_SF16",
            Self::Unsigned | Self::Offset(_) => "BC6H_UF16",
        }
    }

    fn offset(self) -> [f32; 3] {
        match self {
            Self::Offset(o) => o,
            Self::Unsigned | Self::Signed => [0.0; 3],
        }
    }

    /// The KTX2 key/value pairs: an offset image's offset and how to decode it, so the file
    /// alone decodes to the values.
    fn key_values(self) -> Vec<(String, String)> {
        match self {
            Self::Offset(o) => vec![
                ("sbf.offset".into(), format!("{} {} {}", o[0], o[1], o[2])),
                ("sbf.decode".into(), "value = texel - sbf.offset (per channel R G B)".into()),
            ],
            Self::Unsigned | Self::Signed => Vec::new(),
        }
    }
}

/// Compresses one image into `dir/{stem}.dds` and `.ktx2`; returns its record, the decoded
/// image and, for a signed image, its decode through the other [`SignedStorage`].
fn compress_image(
    dir: &Path,
    img: &LightmapImages,
    stem: &str,
    rgb: &[[f32; 3]],
    signed: SignedStorage,
) -> Result<CompressedImage, String> {
    let enc = Encoding::choose(rgb, signed);
    let (blocks, decoded, clamped_values) = enc.encode(img.width, img.height, rgb)?;
    let alternative = match enc {
        Encoding::Unsigned => None,
        Encoding::Signed | Encoding::Offset(_) => Some(Encoding::choose(rgb, signed.other()).encode(img.width, img.height, rgb)?.1),
    };
    let bytes = blocks.len();
    let file = format!("{stem}.dds");
    write_ktx2(&dir.join(format!("{stem}.ktx2")), [img.width, img.height], None, enc.dxgi(), &blocks, enc.key_values())?;
    bc::write_dds(&dir.join(&file), img.width, img.height, enc.dxgi(), blocks)?;
    let (e, s) = rms_pair(&img.validity, decoded.iter().map(|p| dv(*p)), rgb.iter().map(|p| dv(*p)));
    Ok((
        CompressedImageJson {
            file,
            dxgi_format: enc.dxgi_name(),
            ktx2: format!("{stem}.ktx2"),
            source: format!("{stem}.exr"),
            offset: enc.offset(),
            bytes,
            rel_rms: rel(e, s),
            clamped_values,
        },
        decoded,
        alternative,
    ))
}

/// Writes every lightmap image (E/π and each basis lobe) as BC6H DDS next to its EXR and
/// measures what f16 and BC6H storage do to each basis's E/π at the texel normal.
pub fn write_bc6h(
    dir: &Path,
    img: &LightmapImages,
    bases: &[BasisId],
    sg_sharpness: f64,
    signed: SignedStorage,
) -> Result<CompressionJson, String> {
    let t0 = std::time::Instant::now();
    let n = img.width * img.height;
    let texels = (img.width.div_ceil(4) * img.height.div_ceil(4) * 16) as f64 / n.max(1) as f64;
    let mut images = Vec::new();
    let mut out_bases = Vec::new();
    let (rec, irr, irr_alt) = compress_image(dir, img, "irradiance", &img.irradiance, signed)?;
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
        signed_alternative: irr_alt.map(|a| {
            let (ea, _) = rms_pair(&img.validity, a.iter().map(|p| dv(*p)), img.irradiance.iter().map(|p| dv(*p)));
            SignedAlternativeJson {
                compress: signed.other().name(),
                irradiance_rel_rms_bc6h: rel(ea, s),
                error_at_normal_rel_rms_bc6h: Some(rel(ea, s)),
            }
        }),
    });
    let bake: Vec<DVec3> = img.irradiance.iter().map(|p| dv(*p)).collect();
    for (b, kind) in bases.iter().enumerate() {
        let lobes = &img.coefficients[b];
        let mut decoded = Vec::with_capacity(lobes.len());
        let (mut alternative, mut any_signed) = (Vec::with_capacity(lobes.len()), false);
        for (l, lobe) in lobes.iter().enumerate() {
            let (rec, d, a) = compress_image(dir, img, &format!("{}_{l:02}", kind.name()), lobe, signed)?;
            images.push(rec);
            any_signed |= a.is_some();
            alternative.push(a.unwrap_or_else(|| d.clone()));
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
            signed_alternative: any_signed.then(|| {
                let alt: Vec<DVec3> = (0..n).map(|t| at(&|l, t| dv(alternative[l][t]), t)).collect();
                let (ea, _) = rms_pair(&img.validity, alt.iter().copied(), full.iter().copied());
                SignedAlternativeJson {
                    compress: signed.other().name(),
                    irradiance_rel_rms_bc6h: rel(ea, s),
                    error_at_normal_rel_rms_bc6h: Some(vs_bake(&alt)),
                }
            }),
        });
    }
    Ok(CompressionJson {
        format: match signed {
            SignedStorage::Sf16 => "DDS and KTX2, BC6H (one 16-byte block per 4 × 4 texels): BC6H_UF16 for non-negative images, BC6H_SF16 for signed ones",
            SignedStorage::Offset => "DDS and KTX2, BC6H_UF16 (one 16-byte block per 4 × 4 texels); signed images shifted by their per-channel offset",
        },
        encoder: "BC6H_UF16: ISPC Texture Compressor via intel_tex_2 0.5 (very slow settings); BC6H_SF16: DirectXTex via directxtex 1.3, per block the better of it and a mode-11 encoding",
        decoder: "bcdec_rs 0.2 (bc6h_float)",
        images,
        bases: out_bases,
        probes: Vec::new(),
        seconds: t0.elapsed().as_secs_f64(),
    })
}
