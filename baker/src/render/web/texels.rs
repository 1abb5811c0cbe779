//! The viewer's binary data: f16 values, the atlas downsampled to a browser's texture limit
//! and the error that costs, the image-level error of f16 storage.

use crate::layout::lightmap::NO_CHART;
use crate::render::atlas::Atlas;
use crate::render::lighting::LightmapFilter;
use sbf::glam::DVec3;

pub fn f16_bytes(values: impl Iterator<Item = f32>) -> Vec<u8> {
    values.flat_map(|x| half::f16::from_f32(x).to_le_bytes()).collect()
}

/// The atlas downsampled by `f` (box average over each f × f block's valid texels; 0 where
/// it has none) — where the atlas exceeds the browser's texture limit.
pub fn downsample(a: &Atlas, charts: &[u32], f: usize) -> Atlas {
    if f == 1 {
        return a.clone();
    }
    let (w, h) = (a.width.div_ceil(f), a.height.div_ceil(f));
    let lobes = a
        .lobes
        .iter()
        .map(|lobe| {
            (0..w * h)
                .map(|k| {
                    let (x0, y0) = ((k % w) * f, (k / w) * f);
                    let (mut s, mut n) = ([0.0f64; 3], 0usize);
                    for y in y0..(y0 + f).min(a.height) {
                        for x in x0..(x0 + f).min(a.width) {
                            let i = y * a.width + x;
                            if charts[i] != NO_CHART {
                                (0..3).for_each(|c| s[c] += lobe[i][c] as f64);
                                n += 1;
                            }
                        }
                    }
                    if n == 0 {
                        [0.0; 3]
                    } else {
                        s.map(|v| (v / n as f64) as f32)
                    }
                })
                .collect()
        })
        .collect();
    Atlas { width: w, height: h, lobes }
}

/// The relative RMS error at the valid texels of `full`'s first lobe against the bilinear
/// lookup of its downsampled version `small` (factor `f`) at the texel's centre.
pub fn downsample_error(full: &Atlas, small: &Atlas, charts: &[u32], f: usize) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (i, t) in full.lobes[0].iter().enumerate() {
        if charts[i] == NO_CHART {
            continue;
        }
        let uv = [((i % full.width) as f64 + 0.5) / f as f64, ((i / full.width) as f64 + 0.5) / f as f64];
        let s = small.sample(LightmapFilter::Exact, uv)[0];
        let v = DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64);
        num += (s - v).length_squared();
        den += v.length_squared();
    }
    if den > 0.0 {
        (num / den).sqrt()
    } else {
        0.0
    }
}

/// Relative RMS of the total between two shadings of the visible surfaces.
pub fn relative_rms(a: &[DVec3], b: &[DVec3]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (*x - *y).length_squared()).sum();
    let den: f64 = b.iter().map(|y| y.length_squared()).sum();
    if den > 0.0 {
        (num / den).sqrt()
    } else {
        0.0
    }
}
