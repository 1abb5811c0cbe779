//! Camera-based sampling on the GPU (CPU twin [`crate::accumulate::camera`], WGSL
//! `wgsl/camera.wgsl`): per batch the scene rasterised from the jittered view into a
//! texel-index target (R32Uint + depth), the pixels per texel counted (capped), and the
//! batch's per-texel samples and flags written for the compaction of [`super::adaptive`].

use super::compute_pipeline;
use crate::accumulate::camera::CameraSampling;
use crate::accumulate::Targets;
use crate::scene::bvh::Bvh;
use crate::scene::camera::ViewCamera;
use sbf::glam::Vec3;
use wgpu::util::DeviceExt;

const CAMERA_WGSL: &str = include_str!("wgsl/camera.wgsl");

/// WGSL `CameraParams`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraParams {
    view_proj: [[f32; 4]; 4],
    atlas_width: u32,
    atlas_height: u32,
    image_width: u32,
    image_height: u32,
    items: u32,
    max_per_batch: u32,
    pad_a: u32,
    pad_b: u32,
}

/// The raster of texel indices and the kernels that turn it into a batch.
#[derive(Debug)]
pub(crate) struct CameraGpu {
    camera: ViewCamera,
    params: CameraParams,
    params_buf: wgpu::Buffer,
    /// Near and far planes from the scene's bounds.
    depth_range: (f32, f32),
    raster: wgpu::RenderPipeline,
    raster_group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    vertex_count: u32,
    target: wgpu::TextureView,
    depth: wgpu::TextureView,
    pipelines: [wgpu::ComputePipeline; 2],
    groups: [wgpu::BindGroup; 2],
}

impl CameraGpu {
    pub(crate) fn new(
        d: &wgpu::Device,
        targets: &Targets,
        c: &CameraSampling,
        bvh: &Bvh,
        flags: &wgpu::Buffer,
        samples: &wgpu::Buffer,
    ) -> Result<CameraGpu, String> {
        let cam = c.camera;
        shaders::export::validate(CAMERA_WGSL).map_err(|e| format!("camera sampling kernel: {e}"))?;
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("camera"),
            source: wgpu::ShaderSource::Wgsl(CAMERA_WGSL.into()),
        });
        let verts = raster_vertices(targets, bvh);
        let vertices = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("camera vertices"),
            contents: bytemuck::cast_slice(&verts),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let (lo, hi) = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
        let far = 2.0 * ((hi - lo).length() + (cam.eye - 0.5 * (lo + hi)).length()).max(1e-3);
        let depth_range = (far * 1e-5, far);
        let params = CameraParams {
            view_proj: cam.view_proj([0.0; 2], depth_range.0, depth_range.1).to_cols_array_2d(),
            atlas_width: targets.width as u32,
            atlas_height: targets.height as u32,
            image_width: cam.width,
            image_height: cam.height,
            items: targets.items.len() as u32,
            max_per_batch: c.max_per_batch,
            pad_a: 0,
            pad_b: 0,
        };
        let params_buf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("camera params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let size = wgpu::Extent3d { width: cam.width, height: cam.height, depth_or_array_layers: 1 };
        let texture = |label: &str, format: wgpu::TextureFormat, usage: wgpu::TextureUsages| {
            d.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
            .create_view(&Default::default())
        };
        let target = texture(
            "camera texels",
            wgpu::TextureFormat::R32Uint,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let depth = texture("camera depth", wgpu::TextureFormat::Depth32Float, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let raster = raster_pipeline(d, &module);
        let raster_group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("camera raster"),
            layout: &raster.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: params_buf.as_entire_binding() }],
        });
        let mut texel_item = vec![u32::MAX; (targets.width * targets.height).max(1)];
        for (k, it) in targets.items.iter().enumerate() {
            texel_item[it[2] as usize] = k as u32;
        }
        let storage = |label: &str, bytes: &[u8]| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let texel_item = storage("camera texel items", bytemuck::cast_slice(&texel_item));
        let counts = storage("camera pixel counts", &vec![0u8; 4 * targets.items.len().max(1)]);
        let pipelines = ["count_pixels", "camera_flags"].map(|e| compute_pipeline(d, &module, e));
        let group = |k: usize, entries: &[wgpu::BindGroupEntry]| {
            d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("camera"),
                layout: &pipelines[k].get_bind_group_layout(0),
                entries,
            })
        };
        let groups = [
            group(
                0,
                &[
                    wgpu::BindGroupEntry { binding: 0, resource: params_buf.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&target) },
                    wgpu::BindGroupEntry { binding: 2, resource: texel_item.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 3, resource: counts.as_entire_binding() },
                ],
            ),
            group(
                1,
                &[
                    wgpu::BindGroupEntry { binding: 0, resource: params_buf.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 3, resource: counts.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 4, resource: samples.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 5, resource: flags.as_entire_binding() },
                ],
            ),
        ];
        Ok(CameraGpu {
            camera: cam,
            params,
            params_buf,
            depth_range,
            raster,
            raster_group,
            vertices,
            vertex_count: verts.len() as u32,
            target,
            depth,
            pipelines,
            groups,
        })
    }

    /// Records batch `batch`: the jittered raster, the pixel counts, the batch's samples.
    pub(crate) fn record(&self, q: &wgpu::Queue, enc: &mut wgpu::CommandEncoder, batch: u64) {
        let mut params = self.params;
        params.view_proj =
            self.camera.view_proj(crate::accumulate::camera::jitter(batch), self.depth_range.0, self.depth_range.1).to_cols_array_2d();
        q.write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&params));
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("camera raster"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &self.target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r: u32::MAX as f64, g: 0.0, b: 0.0, a: 0.0 }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.raster);
            pass.set_bind_group(0, &self.raster_group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.draw(0..self.vertex_count, 0..1);
        }
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("camera count"), timestamp_writes: None });
        pass.set_pipeline(&self.pipelines[0]);
        pass.set_bind_group(0, &self.groups[0], &[]);
        pass.dispatch_workgroups(self.camera.width.div_ceil(8), self.camera.height.div_ceil(8), 1);
        let groups = (self.params.items as usize).div_ceil(64).max(1) as u32;
        pass.set_pipeline(&self.pipelines[1]);
        pass.set_bind_group(0, &self.groups[1], &[]);
        pass.dispatch_workgroups(groups.min(65535), groups.div_ceil(65535), 1);
    }
}

/// The scene's triangles with their atlas UVs (−1: not lightmapped), unindexed: the
/// raster's vertex buffer (position, atlas UV).
fn raster_vertices(targets: &Targets, bvh: &Bvh) -> Vec<[f32; 5]> {
    let mut verts: Vec<[f32; 5]> = Vec::with_capacity(3 * bvh.tris.len());
    for t in &bvh.tris {
        let uv = targets.triangle_uv.get(t.mesh as usize).and_then(|m| m.get(t.prim as usize)).copied();
        for (k, p) in [t.v0(), t.v0() + t.e1(), t.v0() + t.e2()].iter().enumerate() {
            let w = uv.map_or([-1.0, -1.0], |uv| [uv[k].x, uv[k].y]);
            verts.push([p.x, p.y, p.z, w[0], w[1]]);
        }
    }
    verts
}

/// The texel-index raster: depth-tested triangles writing their texel (R32Uint).
fn raster_pipeline(d: &wgpu::Device, module: &wgpu::ShaderModule) -> wgpu::RenderPipeline {
    d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("camera raster"),
        layout: None,
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("raster_vs"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: 20,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x2],
            })],
        },
        primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("raster_fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: wgpu::TextureFormat::R32Uint,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
