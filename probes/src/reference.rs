//! Reference signals: exact Lambert irradiance (E/π) by quadrature over the map's
//! texels, evaluated at every texel centre of the output grid.
//!
//! Method: E/π(n) = Σ_t Ω_t·L_t·max(0, n·ω_t)/π over all source texels t (exact
//! solid angles; the texel is treated as constant radiance at its centre). Cost is
//! (output texels) × (source texels). Maps larger than 512×256 are first box-filtered
//! (2×2 averages weighted by solid angle, which preserves each texel block's radiant
//! power exactly) until they fit, and the output grid is capped at 512×256: the
//! irradiance is band-limited by the clamped cosine (A_l ~ l^−2.5), so the error of this
//! reduction is that of quadrature on the coarser grid (stated in the report).

use rayon::prelude::*;
use sbf::envmap::{LatLong, LatLongImage};
use sbf::glam::DVec3;
use std::f64::consts::PI;

/// Largest source/output grid the reference evaluates directly.
pub const MAX_REFERENCE_WIDTH: usize = 512;

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

/// Output grid for a map: its own size, capped at 512×256.
pub fn output_grid(map: &LatLongImage) -> LatLong {
    let mut g = map.geometry;
    while g.width > MAX_REFERENCE_WIDTH && g.width % 2 == 0 && g.height % 2 == 0 {
        g = LatLong { width: g.width / 2, height: g.height / 2 };
    }
    g
}
