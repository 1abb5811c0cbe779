//! Reference signals: exact Lambert irradiance (E/π) by quadrature over the map's
//! texels, evaluated at every texel centre of the output grid.
//!
//! Method, maps up to 256×128: E/π(n) = Σ_t Ω_t·L_t·max(0, n·ω_t)/π over all source
//! texels t (exact solid angles; each texel is constant radiance at its centre), at
//! every output texel: cost (output texels) × (source texels).
//!
//! Larger maps: the full-resolution map is projected onto real SH of order
//! [`SH_REFERENCE_ORDER`] (exact texel quadrature, cost ∝ texels) and convolved with
//! the clamped cosine (A_l); the output grid is capped at 512×256. The truncation error
//! is bounded by the first omitted band factor, |A₂₆/π| = 4.5e-4 of the band's
//! radiance energy (A_l decays as l^−2.5), far below the errors the modes make; the
//! cost grows linearly with the map's texel count.

use rayon::prelude::*;
use sbf::envmap::{LatLong, LatLongImage};
use sbf::glam::DVec3;
use std::f64::consts::PI;

/// Largest output grid width.
pub const MAX_REFERENCE_WIDTH: usize = 512;
/// Largest map width evaluated by direct quadrature.
pub const MAX_DIRECT_WIDTH: usize = 256;
/// SH order of the reference for larger maps.
pub const SH_REFERENCE_ORDER: usize = 24;

/// Halves a lat-long image in both directions, averaging 2×2 blocks weighted by their
/// solid angles (rows differ in Ω).
pub fn downsample(map: &LatLongImage) -> LatLongImage {
    let g = map.geometry;
    let (w, h) = (g.width / 2, g.height / 2);
    let mut texels = Vec::with_capacity(w * h);
    for j in 0..h {
        let (w0, w1) = (g.texel_solid_angle(2 * j), g.texel_solid_angle(2 * j + 1));
        for i in 0..w {
            let mut c = [0.0f64; 3];
            for (dj, wt) in [(0, w0), (1, w1)] {
                for di in 0..2 {
                    let t = map.texel(2 * i + di, 2 * j + dj);
                    for k in 0..3 {
                        c[k] += wt * t[k] as f64;
                    }
                }
            }
            let norm = 2.0 * (w0 + w1);
            texels.push([(c[0] / norm) as f32, (c[1] / norm) as f32, (c[2] / norm) as f32]);
        }
    }
    LatLongImage::new(w, h, texels).expect("halved dimensions are valid")
}

/// The source used for references: the map itself, or box-filtered down to ≤ 512 wide.
pub fn reference_source(map: &LatLongImage) -> LatLongImage {
    let mut m = map.clone();
    while m.geometry.width > MAX_REFERENCE_WIDTH && m.geometry.width % 2 == 0 && m.geometry.height % 2 == 0 {
        m = downsample(&m);
    }
    m
}

/// Exact E/π at unit normal `n` from `src` (one output texel; the brute-force form).
pub fn irradiance_at(src: &LatLongImage, n: DVec3) -> [f64; 3] {
    sbf::recon::reference::irradiance_map(src, n)
}

/// Exact E/π at every direction of `dirs`, in parallel (deterministic: each output is
/// an independent ordered sum). The source is flattened to structure-of-arrays with Ω
/// folded into the radiance for speed.
pub fn irradiance_image(src: &LatLongImage, dirs: &[DVec3]) -> Vec<[f64; 3]> {
    let g = src.geometry;
    let mut d = Vec::with_capacity(g.texel_count());
    let mut l = Vec::with_capacity(g.texel_count());
    for j in 0..g.height {
        let w = g.texel_solid_angle(j) / PI;
        for i in 0..g.width {
            let t = src.texel(i, j);
            d.push(g.texel_direction(i, j));
            l.push([w * t[0] as f64, w * t[1] as f64, w * t[2] as f64]);
        }
    }
    dirs.par_iter()
        .map(|n| {
            let mut e = [0.0f64; 3];
            for (dir, rad) in d.iter().zip(&l) {
                let c = n.dot(*dir);
                if c > 0.0 {
                    e[0] += c * rad[0];
                    e[1] += c * rad[1];
                    e[2] += c * rad[2];
                }
            }
            e
        })
        .collect()
}

/// The reference for a map at `dirs`: direct quadrature for maps up to 256 wide, the
/// SH route beyond. Returns the image and a one-line description of the method.
pub fn reference_irradiance(map: &LatLongImage, dirs: &[DVec3]) -> (Vec<[f64; 3]>, String) {
    let g = map.geometry;
    if g.width <= MAX_DIRECT_WIDTH {
        (irradiance_image(map, dirs), format!("exact quadrature over all {}×{} texels", g.width, g.height))
    } else {
        (
            irradiance_image_sh(map, dirs, SH_REFERENCE_ORDER),
            format!(
                "SH L{SH_REFERENCE_ORDER} projection of all {}×{} texels convolved with A_l (first omitted band factor 4.5e-4)",
                g.width, g.height
            ),
        )
    }
}

/// Exact E/π at every texel centre of `grid` by the azimuthal FFT quadrature
/// ([`crate::azimuthal`]) with one cell per texel — the same sum as [`irradiance_image`]
/// (each texel constant at its centre value, exact solid angles: the bilinear radiance at
/// a texel centre is the texel), computed as one FFT convolution per (output row, source
/// row) because max(0, n·ω)/π depends only on the two polar angles and Δφ. Cost
/// O(H_out·H·W log W) instead of O(H_out·W_out·H·W); any map size, exact (no SH
/// truncation). Errors when W_out does not divide W.
pub fn irradiance_image_fft(map: &LatLongImage, grid: LatLong) -> Result<Vec<[f64; 3]>, String> {
    let q = crate::azimuthal::Quadrature::new(map, grid)?;
    Ok(q.integrate_rows(0..grid.height, 1, &CosineRows { h_out: grid.height }))
}

/// max(0, n·ω)/π along a fine azimuth row: n at output row j's polar angle θ_n and
/// azimuth Δφ, ω at (θ, 0), so n·ω = cos θ_n cos θ + sin θ_n sin θ cos Δφ.
#[derive(Debug, Clone, Copy)]
pub struct CosineRows {
    pub h_out: usize,
}

impl crate::azimuthal::RowKernel for CosineRows {
    fn row(&self, j: usize, theta: f64, az: &crate::azimuthal::Azimuths, out: &mut [f64]) -> bool {
        let (sn, cn) = (PI * (j as f64 + 0.5) / self.h_out as f64).sin_cos();
        let (s, c) = theta.sin_cos();
        let (a, b) = (cn * c, sn * s);
        let mut any = false;
        for (o, cp) in out.iter_mut().zip(az.cos) {
            *o = (a + b * cp).max(0.0) / PI;
            any |= *o > 0.0;
        }
        any
    }

    /// n·ω is unchanged by θ_n ↦ π − θ_n, θ ↦ π − θ.
    fn mirror_symmetric(&self) -> bool {
        true
    }
}

/// The reference E/π at every texel centre of `grid`: the azimuthal FFT quadrature over
/// all texels when the grids allow it (always for [`output_grid`]), else
/// [`reference_irradiance`] at the texel directions. Returns the image and the method.
pub fn reference_irradiance_grid(map: &LatLongImage, grid: LatLong) -> (Vec<[f64; 3]>, String) {
    let g = map.geometry;
    match irradiance_image_fft(map, grid) {
        Ok(img) => (img, format!("exact quadrature over all {}×{} texels (azimuthal FFT convolution per row pair)", g.width, g.height)),
        Err(_) => {
            let dirs: Vec<DVec3> =
                (0..grid.height).flat_map(|j| (0..grid.width).map(move |i| (i, j))).map(|(i, j)| grid.texel_direction(i, j)).collect();
            reference_irradiance(map, &dirs)
        }
    }
}

/// E/π from an SH projection of the whole map (rows in parallel, summed in row order:
/// deterministic for any thread count).
pub fn irradiance_image_sh(map: &LatLongImage, dirs: &[DVec3], order: usize) -> Vec<[f64; 3]> {
    use sbf::Basis;
    let sh = sbf::ShBasis::new(order).expect("order within range");
    let n = sh.len();
    let g = map.geometry;
    let rows: Vec<Vec<[f64; 3]>> = (0..g.height)
        .into_par_iter()
        .map(|j| {
            let w = g.texel_solid_angle(j);
            let mut acc = vec![[0.0f64; 3]; n];
            let mut y = vec![0.0; n];
            for i in 0..g.width {
                sh.eval_into(g.texel_direction(i, j), &mut y);
                let t = map.texel(i, j);
                for k in 0..n {
                    let wy = w * y[k];
                    for c in 0..3 {
                        acc[k][c] += wy * t[c] as f64;
                    }
                }
            }
            acc
        })
        .collect();
    let mut c = vec![[0.0f64; 3]; n];
    for r in rows {
        for k in 0..n {
            for ch in 0..3 {
                c[k][ch] += r[k][ch];
            }
        }
    }
    for l in 0..=order {
        let a = sbf::recon::sh::lambert_band_factor(l) / PI;
        for k in l * l..(l + 1) * (l + 1) {
            for ch in 0..3 {
                c[k][ch] *= a;
            }
        }
    }
    dirs.par_iter()
        .map(|d| {
            let mut y = vec![0.0; n];
            sh.eval_into(*d, &mut y);
            let mut e = [0.0; 3];
            for k in 0..n {
                for ch in 0..3 {
                    e[ch] += c[k][ch] * y[k];
                }
            }
            e
        })
        .collect()
}

/// Output grid for a map: its own size, capped at 512×256.
pub fn output_grid(map: &LatLongImage) -> LatLong {
    let mut g = map.geometry;
    while g.width > MAX_REFERENCE_WIDTH && g.width % 2 == 0 && g.height % 2 == 0 {
        g = LatLong { width: g.width / 2, height: g.height / 2 };
    }
    g
}
