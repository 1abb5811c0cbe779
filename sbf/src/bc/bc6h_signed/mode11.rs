//! A mode-11 BC6H_SF16 block encoder, the second candidate per block beside DirectXTex
//! (see the parent module): DirectXTex's mode search is heuristic and on some blocks whose
//! texels lie on one segment it ends worse than this plain one-region encoding.
//!
//! Every block uses mode 11 of the format (Microsoft, "BC6H Format", Direct3D 11
//! documentation: one region, two endpoints of 10 bits per channel stored as they are, 4-bit
//! indices; mode bits 00011). The encoder works in the format's own integer domain: a half
//! float's signed magnitude h ∈ [−0x7BFF, 0x7BFF] is the decoder's final scaling ×31/32 of
//! an interpolated value P ∈ [−0x7FFF, 0x7FFF], so the target of each texel is
//! P = round(h·32/31). Per block: the principal axis of the 16 targets (power iteration on
//! their covariance) gives two endpoints at the extreme projections; each endpoint channel
//! is quantised to the 10-bit signed value whose unquantisation (((|q| << 15) + 0x4000) >> 9,
//! 0x7FFF at |q| ≥ 511) is nearest; each texel takes the palette index nearest its target;
//! two least-squares refits of the endpoints to those indices keep whichever of the
//! candidates has the smaller error, then each channel's endpoint pair is polished by up to
//! ±2 steps for the chosen indices; a uniform block searches every index for the endpoint
//! pairs that interpolate each channel nearest its value. The first texel's index must be below 8 (the anchor's
//! top bit is implicit): where it is not, the endpoints swap and the indices mirror.

/// Interpolation weights of 4-bit indices (×64).
const WEIGHTS: [i32; 16] = [0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64];

/// The decoder's unquantisation of a 10-bit signed endpoint channel.
fn unquantize(q: i32) -> i32 {
    let (s, x) = (q < 0, q.abs());
    let u = if x == 0 {
        0
    } else if x >= 511 {
        0x7FFF
    } else {
        ((x << 15) + 0x4000) >> 9
    };
    if s {
        -u
    } else {
        u
    }
}

/// The 10-bit signed value whose unquantisation is nearest `p`.
fn quantize(p: f64) -> i32 {
    let x = p.abs();
    let guess = ((x - 32.0) / 64.0).round().clamp(0.0, 511.0) as i32;
    let best = [guess - 1, guess, guess + 1, 0, 511]
        .into_iter()
        .filter(|q| (0..=511).contains(q))
        .min_by(|a, b| (unquantize(*a) as f64 - x).abs().total_cmp(&(unquantize(*b) as f64 - x).abs()))
        .unwrap_or(0);
    if p < 0.0 {
        -best
    } else {
        best
    }
}

/// The 10-bit signed value whose unquantisation is the largest ≤ `p` (`up` false) or the
/// smallest ≥ `p` (`up` true), within [−511, 511].
fn quantize_dir(p: f64, up: bool) -> i32 {
    let guess = quantize(p);
    let ok = |q: i32| if up { unquantize(q) as f64 >= p } else { unquantize(q) as f64 <= p };
    let mut q = guess;
    // unquantize is monotonic in q: step towards the side until the bound holds.
    while !ok(q) && (-511..=511).contains(&(q + if up { 1 } else { -1 })) {
        q += if up { 1 } else { -1 };
    }
    q
}

/// The decoder's interpolated value (before the final ×31/32) for index `i`.
fn palette(e0: [i32; 3], e1: [i32; 3], i: usize) -> [i32; 3] {
    let (a, b) = (e0.map(unquantize), e1.map(unquantize));
    [0, 1, 2].map(|c| (a[c] * (64 - WEIGHTS[i]) + b[c] * WEIGHTS[i] + 32) >> 6)
}

/// The target P of a value: its half float's signed magnitude × 32/31; values beyond the
/// half range are clamped (counted), NaN becomes 0 (counted).
fn target(v: f32, clamped: &mut usize) -> f64 {
    if v.is_nan() {
        *clamped += 1;
        return 0.0;
    }
    if v.abs() > crate::bc::F16_MAX {
        *clamped += 1;
    }
    let h = half::f16::from_f32(v.clamp(-crate::bc::F16_MAX, crate::bc::F16_MAX)).to_bits();
    let mag = f64::from(h & 0x7FFF) * 32.0 / 31.0;
    if h & 0x8000 != 0 {
        -mag
    } else {
        mag
    }
}

/// Indices nearest each target for endpoints (e0, e1), and the squared error.
fn assign(t: &[[f64; 3]; 16], e0: [i32; 3], e1: [i32; 3]) -> ([usize; 16], f64) {
    let pal: Vec<[i32; 3]> = (0..16).map(|i| palette(e0, e1, i)).collect();
    let mut idx = [0usize; 16];
    let mut err = 0.0;
    for (k, p) in t.iter().enumerate() {
        let d = |c: &[i32; 3]| (0..3).map(|j| (c[j] as f64 - p[j]).powi(2)).sum::<f64>();
        let (best, e) = pal.iter().enumerate().map(|(i, c)| (i, d(c))).min_by(|a, b| a.1.total_cmp(&b.1)).unwrap_or((0, 0.0));
        idx[k] = best;
        err += e;
    }
    (idx, err)
}

/// Endpoints minimising Σ|(1 − w_k)·E0 + w_k·E1 − P_k|² for fixed indices (normal equations
/// of the 2 × 2 system per channel); None where all indices are equal.
fn refit(t: &[[f64; 3]; 16], idx: &[usize; 16]) -> Option<([f64; 3], [f64; 3])> {
    let (mut aa, mut ab, mut bb) = (0.0, 0.0, 0.0);
    let (mut ra, mut rb) = ([0.0; 3], [0.0; 3]);
    for (p, &i) in t.iter().zip(idx) {
        let w = WEIGHTS[i] as f64 / 64.0;
        let (a, b) = (1.0 - w, w);
        aa += a * a;
        ab += a * b;
        bb += b * b;
        for c in 0..3 {
            ra[c] += a * p[c];
            rb[c] += b * p[c];
        }
    }
    let det = aa * bb - ab * ab;
    if det.abs() < 1e-9 {
        return None;
    }
    Some(([0, 1, 2].map(|c| (bb * ra[c] - ab * rb[c]) / det), [0, 1, 2].map(|c| (aa * rb[c] - ab * ra[c]) / det)))
}

/// For fixed indices, each channel's endpoint pair moved by up to ±2 quantisation steps each
/// (25 pairs per channel, channels independent) to the pair with the least squared error —
/// what lets one index serve channels that sit at different places between their endpoints
/// (a uniform block of any colour).
fn polish(t: &[[f64; 3]; 16], e0: [i32; 3], e1: [i32; 3], idx: &[usize; 16]) -> ([i32; 3], [i32; 3]) {
    let (mut a, mut b) = (e0, e1);
    for c in 0..3 {
        let mut best = (f64::INFINITY, e0[c], e1[c]);
        for d0 in -2..=2 {
            for d1 in -2..=2 {
                let (q0, q1) = (e0[c] + d0, e1[c] + d1);
                if !(-511..=511).contains(&q0) || !(-511..=511).contains(&q1) {
                    continue;
                }
                let (u0, u1) = (unquantize(q0), unquantize(q1));
                let err: f64 =
                    t.iter().zip(idx).map(|(p, &i)| (((u0 * (64 - WEIGHTS[i]) + u1 * WEIGHTS[i] + 32) >> 6) as f64 - p[c]).powi(2)).sum();
                if err < best.0 {
                    best = (err, q0, q1);
                }
            }
        }
        a[c] = best.1;
        b[c] = best.2;
    }
    (a, b)
}

/// A uniform block (16 copies of `p`): one shared index i and per channel the endpoint pair
/// whose interpolation at i is nearest p_c — searched over every index and, per channel,
/// q₀ within ±1 of the nearest value and q₁ within ±4 of q₀.
fn uniform(p: &[f64; 3]) -> ([i32; 3], [i32; 3], [usize; 16]) {
    let mut best = (f64::INFINITY, [0; 3], [0; 3], 0);
    for i in 0..16 {
        let (mut e0, mut e1, mut total) = ([0; 3], [0; 3], 0.0);
        for c in 0..3 {
            let g = quantize(p[c]);
            let mut b = (f64::INFINITY, g, g);
            for q0 in g - 1..=g + 1 {
                for q1 in q0 - 4..=q0 + 4 {
                    if !(-511..=511).contains(&q0) || !(-511..=511).contains(&q1) {
                        continue;
                    }
                    let v = (unquantize(q0) * (64 - WEIGHTS[i]) + unquantize(q1) * WEIGHTS[i] + 32) >> 6;
                    let e = (v as f64 - p[c]).powi(2);
                    if e < b.0 {
                        b = (e, q0, q1);
                    }
                }
            }
            (e0[c], e1[c]) = (b.1, b.2);
            total += b.0;
        }
        if total < best.0 {
            best = (total, e0, e1, i);
        }
    }
    (best.1, best.2, [best.3; 16])
}

/// One block's 16 bytes from its 16 texels (row-major).
pub(super) fn encode_block(px: &[[f32; 3]; 16], clamped: &mut usize) -> [u8; 16] {
    let t: [[f64; 3]; 16] = px.map(|p| p.map(|v| target(v, clamped)));
    let mean: [f64; 3] = [0, 1, 2].map(|c| t.iter().map(|p| p[c]).sum::<f64>() / 16.0);
    let mut cov = [[0.0; 3]; 3];
    for p in &t {
        for i in 0..3 {
            for j in 0..3 {
                cov[i][j] += (p[i] - mean[i]) * (p[j] - mean[j]);
            }
        }
    }
    // Principal axis by power iteration from the largest-variance channel's axis.
    let mut axis = [0.0; 3];
    axis[(0..3).max_by(|a, b| cov[*a][*a].total_cmp(&cov[*b][*b])).unwrap_or(0)] = 1.0;
    for _ in 0..16 {
        let v: [f64; 3] = [0, 1, 2].map(|i| (0..3).map(|j| cov[i][j] * axis[j]).sum());
        let len = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if len <= 0.0 {
            break;
        }
        axis = v.map(|x| x / len);
    }
    let proj = |p: &[f64; 3]| (0..3).map(|c| (p[c] - mean[c]) * axis[c]).sum::<f64>();
    let (lo, hi) = t.iter().map(proj).fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
    let (p0, p1) = ([0, 1, 2].map(|c| mean[c] + lo * axis[c]), [0, 1, 2].map(|c| mean[c] + hi * axis[c]));
    // Two quantisations of the endpoints: nearest, and outward (each channel's range
    // covered, so a narrow or uniform block interpolates between bracketing endpoints).
    let nearest = (p0.map(quantize), p1.map(quantize));
    let outward = ([0, 1, 2].map(|c| quantize_dir(p0[c], p0[c] > p1[c])), [0, 1, 2].map(|c| quantize_dir(p1[c], p1[c] >= p0[c])));
    let (mut e0, mut e1, mut idx, mut err) = {
        let (i0, r0) = assign(&t, nearest.0, nearest.1);
        let (i1, r1) = assign(&t, outward.0, outward.1);
        if r1 < r0 {
            (outward.0, outward.1, i1, r1)
        } else {
            (nearest.0, nearest.1, i0, r0)
        }
    };
    for _ in 0..2 {
        let Some((a, b)) = refit(&t, &idx) else { break };
        let (q0, q1) = (a.map(quantize), b.map(quantize));
        let (i2, e2) = assign(&t, q0, q1);
        if e2 < err {
            (e0, e1, idx, err) = (q0, q1, i2, e2);
        } else {
            break;
        }
    }
    if t.iter().all(|p| p == &t[0]) {
        let (a, b, _) = uniform(&t[0]);
        let (i2, e2) = assign(&t, a, b);
        (e0, e1, idx, err) = (a, b, i2, e2);
    }
    for _ in 0..2 {
        let (q0, q1) = polish(&t, e0, e1, &idx);
        let (i2, e2) = assign(&t, q0, q1);
        if e2 < err {
            (e0, e1, idx, err) = (q0, q1, i2, e2);
        } else {
            break;
        }
    }
    if idx[0] >= 8 {
        std::mem::swap(&mut e0, &mut e1);
        idx = idx.map(|i| 15 - i);
    }
    // Bits, least significant first: mode 00011 (bits 0–4), then rw, gw, bw, rx, gx, bx
    // (10 bits each, two's complement), then the anchor index (3 bits) and 15 × 4 bits.
    let mut bits = 0u128;
    let mut pos = 0;
    let mut put = |v: u128, n: u32| {
        bits |= (v & ((1u128 << n) - 1)) << pos;
        pos += n;
    };
    put(0b00011, 5);
    for e in [e0, e1] {
        for c in e {
            put((c & 0x3FF) as u128, 10);
        }
    }
    put(idx[0] as u128, 3);
    for &i in &idx[1..] {
        put(i as u128, 4);
    }
    debug_assert_eq!(pos, 128);
    bits.to_le_bytes()
}
