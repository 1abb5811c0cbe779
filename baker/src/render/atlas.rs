//! A bake's lightmap as the renderer reads it: one RGB image per lobe (the basis's
//! `{basis}_{lobe:02}.exr`, or `irradiance.exr` for the plain E/π), read back from the
//! bake's folder exactly as an engine would, optionally rounded to f16, and the bilinear
//! lookup both the GPU shader and its CPU twin use: texel centres at (i + ½, j + ½) in
//! atlas texel coordinates, the four nearest centres weighted by the fractional position,
//! indices clamped to the atlas (the bake dilates charts by `padding` texels, so a
//! lookup inside a chart never reaches an empty texel).

use super::lighting::{Encoding, Storage};
use sbf::glam::DVec3;
use std::path::Path;

pub use sbf::recon::lut::{bspline_taps, bspline_weights};

/// Per lobe, the RGB texels of the atlas (row-major, y down).
#[derive(Debug, Clone, PartialEq)]
pub struct Atlas {
    pub width: usize,
    pub height: usize,
    pub lobes: Vec<Vec<[f32; 3]>>,
}

/// The four texels and weights of a bilinear lookup at atlas position `uv` (texels).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    /// Texel indices (x0y0, x1y0, x0y1, x1y1).
    pub texels: [usize; 4],
    pub weights: [f64; 4],
}

/// The bilinear footprint at `uv` (f64; the shader does the same in f32).
pub fn footprint(width: usize, height: usize, uv: [f64; 2]) -> Footprint {
    let (x, y) = (uv[0] - 0.5, uv[1] - 0.5);
    let (fx0, fy0) = (x.floor(), y.floor());
    let (fx, fy) = (x - fx0, y - fy0);
    let clamp = |i: f64, n: usize| (i.max(0.0) as usize).min(n - 1);
    let (x0, x1) = (clamp(fx0, width), clamp(fx0 + 1.0, width));
    let (y0, y1) = (clamp(fy0, height), clamp(fy0 + 1.0, height));
    Footprint {
        texels: [y0 * width + x0, y0 * width + x1, y1 * width + x0, y1 * width + x1],
        weights: [(1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy],
    }
}

/// Whether the widest lookup the renderer makes at `uv` (the B-spline's 4 × 4 texels,
/// which contain the bilinear 2 × 2) reads a texel outside the chart of the texel under
/// `uv`: another chart's, or a gutter texel the bake dilated (`texel_charts`: per texel its
/// chart, [`NO_CHART`](crate::layout::lightmap::NO_CHART) where none). Such pixels are where
/// filtering can leak light across chart borders.
pub fn reaches_outside_chart(texel_charts: &[u32], width: usize, height: usize, uv: [f64; 2]) -> bool {
    let clamp = |v: f64, n: usize| (v.max(0.0) as usize).min(n - 1);
    let own = texel_charts[clamp(uv[1].floor(), height) * width + clamp(uv[0].floor(), width)];
    let (i, j) = ((uv[0] - 0.5).floor(), (uv[1] - 0.5).floor());
    (-1..3).any(|b| {
        let row = clamp(j + b as f64, height) * width;
        (-1..3).any(|a| texel_charts[row + clamp(i + a as f64, width)] != own)
    }) || own == crate::layout::lightmap::NO_CHART
}

impl Atlas {
    /// The files of `encoding` in a bake folder, in lobe order.
    pub fn files(encoding: Encoding) -> Vec<String> {
        match encoding {
            Encoding::Irradiance => vec!["irradiance.exr".into()],
            Encoding::Basis(b) => (0..super::lighting::lobe_count(b)).map(|l| format!("{}_{l:02}.exr", b.name())).collect(),
        }
    }

    /// Reads `encoding`'s images from the bake folder `dir`; every image must be
    /// `width` × `height` (the layout the renderer rebuilt) and hold finite values.
    pub fn read(dir: &Path, encoding: Encoding, width: usize, height: usize) -> Result<Atlas, String> {
        let mut lobes = Vec::new();
        for name in Self::files(encoding) {
            let path = dir.join(&name);
            let img = image::open(&path)
                .map_err(|e| format!("{}: {e} (was the bake made with this basis? bake.json lists its files)", path.display()))?
                .to_rgba32f();
            if (img.width() as usize, img.height() as usize) != (width, height) {
                return Err(format!(
                    "{}: {}×{} texels, but the scene's layout is {width}×{height} (another scene or --texels-per-unit/--padding?)",
                    path.display(),
                    img.width(),
                    img.height()
                ));
            }
            let texels: Vec<[f32; 3]> = img.pixels().map(|p| [p.0[0], p.0[1], p.0[2]]).collect();
            if let Some(k) = texels.iter().position(|t| !t.iter().all(|x| x.is_finite())) {
                return Err(format!("{}: texel ({}, {}) is not finite", path.display(), k % width, k / width));
            }
            lobes.push(texels);
        }
        Ok(Atlas { width, height, lobes })
    }

    /// The atlas as stored on the GPU: f32 unchanged, f16 rounded to nearest (values
    /// beyond f16's range are an error rather than infinities).
    pub fn stored(&self, storage: Storage) -> Result<Atlas, String> {
        if storage == Storage::F32 {
            return Ok(self.clone());
        }
        let max = half::f16::MAX.to_f32();
        let mut out = self.clone();
        for (l, lobe) in out.lobes.iter_mut().enumerate() {
            for (k, t) in lobe.iter_mut().enumerate() {
                if t.iter().any(|x| x.abs() > max) {
                    return Err(format!(
                        "lobe {l} texel ({}, {}) = {:?} exceeds f16's range ±{max}: store this lightmap as f32",
                        k % self.width,
                        k / self.width,
                        t
                    ));
                }
                *t = t.map(|x| half::f16::from_f32(x).to_f32());
            }
        }
        Ok(out)
    }

    /// The lobes' RGB values at atlas position `uv` (texels), bilinear.
    /// Every lobe at `uv` (texels) with `filter`: bilinear (`Exact` and the sampler's
    /// `Hardware`, which the twin computes exactly) or the cubic B-spline (16 texels,
    /// indices clamped to the atlas).
    pub fn sample(&self, filter: super::lighting::LightmapFilter, uv: [f64; 2]) -> Vec<DVec3> {
        match filter {
            super::lighting::LightmapFilter::Bicubic => self.bicubic(uv),
            _ => self.bilinear(uv),
        }
    }

    /// The cubic B-spline over the 4×4 texels around `uv` (texels), indices clamped.
    pub fn bicubic(&self, uv: [f64; 2]) -> Vec<DVec3> {
        let (x, y) = (uv[0] - 0.5, uv[1] - 0.5);
        let (i, j) = (x.floor(), y.floor());
        let (wx, wy) = (bspline_weights(x - i), bspline_weights(y - j));
        let clamp = |v: f64, n: usize| (v.max(0.0) as usize).min(n - 1);
        self.lobes
            .iter()
            .map(|lobe| {
                let mut acc = DVec3::ZERO;
                for (b, wyb) in wy.iter().enumerate() {
                    let row = clamp(j - 1.0 + b as f64, self.height) * self.width;
                    for (a, wxa) in wx.iter().enumerate() {
                        acc += wxa * wyb * DVec3::from(lobe[row + clamp(i - 1.0 + a as f64, self.width)].map(f64::from));
                    }
                }
                acc
            })
            .collect()
    }

    pub fn bilinear(&self, uv: [f64; 2]) -> Vec<DVec3> {
        let f = footprint(self.width, self.height, uv);
        self.lobes
            .iter()
            .map(|lobe| f.texels.iter().zip(f.weights).fold(DVec3::ZERO, |acc, (t, w)| acc + w * DVec3::from(lobe[*t].map(f64::from))))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::{bspline_taps, reaches_outside_chart, Atlas};
    use sbf::glam::DVec3;

    /// A one-lobe 12×10 atlas with texel (x, y) = f(x + ½, y + ½) (its centre).
    fn atlas(f: impl Fn(f64, f64) -> f64) -> Atlas {
        let (w, h) = (12, 10);
        let texels = (0..w * h).map(|k| [f((k % w) as f64 + 0.5, (k / w) as f64 + 0.5) as f32; 3]).collect();
        Atlas { width: w, height: h, lobes: vec![texels] }
    }

    /// The cubic B-spline against its closed forms (de Boor): a partition of unity, exact
    /// on linear functions (away from the clamped border), an impulse's weights 2/3 at its
    /// centre and 1/6 one texel off per axis, 23/48 half a texel off; and the GPU's four
    /// bilinear taps ([`bspline_taps`]) give the 16-texel sum.
    #[test]
    fn bicubic_matches_the_b_spline() {
        let at = |a: &Atlas, u: f64, v: f64| a.bicubic([u, v])[0].x;
        let constant = atlas(|_, _| 0.75);
        let ramp = atlas(|x, y| 0.25 * x - 0.5 * y + 3.0);
        for (u, v) in [(3.2, 4.9), (5.5, 5.5), (7.99, 3.01), (4.5, 6.25)] {
            assert!((at(&constant, u, v) - 0.75).abs() < 1e-6);
            assert!((at(&ramp, u, v) - (0.25 * u - 0.5 * v + 3.0)).abs() < 1e-5, "ramp at ({u}, {v})");
        }
        let impulse = atlas(|x, y| if (x, y) == (5.5, 4.5) { 1.0 } else { 0.0 });
        assert!((at(&impulse, 5.5, 4.5) - 4.0 / 9.0).abs() < 1e-12);
        assert!((at(&impulse, 6.5, 4.5) - 2.0 / 3.0 / 6.0).abs() < 1e-12);
        assert!((at(&impulse, 6.5, 5.5) - 1.0 / 36.0).abs() < 1e-12);
        assert!((at(&impulse, 6.0, 4.5) - 23.0 / 48.0 * 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(at(&impulse, 7.5, 4.5), 0.0);
        // The four taps, each a bilinear lookup, weighted.
        let wavy = atlas(|x, y| (0.7 * x).sin() + (0.4 * y).cos() * x);
        for (u, v) in [(3.2, 4.9), (5.5, 5.5), (7.99, 3.01), (4.5, 6.25), (6.03, 2.97)] {
            let [(px, gx), (py, gy)] = bspline_taps([u, v]);
            let mut sum = DVec3::ZERO;
            for (a, b) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                sum += gx[a] * gy[b] * wavy.bilinear([px[a], py[b]])[0];
            }
            assert!((sum.x - at(&wavy, u, v)).abs() < 1e-5, "taps at ({u}, {v}): {} vs {}", sum.x, at(&wavy, u, v));
        }
    }

    /// Two charts side by side in a 12 × 8 atlas, columns 0–4 chart 0, 5 a gutter, 6–11
    /// chart 1: the B-spline's footprint at x spans texels ⌊x − ½⌋ − 1 … ⌊x − ½⌋ + 2.
    #[test]
    fn outside_chart_means_the_four_by_four_footprint() {
        let none = crate::layout::lightmap::NO_CHART;
        let charts: Vec<u32> = (0..12 * 8)
            .map(|k| match k % 12 {
                0..=4 => 0,
                5 => none,
                _ => 1,
            })
            .collect();
        let at = |x: f64| reaches_outside_chart(&charts, 12, 8, [x, 4.0]);
        // Footprint columns at x = 3.4: 1..4 (inside); at 3.5: 2..5 (the gutter).
        assert!(!at(3.4));
        assert!(at(3.5));
        assert!(at(5.5), "on the gutter itself");
        // Chart 1 from the right: x = 8.5 reads 7..10; x = 7.49 reads 5..8.
        assert!(!at(8.5));
        assert!(at(7.49));
        // Rows clamp at the atlas edge: nothing outside there; the right edge too.
        assert!(!reaches_outside_chart(&charts, 12, 8, [2.0, 0.1]));
        assert!(!reaches_outside_chart(&charts, 12, 8, [11.9, 7.9]));
        // The same along rows: rows 0–3 chart 0, row 4 a gutter, rows 5–7 chart 1 (a
        // single column of texels, 1 × 8).
        let rows: Vec<u32> = (0..8)
            .map(|j| match j {
                0..=3 => 0,
                4 => none,
                _ => 1,
            })
            .collect();
        let at_y = |y: f64| reaches_outside_chart(&rows, 1, 8, [0.5, y]);
        assert!(!at_y(2.4) && at_y(2.5), "rows: 0..3 inside at 2.4, the gutter at 2.5");
        assert!(!at_y(6.5) && at_y(5.4), "rows: chart 1 from below");
        // Inside a wide gutter every texel is "another chart's" only by its own NO_CHART.
        let wide = vec![none; 12 * 8];
        assert!(reaches_outside_chart(&wide, 12, 8, [6.0, 4.0]));
    }
}
