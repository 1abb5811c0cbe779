//! glTF 2.0 import (the `gltf` crate, without its `import` feature): triangle
//! primitives of the default scene's node tree in world space, lightmap UVs from
//! TEXCOORD_1, metallic/roughness materials with emission (× KHR_materials_emissive_strength)
//! and `doubleSided`, and KHR_lights_punctual directional, point and spot lights (cones
//! and ranges honoured).
//! Buffers come from the GLB blob, external files next to the asset, or base64 data URIs.
//! Everything skipped is listed in the [`ImportReport`]; bad data is a [`SceneError`].

use crate::scene::{Environment, Light, Material, Mesh, Scene, SceneError};
use sbf::glam::{Mat3, Mat4, Vec2, Vec3};
use std::path::Path;

/// What the import did beyond the obvious.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ImportReport {
    /// Notes: skipped primitives, spot lights taken as points, missing normals.
    pub notes: Vec<String>,
}

/// Decodes standard base64 (RFC 4648, padding optional).
fn base64(s: &str) -> Result<Vec<u8>, String> {
    let val = |c: u8| -> Result<u32, String> {
        Ok(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return Err(format!("invalid base64 character '{}'", c as char)),
        } as u32)
    };
    let bytes: Vec<u8> = s.bytes().filter(|c| !c.is_ascii_whitespace() && *c != b'=').collect();
    let mut out = Vec::with_capacity(bytes.len() * 3 / 4);
    for chunk in bytes.chunks(4) {
        let mut acc = 0u32;
        for (k, c) in chunk.iter().enumerate() {
            acc |= val(*c)? << (18 - 6 * k);
        }
        let n = match chunk.len() {
            4 => 3,
            3 => 2,
            2 => 1,
            _ => return Err("truncated base64 data".into()),
        };
        out.extend_from_slice(&acc.to_be_bytes()[1..1 + n]);
    }
    Ok(out)
}

fn buffers(doc: &gltf::Document, blob: Option<Vec<u8>>, base: &Path) -> Result<Vec<Vec<u8>>, SceneError> {
    let mut blob = blob;
    let mut out = Vec::new();
    for b in doc.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => {
                blob.take().ok_or_else(|| SceneError::Io("glTF buffer refers to a GLB blob the file does not have".into()))?
            }
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let (_, payload) = rest
                        .split_once(";base64,")
                        .ok_or_else(|| SceneError::Io(format!("buffer {}: data URI is not base64", b.index())))?;
                    base64(payload).map_err(|e| SceneError::Io(format!("buffer {}: {e}", b.index())))?
                } else {
                    let p = base.join(uri);
                    std::fs::read(&p).map_err(|e| SceneError::Io(format!("buffer {}: {}: {e}", b.index(), p.display())))?
                }
            }
        };
        if data.len() < b.length() {
            return Err(SceneError::Io(format!("buffer {}: {} bytes, the asset declares {}", b.index(), data.len(), b.length())));
        }
        out.push(data);
    }
    Ok(out)
}

/// Loads a .gltf or .glb file into a scene (validated) with a report.
pub fn load(path: &Path) -> Result<(Scene, ImportReport), SceneError> {
    let bytes = std::fs::read(path).map_err(|e| SceneError::Io(format!("{}: {e}", path.display())))?;
    let g = gltf::Gltf::from_slice(&bytes).map_err(|e| SceneError::Io(format!("{}: not a valid glTF 2.0 asset: {e}", path.display())))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let data = buffers(&g.document, g.blob.clone(), base)?;
    let mut report = ImportReport::default();
    let mut scene = Scene {
        name: path.file_stem().and_then(|s| s.to_str()).unwrap_or("gltf").to_string(),
        meshes: Vec::new(),
        materials: Vec::new(),
        lights: Vec::new(),
        environment: Environment::Black,
    };
    for m in g.document.materials() {
        let pbr = m.pbr_metallic_roughness();
        let c = pbr.base_color_factor();
        let mut mat = Material::glossy(Vec3::new(c[0], c[1], c[2]), pbr.roughness_factor());
        mat.metallic = pbr.metallic_factor();
        mat.emissive = Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
        mat.double_sided = m.double_sided();
        if pbr.base_color_texture().is_some() || pbr.metallic_roughness_texture().is_some() || m.emissive_texture().is_some() {
            report.notes.push(format!("material '{}': textures are not sampled (factors used)", m.name().unwrap_or("?")));
        }
        scene.materials.push(mat);
    }
    // glTF's default material (white dielectric, roughness 1) for primitives without one.
    let default_material = scene.materials.len();
    scene.materials.push(Material::glossy(Vec3::ONE, 1.0));
    let gscene = g.document.default_scene().or_else(|| g.document.scenes().next()).ok_or(SceneError::Empty)?;
    // Depth-first in document order (the stack holds siblings reversed).
    let mut stack: Vec<(gltf::Node, Mat4)> = gscene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    stack.reverse();
    while let Some((node, parent)) = stack.pop() {
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let children: Vec<gltf::Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
        if let Some(light) = node.light() {
            let col = Vec3::from(light.color()) * light.intensity();
            match light.kind() {
                gltf::khr_lights_punctual::Kind::Directional => {
                    // The light shines along the node's −Z; we store the direction towards it.
                    let towards = world.transform_vector3(Vec3::Z).normalize();
                    scene.lights.push(Light::Directional { direction: towards, irradiance: col });
                }
                gltf::khr_lights_punctual::Kind::Point => {
                    let range = light.range().unwrap_or(f32::INFINITY);
                    scene.lights.push(Light::Point { position: world.transform_point3(Vec3::ZERO), intensity: col, range });
                }
                gltf::khr_lights_punctual::Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                    // The spot shines along the node's −Z.
                    let direction = world.transform_vector3(-Vec3::Z).normalize();
                    scene.lights.push(Light::Spot {
                        position: world.transform_point3(Vec3::ZERO),
                        direction,
                        intensity: col,
                        cos_inner: inner_cone_angle.cos(),
                        cos_outer: outer_cone_angle.cos(),
                        range: light.range().unwrap_or(f32::INFINITY),
                    });
                }
            }
        }
        let Some(mesh) = node.mesh() else { continue };
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        for (pi, prim) in mesh.primitives().enumerate() {
            let name = format!("{}#{pi}", mesh.name().unwrap_or("mesh"));
            if prim.mode() != gltf::mesh::Mode::Triangles {
                report.notes.push(format!("{name}: {:?} primitive skipped (triangles only)", prim.mode()));
                continue;
            }
            let reader = prim.reader(|b| data.get(b.index()).map(|v| &v[..]));
            let Some(pos) = reader.read_positions() else {
                report.notes.push(format!("{name}: no POSITION, skipped"));
                continue;
            };
            let positions: Vec<Vec3> = pos.map(|p| world.transform_point3(Vec3::from(p))).collect();
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..positions.len() as u32).collect(),
            };
            if indices.len() % 3 != 0 {
                return Err(SceneError::LengthMismatch { mesh: name, what: "index (not a multiple of 3)" });
            }
            let indices: Vec<[u32; 3]> = indices.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
            let normals: Vec<Vec3> = match reader.read_normals() {
                Some(n) => n.map(|v| (normal_matrix * Vec3::from(v)).normalize_or_zero()).collect(),
                None => {
                    report.notes.push(format!("{name}: no NORMAL, face normals used"));
                    let mut n = vec![Vec3::ZERO; positions.len()];
                    for t in &indices {
                        if let (Some(a), Some(b), Some(c)) =
                            (positions.get(t[0] as usize), positions.get(t[1] as usize), positions.get(t[2] as usize))
                        {
                            let f = (*b - *a).cross(*c - *a);
                            for &i in t {
                                n[i as usize] += f;
                            }
                        }
                    }
                    n.into_iter().map(|v| v.normalize_or_zero()).collect()
                }
            };
            let lightmap_uv: Option<Vec<Vec2>> = reader.read_tex_coords(1).map(|t| t.into_f32().map(Vec2::from).collect());
            if lightmap_uv.is_none() {
                report.notes.push(format!("{name}: no TEXCOORD_1, lightmap charts generated (planar grouping)"));
            }
            let material = prim.material().index().unwrap_or(default_material);
            let emissive = scene.materials.get(material).is_some_and(|m| m.emissive.max_element() > 0.0);
            scene.meshes.push(Mesh { name, positions, normals, indices, material, lightmap_uv, lightmapped: !emissive });
        }
    }
    let degenerate = scene.validate()?;
    if degenerate > 0 {
        report.notes.push(format!("{degenerate} degenerate (zero-area) triangles skipped"));
    }
    Ok((scene, report))
}
