//! Block-compressed texture storage (feature `bc`): HDR RGB images as BC6H (1 byte per
//! texel; DXGI_FORMAT_BC6H_UF16 for non-negative images, BC6H_SF16 for signed ones
//! ([`encode_bc6h`] picks), or UF16 shifted by a per-channel offset ([`encode_bc6h_offset`]),
//! which keeps more of a signed image but needs the offset beside the file) and 8-bit RGBA
//! images as BC1 (½ byte) or BC7 (1 byte), what engines stream instead of float textures,
//! with an independent decoder to measure the error each adds, and the DDS container.
//!
//! Encoders: ISPC Texture Compressor through `intel_tex_2` (BC6H_UF16 at its "very slow",
//! highest quality settings; BC7 "alpha slow"); its prebuilt C++ object needs the C++
//! runtime, which `build.rs` links on Linux. BC6H_SF16, which ISPC does not write:
//! Microsoft's DirectXTex ([`bc6h_signed`]). Images are padded to whole 4 × 4 blocks by
//! repeating the last row and column; values beyond the f16 range (±65 504) are counted and
//! clamped.
//!
//! Decoder: `bcdec_rs` (a port of bcdec, independent of both encoders).

pub mod bc6h_signed;

pub use ddsfile;
use std::path::Path;

/// The largest finite half float.
pub const F16_MAX: f32 = 65504.0;

/// A BC6H image: its blocks, its DXGI format (UF16 or SF16) and the values clamped.
#[derive(Debug, Clone)]
pub struct Bc6h {
    /// One 16-byte block per 4 × 4 texels, row-major.
    pub blocks: Vec<u8>,
    /// `BC6H_UF16` or `BC6H_SF16`.
    pub format: ddsfile::DxgiFormat,
    /// Values outside the format's range (negative ones for UF16, beyond ±65 504, NaN),
    /// clamped.
    pub clamped: usize,
}

impl Bc6h {
    /// Whether the blocks are BC6H_SF16.
    pub fn signed(&self) -> bool {
        self.format == ddsfile::DxgiFormat::BC6H_SF16
    }

    /// The image decoded by bcdec.
    pub fn decode(&self, width: usize, height: usize) -> Vec<[f32; 3]> {
        decode_bc6h(width, height, &self.blocks, self.signed())
    }
}

/// Encodes one RGB image as BC6H: UF16 (ISPC) when no value is negative, else SF16
/// (DirectXTex).
pub fn encode_bc6h(width: usize, height: usize, rgb: &[[f32; 3]]) -> Result<Bc6h, String> {
    if rgb.iter().flatten().any(|v| *v < 0.0) {
        encode_bc6h_signed(width, height, rgb)
    } else {
        Ok(encode_bc6h_unsigned(width, height, rgb))
    }
}

/// Encodes one RGB image as BC6H_UF16 shifted by a per-channel offset (−its minimum where
/// negative; the reader subtracts it). A signed image loses less this way than as BC6H_SF16,
/// whose blocks interpolate half-float bit patterns across zero, but the file alone no longer
/// decodes to its values: the offset must travel beside it. Returns (blocks, offset, clamped
/// count).
pub fn encode_bc6h_offset(width: usize, height: usize, rgb: &[[f32; 3]]) -> (Vec<u8>, [f32; 3], usize) {
    let mut offset = [0.0f32; 3];
    for p in rgb {
        for k in 0..3 {
            offset[k] = offset[k].max(-p[k]);
        }
    }
    let shifted: Vec<[f32; 3]> = rgb.iter().map(|p| [0, 1, 2].map(|k| p[k] + offset[k])).collect();
    let b = encode_bc6h_unsigned(width, height, &shifted);
    (b.blocks, offset, b.clamped)
}

/// Decodes BC6H_UF16 blocks written by [`encode_bc6h_offset`] and removes the offset.
pub fn decode_bc6h_offset(width: usize, height: usize, blocks: &[u8], offset: [f32; 3]) -> Vec<[f32; 3]> {
    decode_bc6h(width, height, blocks, false).into_iter().map(|p| [0, 1, 2].map(|k| p[k] - offset[k])).collect()
}

/// Encodes one RGB image as BC6H_SF16 ([`bc6h_signed`]: DirectXTex, every mode).
pub fn encode_bc6h_signed(width: usize, height: usize, rgb: &[[f32; 3]]) -> Result<Bc6h, String> {
    let (blocks, clamped) = bc6h_signed::encode(width, height, rgb)?;
    Ok(Bc6h { blocks, format: ddsfile::DxgiFormat::BC6H_SF16, clamped })
}

/// Encodes one RGB image as BC6H_UF16 (ISPC); negative values are clamped to 0 (counted).
pub fn encode_bc6h_unsigned(width: usize, height: usize, rgb: &[[f32; 3]]) -> Bc6h {
    let (pw, ph) = (width.div_ceil(4) * 4, height.div_ceil(4) * 4);
    let clamped = rgb.iter().flatten().filter(|v| !(0.0..=F16_MAX).contains(*v)).count();
    let mut data = Vec::with_capacity(pw * ph * 8);
    for y in 0..ph {
        for x in 0..pw {
            let p = rgb[y.min(height - 1) * width + x.min(width - 1)];
            for v in p {
                let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, F16_MAX) };
                data.extend_from_slice(&half::f16::from_f32(v).to_le_bytes());
            }
            data.extend_from_slice(&half::f16::ONE.to_le_bytes());
        }
    }
    let surface = intel_tex_2::RgbaSurface { data: &data, width: pw as u32, height: ph as u32, stride: (pw * 8) as u32 };
    let blocks = intel_tex_2::bc6h::compress_blocks(&intel_tex_2::bc6h::very_slow_settings(), &surface);
    Bc6h { blocks, format: ddsfile::DxgiFormat::BC6H_UF16, clamped }
}

/// Decodes BC6H blocks of a `width` × `height` image (bcdec; `signed`: BC6H_SF16).
pub fn decode_bc6h(width: usize, height: usize, blocks: &[u8], signed: bool) -> Vec<[f32; 3]> {
    let bw = width.div_ceil(4);
    let mut out = vec![[0.0f32; 3]; width * height];
    let mut texels = [0.0f32; 48];
    for (b, block) in blocks.chunks_exact(16).enumerate() {
        bcdec_rs::bc6h_float(block, &mut texels, 12, signed);
        let (bx, by) = (b % bw, b / bw);
        for j in 0..4 {
            for i in 0..4 {
                let (x, y) = (bx * 4 + i, by * 4 + j);
                if x < width && y < height {
                    let t = &texels[j * 12 + i * 3..j * 12 + i * 3 + 3];
                    out[y * width + x] = [t[0], t[1], t[2]];
                }
            }
        }
    }
    out
}

/// An 8-bit RGBA image (values in [0, 1], rounded to k/255) as BC1 (RGB, `alpha` false:
/// 8 bytes per 4 × 4 block) or BC7 (RGBA, 16 bytes per block; ISPC's "alpha slow" settings),
/// padded like [`encode_bc6h`]; returns (blocks, DXGI format, the bcdec decode in [0, 1]).
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
pub fn write_dds(path: &Path, width: usize, height: usize, format: ddsfile::DxgiFormat, blocks: Vec<u8>) -> Result<(), String> {
    write_dds_volume(path, width, height, None, format, blocks)
}

/// [`write_dds`] for a volume (`depth` Some: a Texture3D whose slices follow each other,
/// each in its own 4 × 4 blocks, flagged `DDSCAPS2_VOLUME` with the DX10 header's
/// `TEXTURE3D` dimension), e.g. a probe grid's coefficient.
pub fn write_dds_volume(
    path: &Path,
    width: usize,
    height: usize,
    depth: Option<usize>,
    format: ddsfile::DxgiFormat,
    blocks: Vec<u8>,
) -> Result<(), String> {
    let mut dds = ddsfile::Dds::new_dxgi(ddsfile::NewDxgiParams {
        height: height as u32,
        width: width as u32,
        depth: depth.map(|d| d as u32),
        format,
        mipmap_levels: None,
        array_layers: None,
        caps2: depth.map(|_| ddsfile::Caps2::VOLUME),
        is_cubemap: false,
        resource_dimension: if depth.is_some() {
            ddsfile::D3D10ResourceDimension::Texture3D
        } else {
            ddsfile::D3D10ResourceDimension::Texture2D
        },
        alpha_mode: ddsfile::AlphaMode::Unknown,
    })
    .map_err(|e| format!("DDS header for {}: {e}", path.display()))?;
    dds.data = blocks;
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(|e| format!("creating {}: {e}", path.display()))?);
    dds.write(&mut f).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// The KTX2 format of a DDS DXGI format the baker writes (BC6H, BC1, BC7).
pub fn ktx2_format(dxgi: ddsfile::DxgiFormat) -> Option<crate::ktx::Format> {
    use ddsfile::DxgiFormat as D;
    Some(match dxgi {
        D::BC6H_UF16 => crate::ktx::Format::BC6H_UFLOAT_BLOCK,
        D::BC6H_SF16 => crate::ktx::Format::BC6H_SFLOAT_BLOCK,
        D::BC1_UNorm => crate::ktx::Format::BC1_RGB_UNORM_BLOCK,
        D::BC7_UNorm => crate::ktx::Format::BC7_UNORM_BLOCK,
        _ => return None,
    })
}
