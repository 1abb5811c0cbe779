//! A pinhole view camera (eye, target, vertical field of view, image size): its rays,
//! its jittered projection, and the default view the previews use.

use super::bvh::Bvh;
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
