//! Environment-map geometry (no file I/O): lat-long and cube-map texel
//! directions and exact solid angles, bilinear lookup, quadrature over a map.
//!
//! Lat-long convention (design.md; the bundled probes): +Y up, row 0 at the
//! zenith, image centre facing −Z:
//!   u = (1 + atan2(x, −z)/π)/2,  v = acos(y)/π,
//! so direction(u, v) = (sin θ sin φ, cos θ, −sin θ cos φ), θ = πv, φ = π(2u − 1).
//!
//! Cube-map convention: the Vulkan/D3D/OpenGL face table (faces +X, −X, +Y, −Y,
//! +Z, −Z; s to the right, t downwards in each face image), with
//! (s, t) = (2u − 1, 2v − 1) and direction before normalisation:
//! +X (1, −t, −s), −X (−1, −t, s), +Y (s, 1, t), −Y (s, −1, −t), +Z (s, −t, 1), −Z (−s, −t, −1).

use crate::error::{check_len, SbfError};
use crate::quadrature::KahanSum;
use glam::DVec3;
use std::f64::consts::PI;

/// Lat-long (equirectangular) map geometry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LatLong {
    /// Texels per row (2π of azimuth).
    pub width: usize,
    /// Rows (π of polar angle, row 0 at the zenith).
    pub height: usize,
}

impl LatLong {
    /// Errors if either dimension is zero.
    pub fn new(width: usize, height: usize) -> Result<Self, SbfError> {
        if width == 0 || height == 0 {
            return Err(SbfError::InvalidParameter {
                name: "lat-long size",
                value: (width * height) as f64,
                reason: "width and height must be > 0",
            });
        }
        Ok(LatLong { width, height })
    }

    /// Unit direction at texture coordinates (u, v) ∈ \[0, 1\]².
    pub fn uv_to_direction(u: f64, v: f64) -> DVec3 {
        let theta = PI * v;
        let phi = PI * (2.0 * u - 1.0);
        let (st, ct) = theta.sin_cos();
        DVec3::new(st * phi.sin(), ct, -st * phi.cos())
    }

    /// Texture coordinates of a unit direction; u ∈ [0, 1), v ∈ [0, 1].
    pub fn direction_to_uv(d: DVec3) -> (f64, f64) {
        let u = 0.5 * (1.0 + d.x.atan2(-d.z) / PI);
        let u = if u >= 1.0 { u - 1.0 } else { u };
        (u, d.y.clamp(-1.0, 1.0).acos() / PI)
    }

    /// Direction through the centre of texel (i, j) (column i, row j).
    pub fn texel_direction(&self, i: usize, j: usize) -> DVec3 {
        Self::uv_to_direction((i as f64 + 0.5) / self.width as f64, (j as f64 + 0.5) / self.height as f64)
    }

    /// Exact solid angle of any texel in row j:
    /// Δφ·(cos θ₀ − cos θ₁) = (2π/W)·2·sin((θ₀+θ₁)/2)·sin((θ₁−θ₀)/2) (no cancellation near the poles).
    pub fn texel_solid_angle(&self, j: usize) -> f64 {
        let dt = PI / self.height as f64;
        let t0 = j as f64 * dt;
        let t1 = t0 + dt;
        (2.0 * PI / self.width as f64) * 2.0 * (0.5 * (t0 + t1)).sin() * (0.5 * dt).sin()
    }

    /// Number of texels.
    pub fn texel_count(&self) -> usize {
        self.width * self.height
    }

    /// Midpoint-rule quadrature with exact texel solid angles: Σ f(dir_ij)·Ω_j,
    /// in row-major order (deterministic).
    pub fn integrate(&self, mut f: impl FnMut(DVec3) -> f64) -> f64 {
        let mut acc = KahanSum::default();
        for j in 0..self.height {
            let w = self.texel_solid_angle(j);
            for i in 0..self.width {
                acc.add(w * f(self.texel_direction(i, j)));
            }
        }
        acc.value()
    }
}

/// An RGB lat-long image (f32 texels, row-major, row 0 at the zenith).
#[derive(Debug, Clone, PartialEq)]
pub struct LatLongImage {
    /// Its size.
    pub geometry: LatLong,
    /// RGB radiance, `width × height`, row-major.
    pub texels: Vec<[f32; 3]>,
}

impl LatLongImage {
    /// Wraps texel data; errors if its length is not width × height.
    pub fn new(width: usize, height: usize, texels: Vec<[f32; 3]>) -> Result<Self, SbfError> {
        let geometry = LatLong::new(width, height)?;
        check_len("lat-long texels", width * height, texels.len())?;
        Ok(LatLongImage { geometry, texels })
    }

    /// Samples `f` at every texel centre.
    pub fn from_fn(width: usize, height: usize, f: impl Fn(DVec3) -> [f64; 3]) -> Result<Self, SbfError> {
        let geometry = LatLong::new(width, height)?;
        let mut texels = Vec::with_capacity(width * height);
        for j in 0..height {
            for i in 0..width {
                let c = f(geometry.texel_direction(i, j));
                texels.push([c[0] as f32, c[1] as f32, c[2] as f32]);
            }
        }
        Ok(LatLongImage { geometry, texels })
    }

    /// Texel (i, j).
    pub fn texel(&self, i: usize, j: usize) -> [f32; 3] {
        self.texels[j * self.geometry.width + i]
    }

    /// Bilinear lookup in direction d (unit): wraps in u, clamps in v, texel
    /// centres at (i + ½)/W, (j + ½)/H.
    pub fn bilinear(&self, d: DVec3) -> [f64; 3] {
        let (u, v) = LatLong::direction_to_uv(d);
        self.bilinear_uv(u, v)
    }

    /// Bilinear lookup at texture coordinates (u, v) ∈ [0, 1]² (see [`Self::bilinear`]).
    pub fn bilinear_uv(&self, u: f64, v: f64) -> [f64; 3] {
        let (w, h) = (self.geometry.width, self.geometry.height);
        let x = u * w as f64 - 0.5;
        let y = (v * h as f64 - 0.5).clamp(0.0, (h - 1) as f64);
        let x0 = x.floor();
        let fx = x - x0;
        let y0 = y.floor();
        let fy = y - y0;
        let i0 = (x0 as i64).rem_euclid(w as i64) as usize;
        let i1 = (i0 + 1) % w;
        let j0 = y0 as usize;
        let j1 = (j0 + 1).min(h - 1);
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate() {
            let t = |i: usize, j: usize| self.texel(i, j)[c] as f64;
            let top = t(i0, j0) * (1.0 - fx) + t(i1, j0) * fx;
            let bot = t(i0, j1) * (1.0 - fx) + t(i1, j1) * fx;
            *o = top * (1.0 - fy) + bot * fy;
        }
        out
    }

    /// Σ over texels of f(direction, texel)·Ω, per channel (deterministic order).
    pub fn integrate(&self, mut f: impl FnMut(DVec3, [f64; 3]) -> [f64; 3]) -> [f64; 3] {
        let g = self.geometry;
        let mut acc = [KahanSum::default(); 3];
        for j in 0..g.height {
            let w = g.texel_solid_angle(j);
            for i in 0..g.width {
                let t = self.texel(i, j);
                let v = f(g.texel_direction(i, j), [t[0] as f64, t[1] as f64, t[2] as f64]);
                for c in 0..3 {
                    acc[c].add(w * v[c]);
                }
            }
        }
        acc.map(|a| a.value())
    }
}

/// Cube-map face order.
pub const CUBE_FACES: [&str; 6] = ["+X", "-X", "+Y", "-Y", "+Z", "-Z"];

/// Cube-map geometry with square faces of `size` texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CubeMap {
    /// Texels per face side.
    pub size: usize,
}

impl CubeMap {
    /// A cube map of `size` × `size` faces (size > 0).
    pub fn new(size: usize) -> Result<Self, SbfError> {
        if size == 0 {
            return Err(SbfError::InvalidParameter { name: "cube-map size", value: 0.0, reason: "must be > 0" });
        }
        Ok(CubeMap { size })
    }

    /// Unnormalised direction for face coordinates (s, t) ∈ [−1, 1]².
    ///
    /// # Panics
    /// If `face >= 6` (a programming error: faces are indexed by [`CUBE_FACES`]).
    pub fn face_st_to_vector(face: usize, s: f64, t: f64) -> DVec3 {
        match face {
            0 => DVec3::new(1.0, -t, -s),
            1 => DVec3::new(-1.0, -t, s),
            2 => DVec3::new(s, 1.0, t),
            3 => DVec3::new(s, -1.0, -t),
            4 => DVec3::new(s, -t, 1.0),
            5 => DVec3::new(-s, -t, -1.0),
            _ => panic!("cube face index {face} out of range 0..6"),
        }
    }

    /// Face and (s, t) ∈ [−1, 1]² of a direction (the inverse of [`Self::face_st_to_vector`]).
    pub fn vector_to_face_st(d: DVec3) -> (usize, f64, f64) {
        let a = d.abs();
        if a.x >= a.y && a.x >= a.z {
            if d.x > 0.0 {
                (0, -d.z / a.x, -d.y / a.x)
            } else {
                (1, d.z / a.x, -d.y / a.x)
            }
        } else if a.y >= a.z {
            if d.y > 0.0 {
                (2, d.x / a.y, d.z / a.y)
            } else {
                (3, d.x / a.y, -d.z / a.y)
            }
        } else if d.z > 0.0 {
            (4, d.x / a.z, -d.y / a.z)
        } else {
            (5, -d.x / a.z, -d.y / a.z)
        }
    }

    /// Unit direction through the centre of texel (i, j) of `face`.
    pub fn texel_direction(&self, face: usize, i: usize, j: usize) -> DVec3 {
        let n = self.size as f64;
        let s = 2.0 * (i as f64 + 0.5) / n - 1.0;
        let t = 2.0 * (j as f64 + 0.5) / n - 1.0;
        Self::face_st_to_vector(face, s, t).normalize()
    }

    /// Exact solid angle of texel (i, j) (same on every face):
    /// Ω = F(s₁,t₁) − F(s₀,t₁) − F(s₁,t₀) + F(s₀,t₀), F(s,t) = atan(st/√(s² + t² + 1)).
    pub fn texel_solid_angle(&self, i: usize, j: usize) -> f64 {
        let n = self.size as f64;
        let e = |k: usize| 2.0 * k as f64 / n - 1.0;
        let f = |s: f64, t: f64| (s * t / (s * s + t * t + 1.0).sqrt()).atan();
        let (s0, s1, t0, t1) = (e(i), e(i + 1), e(j), e(j + 1));
        f(s1, t1) - f(s0, t1) - f(s1, t0) + f(s0, t0)
    }

    /// Midpoint-rule quadrature over all six faces with exact texel solid angles.
    pub fn integrate(&self, mut f: impl FnMut(DVec3) -> f64) -> f64 {
        let mut acc = KahanSum::default();
        for face in 0..6 {
            for j in 0..self.size {
                for i in 0..self.size {
                    acc.add(self.texel_solid_angle(i, j) * f(self.texel_direction(face, i, j)));
                }
            }
        }
        acc.value()
    }
}

/// Built-in procedural HDR environment (no file needed): a sky gradient, a sun and
/// a coloured ground, in linear radiance units. Used by demos and tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProceduralSky {
    /// Unit direction towards the sun.
    pub sun_direction: DVec3,
    /// Angular radius of the sun disc (radians), with a smooth edge.
    pub sun_radius: f64,
    /// Radiance of the sun disc (RGB).
    pub sun_radiance: [f64; 3],
    /// Sky radiance at the zenith and at the horizon.
    pub zenith: [f64; 3],
    /// Sky radiance at the horizon (interpolated towards the zenith).
    pub horizon: [f64; 3],
    /// Ground radiance (below the horizon).
    pub ground: [f64; 3],
}

impl Default for ProceduralSky {
    /// A clear afternoon: sun 35° above the horizon, 3° disc (broad enough that a
    /// 256×128 map resolves it), blue sky, warm ground.
    fn default() -> Self {
        let elev = 35f64.to_radians();
        let az = 40f64.to_radians();
        ProceduralSky {
            sun_direction: DVec3::new(elev.cos() * az.sin(), elev.sin(), -elev.cos() * az.cos()),
            sun_radius: 3f64.to_radians(),
            sun_radiance: [400.0, 360.0, 300.0],
            zenith: [0.25, 0.45, 1.0],
            horizon: [0.9, 0.95, 1.1],
            ground: [0.35, 0.25, 0.15],
        }
    }
}

impl ProceduralSky {
    /// Radiance in unit direction d (+Y up).
    pub fn radiance(&self, d: DVec3) -> [f64; 3] {
        let y = d.y;
        let mut c = if y >= 0.0 {
            // Horizon→zenith blend with a soft exponent.
            let t = y.sqrt();
            [0, 1, 2].map(|k| self.horizon[k] * (1.0 - t) + self.zenith[k] * t)
        } else {
            // Ground darkens slightly towards the nadir.
            let t = (-y).sqrt();
            [0, 1, 2].map(|k| self.ground[k] * (1.0 - 0.4 * t))
        };
        let cos_sun = d.dot(self.sun_direction).clamp(-1.0, 1.0);
        let ang = cos_sun.acos();
        if ang < self.sun_radius * 1.5 {
            // Smoothstep edge between 1.0 and 1.5 radii.
            let x = ((1.5 * self.sun_radius - ang) / (0.5 * self.sun_radius)).clamp(0.0, 1.0);
            let w = x * x * (3.0 - 2.0 * x);
            for k in 0..3 {
                c[k] += w * self.sun_radiance[k];
            }
        }
        c
    }
}
