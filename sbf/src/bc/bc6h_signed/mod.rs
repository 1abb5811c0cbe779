//! BC6H_SF16 (signed half float) blocks, which the ISPC compressor behind
//! [`super::encode_bc6h_unsigned`] does not write: Microsoft's DirectXTex codec
//! (`DirectXTex/BC6HBC7.cpp`, through the `directxtex` crate's bindings), which searches all
//! 14 modes of the format — the one-region modes 11–14 and the two-region modes 1–10 with
//! their 32 partitions (Microsoft, "BC6H Format", Direct3D 11 documentation).
//!
//! The modes matter for signed lightmap lobes. BC6H interpolates the endpoints' half-float
//! bit patterns (sign and magnitude), so a region whose values change sign passes through
//! magnitudes far below both ends. On the glTF room (docs/baker.md), Godot 4.0–4.3's signed
//! SH layers through a mode-11-only encoder lost 65 % of E/π at the texel normal; with
//! DirectXTex's modes storage adds 3.0–7.1 % (1 024 and 256 passes).
//!
//! DirectXTex chooses a block's mode and endpoints by a heuristic (rough error per partition,
//! then refinement of the best quarter), not an exhaustive search, and on some blocks it ends
//! worse than a plain one-region encoding. So every block is also encoded by `mode11`, and
//! the one whose bcdec decode has the smaller summed squared error in half-float bit steps —
//! DirectXTex's own metric (`Norm` over `INTColor`) — is kept.
//!
//! Each block is encoded on its own, so the image is cut into bands of whole block rows that
//! are encoded in parallel (`std::thread::scope`): the same blocks for any thread count.

mod mode11;

use super::F16_MAX;
use directxtex::{ScratchImage, CP_FLAGS, DXGI_FORMAT, TEX_COMPRESS_FLAGS};

/// Block rows per band handed to one DirectXTex call.
const BAND_BLOCK_ROWS: usize = 8;

/// Encodes one RGB image (row-major, `width` × `height`) as BC6H_SF16 blocks, padded to whole
/// 4 × 4 blocks by repeating the last row and column; values beyond ±65 504 and NaN are
/// clamped (NaN to 0) and counted. Returns (blocks, clamped count).
pub fn encode(width: usize, height: usize, rgb: &[[f32; 3]]) -> Result<(Vec<u8>, usize), String> {
    assert_eq!(rgb.len(), width * height, "{width} × {height} image with {} texels", rgb.len());
    let clamped = rgb.iter().flatten().filter(|v| !(-F16_MAX..=F16_MAX).contains(*v)).count();
    let (pw, bh) = (width.div_ceil(4) * 4, height.div_ceil(4));
    let bands: Vec<(usize, usize)> = (0..bh).step_by(BAND_BLOCK_ROWS).map(|b0| (b0, (b0 + BAND_BLOCK_ROWS).min(bh))).collect();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(bands.len()).max(1);
    let encoded: Vec<Result<Vec<u8>, String>> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let bands = &bands;
                s.spawn(move || {
                    bands.iter().skip(t).step_by(threads).map(|&(b0, b1)| encode_band(width, height, pw, b0, b1, rgb)).collect::<Vec<_>>()
                })
            })
            .collect();
        let per_thread: Vec<Vec<_>> = workers.into_iter().map(|w| w.join().expect("BC6H_SF16 encoder thread panicked")).collect();
        // Back in band order: band i was thread i mod threads' (i / threads)-th.
        let mut iters: Vec<_> = per_thread.into_iter().map(Vec::into_iter).collect();
        (0..bands.len()).map(|i| iters[i % threads].next().expect("one result per band")).collect()
    });
    let mut blocks = Vec::with_capacity(pw / 4 * bh * 16);
    for band in encoded {
        blocks.extend(band?);
    }
    Ok((blocks, clamped))
}

/// Block rows `b0..b1` of the padded image, as one RGBA f32 image through DirectXTex.
fn encode_band(width: usize, height: usize, pw: usize, b0: usize, b1: usize, rgb: &[[f32; 3]]) -> Result<Vec<u8>, String> {
    let rows = (b1 - b0) * 4;
    let mut img = ScratchImage::default();
    img.initialize_2d(DXGI_FORMAT::DXGI_FORMAT_R32G32B32A32_FLOAT, pw, rows, 1, 1, CP_FLAGS::CP_FLAGS_NONE)
        .map_err(|e| format!("DirectXTex: a {pw} × {rows} f32 image: {e:?}"))?;
    let px = img.pixels_mut();
    for r in 0..rows {
        let y = (b0 * 4 + r).min(height - 1);
        for x in 0..pw {
            let p = rgb[y * width + x.min(width - 1)];
            let o = (r * pw + x) * 16;
            for (k, v) in [p[0], p[1], p[2], 1.0].into_iter().enumerate() {
                let v = if v.is_nan() { 0.0 } else { v.clamp(-F16_MAX, F16_MAX) };
                px[o + k * 4..o + k * 4 + 4].copy_from_slice(&v.to_le_bytes());
            }
        }
    }
    let c = img
        .compress(DXGI_FORMAT::DXGI_FORMAT_BC6H_SF16, TEX_COMPRESS_FLAGS::TEX_COMPRESS_DEFAULT, 0.5)
        .map_err(|e| format!("DirectXTex BC6H_SF16 compression: {e:?}"))?;
    let want = pw / 4 * (b1 - b0) * 16;
    let mut out = c.pixels().to_vec();
    if out.len() != want {
        return Err(format!("DirectXTex returned {} bytes for {} blocks", out.len(), want / 16));
    }
    for (i, block) in out.chunks_exact_mut(16).enumerate() {
        let (bx, by) = (i % (pw / 4), b0 + i / (pw / 4));
        let texels: [[f32; 3]; 16] = std::array::from_fn(|k| {
            let (x, y) = ((bx * 4 + k % 4).min(width - 1), (by * 4 + k / 4).min(height - 1));
            rgb[y * width + x].map(|v| if v.is_nan() { 0.0 } else { v.clamp(-F16_MAX, F16_MAX) })
        });
        let plain = mode11::encode_block(&texels, &mut 0);
        if block_sse(&plain, &texels) < block_sse(block, &texels) {
            block.copy_from_slice(&plain);
        }
    }
    Ok(out)
}

/// A half float's signed magnitude (the bit pattern with the sign moved out).
fn signed_bits(v: f32) -> i64 {
    let h = half::f16::from_f32(v).to_bits();
    let m = i64::from(h & 0x7FFF);
    if h & 0x8000 != 0 {
        -m
    } else {
        m
    }
}

/// Summed squared error of a block's bcdec decode against its texels, in half-float bit steps.
fn block_sse(block: &[u8], texels: &[[f32; 3]; 16]) -> i64 {
    let mut d = [0.0f32; 48];
    bcdec_rs::bc6h_float(block, &mut d, 12, true);
    let mut sse = 0;
    for (k, t) in texels.iter().enumerate() {
        for c in 0..3 {
            let e = signed_bits(d[(k / 4) * 12 + (k % 4) * 3 + c]) - signed_bits(t[c]);
            sse += e * e;
        }
    }
    sse
}
