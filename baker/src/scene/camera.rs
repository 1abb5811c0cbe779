//! A pinhole view camera (eye, target, vertical field of view, image size): its rays,
//! its jittered projection, and the default view the previews use.

use super::bvh::Bvh;
use sbf::glam::{Mat4, Vec3, Vec4};

/// A perspective camera of a scene file (glTF 2.0 §5.12: the node looks down its local
/// −Z with +Y up; its world transform places it).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneCamera {
    /// The camera's name, else its node's, else "camera N".
    pub name: String,
    pub eye: Vec3,
    /// Unit view direction and the unit up direction perpendicular to it.
    pub forward: Vec3,
    pub up: Vec3,
    /// Vertical field of view (radians).
    pub fov_y: f32,
    /// The aspect ratio the file states (width / height), if any.
    pub aspect: Option<f32>,
}

impl SceneCamera {
    /// The camera of a node with world transform `world` (rotation and translation; a
    /// scale only stretches the axes, which are normalised), or an error for a transform
    /// that leaves no view direction.
    pub fn from_node(name: String, world: Mat4, fov_y: f32, aspect: Option<f32>) -> Result<SceneCamera, String> {
        let eye = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(-Vec3::Z).normalize_or_zero();
        let up_raw = world.transform_vector3(Vec3::Y);
        let up = (up_raw - forward * up_raw.dot(forward)).normalize_or_zero();
        if !eye.is_finite() || forward == Vec3::ZERO || up == Vec3::ZERO {
            return Err(format!("camera '{name}': its node's transform is singular"));
        }
        if !(fov_y > 0.0 && fov_y < std::f32::consts::PI) {
            return Err(format!("camera '{name}': vertical field of view {fov_y} rad is not in (0, π)"));
        }
        Ok(SceneCamera { name, eye, forward, up, fov_y, aspect })
    }
}

/// A pinhole camera looking from `eye` at `target`, `up` the image's up direction (the
/// component perpendicular to the view direction counts), vertical field of view `fov_y`
/// (radians), an image of `width` × `height` pixels.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewCamera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
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
        if !(fov > 0.0 && fov < 180.0) {
            return Err(format!("--camera: field of view {fov}° must be in (0°, 180°)"));
        }
        if (target - eye).cross(Vec3::Y).length_squared() <= 1e-12 * (target - eye).length_squared() {
            return Err(format!("--camera '{s}': the view direction is vertical (up is +Y); tilt it slightly"));
        }
        Ok(ViewCamera { eye, target, up: Vec3::Y, fov_y: fov.to_radians(), width, height })
    }

    /// The preview's default camera: at the front of the scene's bounds, centred,
    /// looking towards −Z with an 80° horizontal field of view.
    pub fn preview(bvh: &Bvh, width: u32, height: u32) -> ViewCamera {
        let (lo, hi) = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
        let centre = 0.5 * (lo + hi);
        let eye = centre + Vec3::new(0.0, 0.0, 0.49 * (hi.z - lo.z));
        let tan_x = 40f32.to_radians().tan();
        let fov_y = 2.0 * (tan_x * height as f32 / width as f32).atan();
        ViewCamera { eye, target: eye - Vec3::Z, up: Vec3::Y, fov_y, width, height }
    }

    /// The view of a camera the scene defines (a glTF camera node), at `width` × `height`.
    pub fn from_scene(c: &SceneCamera, width: u32, height: u32) -> ViewCamera {
        ViewCamera { eye: c.eye, target: c.eye + c.forward, up: c.up, fov_y: c.fov_y, width, height }
    }

    /// (right, up, forward), orthonormal.
    fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let f = (self.target - self.eye).normalize();
        let r = f.cross(self.up).normalize();
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
