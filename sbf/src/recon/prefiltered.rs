//! GGX-prefiltered environment maps, the representation engines store for glossy specular
//! (Karis 2013, "Real Shading in Unreal Engine 4", the split-sum approximation; Filament's
//! cmgen, Unity's and Unreal's reflection probes): a cube map with a mip chain, mip m holding
//! the radiance prefiltered at roughness α_m, read with trilinear filtering at the reflected
//! direction and multiplied by the DFG terms.
//!
//! - **Prefilter** (Karis 2013, with n = v = r): P_α(r) = ∫ L(l)·D(h)·(r·l) dl / W(α) over
//!   r·l > 0, h the half vector of r and l, D the GGX distribution (Walter et al. 2007,
//!   eq. 33): a kernel that depends on r·l alone ([`prefilter_weight`]), normalised by its
//!   integral W(α) in closed form ([`prefilter_norm`]), so a constant map stays constant.
//! - **Mip ↔ roughness** (resolution-matched, as UE4's reflection captures): mip m, of
//!   faces size/2^m, holds α_m = min(1, κ·2^m/size) ([`mip_alpha`], [`KAPPA`]): every mip
//!   spans the same number of texels per lobe width; a lookup at α reads level
//!   log₂(α·size/κ) ([`lod`]), trilinear between the two mips about it. Sharper lobes than
//!   mip 0's read mip 0: the chain's size bounds the sharpest α it represents.
//! - **Chain**: faces of `size` = 2^k texels, mips down to 1 × 1 (M = k + 1), faces in
//!   [`CUBE_FACES`](crate::envmap::CUBE_FACES) order, rows top to bottom.
//! - **Lookup** ([`PrefilteredCube::sample`]): seamless bilinear within a mip, as GPUs filter
//!   cube maps: a neighbour texel beyond a face edge is the texel of the adjacent face that
//!   its centre's direction falls in.
//! - **Specular** ([`PrefilteredCube::specular`]): P(reflect(v, n), α)·(f0·A + f90·B), A and
//!   B the DFG terms at (n·v, α) the caller reads from its table.
//! - **Storage**: [`rgb9e5`] and [`rgb9e5_decode`], the shared-exponent format
//!   (EXT_texture_shared_exponent; DXGI R9G9B9E5_SHAREDEXP) a prefiltered map is often kept in.

use crate::envmap::CubeMap;
use crate::error::SbfError;
use glam::DVec3;
use std::f64::consts::PI;

/// Mips of a chain whose mip 0 has `size` × `size` faces (`size` a power of two): log₂ size + 1.
pub fn mip_count(size: usize) -> usize {
    size.max(1).ilog2() as usize + 1
}

/// Face texels per unit of roughness a mip keeps: mip m of a chain whose mip 0 has faces of
/// `size` holds α_m = min(1, κ·2^m/size) — the lobe (half-width ≈ 2α radians) spans about
/// 4κ/π face texels (π/2 radians per face) at every mip, as resolution-matched chains do
/// (UE4's reflection captures: a mip per halving of the lobe width). κ = 2 measured best of
/// 1, 2 and 4 on the built-in sky (docs/probes.md).
pub const KAPPA: f64 = 2.0;

/// Roughness α of mip `m` of a chain whose mip 0 has faces of `size`: min(1, κ·2^m/size).
pub fn mip_alpha(m: usize, size: usize) -> f64 {
    (KAPPA * (1u64 << m) as f64 / size.max(1) as f64).min(1.0)
}

/// The (fractional) mip level a lookup at roughness α reads in a chain whose mip 0 has faces
/// of `size`: log₂(α·size/κ), clamped to the chain (α below mip 0's reads mip 0; above the
/// first mip at α = 1 reads that mip).
pub fn lod(alpha: f64, size: usize) -> f64 {
    let top = (0..mip_count(size)).find(|m| mip_alpha(*m, size) >= 1.0).unwrap_or(mip_count(size) - 1);
    if alpha <= 0.0 {
        return 0.0;
    }
    (alpha * size as f64 / KAPPA).log2().clamp(0.0, top as f64)
}

/// Which kernel a map is prefiltered with (both zonal about r, normalised to integrate to 1):
/// - `Karis`: D(h)·(r·l), Karis 2013's weight (engines' reflection captures and the
///   split-sum literature): [`prefilter_weight`], [`prefilter_norm`];
/// - `NormalIncidence`: the GGX BRDF × cosine itself at n = v = r, D(h)·G2(r, l)/4
///   (height-correlated Smith, Λ(v) = 0 at n = v): the split sum is then exact wherever the
///   view is along the normal, and differs from Karis's by the shape G2/(4 r·l) across the
///   lobe (≈ 20 % at its edge for α = 0.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PrefilterKernel {
    /// D(h)·(r·l) (Karis 2013).
    Karis,
    /// D(h)·G2(r, l)/4: the BRDF × cosine at n = v = r.
    NormalIncidence,
}

impl PrefilterKernel {
    /// The kernel at cos γ = r·l with 1 − cos γ given separately (see [`prefilter_weight`]);
    /// not normalised.
    pub fn weight(self, cos_gamma: f64, one_minus: f64, alpha: f64) -> f64 {
        match self {
            PrefilterKernel::Karis => prefilter_weight(cos_gamma, one_minus, alpha),
            PrefilterKernel::NormalIncidence => {
                if cos_gamma <= 0.0 {
                    return 0.0;
                }
                // D·cos γ / cos γ · G2/4, Λ(l) from tan²θ_l = sin²γ/cos²γ, sin²γ = (1 − c)(1 + c).
                let a = alpha * alpha * one_minus * (1.0 + cos_gamma) / (cos_gamma * cos_gamma);
                let lambda = a / (2.0 * (1.0 + (1.0 + a).sqrt()));
                prefilter_weight(cos_gamma, one_minus, alpha) / cos_gamma * 0.25 / (1.0 + lambda)
            }
        }
    }

    /// The kernel's integral over the sphere: [`prefilter_norm`] for Karis's; for the
    /// normal-incidence kernel the directional albedo at n·v = 1 (F ≡ 1), by composite
    /// Gauss–Legendre over γ ∈ [0, π/2] on intervals doubling from 2α (the lobe's width).
    pub fn norm(self, alpha: f64) -> f64 {
        match self {
            PrefilterKernel::Karis => prefilter_norm(alpha),
            PrefilterKernel::NormalIncidence => integrate_zonal(|c, om| self.weight(c, om, alpha), alpha),
        }
    }
}

/// ∫ over the sphere of a kernel zonal about r, f(cos γ, 1 − cos γ), over γ ∈ [0, π/2]:
/// 2π ∫ f sin γ dγ by 24-point Gauss–Legendre on [0, 2α], [2α, 4α], … (the last cut at π/2).
pub fn integrate_zonal(f: impl Fn(f64, f64) -> f64, alpha: f64) -> f64 {
    let (x, w) = crate::quadrature::gauss_legendre(24);
    let half_pi = 0.5 * PI;
    let (mut a, mut b, mut total) = (0.0, (2.0 * alpha).clamp(1e-6, half_pi), 0.0);
    loop {
        let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
        for (t, wt) in x.iter().zip(&w) {
            let g = m + h * t;
            // 1 − cos γ = 2 sin²(γ/2): exact for small γ.
            let om = 2.0 * (0.5 * g).sin().powi(2);
            total += wt * h * f(g.cos(), om) * g.sin();
        }
        if b >= half_pi {
            return 2.0 * PI * total;
        }
        a = b;
        b = (2.0 * b).min(half_pi);
    }
}

/// The prefilter's kernel (module docs) at cos γ = r·l: D(h)·cos γ with cos²θ_h = (1 + cos γ)/2,
/// 0 for cos γ ≤ 0. With 1 − cos γ given separately (`one_minus`, exact for nearby
/// directions) the half-angle sine carries no cancellation.
pub fn prefilter_weight(cos_gamma: f64, one_minus: f64, alpha: f64) -> f64 {
    if cos_gamma <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let (c2, s2) = (0.5 * (1.0 + cos_gamma), 0.5 * one_minus);
    let t = a2 * c2 + s2;
    a2 / (PI * t * t) * cos_gamma
}

/// W(α) = ∫ D(h)·(r·l) dl over r·l > 0 (module docs). With dl = 4(r·h) dh and x = cos²θ_h:
/// W = 4α² ∫_{½}^{1} (2x − 1)/(1 + kx)² dx, k = α² − 1,
///   = 4α²/k² · [2 ln(u₁/u₀) + (2 + k)(1/u₁ − 1/u₀)], u₀ = 1 + k/2, u₁ = α².
/// Near α = 1 (|k| small) the bracket cancels to O(k²): there the integral itself is taken by
/// 32-point Gauss–Legendre (its integrand is then a polynomial-like smooth function).
pub fn prefilter_norm(alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let k = a2 - 1.0;
    if k.abs() > 0.25 {
        let (u0, u1) = (1.0 + 0.5 * k, a2);
        4.0 * a2 / (k * k) * (2.0 * (u1 / u0).ln() + (2.0 + k) * (1.0 / u1 - 1.0 / u0))
    } else {
        let (x, w) = crate::quadrature::gauss_legendre(32);
        let s: f64 = x
            .iter()
            .zip(&w)
            .map(|(t, w)| {
                let x = 0.75 + 0.25 * t;
                let u = 1.0 + k * x;
                0.25 * w * (2.0 * x - 1.0) / (u * u)
            })
            .sum();
        4.0 * a2 * s
    }
}

/// Encodes RGB as R9G9B9E5 (EXT_texture_shared_exponent: 9-bit mantissas, a 5-bit shared
/// exponent, bias 15): each channel clamped to [0, 65408] first (NaN as 0), rounded to
/// nearest. Bits: R 0–8, G 9–17, B 18–26, exponent 27–31.
pub fn rgb9e5(rgb: [f32; 3]) -> u32 {
    const N: i32 = 9;
    const B: i32 = 15;
    const MAX: f32 = 65408.0; // (2⁹ − 1)/2⁹ · 2¹⁶
    let c = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, MAX) });
    let max_c = c[0].max(c[1]).max(c[2]);
    // The spec's floor(log₂(max)) (exact from the f32 exponent), at least −B − 1.
    let floor_log2 = if max_c > 0.0 { ((max_c.to_bits() >> 23) as i32 - 127).max(-B - 1) } else { -B - 1 };
    let mut exp = floor_log2 + 1 + B;
    let scale = |e: i32| 2f64.powi(e - B - N);
    let max_s = (max_c as f64 / scale(exp) + 0.5).floor() as i32;
    if max_s == 1 << N {
        exp += 1;
    }
    let m = c.map(|v| ((v as f64 / scale(exp) + 0.5).floor() as u32).min((1 << N) - 1));
    m[0] | (m[1] << 9) | (m[2] << 18) | ((exp as u32) << 27)
}

/// Decodes [`rgb9e5`]'s bits: mantissa · 2^(exponent − 15 − 9).
pub fn rgb9e5_decode(bits: u32) -> [f32; 3] {
    let scale = 2f64.powi((bits >> 27) as i32 - 15 - 9);
    [0, 9, 18].map(|s| (((bits >> s) & 0x1ff) as f64 * scale) as f32)
}

/// A prefiltered cube map with its mip chain (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct PrefilteredCube {
    /// Texels per face side of mip 0 (a power of two).
    pub size: usize,
    /// Per mip m (size/2^m per side): 6 faces × rows × columns of RGB.
    pub mips: Vec<Vec<[f32; 3]>>,
}

impl PrefilteredCube {
    /// Texels of a whole chain of `size` (every mip, six faces).
    pub fn texel_count(size: usize) -> usize {
        (0..mip_count(size)).map(|m| 6 * (size >> m) * (size >> m)).sum()
    }

    /// A chain from its texels, mip after mip (as [`Self::texels`] lists them).
    pub fn from_texels(size: usize, texels: &[[f32; 3]]) -> Result<PrefilteredCube, SbfError> {
        if !size.is_power_of_two() {
            return Err(SbfError::InvalidParameter { name: "prefiltered cube size", value: size as f64, reason: "must be a power of two" });
        }
        crate::error::check_len("prefiltered cube texels", Self::texel_count(size), texels.len())?;
        let mut mips = Vec::new();
        let mut at = 0;
        for m in 0..mip_count(size) {
            let n = 6 * (size >> m) * (size >> m);
            mips.push(texels[at..at + n].to_vec());
            at += n;
        }
        Ok(PrefilteredCube { size, mips })
    }

    /// Builds the chain: texel (face, i, j) of mip m is `f(m, α_m, face, i, j)`.
    pub fn build(size: usize, f: impl Fn(usize, f64, usize, usize, usize) -> [f32; 3] + Sync) -> Result<PrefilteredCube, SbfError> {
        if !size.is_power_of_two() {
            return Err(SbfError::InvalidParameter { name: "prefiltered cube size", value: size as f64, reason: "must be a power of two" });
        }
        let count = mip_count(size);
        let mips = (0..count)
            .map(|m| {
                let n = size >> m;
                let alpha = mip_alpha(m, size);
                (0..6 * n * n).map(|k| f(m, alpha, k / (n * n), k % n, (k / n) % n)).collect()
            })
            .collect();
        Ok(PrefilteredCube { size, mips })
    }

    /// Every texel, mip after mip.
    pub fn texels(&self) -> impl Iterator<Item = &[f32; 3]> {
        self.mips.iter().flatten()
    }

    /// Mip `m`'s faces side.
    fn side(&self, m: usize) -> usize {
        self.size >> m
    }

    /// Texel (i, j) of `face` in mip `m`, for i, j possibly one beyond the face's edge: there
    /// the texel of the adjacent face that the virtual texel centre's direction falls in.
    fn fetch(&self, m: usize, face: usize, i: i64, j: i64) -> [f32; 3] {
        let n = self.side(m);
        let inside = |x: i64| (0..n as i64).contains(&x);
        let (face, i, j) = if inside(i) && inside(j) {
            (face, i as usize, j as usize)
        } else {
            let st = |x: i64| 2.0 * (x as f64 + 0.5) / n as f64 - 1.0;
            let (f, s, t) = CubeMap::vector_to_face_st(CubeMap::face_st_to_vector(face, st(i), st(j)));
            let texel = |u: f64| (((u + 1.0) * 0.5 * n as f64).floor() as i64).clamp(0, n as i64 - 1) as usize;
            (f, texel(s), texel(t))
        };
        self.mips[m][(face * n + j) * n + i]
    }

    /// Seamless bilinear lookup of mip `m` at direction `d` (module docs).
    pub fn bilinear(&self, m: usize, d: DVec3) -> [f64; 3] {
        let n = self.side(m) as f64;
        let (face, s, t) = CubeMap::vector_to_face_st(d);
        let (x, y) = ((s + 1.0) * 0.5 * n - 0.5, (t + 1.0) * 0.5 * n - 0.5);
        let (i0, j0) = (x.floor(), y.floor());
        let (fx, fy) = (x - i0, y - j0);
        let (i0, j0) = (i0 as i64, j0 as i64);
        let mut out = [0.0; 3];
        for (di, dj, w) in [(0, 0, (1.0 - fx) * (1.0 - fy)), (1, 0, fx * (1.0 - fy)), (0, 1, (1.0 - fx) * fy), (1, 1, fx * fy)] {
            if w == 0.0 {
                continue;
            }
            let v = self.fetch(m, face, i0 + di, j0 + dj);
            for c in 0..3 {
                out[c] += w * v[c] as f64;
            }
        }
        out
    }

    /// Trilinear lookup at direction `d` and roughness α (module docs).
    pub fn sample(&self, d: DVec3, alpha: f64) -> [f64; 3] {
        let count = self.mips.len();
        let level = lod(alpha, self.size);
        let m0 = (level.floor() as usize).min(count - 1);
        let f = level - m0 as f64;
        let a = self.bilinear(m0, d);
        if f == 0.0 || m0 + 1 >= count {
            return a;
        }
        let b = self.bilinear(m0 + 1, d);
        [0, 1, 2].map(|c| a[c] + f * (b[c] - a[c]))
    }

    /// The split-sum specular (module docs): P(reflect(v, n), α)·(f0·A + f90·B), `dfg` = [A, B]
    /// at (n·v, α). Zero where v is below the surface.
    pub fn specular(&self, n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64, dfg: [f64; 2]) -> [f64; 3] {
        if n.dot(v) <= 0.0 {
            return [0.0; 3];
        }
        let r = crate::ggx::reflect(v, n);
        let p = self.sample(r, alpha);
        let scale = f0 * dfg[0] + f90 * dfg[1];
        p.map(|x| x * scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// W(α) against a direct 2D midpoint rule over (θ_l) of D(h)·cos γ (about the pole: the
    /// azimuth integrates to 2π), 200 000 cells; the two branches of `prefilter_norm` meet
    /// at |α² − 1| = 0.25 continuously.
    #[test]
    fn prefilter_norm_matches_a_direct_integral() {
        for alpha in [0.02, 0.1, 0.3, 0.6, 0.85, 0.9, 1.0] {
            let n = 200_000;
            let mut s = 0.0;
            for k in 0..n {
                let g = (k as f64 + 0.5) / n as f64 * 0.5 * PI;
                let (sg, cg) = g.sin_cos();
                s += prefilter_weight(cg, 1.0 - cg, alpha) * sg * 2.0 * PI * (0.5 * PI / n as f64);
            }
            let w = prefilter_norm(alpha);
            assert!((w / s - 1.0).abs() < 1e-5, "α {alpha}: closed form {w} vs midpoint {s}");
        }
        for alpha in [0.003, 0.05, 0.2, 0.7, 1.0] {
            let q = integrate_zonal(|c, om| prefilter_weight(c, om, alpha), alpha);
            assert!((q / prefilter_norm(alpha) - 1.0).abs() < 1e-9, "α {alpha}: composite Gauss–Legendre {q} vs closed form");
        }
        let (a, b) = (prefilter_norm((0.75f64).sqrt() - 1e-12), prefilter_norm((0.75f64).sqrt() + 1e-12));
        assert!((a / b - 1.0).abs() < 1e-9, "{a} vs {b}");
    }

    /// The spec's worked values: 1.0 → mantissa 256 at exponent 16; 0 → 0; the largest value
    /// 65408 is kept; every value of a channel spread is within half a step of the shared
    /// exponent's quantum (the format's bound).
    #[test]
    fn rgb9e5_round_trips_within_half_a_step() {
        assert_eq!(rgb9e5([1.0, 0.0, 0.0]), 256 | (16 << 27));
        assert_eq!(rgb9e5_decode(rgb9e5([0.0; 3])), [0.0; 3]);
        assert_eq!(rgb9e5_decode(rgb9e5([65408.0, 1.0, 0.5]))[0], 65408.0);
        for v in [[0.3f32, 1.7, 12.5], [1e-3, 2e-4, 5e-5], [3000.0, 0.01, 70000.0]] {
            let bits = rgb9e5(v);
            let step = 2f64.powi((bits >> 27) as i32 - 24);
            let d = rgb9e5_decode(bits);
            for c in 0..3 {
                let want = (v[c] as f64).min(65408.0);
                assert!((d[c] as f64 - want).abs() <= 0.5 * step + 1e-12 * want, "{v:?}: {d:?}");
            }
        }
    }
}

#[cfg(test)]
mod kernel_tests {
    use super::*;

    /// The normal-incidence kernel's integral is the directional albedo at n·v = 1 with F ≡ 1:
    /// against an independent estimate, the mean of the visible-normal sampler's weight
    /// G2/G1(v) (Heitz 2018; G1(v) = 1 at n = v, so the weight is G2(v, l)) over a 512 × 512
    /// midpoint grid of its two uniforms — quadrature, not the same composite rule.
    #[test]
    fn normal_incidence_norm_is_the_albedo() {
        for alpha in [0.05, 0.2, 0.5, 1.0] {
            let v = DVec3::Z;
            let n = 512;
            let mut s = 0.0;
            for j in 0..n {
                for i in 0..n {
                    let u = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
                    let h = crate::ggx::sample_vndf(v, alpha, u);
                    let l = crate::ggx::reflect(v, h);
                    if l.z > 0.0 {
                        s += crate::ggx::g2(v, l, alpha) / crate::ggx::g1(v, alpha);
                    }
                }
            }
            let albedo = s / (n * n) as f64;
            let w = PrefilterKernel::NormalIncidence.norm(alpha);
            assert!((w / albedo - 1.0).abs() < 2e-3, "α {alpha}: ∫ kernel {w} vs albedo {albedo}");
        }
    }
}

#[cfg(test)]
mod lookup_tests {
    use super::*;

    /// A chain whose every texel holds its own (mip, face, i, j) code.
    fn coded(size: usize) -> PrefilteredCube {
        PrefilteredCube::build(size, |m, _, f, i, j| [m as f32, (f * 1000 + j * 32 + i) as f32, 1.0]).unwrap()
    }

    /// At α_m — written here from the documented mapping, min(1, 2·2^m/size), not read from
    /// the library — a lookup at a texel's centre direction returns that texel of mip m
    /// exactly (bilinear weight 1 at a centre, trilinear weight 1 at an integer level).
    /// Mutations caught: `lod` or `mip_alpha` off by one mip.
    #[test]
    fn a_lookup_at_a_mips_alpha_reads_that_mip() {
        for size in [8usize, 16] {
            let cube = coded(size);
            let count = mip_count(size);
            for m in 0..count {
                let alpha = (2.0 * (1u64 << m) as f64 / size as f64).min(1.0);
                // The first mip at α = 1 is what a lookup at α = 1 reads.
                if alpha >= 1.0 && m > 0 && (2.0 * (1u64 << (m - 1)) as f64 / size as f64) >= 1.0 {
                    continue;
                }
                let n = size >> m;
                let geo = CubeMap { size: n };
                for (f, i, j) in [(0, 0, 0), (2, n - 1, n / 2), (5, n / 2, n - 1)] {
                    let got = cube.sample(geo.texel_direction(f, i, j), alpha);
                    let want = cube.mips[m][(f * n + j) * n + i];
                    for c in 0..3 {
                        assert!(
                            (got[c] - want[c] as f64).abs() <= 1e-9 * (1.0 + want[c].abs() as f64),
                            "size {size} mip {m} α {alpha} texel {f},{i},{j}: {got:?} vs {want:?}"
                        );
                    }
                }
            }
        }
    }

    /// Seamless filtering: on the edge between +X and +Z (direction (1, 0, 1)), halfway down,
    /// the bilinear lookup averages the two faces' texels across the edge (faces holding
    /// constants 1 and 5 give 3); halfway between two texel rows the rows average too.
    #[test]
    fn bilinear_lookups_cross_face_edges() {
        let cube = PrefilteredCube::build(8, |_, _, f, _, _| [f as f32 + 1.0; 3]).unwrap();
        let v = cube.bilinear(0, DVec3::new(1.0, 0.0, 1.0).normalize());
        assert!((v[0] - 3.0).abs() < 1e-12, "{v:?}");
        // +Y's texels next to +Z (its last row): the edge between +Y (3) and +Z (5).
        let v = cube.bilinear(0, DVec3::new(0.0, 1.0, 1.0).normalize());
        assert!((v[0] - 4.0).abs() < 1e-12, "{v:?}");
    }
}
