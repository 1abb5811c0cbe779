//! The visible surface of every pixel: what the rasteriser interpolates (world position,
//! shading normal, lightmap UV in atlas texels, material), found on the CPU by casting
//! the camera ray through the pixel centre into the BVH — the rasteriser's CPU twin — and
//! the CPU image it shades ([`shade_pixels`]).

use super::atlas::Atlas;
use super::lighting::{LightmapFilter, SurfaceMaterial};
use super::normal_map::NormalMaps;
use super::probes::ProbeField;
use super::shade::{Shader, Terms};
use crate::layout::lightmap::Lightmap;
use crate::scene::bvh::{Bvh, Hit};
use crate::scene::camera::ViewCamera;
use crate::scene::geometry::shading_normal;
use crate::scene::Scene;
use rayon::prelude::*;
use sbf::glam::{DVec3, Vec3};

/// A pixel's visible surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Visible {
    pub position: Vec3,
    /// Unit shading normal: the interpolated vertex normal (the face normal where they
    /// cancel), perturbed by the material's normal map where one is applied
    /// ([`super::normal_map`]).
    pub normal: Vec3,
    /// The interpolated normal itself: the lightmap's texels are baked in its tangent frame.
    pub frame_normal: Vec3,
    /// Unit geometric normal.
    pub geometric: Vec3,
    /// Lightmap position in atlas texels (texel (i, j) covers [i, i + 1) × [j, j + 1)).
    pub uv: [f32; 2],
    /// Index into the scene's materials.
    pub material: u32,
    /// The pixel sees the lit side of a surface that has a lightmap (else it is not
    /// shaded from the bake: no lightmap, or the back of a surface, which the lightmap —
    /// the light arriving at the side the face normal points to — does not cover).
    pub lightmapped: bool,
    /// The pixel sees the front of a dynamic object (no lightmap, not an emitter): shaded
    /// from the probe grid ([`super::probes`]).
    pub probed: bool,
}

/// The surface of triangle hit `h` (barycentrics u, v at corners 1 and 2) seen along `d`,
/// its shading normal perturbed by `maps` where they apply.
pub fn surface_at(scene: &Scene, bvh: &Bvh, lm: &Lightmap, maps: Option<&NormalMaps>, o: Vec3, d: Vec3, h: &Hit) -> Visible {
    let tri = &bvh.tris[h.tri as usize];
    let mesh = &scene.meshes[tri.mesh as usize];
    let idx = mesh.indices[tri.prim as usize];
    let w = [1.0 - h.u - h.v, h.u, h.v];
    let ng = tri.e1().cross(tri.e2()).normalize_or_zero();
    let vn = idx.map(|i| mesh.normals[i as usize]);
    let uvs = lm.triangle_uv[tri.mesh as usize][tri.prim as usize];
    let uv = uvs[0] * w[0] + uvs[1] * w[1] + uvs[2] * w[2];
    let n = shading_normal(vn, w, ng);
    Visible {
        position: o + d * h.t,
        normal: maps.map_or(n, |m| m.perturb(scene, tri.mesh as usize, tri.prim as usize, w, n)),
        frame_normal: n,
        geometric: ng,
        uv: [uv.x, uv.y],
        material: tri.material,
        lightmapped: mesh.lightmapped && d.dot(ng) < 0.0,
        probed: !mesh.lightmapped && d.dot(ng) < 0.0 && scene.materials[tri.material as usize].emissive.max_element() <= 0.0,
    }
}

/// The visible surface through every pixel centre of `cam` (row-major; None: the ray
/// leaves the scene).
pub fn cast(scene: &Scene, bvh: &Bvh, lm: &Lightmap, cam: &ViewCamera) -> Vec<Option<Visible>> {
    cast_mapped(scene, bvh, lm, None, cam)
}

/// [`cast`] with the shading normals perturbed by `maps`.
pub fn cast_mapped(scene: &Scene, bvh: &Bvh, lm: &Lightmap, maps: Option<&NormalMaps>, cam: &ViewCamera) -> Vec<Option<Visible>> {
    (0..cam.width * cam.height)
        .into_par_iter()
        .map(|k| {
            let (x, y) = (k % cam.width, k / cam.width);
            let (o, d) = cam.ray(x as f32 + 0.5, y as f32 + 0.5);
            bvh.intersect(o, d, 0.0, f32::INFINITY).map(|h| surface_at(scene, bvh, lm, maps, o, d, &h))
        })
        .collect()
}

/// The shading of one visible surface seen from `eye`: from the lightmap, or from the
/// probes for a dynamic object (zero where neither applies).
pub fn shade_one(
    shader: &Shader,
    atlas: &Atlas,
    filter: LightmapFilter,
    probes: Option<&ProbeField>,
    materials: &[SurfaceMaterial],
    eye: DVec3,
    s: &Visible,
) -> Terms {
    if s.probed {
        let v = (eye - s.position.as_dvec3()).normalize();
        return match probes.and_then(|p| p.at(s.position)) {
            Some(c) => super::shade::probe_terms(&c, &materials[s.material as usize], s.normal.as_dvec3().normalize(), v),
            None => Terms::default(),
        };
    }
    if !s.lightmapped {
        return Terms::default();
    }
    let c = atlas.sample(filter, [s.uv[0] as f64, s.uv[1] as f64]);
    let p = s.position.as_dvec3();
    let v = (eye - p).normalize();
    shader.terms_at(&c, &materials[s.material as usize], s.frame_normal.as_dvec3().normalize(), s.normal.as_dvec3().normalize(), v)
}

/// The CPU image: every pixel's terms (zero where neither a lightmap nor the probes apply).
pub fn shade_pixels(
    shader: &Shader,
    atlas: &Atlas,
    filter: LightmapFilter,
    probes: Option<&ProbeField>,
    scene: &Scene,
    eye: Vec3,
    visible: &[Option<Visible>],
) -> Vec<Terms> {
    let materials: Vec<SurfaceMaterial> = scene.materials.iter().map(SurfaceMaterial::of).collect();
    let eye = eye.as_dvec3();
    visible
        .par_iter()
        .map(|s| s.as_ref().map(|s| shade_one(shader, atlas, filter, probes, &materials, eye, s)).unwrap_or_default())
        .collect()
}
