//! Owen-scrambled, shuffled Sobol points in 4 dimensions (Burley 2020, "Practical
//! Hash-based Owen Scrambling", JCGT 9(4)), for progressive Monte Carlo with any number
//! of dimensions by padding: each group of up to four dimensions gets its own seed, which
//! shuffles the point order and scrambles the digits independently of every other group.
//!
//! - Sobol' (1967) points in base 2: x_d(i) = ⊕_{bit b of i} v_{d,b}, with the direction
//!   numbers v of the first four dimensions from Joe & Kuo (2008, `new-joe-kuo-6.21201`):
//!   dimension 0 is the van der Corput sequence, 1–3 come from the primitive polynomials
//!   x + 1, x² + x + 1, x³ + x + 1 with initial m = (1), (1, 3), (1, 3, 1).
//! - Nested uniform (Owen) scrambling by the Laine–Karras hash with Burley's improved
//!   constants, applied in bit-reversed order so that each output bit depends only on the
//!   bits above it: every point is uniform on [0,1)⁴ over seeds (unbiased estimates), and
//!   each 2^m-aligned block stays a (t, m, s)-net.
//! - The index itself is Owen-scrambled (the "shuffle"): the first 2^m shuffled indices
//!   are one 2^m-aligned block of the sequence, so every power-of-two prefix is still a
//!   net — the progressive ordering [Roughton19 §7.3.1] requires — while different seeds
//!   (items, dimension groups) see decorrelated orders.
//!
//! The WGSL twin (the baker's `sobol.wgsl`) computes the same u32 values.

/// Direction numbers v_{d,b} (b = bit of the index) of the first four Sobol' dimensions.
pub const SOBOL_DIRECTIONS: [[u32; 32]; 4] =
    [directions(0, 0, &[]), directions(1, 0, &[1]), directions(2, 1, &[1, 3]), directions(3, 1, &[1, 3, 1])];

/// Direction numbers from a primitive polynomial of degree `s` with coefficient bits `a`
/// and initial m values (Bratley & Fox 1988, Joe & Kuo 2008): v_k = m_k·2^(31−k) for k < s,
/// then v_k = v_{k−s} ⊕ (v_{k−s} ≫ s) ⊕ ⊕_{j=1}^{s−1} a_j·v_{k−j}. s = 0: van der Corput.
const fn directions(dim: usize, a: u32, m: &[u32]) -> [u32; 32] {
    let mut v = [0u32; 32];
    let s = m.len();
    let mut k = 0;
    while k < 32 {
        v[k] = if dim == 0 {
            1 << (31 - k)
        } else if k < s {
            m[k] << (31 - k)
        } else {
            let mut x = v[k - s] ^ (v[k - s] >> s);
            let mut j = 1;
            while j < s {
                if (a >> (s - 1 - j)) & 1 == 1 {
                    x ^= v[k - j];
                }
                j += 1;
            }
            x
        };
        k += 1;
    }
    v
}

/// The unscrambled Sobol' point i in dimension `dim` (< 4), as a 32-bit fraction.
pub fn sobol_u32(i: u32, dim: usize) -> u32 {
    let v = &SOBOL_DIRECTIONS[dim];
    let mut x = 0;
    let mut bits = i;
    let mut b = 0;
    while bits != 0 {
        if bits & 1 == 1 {
            x ^= v[b];
        }
        bits >>= 1;
        b += 1;
    }
    x
}

/// Laine & Karras (2011) scrambling hash with Burley's (2020) constants: a bijection on
/// u32 whose output bit k depends only on input bits ≤ k.
pub fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Nested uniform scramble of a 32-bit fraction (bit 31 is the first digit).
pub fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// Burley's seed mixing (boost's hash_combine).
pub fn hash_combine(seed: u32, v: u32) -> u32 {
    seed ^ v.wrapping_add(seed << 6).wrapping_add(seed >> 2)
}

/// A 32-bit hash (Jarzynski & Olano 2020's PCG hash) for deriving seeds.
pub fn pcg_hash(x: u32) -> u32 {
    let state = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// Point `i` of the shuffled, Owen-scrambled 4D Sobol' sequence of `seed`, as 32-bit
/// fractions.
pub fn owen_sobol4_u32(i: u32, seed: u32) -> [u32; 4] {
    let j = nested_uniform_scramble(i, seed);
    std::array::from_fn(|d| nested_uniform_scramble(sobol_u32(j, d), hash_combine(seed, d as u32)))
}

/// [`owen_sobol4_u32`] on [0,1)⁴ (exact: 32-bit fractions are f64 values).
pub fn owen_sobol4(i: u32, seed: u32) -> [f64; 4] {
    owen_sobol4_u32(i, seed).map(|x| x as f64 * (1.0 / 4_294_967_296.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether points (as 32-bit fractions) form a (0, m, 2)-net in base 2: for every
    /// split m = a + b, each 2^−a × 2^−b elementary box holds exactly one of the 2^m points.
    fn is_02_net(pts: &[[u32; 2]], m: u32) -> bool {
        (0..=m).all(|a| {
            let b = m - a;
            let mut seen = vec![false; 1 << m];
            pts.iter().all(|p| {
                let cx = if a == 0 { 0 } else { p[0] >> (32 - a) };
                let cy = if b == 0 { 0 } else { p[1] >> (32 - b) };
                let k = ((cx << b) | cy) as usize;
                !std::mem::replace(&mut seen[k], true)
            })
        })
    }

    /// Oracle: the defining property of Sobol's first two dimensions — every 2^m-aligned
    /// block of points is a (0, m, 2)-net (Sobol' 1967; Niederreiter 1992, §4.5), and each
    /// dimension alone a (0, m, 1)-net. Owen scrambling preserves nets (Owen 1995), and the
    /// shuffle keeps prefixes as aligned blocks; so the scrambled, shuffled sequence must
    /// pass the same check for any seed. Mutations tried: a broken recurrence
    /// (v_{k−s} ≫ (s+1)), a digit scramble without the bit reversal, a shuffle without it:
    /// each fails; dropping one of the hash's four rounds passes (a weaker but still
    /// valid scramble).
    #[test]
    fn prefixes_are_nets_scrambled_or_not() {
        for m in 0..=10u32 {
            for block in [0u32, 1, 5] {
                let pts: Vec<[u32; 2]> = (0..1u32 << m).map(|k| block * (1 << m) + k).map(|i| [sobol_u32(i, 0), sobol_u32(i, 1)]).collect();
                assert!(is_02_net(&pts, m), "block {block} of 2^{m} is not a (0,{m},2)-net");
            }
            for seed in [0u32, 1, 0xdead_beef, 12345] {
                let pts: Vec<[u32; 4]> = (0..1u32 << m).map(|i| owen_sobol4_u32(i, seed)).collect();
                assert!(is_02_net(&pts.iter().map(|p| [p[0], p[1]]).collect::<Vec<_>>(), m), "seed {seed}, m {m}");
                for d in 0..4 {
                    let mut cells: Vec<u32> = pts.iter().map(|p| if m == 0 { 0 } else { p[d] >> (32 - m) }).collect();
                    cells.sort_unstable();
                    assert!(cells.iter().enumerate().all(|(k, c)| *c == k as u32), "dim {d} not stratified at 2^{m}");
                }
            }
        }
    }

    /// The direction numbers against closed forms and published values: dimension 0 is
    /// van der Corput (v_b = 2^(31−b)); dimension 1 (polynomial x + 1, m = 1) has v_b =
    /// row b of Pascal's triangle mod 2 as binary digits (its generator matrix is the
    /// Pascal matrix, Faure 1982).
    #[test]
    fn direction_numbers_match_closed_forms() {
        for b in 0..32 {
            assert_eq!(SOBOL_DIRECTIONS[0][b], 1u32 << (31 - b));
            // Row b of Pascal's triangle mod 2: C(b, j) odd ⇔ j & b == j (Lucas).
            let row: u32 = (0..=b).filter(|j| j & b == *j).map(|j| 1u32 << (31 - j)).sum();
            assert_eq!(SOBOL_DIRECTIONS[1][b], row, "bit {b}");
        }
        // Dimensions 2 and 3 against the leading words of the published 32-bit tables
        // (Joe & Kuo 2008 as printed in Burley 2020's supplement): m = 1, 3, 3, 9, 29, 23
        // and 1, 3, 1, 5, 31.
        assert_eq!(SOBOL_DIRECTIONS[2][..6], [0x8000_0000, 0xc000_0000, 0x6000_0000, 0x9000_0000, 0xe800_0000, 0x5c00_0000]);
        assert_eq!(SOBOL_DIRECTIONS[2][31], 0xc500_5555);
        assert_eq!(SOBOL_DIRECTIONS[3][..5], [0x8000_0000, 0xc000_0000, 0x2000_0000, 0x5000_0000, 0xf800_0000]);
    }

    /// Unbiasedness: Owen scrambling makes each point uniform on [0,1)⁴, so the mean over
    /// seeds of f(point i) is ∫f for any fixed i. f = x₀x₁x₂x₃·16 (∫ = 1, variance per
    /// sample (4/3)⁴ − 1 = 2.16); 4 096 seeds → σ = 0.023; the test allows 4σ.
    #[test]
    fn each_point_is_uniform_over_seeds() {
        for i in [0u32, 1, 7, 1000] {
            let n = 4096;
            let mean: f64 = (0..n).map(|s| owen_sobol4(i, pcg_hash(s)).iter().product::<f64>() * 16.0).sum::<f64>() / n as f64;
            let sigma = (((4.0f64 / 3.0).powi(4) - 1.0) / n as f64).sqrt();
            assert!((mean - 1.0).abs() < 4.0 * sigma, "point {i}: mean {mean}");
        }
    }
}
