//! `sbf::bc::bc6h_signed`, the BC6H_SF16 encoder (DirectXTex), decoded by bcdec (`bcdec_rs`, a
//! port of an independent decoder) — against the values encoded, with a bound from the format.
//!
//! Error model. BC6H's signed decode (Microsoft, "BC6H Format") maps a 10-bit endpoint q to
//! P = ((|q| << 15) + 0x4000) >> 9 (±0x7FFF at |q| ≥ 511), interpolates P with 4-bit weights
//! w/64 and ends with h = P·31/32, h the half float's signed magnitude. DirectXTex minimises a
//! block's summed squared error in these units (`Norm` over `INTColor`, BC6HBC7.cpp) over all
//! 14 modes. So per block its error cannot exceed that of the plainest legal encoding, which
//! the test builds itself from the spec: mode 11 with each channel's endpoints the block's
//! extreme texels along the segment the texels lie on, quantised to the nearest q, and each
//! texel's index nearest in 3D — [`reference_sse`]. A texel alone may exceed its own
//! reference error (another mode trades it for the rest); the block's sum may not.

use sbf::bc;

/// A half float's signed magnitude (the bit pattern with the sign moved out).
fn signed_bits(v: f32) -> i32 {
    let h = half::f16::from_f32(v).to_bits();
    let m = (h & 0x7FFF) as i32;
    if h & 0x8000 != 0 {
        -m
    } else {
        m
    }
}

/// The value of a signed magnitude P·31/32 rounded down (the decoder's finish).
fn value_of_p(p: i32) -> f32 {
    let m = (p.abs() * 31) >> 5;
    let bits = if p < 0 { 0x8000 | m as u16 } else { m as u16 };
    half::f16::from_bits(bits).to_f32()
}

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The decoder's unquantisation of a 10-bit signed endpoint (BC6H spec, signed, prec 10).
fn unquantize(q: i32) -> i32 {
    let x = q.abs();
    let u = if x == 0 {
        0
    } else if x >= 511 {
        0x7FFF
    } else {
        ((x << 15) + 0x4000) >> 9
    };
    q.signum() * u
}

/// Summed squared error, in half-float bit steps, of the mode-11 encoding of `texels` with
/// endpoints `ends` (each channel quantised to the nearest 10-bit q) and each texel's index
/// the palette entry nearest in 3D.
fn reference_sse(texels: &[[f32; 3]], ends: [[f32; 3]; 2]) -> f64 {
    const W: [i32; 16] = [0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64];
    let q = ends.map(|e| {
        e.map(|v| {
            let p = signed_bits(v) as f64 * 32.0 / 31.0;
            (-511..=511).min_by_key(|q| (unquantize(*q) as f64 - p).abs() as i64).unwrap()
        })
    });
    let palette: Vec<[i32; 3]> = W
        .iter()
        .map(|w| {
            [0, 1, 2].map(|c| {
                let p = (unquantize(q[0][c]) * (64 - w) + unquantize(q[1][c]) * w + 32) >> 6;
                p.signum() * ((p.abs() * 31) >> 5)
            })
        })
        .collect();
    texels
        .iter()
        .map(|t| {
            let b = t.map(signed_bits);
            palette.iter().map(|e| (0..3).map(|c| ((e[c] - b[c]) as f64).powi(2)).sum::<f64>()).fold(f64::MAX, f64::min)
        })
        .sum()
}

#[test]
fn signed_blocks_decode_within_the_format_bound() {
    // Blocks of 16 texels on a segment in value (a lobe's smooth variation), the ends' channels
    // of random sign and magnitude 10^(−3…3), so many blocks change sign in some channel.
    let (bw, bh) = (8usize, 6usize);
    let (w, h) = (bw * 4, bh * 4);
    let mut rng = Lcg(3);
    let mut img = vec![[0.0f32; 3]; w * h];
    let mut ends = vec![[[0.0f32; 3]; 2]; bw * bh];
    for by in 0..bh {
        for bx in 0..bw {
            let e: [[f32; 3]; 2] =
                [0, 1].map(|_| [0, 1, 2].map(|_| ((rng.next() * 2.0 - 1.0).signum() * 10f64.powf(rng.next() * 6.0 - 3.0)) as f32));
            ends[by * bw + bx] = e;
            for k in 0..16 {
                // Both ends appear (k = 0, 15), the rest anywhere between.
                let t = match k {
                    0 => 0.0,
                    15 => 1.0,
                    _ => rng.next() as f32,
                };
                img[(by * 4 + k / 4) * w + bx * 4 + k % 4] = [0, 1, 2].map(|c| e[0][c] + t * (e[1][c] - e[0][c]));
            }
        }
    }
    let b = bc::encode_bc6h(w, h, &img).unwrap();
    assert!(b.signed(), "an image with negative values is BC6H_SF16");
    assert_eq!((b.blocks.len(), b.clamped), (bw * bh * 16, 0));
    let mut out = [0.0f32; 48];
    let (mut worst, mut total, mut total_ref) = (0.0f64, 0.0, 0.0);
    for (i, block) in b.blocks.chunks_exact(16).enumerate() {
        bcdec_rs::bc6h_float(block, &mut out, 12, true);
        let (bx, by) = (i % bw, i / bw);
        let texels: Vec<[f32; 3]> = (0..16).map(|k| img[(by * 4 + k / 4) * w + bx * 4 + k % 4]).collect();
        let sse: f64 = (0..16)
            .map(|k| {
                (0..3).map(|c| ((signed_bits(out[(k / 4) * 12 + (k % 4) * 3 + c]) - signed_bits(texels[k][c])) as f64).powi(2)).sum::<f64>()
            })
            .sum();
        let reference = reference_sse(&texels, ends[i]);
        worst = worst.max(sse / reference.max(1.0));
        total += sse;
        total_ref += reference;
        assert!(sse <= reference, "block {i} {:?}: {sse:.0} squared half steps, the plain mode-11 encoding {reference:.0}", ends[i]);
    }
    println!("error / plain mode 11's: worst block {worst:.3}, all blocks {:.3}", total / total_ref);
}

#[test]
fn a_uniform_signed_block_is_kept_to_the_palette_spacing() {
    // 16 copies of one value: outward-rounded endpoints bracket it, so the nearest palette
    // entry is within half a spacing of ≤ 64·5/64 = 5 steps of P: ≤ 3 half-float steps (with
    // rounding), a relative error ≤ 3·2⁻¹⁰ in f16's normal range.
    for v in [-0.4f32, -1234.5, 0.015, -7.0e-3, 3.25] {
        let img = vec![[v, -v, 0.5 * v]; 16];
        let b = bc::encode_bc6h_signed(4, 4, &img).unwrap();
        let d = b.decode(4, 4);
        for p in &d {
            for c in 0..3 {
                let want = img[0][c];
                assert!((p[c] - want).abs() <= want.abs() * 3.0 / 1024.0 + 1e-6, "{want} decoded {}", p[c]);
            }
        }
    }
}

#[test]
fn dds_volume_header_carries_the_volume_flag() {
    let dir = std::env::temp_dir().join(format!("sbf-bc-volume-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("v.dds");
    let b = bc::encode_bc6h_signed(4, 4, &[[-1.0, 0.5, 2.0]; 16]).unwrap();
    let blocks = [b.blocks.clone(), b.blocks.clone(), b.blocks].concat();
    bc::write_dds_volume(&path, 4, 4, Some(3), bc::ddsfile::DxgiFormat::BC6H_SF16, blocks).unwrap();
    // DDS_HEADER after the magic (Microsoft, "DDS_HEADER structure"): dwFlags at 8 (DDSD_DEPTH
    // 0x800000), dwDepth at 24, dwCaps2 at 112 (DDSCAPS2_VOLUME 0x200000); DDS_HEADER_DXT10
    // at 128: dxgiFormat (BC6H_SF16 = 96), resourceDimension (TEXTURE3D = 4).
    let raw = std::fs::read(&path).unwrap();
    let u = |o: usize| u32::from_le_bytes(raw[o..o + 4].try_into().unwrap());
    assert_eq!(&raw[..4], b"DDS ");
    assert!(u(8) & 0x80_0000 != 0, "flags {:#x}", u(8));
    assert_eq!(u(24), 3);
    assert!(u(112) & 0x20_0000 != 0, "caps2 {:#x}", u(112));
    assert_eq!((u(128), u(132)), (96, 4));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_endpoint_value_decodes_bit_exactly() {
    // A uniform block whose value is an endpoint's own decode — P = ((|q| << 15) + 0x4000) >> 9
    // (the spec's unquantisation, typed here), finished ×31/32 — is representable exactly (index
    // 0 or 15 selects the endpoint): bcdec must return the same half bits, for either sign.
    for q in [1i32, 2, 37, 200, 447, 510] {
        for sign in [1, -1] {
            let p = sign * (((q << 15) + 0x4000) >> 9);
            let v = value_of_p(p);
            let b = bc::encode_bc6h_signed(4, 4, &[[v, -v, v]; 16]).unwrap();
            let d = b.decode(4, 4);
            assert_eq!(
                [d[0][0], d[0][1], d[0][2]].map(|x| half::f16::from_f32(x).to_bits()),
                [v, -v, v].map(|x| half::f16::from_f32(x).to_bits()),
                "q {q} sign {sign}: {v} decoded {:?}",
                d[0]
            );
        }
    }
}
