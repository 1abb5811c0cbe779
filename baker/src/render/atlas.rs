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
    pub fn bilinear(&self, uv: [f64; 2]) -> Vec<DVec3> {
        let f = footprint(self.width, self.height, uv);
        self.lobes
            .iter()
            .map(|lobe| f.texels.iter().zip(f.weights).fold(DVec3::ZERO, |acc, (t, w)| acc + w * DVec3::from(lobe[*t].map(f64::from))))
            .collect()
    }
}
