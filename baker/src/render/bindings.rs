//! What the render pipelines bind, shared by all of them: the bind group layout (frame
//! uniform, materials, lightmap array, 2D table, lobe table (3D, filtered), probes, DFG
//! table, the lightmap's sampler, the lobe table's sampler — the bindings of
//! `wgsl/render.wgsl`), the probe grid as the shader's rows, and the scene's vertices and
//! materials as the render pipelines (and the browser viewer, [`super::web`]) read them.

use super::lighting::{LightmapFilter, SurfaceMaterial};
use super::probes::ProbeField;
use crate::layout::lightmap::Lightmap;
use crate::scene::camera::ViewCamera;
use crate::scene::Scene;
use sbf::glam::Vec3;

/// WGSL `Frame`'s probe lattice: (probes along x, y, z; count), first and last position.
pub(crate) type Lattice = ([u32; 4], [f32; 4], [f32; 4]);

/// The bind group layout every render pipeline shares (frame, materials, lightmap, table,
/// lobe table, probes, DFG, lightmap sampler, lobe table sampler) and the pipeline layout
/// around it;
/// `filtering`: the lightmap is read through a filtering sampler (else a non-filtering
/// one the shader never samples with).
pub(super) fn layouts(d: &wgpu::Device, filtering: bool) -> (wgpu::BindGroupLayout, wgpu::PipelineLayout) {
    let texture = |binding: u32, dim: wgpu::TextureViewDimension| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            // The lightmap when it is sampled; the lobe table (3D), always.
            sample_type: wgpu::TextureSampleType::Float { filterable: (filtering && binding == 2) || binding == 4 },
            view_dimension: dim,
            multisampled: false,
        },
        count: None,
    };
    let buffer = |binding: u32, ty: wgpu::BufferBindingType| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    };
    let group_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("render"),
        entries: &[
            buffer(0, wgpu::BufferBindingType::Uniform),
            buffer(1, wgpu::BufferBindingType::Storage { read_only: true }),
            texture(2, wgpu::TextureViewDimension::D2Array),
            texture(3, wgpu::TextureViewDimension::D2),
            texture(4, wgpu::TextureViewDimension::D3),
            buffer(5, wgpu::BufferBindingType::Storage { read_only: true }),
            texture(6, wgpu::TextureViewDimension::D2),
            wgpu::BindGroupLayoutEntry {
                binding: 7,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Sampler(if filtering {
                    wgpu::SamplerBindingType::Filtering
                } else {
                    wgpu::SamplerBindingType::NonFiltering
                }),
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 8,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    });
    let layout = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("render"),
        bind_group_layouts: &[Some(&group_layout)],
        immediate_size: 0,
    });
    (group_layout, layout)
}

/// The probes as WGSL rows (9 per probe, row 0's w the validity) and the lattice
/// (dims + count, first, last); one zero row and a count of 0 without probes.
pub(crate) fn probe_rows(probes: Option<&ProbeField>) -> (Vec<[f32; 4]>, Lattice) {
    match probes {
        Some(p) => {
            let rows: Vec<[f32; 4]> = p
                .coefficients
                .iter()
                .zip(&p.valid)
                .flat_map(|(c, v)| {
                    c.iter().enumerate().map(move |(l, x)| [x.x as f32, x.y as f32, x.z as f32, if l == 0 && *v { 1.0 } else { 0.0 }])
                })
                .collect();
            let dims = [p.dims[0] as u32, p.dims[1] as u32, p.dims[2] as u32, p.coefficients.len() as u32];
            (rows, (dims, [p.first.x, p.first.y, p.first.z, 0.0], [p.last.x, p.last.y, p.last.z, 0.0]))
        }
        None => (vec![[0.0; 4]], ([0; 4], [0.0; 4], [0.0; 4])),
    }
}

/// The lightmap's sampler: bilinear and clamped to the edge for the filters that sample
/// ([`LightmapFilter::samples`]; texel centres at (i + ½)/size, as the exact footprint),
/// nearest otherwise (bound, never sampled).
pub(super) fn lightmap_sampler(d: &wgpu::Device, filter: LightmapFilter) -> wgpu::Sampler {
    let f = if filter.samples() { wgpu::FilterMode::Linear } else { wgpu::FilterMode::Nearest };
    d.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("lightmap"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: f,
        min_filter: f,
        ..Default::default()
    })
}

/// What binds in the lobe table's place when a configuration reads no table: a 1 × 1 × 1
/// rg16float 3D texture.
pub(super) fn no_lobe_table(d: &wgpu::Device) -> wgpu::Texture {
    d.create_texture(&wgpu::TextureDescriptor {
        label: Some("no lobe table"),
        size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D3,
        format: wgpu::TextureFormat::Rg16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

/// WGSL `MaterialGpu`: xyz the Lambert albedo, w GGX α; xyz Schlick F0 (f90 = 1).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct MaterialGpu {
    pub albedo_alpha: [f32; 4],
    pub f0: [f32; 4],
}

/// The vertex layout (48 bytes): position, normal, atlas UV (texels), material (|
/// [`LIGHTMAPPED`] or [`PROBED`]), the triangle's face normal.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    pub material: u32,
    pub face: [f32; 3],
}

/// The material bit of a surface with a lightmap.
pub(crate) const LIGHTMAPPED: u32 = 0x8000_0000;
/// The material bit of a dynamic object (no lightmap, not an emitter): shaded from the probes.
pub(crate) const PROBED: u32 = 0x4000_0000;

/// The scene's triangles as unindexed vertices (with `lm`'s atlas UVs) and their bounds.
pub(crate) fn scene_vertices(scene: &Scene, lm: &Lightmap) -> Result<(Vec<Vertex>, (Vec3, Vec3)), String> {
    let mut verts = Vec::new();
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for (mi, m) in scene.meshes.iter().enumerate() {
        let emitter = scene.materials[m.material].emissive.max_element() > 0.0;
        let flag = if m.lightmapped {
            LIGHTMAPPED
        } else if !emitter {
            PROBED
        } else {
            0
        };
        for (ti, idx) in m.indices.iter().enumerate() {
            let c = idx.map(|i| m.positions[i as usize]);
            let face = (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero().to_array();
            for (k, i) in idx.iter().enumerate() {
                let p = m.positions[*i as usize];
                lo = lo.min(p);
                hi = hi.max(p);
                let uv = if m.lightmapped { lm.triangle_uv[mi][ti][k] } else { sbf::glam::Vec2::ZERO };
                verts.push(Vertex {
                    position: p.to_array(),
                    normal: m.normals[*i as usize].to_array(),
                    uv: uv.to_array(),
                    material: m.material as u32 | flag,
                    face,
                });
            }
        }
    }
    if verts.is_empty() {
        return Err("the scene has no triangles to render".into());
    }
    Ok((verts, (lo, hi)))
}

/// The scene's materials as shader rows.
pub(crate) fn material_rows(scene: &Scene) -> Vec<MaterialGpu> {
    scene
        .materials
        .iter()
        .map(|m| {
            let s = SurfaceMaterial::of(m);
            let (a, f) = (s.albedo.as_vec3(), s.f0.as_vec3());
            MaterialGpu { albedo_alpha: [a.x, a.y, a.z, s.alpha as f32], f0: [f.x, f.y, f.z, 0.0] }
        })
        .collect()
}

/// Near and far planes that hold the scene (`bounds`) seen from `cam`.
pub(crate) fn depth_range(bounds: (Vec3, Vec3), cam: &ViewCamera) -> (f32, f32) {
    let (lo, hi) = bounds;
    let far = 2.0 * ((hi - lo).length() + (cam.eye - 0.5 * (lo + hi)).length()).max(1e-3);
    (far * 1e-5, far)
}
