//! Camera-based lightmap sampling (seed 004 §3.4.2, after Hillaire 2018): each batch
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

use crate::bake::Targets;
use crate::bvh::Bvh;
use sbf::glam::{Mat4, Vec3, Vec4};

/// A pinhole camera looking from `eye` at `target` (+Y up), vertical field of view
/// `fov_y` (radians), an image of `width` × `height` pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewCamera {
    pub eye: Vec3,
    pub target: Vec3,
    pub fov_y: f32,
    pub width: u32,
    pub height: u32,
}

/// Camera-based sampling settings.
#[derive(Debug, Clone, Copy, PartialEq)]
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
        if !(1..=crate::adapt::MAX_SAMPLES_PER_BATCH).contains(&self.max_per_batch) {
            return Err(format!("camera samples per batch {} must be in 1..={}", self.max_per_batch, crate::adapt::MAX_SAMPLES_PER_BATCH));
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

impl ViewCamera {
    /// Parses `ex,ey,ez:tx,ty,tz[:fov°]` (vertical field of view, default 60°).
    pub fn parse(s: &str, width: u32, height: u32) -> Result<ViewCamera, String> {
        let parts: Vec<&str> = s.split(':').collect();
        let v3 = |p: &str| -> Result<Vec3, String> {
            let v: Vec<f32> = p
                .split(',')
                .map(|x| x.trim().parse::<f32>().map_err(|_| format!("--camera: '{x}' is not a number")))
                .collect::<Result<_, _>>()?;
            match v[..] {
                [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(Vec3::new(x, y, z)),
                _ => Err(format!("--camera: '{p}' is not x,y,z")),
            }
        };
        let (eye, target, fov) = match parts[..] {
            [e, t] => (v3(e)?, v3(t)?, 60.0),
            [e, t, f] => (v3(e)?, v3(t)?, f.trim().parse::<f32>().map_err(|_| format!("--camera: field of view '{f}' is not a number"))?),
            _ => return Err(format!("--camera '{s}': expected eye:target[:fov], e.g. 0,1,3:0,1,0:60")),
        };
        Ok(ViewCamera { eye, target, fov_y: fov.to_radians(), width, height })
    }

    /// The preview's default camera: at the front of the scene's bounds, centred,
    /// looking towards −Z with an 80° horizontal field of view.
    pub fn preview(bvh: &Bvh, width: u32, height: u32) -> ViewCamera {
        let (lo, hi) = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
        let centre = 0.5 * (lo + hi);
        let eye = centre + Vec3::new(0.0, 0.0, 0.49 * (hi.z - lo.z));
        let tan_x = 40f32.to_radians().tan();
        let fov_y = 2.0 * (tan_x * height as f32 / width as f32).atan();
        ViewCamera { eye, target: eye - Vec3::Z, fov_y, width, height }
    }

    /// (right, up, forward), orthonormal.
    fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let f = (self.target - self.eye).normalize();
        let r = f.cross(Vec3::Y).normalize();
        (r, r.cross(f), f)
    }

    /// The ray through image position (px, py) in pixels (y down; pixel centres at +0.5).
    pub fn ray(&self, px: f32, py: f32) -> (Vec3, Vec3) {
        let (r, u, f) = self.basis();
        let t = (0.5 * self.fov_y).tan();
        let aspect = self.width as f32 / self.height as f32;
        let sx = (px / self.width as f32 * 2.0 - 1.0) * t * aspect;
        let sy = (1.0 - py / self.height as f32 * 2.0) * t;
        (self.eye, (f + r * sx + u * sy).normalize())
    }

    /// World → clip (wgpu: depth in [0, 1]) with the image shifted by `jitter` pixels:
    /// the rasteriser's pixel (x, y) centre then sees what [`ViewCamera::ray`] at
    /// (x + 0.5 + jitter.x, y + 0.5 + jitter.y) sees.
    pub fn view_proj(&self, jitter: [f32; 2], near: f32, far: f32) -> Mat4 {
        // Right-handed look-at (rows r, u, −f) and perspective with depth in [0, 1].
        let (r, u, f) = self.basis();
        let view = Mat4::from_cols(
            Vec4::new(r.x, u.x, -f.x, 0.0),
            Vec4::new(r.y, u.y, -f.y, 0.0),
            Vec4::new(r.z, u.z, -f.z, 0.0),
            Vec4::new(-r.dot(self.eye), -u.dot(self.eye), f.dot(self.eye), 1.0),
        );
        let aspect = self.width as f32 / self.height as f32;
        let h = 1.0 / (0.5 * self.fov_y).tan();
        let depth = far / (near - far);
        let proj = Mat4::from_cols(
            Vec4::new(h / aspect, 0.0, 0.0, 0.0),
            Vec4::new(0.0, h, 0.0, 0.0),
            Vec4::new(0.0, 0.0, depth, -1.0),
            Vec4::new(0.0, 0.0, depth * near, 0.0),
        );
        // A pixel is 2/width of NDC in x and 2/height in y (NDC y up, image y down).
        let shift = Mat4::from_translation(Vec3::new(-2.0 * jitter[0] / self.width as f32, 2.0 * jitter[1] / self.height as f32, 0.0));
        shift * proj * view
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
