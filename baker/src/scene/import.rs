//! glTF 2.0 import (the `gltf` crate, without its `import` feature): triangle
//! primitives of the default scene's node tree in world space, lightmap UVs from
//! TEXCOORD_1, metallic/roughness materials with emission (× KHR_materials_emissive_strength)
//! and `doubleSided`, and KHR_lights_punctual directional, point and spot lights (cones
//! and ranges honoured), and perspective cameras.
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
    /// The perspective cameras of the scene's node tree, in document order.
    pub cameras: Vec<super::camera::SceneCamera>,
}

/// Reads an external buffer file: a regular file, at most `declared` bytes taken (so a
/// special file such as /dev/zero or a huge file costs no more than the asset declares).
fn read_bounded(p: &Path, declared: usize, index: usize) -> Result<Vec<u8>, SceneError> {
    use std::io::Read;
    let err = |e: String| SceneError::Io(format!("buffer {index}: {}: {e}", p.display()));
    let f = std::fs::File::open(p).map_err(|e| err(e.to_string()))?;
    let meta = f.metadata().map_err(|e| err(e.to_string()))?;
    if !meta.is_file() {
        return Err(err("not a regular file".into()));
    }
    let mut data = Vec::with_capacity(declared.min(meta.len() as usize));
    f.take(declared as u64).read_to_end(&mut data).map_err(|e| err(e.to_string()))?;
    Ok(data)
}

/// What an accessor must be for its use.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Use {
    Position,
    Normal,
    /// TEXCOORD_0 (the material maps' coordinates).
    Uv,
    /// TEXCOORD_1.
    LightmapUv,
    Indices,
}

/// Checks an accessor before the `gltf` reader touches it: a type the use allows
/// (indices: unsigned SCALAR; positions and normals: float VEC3; lightmap UVs: float or
/// normalised unsigned VEC2), no sparse storage, and every element inside its buffer
/// view and the view inside the loaded buffer. The error names mesh, accessor and what
/// is out of range.
fn check_accessor(a: &gltf::Accessor, usage: Use, mesh: &str, data: &[Vec<u8>]) -> Result<(), SceneError> {
    use gltf::accessor::{DataType as T, Dimensions as D};
    let bad = |what: String| SceneError::Io(format!("mesh '{mesh}': accessor {} ({usage:?}): {what}", a.index()));
    let ok_type = match usage {
        Use::Position | Use::Normal => a.data_type() == T::F32 && a.dimensions() == D::Vec3,
        Use::Uv | Use::LightmapUv => {
            a.dimensions() == D::Vec2 && (a.data_type() == T::F32 || (a.normalized() && matches!(a.data_type(), T::U8 | T::U16)))
        }
        Use::Indices => a.dimensions() == D::Scalar && matches!(a.data_type(), T::U8 | T::U16 | T::U32),
    };
    if !ok_type {
        return Err(bad(format!(
            "type {:?} {:?}{} is not allowed here",
            a.data_type(),
            a.dimensions(),
            if a.normalized() { " normalized" } else { "" }
        )));
    }
    if a.sparse().is_some() {
        return Err(bad("sparse accessors are not supported".into()));
    }
    let view = a.view().ok_or_else(|| bad("no bufferView".into()))?;
    let buf = data.get(view.buffer().index()).ok_or_else(|| bad(format!("buffer {} was not loaded", view.buffer().index())))?;
    let view_end = view.offset().checked_add(view.length()).ok_or_else(|| bad("bufferView range overflows".into()))?;
    if view_end > buf.len() {
        return Err(bad(format!("bufferView {} ends at byte {view_end}, its buffer has {} bytes", view.index(), buf.len())));
    }
    let elem = a.size();
    let stride = view.stride().unwrap_or(elem);
    if a.count() > 0 {
        let last = (a.count() - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(a.offset()))
            .and_then(|x| x.checked_add(elem))
            .ok_or_else(|| bad(format!("count {} overflows", a.count())))?;
        if last > view.length() {
            return Err(bad(format!(
                "count {} × stride {stride} from offset {} needs {last} bytes, bufferView {} has {}",
                a.count(),
                a.offset(),
                view.index(),
                view.length()
            )));
        }
    }
    Ok(())
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
                    super::uri::base64(payload).map_err(|e| SceneError::Io(format!("buffer {}: {e}", b.index())))?
                } else {
                    read_bounded(&base.join(super::uri::percent_decode(uri)), b.length(), b.index())?
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

/// Checks the accessor references of every primitive (attributes, indices, morph targets)
/// before the `gltf` crate validates the document: its validation hook indexes the
/// accessor list with the POSITION reference unchecked and panics on a bad one.
fn precheck_references(json: &[u8]) -> Result<(), String> {
    let v: serde_json::Value = serde_json::from_slice(json).map_err(|e| format!("not valid JSON: {e}"))?;
    let accessors = v.get("accessors").and_then(|a| a.as_array()).map_or(0, |a| a.len());
    let check = |what: String, r: &serde_json::Value| -> Result<(), String> {
        match r.as_u64() {
            Some(i) if (i as usize) < accessors => Ok(()),
            _ => Err(format!("{what} refers to accessor {r}, the asset has {accessors}")),
        }
    };
    for (mi, m) in v.get("meshes").and_then(|m| m.as_array()).into_iter().flatten().enumerate() {
        for (pi, p) in m.get("primitives").and_then(|p| p.as_array()).into_iter().flatten().enumerate() {
            let maps = p.get("attributes").into_iter().chain(p.get("targets").and_then(|t| t.as_array()).into_iter().flatten());
            for attrs in maps {
                for (k, r) in attrs.as_object().into_iter().flatten() {
                    check(format!("mesh {mi} primitive {pi} attribute {k}"), r)?;
                }
            }
            if let Some(r) = p.get("indices") {
                check(format!("mesh {mi} primitive {pi} indices"), r)?;
            }
        }
    }
    Ok(())
}

/// Loads a .gltf or .glb file into a scene (validated) with a report.
pub fn load(path: &Path) -> Result<(Scene, ImportReport), SceneError> {
    let meta = std::fs::metadata(path).map_err(|e| SceneError::Io(format!("{}: {e}", path.display())))?;
    if !meta.is_file() {
        return Err(SceneError::Io(format!("{}: not a regular file", path.display())));
    }
    let bytes = std::fs::read(path).map_err(|e| SceneError::Io(format!("{}: {e}", path.display())))?;
    let invalid = |e: String| SceneError::Io(format!("{}: not a valid glTF 2.0 asset: {e}", path.display()));
    let json: std::borrow::Cow<[u8]> = if bytes.starts_with(b"glTF") {
        gltf::Glb::from_slice(&bytes).map_err(|e| invalid(e.to_string()))?.json
    } else {
        std::borrow::Cow::Borrowed(&bytes[..])
    };
    precheck_references(&json).map_err(invalid)?;
    let g = gltf::Gltf::from_slice(&bytes).map_err(|e| invalid(e.to_string()))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let data = buffers(&g.document, g.blob.clone(), base)?;
    let mut report = ImportReport::default();
    let mut scene = Scene {
        name: path.file_stem().and_then(|s| s.to_str()).unwrap_or("gltf").to_string(),
        meshes: Vec::new(),
        materials: Vec::new(),
        lights: Vec::new(),
        environment: Environment::Black,
        textures: Vec::new(),
        normal_textures: Vec::new(),
    };
    scene.materials = materials(&g.document);
    let maps = super::import_maps::load(&g.document, &data, base, &mut report.notes).map_err(SceneError::Io)?;
    for (m, maps) in scene.materials.iter_mut().zip(maps.maps) {
        m.maps = maps;
    }
    scene.textures = maps.textures;
    scene.normal_textures = maps.normal_textures;
    // glTF's default material (white dielectric, roughness 1) for primitives without one.
    let default_material = scene.materials.len();
    scene.materials.push(Material::glossy(Vec3::ONE, 1.0));
    let gscene = g.document.default_scene().or_else(|| g.document.scenes().next()).ok_or(SceneError::Empty)?;
    // Depth-first in document order (the stack holds siblings reversed).
    let mut stack: Vec<(gltf::Node, Mat4)> = gscene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    stack.reverse();
    // glTF nodes form disjoint trees: a node reached twice is a cycle or has two parents.
    let mut seen = vec![false; g.document.nodes().len()];
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(SceneError::Io(format!(
                "node {} is reached twice from the scene (a cycle in `children` or a node with two parents)",
                node.index()
            )));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let children: Vec<gltf::Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
        if let Some(light) = node.light() {
            scene.lights.push(punctual_light(&light, world));
        }
        if let Some(cam) = node.camera() {
            camera(&cam, &node, world, &mut report).map_err(SceneError::Io)?;
        }
        let Some(mesh) = node.mesh() else { continue };
        for (pi, prim) in mesh.primitives().enumerate() {
            let name = format!("{}#{pi}", mesh.name().unwrap_or("mesh"));
            if let Some(m) = primitive(&prim, name, world, &data, &scene.materials, default_material, &mut report)? {
                scene.meshes.push(m);
            }
        }
    }
    let degenerate = scene.validate()?;
    if degenerate > 0 {
        report.notes.push(format!("{degenerate} degenerate (zero-area) triangles skipped"));
    }
    Ok((scene, report))
}

/// A camera node: perspective cameras are kept, orthographic ones noted and skipped.
fn camera(cam: &gltf::Camera, node: &gltf::Node, world: Mat4, report: &mut ImportReport) -> Result<(), String> {
    let name = cam.name().or(node.name()).map_or_else(|| format!("camera {}", report.cameras.len()), str::to_string);
    match cam.projection() {
        gltf::camera::Projection::Perspective(p) => {
            report.cameras.push(super::camera::SceneCamera::from_node(name, world, p.yfov(), p.aspect_ratio())?);
        }
        gltf::camera::Projection::Orthographic(_) => {
            report.notes.push(format!("camera '{name}' is orthographic: skipped (views are pinhole cameras)"));
        }
    }
    Ok(())
}

/// The materials of a glTF document (their factors; the maps come from
/// [`super::import_maps`]).
fn materials(doc: &gltf::Document) -> Vec<Material> {
    let mut out = Vec::new();
    for m in doc.materials() {
        let pbr = m.pbr_metallic_roughness();
        let c = pbr.base_color_factor();
        let mut mat = Material::glossy(Vec3::new(c[0], c[1], c[2]), pbr.roughness_factor());
        mat.metallic = pbr.metallic_factor();
        mat.emissive = Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
        mat.double_sided = m.double_sided();
        out.push(mat);
    }
    out
}

/// A KHR_lights_punctual light at the node transform `world`.
fn punctual_light(light: &gltf::khr_lights_punctual::Light, world: Mat4) -> Light {
    let col = Vec3::from(light.color()) * light.intensity();
    match light.kind() {
        gltf::khr_lights_punctual::Kind::Directional => {
            // The light shines along the node's −Z; we store the direction towards it.
            let towards = world.transform_vector3(Vec3::Z).normalize();
            Light::Directional { direction: towards, irradiance: col }
        }
        gltf::khr_lights_punctual::Kind::Point => {
            let range = light.range().unwrap_or(f32::INFINITY);
            Light::Point { position: world.transform_point3(Vec3::ZERO), intensity: col, range }
        }
        gltf::khr_lights_punctual::Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            // The spot shines along the node's −Z.
            let direction = world.transform_vector3(-Vec3::Z).normalize();
            Light::Spot {
                position: world.transform_point3(Vec3::ZERO),
                direction,
                intensity: col,
                cos_inner: inner_cone_angle.cos(),
                cos_outer: outer_cone_angle.cos(),
                range: light.range().unwrap_or(f32::INFINITY),
            }
        }
    }
}

/// One triangle primitive of a mesh node as a scene mesh in world space (None: skipped,
/// with a note), every accessor bounds-checked first.
fn primitive(
    prim: &gltf::Primitive,
    name: String,
    world: Mat4,
    data: &[Vec<u8>],
    materials: &[Material],
    default_material: usize,
    report: &mut ImportReport,
) -> Result<Option<Mesh>, SceneError> {
    let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
    if prim.mode() != gltf::mesh::Mode::Triangles {
        report.notes.push(format!("{name}: {:?} primitive skipped (triangles only)", prim.mode()));
        return Ok(None);
    }
    let Some(pa) = prim.get(&gltf::Semantic::Positions) else {
        report.notes.push(format!("{name}: no POSITION, skipped"));
        return Ok(None);
    };
    check_accessor(&pa, Use::Position, &name, data)?;
    let vertices = pa.count();
    for (sem, usage) in
        [(gltf::Semantic::Normals, Use::Normal), (gltf::Semantic::TexCoords(0), Use::Uv), (gltf::Semantic::TexCoords(1), Use::LightmapUv)]
    {
        if let Some(a) = prim.get(&sem) {
            check_accessor(&a, usage, &name, data)?;
            if a.count() != vertices {
                return Err(SceneError::Io(format!(
                    "mesh '{name}': accessor {} ({usage:?}) has {} elements, POSITION has {vertices}",
                    a.index(),
                    a.count()
                )));
            }
        }
    }
    if let Some(a) = prim.indices() {
        check_accessor(&a, Use::Indices, &name, data)?;
    }
    let reader = prim.reader(|b| data.get(b.index()).map(|v| &v[..]));
    let Some(pos) = reader.read_positions() else {
        return Err(SceneError::Io(format!("mesh '{name}': POSITION accessor {} could not be read", pa.index())));
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
        report.notes.push(format!("{name}: no TEXCOORD_1, lightmap charts generated (uvunwrap: normal-cone charts, planar or LSCM)"));
    }
    let uv: Option<Vec<Vec2>> = reader.read_tex_coords(0).map(|t| t.into_f32().map(Vec2::from).collect());
    let material = prim.material().index().unwrap_or(default_material);
    if let Some(m) = materials.get(material) {
        let maps = [m.maps.base_color, m.maps.metallic_roughness, m.maps.emissive];
        let missing = |set: u32, have: bool| !have && maps.iter().flatten().any(|r| r.texcoord == set);
        for (set, have) in [(0, uv.is_some()), (1, lightmap_uv.is_some())] {
            if missing(set, have) {
                report.notes.push(format!("{name}: its material's maps read TEXCOORD_{set}, which it lacks: factors used there"));
            }
        }
    }
    let emissive = materials.get(material).is_some_and(|m| m.emissive.max_element() > 0.0);
    Ok(Some(Mesh { name, positions, normals, indices, material, lightmap_uv, lightmapped: !emissive, uv }))
}
