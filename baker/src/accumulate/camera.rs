//! Camera-based lightmap sampling ([Roughton19 §3.4.2], after Hillaire 2018): each batch
//! traces paths from the texels a view camera sees — the scene rasterised (GPU, a
//! jittered projection per batch) into a texel-index target, one path per pixel, so a
//! texel gets as many samples as pixels it covers (at most `max_per_batch`) and texels
//! out of view none. The same camera frames the preview image.
//!
//! The CPU twin casts one ray per pixel through the same jittered pixel positions and
//! finds the texel by the hit's barycentric lightmap UV ([`pixel_counts`]); the GPU
//! rasteriser may decide a pixel on a triangle or texel edge the other way (tested:
//! `tests/camera.rs`). Which texels a batch takes depends on the view only, never on the
//! samples, so each texel's mean stays unbiased.

use super::Targets;
use crate::scene::bvh::Bvh;
use crate::scene::camera::ViewCamera;
use sbf::glam::Vec3;

/// Camera-based sampling settings.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSampling {
    pub camera: ViewCamera,
    /// Uniform passes first (every texel a value, also those out of view).
    pub pilot_passes: u64,
    /// The most samples a texel takes per batch (pixels beyond are dropped).
    pub max_per_batch: u32,
}

impl CameraSampling {
    pub fn validate(&self) -> Result<(), String> {
        let c = &self.camera;
        if !(c.fov_y > 0.0 && c.fov_y < std::f32::consts::PI) {
            return Err(format!("camera field of view {}° must be in (0°, 180°)", c.fov_y.to_degrees()));
        }
        if c.width == 0 || c.height == 0 || c.width > 8192 || c.height > 8192 {
            return Err(format!("camera image {}×{} must be 1 to 8192 pixels a side", c.width, c.height));
        }
        if !(c.eye - c.target).is_finite()
            || (c.eye - c.target).length() == 0.0
            || (c.target - c.eye).normalize().cross(Vec3::Y).length() < 1e-6
        {
            return Err("the camera must look from an eye to a different target, not straight up or down".into());
        }
        if !(1..=crate::accumulate::adaptive::MAX_SAMPLES_PER_BATCH).contains(&self.max_per_batch) {
            return Err(format!(
                "camera samples per batch {} must be in 1..={}",
                self.max_per_batch,
                crate::accumulate::adaptive::MAX_SAMPLES_PER_BATCH
            ));
        }
        Ok(())
    }
}

impl CameraSampling {
    /// With the image sized to about `texels` pixels at 4:3 where it was left 0 × 0.
    pub fn sized_for(mut self, texels: usize) -> CameraSampling {
        if self.camera.width == 0 || self.camera.height == 0 {
            let h = ((texels as f64 * 0.75).sqrt().round() as u32).clamp(12, 6144);
            (self.camera.width, self.camera.height) = ((h * 4).div_ceil(3), h);
        }
        self
    }
}

/// The sub-pixel jitter of batch `b` in (−½, ½)²: an R2 point (Roberts 2018) per batch.
pub fn jitter(b: u64) -> [f32; 2] {
    let u = sbf::sampling::R2::new().point(b);
    [(u[0] - 0.5) as f32, (u[1] - 0.5) as f32]
}

/// The atlas texel id a hit on triangle `tri` at barycentrics (u, v) falls in (None: the
/// mesh is not lightmapped or the UV is outside the atlas).
pub fn texel_at(bvh: &Bvh, targets: &Targets, tri: u32, u: f32, v: f32) -> Option<u32> {
    let t = &bvh.tris[tri as usize];
    let uvs = targets.triangle_uv.get(t.mesh as usize)?.get(t.prim as usize)?;
    let p = uvs[0] * (1.0 - u - v) + uvs[1] * u + uvs[2] * v;
    let (x, y) = (p.x.floor(), p.y.floor());
    (x >= 0.0 && y >= 0.0 && (x as usize) < targets.width && (y as usize) < targets.height)
        .then(|| (y as usize * targets.width + x as usize) as u32)
}

/// CPU twin of the GPU's texel raster: per item, how many pixels of `cam` (shifted by
/// `jitter`) see it — a ray through each jittered pixel centre, its first hit's texel.
pub fn pixel_counts(cam: &ViewCamera, jitter: [f32; 2], bvh: &Bvh, targets: &Targets) -> Vec<u32> {
    let mut item_of = vec![u32::MAX; targets.width * targets.height];
    for (k, it) in targets.items.iter().enumerate() {
        item_of[it[2] as usize] = k as u32;
    }
    let mut counts = vec![0u32; targets.items.len()];
    for y in 0..cam.height {
        for x in 0..cam.width {
            let (o, d) = cam.ray(x as f32 + 0.5 + jitter[0], y as f32 + 0.5 + jitter[1]);
            if let Some(h) = bvh.intersect(o, d, 0.0, f32::INFINITY) {
                if let Some(t) = texel_at(bvh, targets, h.tri, h.u, h.v) {
                    if let Some(k) = item_of.get(t as usize).filter(|k| **k != u32::MAX) {
                        counts[*k as usize] += 1;
                    }
                }
            }
        }
    }
    counts
}
