//! # The scene layer: what is lit and what lights it
//!
//! Triangle meshes with materials, lights and an environment ([`Scene`]), where they come
//! from ([`builtin`] scenes, [`import`] of glTF 2.0, [`load`] by name), how rays find them ([`bvh`]), light
//! evaluation at a point ([`lights`]), tangent frames ([`geometry`]) and the view camera
//! ([`camera`]). Every other layer builds on this one; it uses none of them.
//!
//! Conventions as in `sbf`: right-handed, +Y up, metres. Triangles are one-sided for
//! emission (they emit on the side their normal faces) and two-sided for reflection.

pub mod builtin;
pub mod bvh;
pub mod camera;
pub mod geometry;
pub mod import;
mod import_maps;
pub mod lights;
pub mod load;
pub mod texture;
mod uri;

pub use builtin::{atrium, cornell, dense, disk_light, furnace, museum, room_1m, slit, sphere_light, sunbeam, uv_sphere};

use sbf::glam::{Vec2, Vec3};

/// Material of [Roughton19 §6.3.1]: a Lambert layer and a GGX layer added together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Base colour (linear RGB, each in [0, 1]).
    pub base_color: Vec3,
    /// 0 = dielectric, 1 = metal (glTF metallic/roughness).
    pub metallic: f32,
    /// Perceptual roughness; GGX α = roughness².
    pub roughness: f32,
    /// Dielectric specular weight: F0 = 0.04·specular (1 for glTF's default, 0 for a
    /// pure Lambert surface such as the furnace's).
    pub specular: f32,
    /// Emitted radiance (W/(m²·sr), linear RGB).
    pub emissive: Vec3,
    /// glTF `doubleSided`. A single-sided surface has no back: a baked point whose
    /// sample ray first meets a back face is inside geometry, and the sample is
    /// rejected and counted (texel validity). Reflection is two-sided either way.
    pub double_sided: bool,
    /// Texture maps multiplying the factors above (glTF 2.0 §3.9.2); evaluated at a point
    /// by [`Scene::material_at`].
    pub maps: texture::Maps,
}

impl Material {
    /// Pure Lambert with albedo `c`.
    pub fn lambert(c: Vec3) -> Self {
        Material {
            base_color: c,
            metallic: 0.0,
            roughness: 1.0,
            specular: 0.0,
            emissive: Vec3::ZERO,
            double_sided: false,
            maps: texture::Maps { base_color: None, metallic_roughness: None, emissive: None, mask: None, normal: None },
        }
    }
    /// glTF-style dielectric with GGX roughness.
    pub fn glossy(c: Vec3, roughness: f32) -> Self {
        Material {
            base_color: c,
            metallic: 0.0,
            roughness,
            specular: 1.0,
            emissive: Vec3::ZERO,
            double_sided: false,
            maps: texture::Maps { base_color: None, metallic_roughness: None, emissive: None, mask: None, normal: None },
        }
    }
    /// A black emitter.
    pub fn emitter(radiance: Vec3) -> Self {
        Material {
            base_color: Vec3::ZERO,
            metallic: 0.0,
            roughness: 1.0,
            specular: 0.0,
            emissive: radiance,
            double_sided: false,
            maps: texture::Maps { base_color: None, metallic_roughness: None, emissive: None, mask: None, normal: None },
        }
    }
    /// Albedo of the Lambert layer: base·(1 − metallic).
    pub fn diffuse_albedo(&self) -> Vec3 {
        self.base_color * (1.0 - self.metallic)
    }
    /// GGX F0: mix(0.04·specular, base, metallic).
    pub fn specular_f0(&self) -> Vec3 {
        Vec3::splat(0.04 * self.specular).lerp(self.base_color, self.metallic)
    }
    /// GGX α = roughness², clamped to 1e-3 (below, a mirror: not supported by the
    /// sampler's pdf in f32).
    pub fn alpha(&self) -> f32 {
        (self.roughness * self.roughness).max(1e-3)
    }
    /// Whether the GGX layer contributes.
    pub fn is_glossy(&self) -> bool {
        // A metallic-roughness map can lower metallic below its factor, uncovering the
        // dielectric 0.04·specular.
        self.specular_f0().max_element() > 0.0 || (self.maps.metallic_roughness.is_some() && self.specular > 0.0)
    }
}

/// A triangle mesh.
#[derive(Debug, Clone)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (unit).
    pub normals: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
    pub material: usize,
    /// Lightmap UVs (glTF TEXCOORD_1) when the source has them; `None` → the layout
    /// generates charts.
    pub lightmap_uv: Option<Vec<Vec2>>,
    /// Whether the mesh receives a lightmap (emitters and helper geometry do not).
    pub lightmapped: bool,
    /// Texture coordinates (glTF TEXCOORD_0) for its material's maps; `None`: none.
    pub uv: Option<Vec<Vec2>>,
}

/// Delta light sources (area lights are emissive triangles: see [`disk_light`] and
/// [`sphere_light`]). Evaluation: [`crate::scene::lights`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// Direction *towards* the light (unit) and irradiance at normal incidence (W/m²).
    Directional { direction: Vec3, irradiance: Vec3 },
    /// Point light: intensity (W/sr); `range` > 0 windows the falloff to zero at that
    /// distance (KHR_lights_punctual; ∞ = unbounded).
    Point { position: Vec3, intensity: Vec3, range: f32 },
    /// Spot light: a point light shining along unit `direction`, with the smooth cone of
    /// KHR_lights_punctual between the cosines of its inner and outer angles.
    Spot { position: Vec3, direction: Vec3, intensity: Vec3, cos_inner: f32, cos_outer: f32, range: f32 },
}

/// Radiance arriving from directions that leave the scene.
#[derive(Debug, Clone)]
pub enum Environment {
    Black,
    Constant(Vec3),
    /// A simple analytic sky: `zenith` at +Y blending to `horizon`, `ground` below.
    Sky {
        zenith: Vec3,
        horizon: Vec3,
        ground: Vec3,
    },
    /// A lat-long HDR map (sbf's convention: +Y up, u from atan2(x, −z)), looked up at
    /// the nearest texel (CPU and GPU alike).
    Map(std::sync::Arc<sbf::envmap::LatLongImage>),
}

impl PartialEq for Environment {
    fn eq(&self, o: &Self) -> bool {
        match (self, o) {
            (Environment::Black, Environment::Black) => true,
            (Environment::Constant(a), Environment::Constant(b)) => a == b,
            (Environment::Sky { zenith: a, horizon: b, ground: c }, Environment::Sky { zenith: x, horizon: y, ground: z }) => {
                a == x && b == y && c == z
            }
            (Environment::Map(a), Environment::Map(b)) => std::sync::Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

/// Nearest texel (column, row) of a `width × width/2` lat-long map for unit `d`.
pub fn latlong_texel(d: Vec3, width: usize) -> (usize, usize) {
    let h = width / 2;
    let u = 0.5 * (1.0 + d.x.atan2(-d.z) / std::f32::consts::PI);
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    (((u * width as f32) as usize).min(width - 1), ((v * h as f32) as usize).min(h - 1))
}

impl Environment {
    /// Radiance from unit direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        match self {
            Environment::Black => Vec3::ZERO,
            Environment::Constant(c) => *c,
            Environment::Sky { zenith, horizon, ground } => {
                if d.y >= 0.0 {
                    horizon.lerp(*zenith, d.y.sqrt())
                } else {
                    *ground
                }
            }
            Environment::Map(m) => {
                let (i, j) = latlong_texel(d, m.geometry.width);
                Vec3::from(m.texel(i, j))
            }
        }
    }
}

/// A complete scene.
#[derive(Debug, Clone)]
pub struct Scene {
    pub name: String,
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    pub environment: Environment,
    /// The images the materials' maps read ([`texture`]).
    pub textures: Vec<texture::Texture>,
    /// The images of the materials' normal maps (the renderer's shading reads them, the
    /// bake does not).
    pub normal_textures: Vec<texture::Texture>,
}

/// The largest coordinate magnitude a scene may hold (cross products of edges must stay
/// finite in f32).
pub const MAX_COORDINATE: f32 = 1e15;

/// Errors in scene data.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneError {
    Empty,
    NonFinite { mesh: String, what: &'static str },
    BadIndex { mesh: String, index: u32, vertices: usize },
    BadMaterial { mesh: String, material: usize },
    BadMaterialValue { material: usize, what: &'static str },
    LengthMismatch { mesh: String, what: &'static str },
    UvOutOfRange { mesh: String, u: f32, v: f32 },
    BadLight { light: usize, what: &'static str },
    OutOfRange { mesh: String, what: &'static str },
    Io(String),
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SceneError::Empty => write!(f, "the scene has no non-degenerate triangles"),
            SceneError::NonFinite { mesh, what } => write!(f, "mesh '{mesh}': {what} contain NaN or Inf"),
            SceneError::BadIndex { mesh, index, vertices } => write!(f, "mesh '{mesh}': index {index} out of range ({vertices} vertices)"),
            SceneError::BadMaterial { mesh, material } => write!(f, "mesh '{mesh}': material {material} does not exist"),
            SceneError::BadMaterialValue { material, what } => write!(f, "material {material}: {what}"),
            SceneError::LengthMismatch { mesh, what } => write!(f, "mesh '{mesh}': {what} count differs from the vertex count"),
            SceneError::UvOutOfRange { mesh, u, v } => {
                write!(f, "mesh '{mesh}': lightmap UV ({u}, {v}) outside [0, 1] (lightmap UVs must lie in the unit square)")
            }
            SceneError::BadLight { light, what } => write!(f, "light {light}: {what}"),
            SceneError::OutOfRange { mesh, what } => write!(f, "mesh '{mesh}': {what}"),
            SceneError::Io(s) => write!(f, "{s}"),
        }
    }
}

impl std::error::Error for SceneError {}

impl Scene {
    /// The material of BVH triangle `tri` at barycentric (u, v), the point at corner +
    /// u·edge_u + v·edge_v: its factors times its maps sampled there (glTF 2.0 §3.9.2: the
    /// base colour times the sRGB-decoded map, roughness times G and metallic times B of
    /// the metallic-roughness map, emission times the sRGB-decoded emissive map). Without
    /// maps, the material itself.
    pub fn material_at(&self, tri: &bvh::Tri, u: f32, v: f32) -> Material {
        let m = self.materials[tri.material as usize];
        if m.maps.is_empty() {
            return m;
        }
        let read = |r: &texture::TextureRef, srgb: bool| self.map_at(tri, r, u, v, srgb);
        let mut out = m;
        if let Some(t) = m.maps.base_color.as_ref().and_then(|r| read(r, true)) {
            out.base_color *= t.truncate();
        }
        if let Some(t) = m.maps.metallic_roughness.as_ref().and_then(|r| read(r, false)) {
            out.roughness *= t.y;
            out.metallic *= t.z;
        }
        if let Some(t) = m.maps.emissive.as_ref().and_then(|r| read(r, true)) {
            out.emissive *= t.truncate();
        }
        out
    }

    /// Map `r` of BVH triangle `tri`'s material at barycentric (u, v); None where its mesh
    /// lacks the map's coordinate set (the importer notes it; the factor stands alone).
    fn map_at(&self, tri: &bvh::Tri, r: &texture::TextureRef, u: f32, v: f32, srgb: bool) -> Option<sbf::glam::Vec4> {
        let mesh = &self.meshes[tri.mesh as usize];
        let set = if r.texcoord == 1 { mesh.lightmap_uv.as_ref() } else { mesh.uv.as_ref() }?;
        let [a, b, c] = mesh.indices[tri.prim as usize].map(|i| set[i as usize]);
        let uv = a * (1.0 - u - v) + b * u + c * v;
        Some(self.textures[r.texture].sample(r.apply(uv), srgb))
    }

    /// Whether rays pass through BVH triangle `tri` at barycentric (u, v): its material's
    /// alpha mask (factor × the base colour map's alpha) is below the cutoff there.
    pub fn is_hole(&self, tri: &bvh::Tri, u: f32, v: f32) -> bool {
        let m = &self.materials[tri.material as usize];
        let Some(mask) = m.maps.mask else { return false };
        let alpha = match m.maps.base_color {
            None => 1.0,
            Some(r) => self.map_at(tri, &r, u, v, false).map_or(1.0, |t| t.w),
        };
        mask.factor * alpha < mask.cutoff
    }

    /// Whether any material has a texture map (or an alpha mask).
    pub fn has_textures(&self) -> bool {
        self.materials.iter().any(|m| !m.maps.is_empty())
    }

    /// The scene with its materials' factors alone (maps and textures dropped).
    pub fn without_maps(mut self) -> Scene {
        for m in &mut self.materials {
            m.maps = texture::Maps::default();
        }
        self.textures.clear();
        self.normal_textures.clear();
        self
    }

    /// Checks the scene; returns the number of degenerate (zero-area) triangles, which
    /// are skipped by the BVH and the layout (documented handling, not an error).
    pub fn validate(&self) -> Result<usize, SceneError> {
        let mut degenerate = 0;
        let mut good = 0;
        for (k, m) in self.materials.iter().enumerate() {
            let ok = m.base_color.is_finite() && m.emissive.is_finite() && m.metallic.is_finite() && m.roughness.is_finite();
            if !ok {
                return Err(SceneError::BadMaterialValue { material: k, what: "non-finite value" });
            }
            if m.base_color.min_element() < 0.0 || m.base_color.max_element() > 1.0 || m.emissive.min_element() < 0.0 {
                return Err(SceneError::BadMaterialValue { material: k, what: "base colour outside [0, 1] or negative emission" });
            }
            if m.emissive.max_element() > lights::MAX_LIGHT_VALUE {
                return Err(SceneError::BadMaterialValue { material: k, what: "emission above 1e18 (beyond f32 estimation)" });
            }
        }
        for (k, l) in self.lights.iter().enumerate() {
            lights::validate(l).map_err(|what| SceneError::BadLight { light: k, what })?;
        }
        for m in &self.meshes {
            if m.positions.iter().any(|p| !p.is_finite()) {
                return Err(SceneError::NonFinite { mesh: m.name.clone(), what: "positions" });
            }
            if m.positions.iter().any(|p| p.abs().max_element() > MAX_COORDINATE) {
                return Err(SceneError::OutOfRange {
                    mesh: m.name.clone(),
                    what: "a coordinate beyond ±1e15 (f32 ray arithmetic would overflow: scale the scene)",
                });
            }
            if m.normals.len() != m.positions.len() {
                return Err(SceneError::LengthMismatch { mesh: m.name.clone(), what: "normal" });
            }
            if m.normals.iter().any(|p| !p.is_finite()) {
                return Err(SceneError::NonFinite { mesh: m.name.clone(), what: "normals" });
            }
            if m.material >= self.materials.len() {
                return Err(SceneError::BadMaterial { mesh: m.name.clone(), material: m.material });
            }
            if let Some(uv) = &m.lightmap_uv {
                if uv.len() != m.positions.len() {
                    return Err(SceneError::LengthMismatch { mesh: m.name.clone(), what: "lightmap UV" });
                }
                if let Some(p) = uv.iter().find(|p| !p.is_finite() || p.min_element() < 0.0 || p.max_element() > 1.0) {
                    return Err(SceneError::UvOutOfRange { mesh: m.name.clone(), u: p.x, v: p.y });
                }
            }
            for t in &m.indices {
                for &i in t {
                    if i as usize >= m.positions.len() {
                        return Err(SceneError::BadIndex { mesh: m.name.clone(), index: i, vertices: m.positions.len() });
                    }
                }
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                if (b - a).cross(c - a).length() > 0.0 {
                    good += 1;
                } else {
                    degenerate += 1;
                }
            }
        }
        if good == 0 {
            return Err(SceneError::Empty);
        }
        Ok(degenerate)
    }

    /// Whether any material has a GGX layer (else specular encodings are left out).
    pub fn has_glossy(&self) -> bool {
        self.meshes.iter().any(|m| self.materials[m.material].is_glossy())
    }
}
