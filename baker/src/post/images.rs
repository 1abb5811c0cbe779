//! The lightmap as images: a state's per-item results scattered into the atlas (E/π, its
//! standard error, every basis's coefficients, the texels' normals and validity), the
//! dilation of empty texels, and bilinear lookups.

use crate::accumulate::{BakeState, Targets};
use crate::layout::lightmap::Lightmap;
use sbf::glam::{Vec2, Vec3};

/// Per-atlas-texel images of a lightmap bake.
#[derive(Debug, Clone)]
pub struct LightmapImages {
    pub width: usize,
    pub height: usize,
    /// 1 for baked texels, 0 for empty ones (dilated or not).
    pub validity: Vec<f32>,
    /// Mean E/π.
    pub irradiance: Vec<[f32; 3]>,
    /// Standard error of E/π.
    pub standard_error: Vec<[f32; 3]>,
    /// `coefficients[b][lobe][texel]` for the configured bases.
    pub coefficients: Vec<Vec<Vec<[f32; 3]>>>,
    /// World-space unit shading normal of each texel (the normalised mean of its
    /// sub-texel points' normals): the frame its coefficients are in.
    pub normals: Vec<[f32; 3]>,
}

impl LightmapImages {
    /// Scatters a state's per-item results into the atlas.
    pub fn new(lm: &Lightmap, targets: &Targets, state: &BakeState) -> Self {
        let n = lm.width * lm.height;
        let mut img = LightmapImages {
            width: lm.width,
            height: lm.height,
            validity: vec![0.0; n],
            irradiance: vec![[0.0; 3]; n],
            standard_error: vec![[0.0; 3]; n],
            coefficients: state
                .encoders
                .iter()
                .map(|e| vec![vec![[0.0; 3]; n]; e.first().map(|x| x.coefficients().nrows()).unwrap_or(0)])
                .collect(),
            normals: vec![[0.0; 3]; n],
        };
        let (mean, se, valid) = (state.mean(), state.standard_error(), state.valid());
        if let Some(f) = &state.filtered {
            img.fill_filtered(lm, targets, f, &valid);
            return img;
        }
        for (k, it) in targets.items.iter().enumerate() {
            // Inside geometry (back-face samples): left empty, dilated over.
            if !valid[k] {
                continue;
            }
            let t = it[2] as usize;
            img.validity[t] = 1.0;
            let sum: Vec3 = lm.texels[t].points.iter().map(|p| p.normal).sum();
            img.normals[t] = sum.normalize_or_zero().to_array();
            img.irradiance[t] = mean[k].map(|x| x as f32);
            img.standard_error[t] = se[k].map(|x| if x.is_finite() { x as f32 } else { 0.0 });
            for (b, encs) in state.encoders.iter().enumerate() {
                let c = encs[k].coefficients();
                for (l, lobe) in img.coefficients[b].iter_mut().enumerate() {
                    lobe[t] = [c[(l, 0)] as f32, c[(l, 1)] as f32, c[(l, 2)] as f32];
                }
            }
        }
        img
    }

    /// The filtered accumulation's results ([`crate::accumulate::filter`]): every gather target with
    /// weight (an item texel only if the item itself is valid). A target covered by no
    /// sub-position takes the mean normal of the item texels of its chart around it.
    fn fill_filtered(&mut self, lm: &Lightmap, targets: &Targets, f: &crate::accumulate::filter::FilteredState, item_valid: &[bool]) {
        let list = crate::accumulate::filter::gather_targets(targets);
        let w = lm.width;
        let mut item_normals = vec![None; lm.texels.len()];
        for (k, it) in targets.items.iter().enumerate() {
            let t = it[2] as usize;
            let sum: Vec3 = lm.texels[t].points.iter().map(|p| p.normal).sum();
            if item_valid[k] {
                item_normals[t] = Some(sum.normalize_or_zero());
            }
        }
        for (j, &t) in list.iter().enumerate() {
            let t = t as usize;
            let m = &f.moments[j];
            if m.weight <= 0.0 || (j < targets.items.len() && !item_valid[j]) {
                continue;
            }
            let normal = item_normals[t].unwrap_or_else(|| {
                let (x, y) = ((t % w) as i64, (t / w) as i64);
                let mut sum = Vec3::ZERO;
                for (dx, dy) in (-1i64..=1).flat_map(|dy| (-1i64..=1).map(move |dx| (dx, dy))) {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx >= 0 && ny >= 0 && (nx as usize) < w && (ny as usize) < lm.height {
                        let n = ny as usize * w + nx as usize;
                        if lm.texel_charts[n] == lm.texel_charts[t] {
                            sum += item_normals[n].unwrap_or(Vec3::ZERO);
                        }
                    }
                }
                sum.normalize_or_zero()
            });
            self.validity[t] = 1.0;
            self.normals[t] = normal.to_array();
            self.irradiance[t] = m.mean.map(|x| x as f32);
            self.standard_error[t] = m.standard_error().map(|x| if x.is_finite() { x as f32 } else { 0.0 });
            for (b, encs) in f.encoders.iter().enumerate() {
                let c = encs[j].coefficients();
                for (l, lobe) in self.coefficients[b].iter_mut().enumerate() {
                    lobe[t] = [c[(l, 0)] as f32, c[(l, 1)] as f32, c[(l, 2)] as f32];
                }
            }
        }
    }

    /// Fills empty texels from the mean of their filled 8-neighbours, ring by ring, for
    /// `rings` rings (the padding around charts: bilinear filtering at chart edges then
    /// reads baked values, not black). Validity stays 0 for filled texels. Returns the
    /// number of texels filled.
    pub fn dilate(&mut self, rings: usize) -> usize {
        self.dilate_keeping(rings, &[])
    }

    /// [`LightmapImages::dilate`] treating the empty texels `keep` as filled (they hold
    /// values already, e.g. written by seam stitching; validity stays 0).
    pub fn dilate_keeping(&mut self, rings: usize, keep: &[usize]) -> usize {
        let (w, h) = (self.width, self.height);
        let mut filled: Vec<bool> = self.validity.iter().map(|v| *v > 0.0).collect();
        for t in keep {
            filled[*t] = true;
        }
        let mut total = 0;
        for _ in 0..rings {
            let mut add = Vec::new();
            for y in 0..h {
                for x in 0..w {
                    if filled[y * w + x] {
                        continue;
                    }
                    let mut src = Vec::new();
                    for (dx, dy) in [(-1i64, -1i64), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                        let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                        if nx >= 0 && ny >= 0 && (nx as usize) < w && (ny as usize) < h && filled[ny as usize * w + nx as usize] {
                            src.push(ny as usize * w + nx as usize);
                        }
                    }
                    if !src.is_empty() {
                        add.push((y * w + x, src));
                    }
                }
            }
            if add.is_empty() {
                break;
            }
            let avg = |v: &[[f32; 3]], src: &[usize]| -> [f32; 3] {
                let mut a = [0.0; 3];
                for &s in src {
                    for c in 0..3 {
                        a[c] += v[s][c] / src.len() as f32;
                    }
                }
                a
            };
            for (t, src) in &add {
                self.irradiance[*t] = avg(&self.irradiance, src);
                self.standard_error[*t] = avg(&self.standard_error, src);
                self.normals[*t] = Vec3::from(avg(&self.normals, src)).normalize_or_zero().to_array();
                for b in self.coefficients.iter_mut() {
                    for lobe in b.iter_mut() {
                        lobe[*t] = avg(lobe, src);
                    }
                }
            }
            for (t, _) in &add {
                filled[*t] = true;
            }
            total += add.len();
        }
        total
    }

    /// Bilinear E/π at atlas coordinates in texels (texel centres at +0.5).
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let p = uv - Vec2::splat(0.5);
        let (x0, y0) = (p.x.floor(), p.y.floor());
        let (fx, fy) = (p.x - x0, p.y - y0);
        let at = |x: f32, y: f32| {
            let xi = (x.max(0.0) as usize).min(self.width - 1);
            let yi = (y.max(0.0) as usize).min(self.height - 1);
            Vec3::from(self.irradiance[yi * self.width + xi])
        };
        let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
        let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }
}
