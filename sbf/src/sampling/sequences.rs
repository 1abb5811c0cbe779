//! Low-discrepancy sequences on [0,1)².

/// Radical inverse of `i` in `base` (van der Corput), exact in f64 for i < 2^53.
pub fn radical_inverse(base: u32, mut i: u64) -> f64 {
    debug_assert!(base >= 2);
    let b = base as u64;
    let inv = 1.0 / base as f64;
    let mut f = inv;
    let mut r = 0.0;
    while i > 0 {
        r += (i % b) as f64 * f;
        i /= b;
        f *= inv;
    }
    r
}

/// Point i of the Halton sequence in bases (2, 3). A sequence: every prefix is
/// well distributed, so it can drive progressive encoding.
pub fn halton2(i: u64) -> [f64; 2] {
    [radical_inverse(2, i), radical_inverse(3, i)]
}

/// Point i of the n-point Hammersley set: ((i + ½)/n, φ₂(i)). A *set*: prefixes
/// are badly distributed (first coordinate sweeps monotonically), which breaks the
/// progressive encoder when consumed in order ([Roughton19 Fig. 7.6]).
pub fn hammersley2(i: u64, n: u64) -> [f64; 2] {
    debug_assert!(i < n);
    [(i as f64 + 0.5) / n as f64, radical_inverse(2, i)]
}

/// R2 sequence (Roberts 2018, "The Unreasonable Effectiveness of Quasirandom
/// Sequences"): x_i = frac(s + i·(1/g, 1/g²)) with g the plastic number
/// (root of x³ = x + 1). `s` is a Cranley–Patterson shift (randomisation by seed).
#[derive(Debug, Clone, Copy)]
pub struct R2 {
    shift: [f64; 2],
}

impl R2 {
    /// 1/g and 1/g² for the plastic number g = 1.324717957244746…
    pub const ALPHA: [f64; 2] = [0.754_877_666_246_692_7, 0.569_840_290_998_053_3];

    /// Unshifted sequence starting at (½, ½) as recommended by Roberts.
    pub fn new() -> Self {
        R2 { shift: [0.5, 0.5] }
    }
    /// Shifted by a deterministic pseudo-random offset derived from `seed`.
    pub fn with_seed(seed: u64) -> Self {
        let mut rng = super::Pcg32::new(seed, 0x5232);
        R2 { shift: rng.next_2d() }
    }
    /// Point i.
    pub fn point(&self, i: u64) -> [f64; 2] {
        // i·α mod 1 evaluated with the integer part removed first to keep precision
        // for large i.
        let f = |a: f64, s: f64| {
            let x = s + (i as f64) * a;
            x - x.floor()
        };
        [f(Self::ALPHA[0], self.shift[0]), f(Self::ALPHA[1], self.shift[1])]
    }
}

/// R3 sequence (Roberts 2018, the d = 3 member of R_d): x_i = frac(s + i·(1/g, 1/g²,
/// 1/g³)) with g = 1.2207440846… the root of x⁴ = x + 1; Cranley–Patterson shifted.
/// Three stratified dimensions, e.g. a direction and the choice of a mixture component.
#[derive(Debug, Clone, Copy)]
pub struct R3 {
    shift: [f64; 3],
}

impl R3 {
    /// 1/g, 1/g², 1/g³.
    pub const ALPHA: [f64; 3] = [0.819_172_513_396_164_4, 0.671_043_606_703_789_2, 0.549_700_477_901_970_3];

    /// Shifted by a deterministic pseudo-random offset derived from `seed`.
    pub fn with_seed(seed: u64) -> Self {
        let mut rng = super::Pcg32::new(seed, 0x5233);
        let [a, b] = rng.next_2d();
        R3 { shift: [a, b, rng.next_f64()] }
    }
    /// Point i.
    pub fn point(&self, i: u64) -> [f64; 3] {
        std::array::from_fn(|k| {
            let x = self.shift[k] + (i as f64) * Self::ALPHA[k];
            x - x.floor()
        })
    }
}

impl Default for R2 {
    fn default() -> Self {
        Self::new()
    }
}
