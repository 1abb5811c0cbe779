//! Normal-mapped shading (`render --normal-maps`): the materials' glTF normal maps perturb
//! the shading normal of every visible surface, and the lightmap's directional lobes —
//! baked in the tangent frame of the interpolated normal — are evaluated at the perturbed
//! normal, as engines shade normal-mapped surfaces from directional lightmaps. The
//! reference path-traces with the same perturbed normal, so the comparison measures what
//! each basis keeps of the light's direction.
//!
//! The tangent frame (glTF 2.0 §3.7.2.1, §3.9.3): MikkTSpace tangents (Mikkelsen 2008,
//! through the `mikktspace` crate) of the texture coordinates the map reads (after its
//! KHR_texture_transform), per triangle corner, interpolated over the triangle and made
//! orthogonal to the shading normal n (Gram–Schmidt); the bitangent b = w·(n × t) with the
//! tangent's handedness w. glTF's texture coordinates run down the image while its normal
//! maps' +Y points up it, so MikkTSpace is given (u, 1 − v) (three.js negates the sign for
//! glTF instead, the same frame). A texel's normal is (2·rgb − 1) with x, y × the map's
//! scale; the shading normal is normalize(x·t + y·b + z·n). Meshes' own TANGENT attributes
//! are not read (the importer does not keep them): the frame is always MikkTSpace's.

use crate::scene::texture::{NormalMap, Texture};
use crate::scene::{Mesh, Scene};
use sbf::glam::{Vec2, Vec3, Vec4};

/// Every normal-mapped material's map, its textures and the tangents of its meshes.
#[derive(Debug, Clone)]
pub struct NormalMaps {
    /// Per material.
    maps: Vec<Option<NormalMap>>,
    textures: Vec<Texture>,
    /// Per mesh (None: its material has no normal map): per triangle, its corners'
    /// tangents (xyz) and handedness (w).
    tangents: Vec<Option<Vec<[Vec4; 3]>>>,
}

/// A mesh's triangles as MikkTSpace reads and writes them.
struct Faces<'a> {
    mesh: &'a Mesh,
    uv: Vec<Vec2>,
    out: Vec<[Vec4; 3]>,
}

impl mikktspace::Geometry for Faces<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len()
    }
    fn num_vertices_of_face(&self, _: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.mesh.indices[face][vert] as usize].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.mesh.indices[face][vert] as usize].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uv[self.mesh.indices[face][vert] as usize];
        [uv.x, 1.0 - uv.y]
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        self.out[face][vert] = Vec4::from(tangent);
    }
}

impl NormalMaps {
    /// The normal maps of `scene` (None when no material has one); `notes` says which
    /// meshes cannot use theirs (no texture coordinates, or MikkTSpace failed).
    pub fn build(scene: &Scene, notes: &mut dyn FnMut(String)) -> Option<NormalMaps> {
        let maps: Vec<Option<NormalMap>> = scene.materials.iter().map(|m| m.maps.normal).collect();
        if maps.iter().all(Option::is_none) {
            return None;
        }
        let tangents = scene
            .meshes
            .iter()
            .map(|mesh| {
                let map = maps.get(mesh.material).copied().flatten()?;
                let uv = match map.texture.texcoord {
                    0 => mesh.uv.as_ref(),
                    _ => mesh.lightmap_uv.as_ref(),
                };
                let Some(uv) = uv else {
                    notes(format!("{}: its normal map reads TEXCOORD_{}, which it lacks: not applied", mesh.name, map.texture.texcoord));
                    return None;
                };
                let uv = uv.iter().map(|t| map.texture.apply(*t)).collect();
                let mut faces = Faces { mesh, uv, out: vec![[Vec4::ZERO; 3]; mesh.indices.len()] };
                if !mikktspace::generate_tangents(&mut faces) {
                    notes(format!("{}: MikkTSpace found no tangent frame: its normal map is not applied", mesh.name));
                    return None;
                }
                Some(faces.out)
            })
            .collect();
        Some(NormalMaps { maps, textures: scene.normal_textures.clone(), tangents })
    }

    /// Whether mesh `mesh` is shaded with a normal map.
    pub fn applies_to(&self, mesh: usize) -> bool {
        self.tangents.get(mesh).is_some_and(Option::is_some)
    }

    /// The shading normal of triangle `prim` of mesh `mesh` at barycentrics `w`, from its
    /// interpolated unit normal `n` (see the module docs); `n` itself where the mesh has no
    /// map or the frame degenerates.
    pub fn perturb(&self, scene: &Scene, mesh: usize, prim: usize, w: [f32; 3], n: Vec3) -> Vec3 {
        let (Some(Some(tangents)), Some(m)) = (self.tangents.get(mesh), scene.meshes.get(mesh)) else { return n };
        let Some(map) = self.maps[m.material] else { return n };
        let corners = tangents[prim];
        let t = corners.iter().zip(w).fold(Vec3::ZERO, |acc, (c, wi)| acc + c.truncate() * wi);
        let t = (t - n * n.dot(t)).normalize_or_zero();
        if t == Vec3::ZERO {
            return n;
        }
        let b = n.cross(t) * if corners[0].w < 0.0 { -1.0 } else { 1.0 };
        let uvs = match map.texture.texcoord {
            0 => m.uv.as_ref(),
            _ => m.lightmap_uv.as_ref(),
        };
        let Some(uvs) = uvs else { return n };
        let idx = m.indices[prim];
        let uv = idx.iter().zip(w).fold(Vec2::ZERO, |acc, (i, wi)| acc + uvs[*i as usize] * wi);
        let texel = self.textures[map.texture.texture].sample(map.texture.apply(uv), false);
        let local = Vec3::new((2.0 * texel.x - 1.0) * map.scale, (2.0 * texel.y - 1.0) * map.scale, 2.0 * texel.z - 1.0);
        let out = (t * local.x + b * local.y + n * local.z).normalize_or_zero();
        if out == Vec3::ZERO || !out.is_finite() {
            n
        } else {
            out
        }
    }
}
