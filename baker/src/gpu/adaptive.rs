//! Adaptive sampling on the GPU (CPU twin [`crate::accumulate::adaptive`], WGSL `wgsl/adapt.wgsl`): per
//! batch, recorded into one command encoder before the bake's dispatch — the tiles' mean
//! σ (a workgroup per 8×8 tile), their sum (the distribution's normaliser), each texel's
//! samples in the batch (from its own Sobol' stream), the compaction of the texels with
//! samples into the batch's item list (prefix sum + scatter, [`crate::gpu::prims`]) and the indirect dispatch
//! arguments from its length. The bake kernel then runs the batch by
//! `dispatch_workgroups_indirect`, each thread taking one listed texel through its samples
//! from its own sample index (`wgsl/adapt_batch.wgsl`). Nothing is read back between batches, and nothing is
//! allocated per batch: the batch index lives on the GPU (advanced by each batch), so a
//! run of batches is recorded into one submission.
//!
//! A batch is one dispatch (about f·N texels): the frame-time load balancing of uniform
//! passes does not split it.

use crate::accumulate::adaptive::{AdaptiveOptions, Tiles};
use crate::accumulate::camera::CameraSampling;
use crate::accumulate::Targets;
use crate::gpu::prims::Prims;
use crate::scene::bvh::Bvh;
use crate::scene::camera::ViewCamera;
use sbf::glam::Vec3;
use wgpu::util::DeviceExt;

const ADAPT_WGSL: &str = include_str!("wgsl/adapt.wgsl");
const CAMERA_WGSL: &str = include_str!("wgsl/camera.wgsl");

/// WGSL `AdaptParams`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct AdaptParams {
    seed: u32,
    sampler: u32,
    items: u32,
    tiles: u32,
    pad0: u32,
    fraction: f32,
    floor: f32,
    max_per_batch: f32,
}

/// Which texels a batch takes.
#[derive(Debug, Clone, Copy)]
pub enum BatchSource<'a> {
    /// By their tile's noise ([`crate::accumulate::adaptive`]).
    Variance(AdaptiveOptions),
    /// The texels a camera sees ([`crate::accumulate::camera`]).
    Camera(&'a CameraSampling, &'a Bvh),
}

/// The selection kernels, their buffers and bind groups.
#[derive(Debug)]
pub struct AdaptGpu {
    /// Uniform passes before the first batch.
    pub pilot_passes: u64,
    selector: Selector,
    /// `batch_args` (indirect arguments from the batch's length; advances the batch index).
    args_pipeline: wgpu::ComputePipeline,
    args_group: wgpu::BindGroup,
    /// The next batch's index (advanced on the GPU by each batch's `batch_args`).
    batch_index: wgpu::Buffer,
    compact: crate::gpu::prims::CompactPlan,
    /// The batch's items (read by the bake kernel, binding 11).
    pub selected: wgpu::Buffer,
    /// The batch's length (binding 12).
    pub count: wgpu::Buffer,
    /// Per item, its samples in the batch (binding 13).
    pub samples: wgpu::Buffer,
    /// Indirect dispatch arguments of the bake kernel.
    pub args: wgpu::Buffer,
    prims: Prims,
}

#[derive(Debug)]
enum Selector {
    /// tile_sigma, sum_tiles, select_items with their bind groups.
    Variance {
        pipelines: [wgpu::ComputePipeline; 3],
        groups: [wgpu::BindGroup; 3],
        items: usize,
        tiles: usize,
    },
    Camera(Box<CameraGpu>),
}

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
    pad0: u32,
    pad1: u32,
}

/// The raster of texel indices and the kernels that turn it into a batch.
#[derive(Debug)]
struct CameraGpu {
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

impl AdaptGpu {
    /// Builds the selection for `targets` (lightmap texels) reading the bake's `moments`.
    pub fn new(
        d: &wgpu::Device,
        targets: &Targets,
        source: BatchSource,
        config: &crate::accumulate::BakeConfig,
        moments: &wgpu::Buffer,
    ) -> Result<AdaptGpu, String> {
        let tiles = Tiles::new(targets, targets.width)?;
        let items = targets.items.len();
        let options = match source {
            BatchSource::Variance(o) => o,
            BatchSource::Camera(..) => AdaptiveOptions::default(),
        };
        let params = AdaptParams {
            seed: crate::sampling::sequence::gpu_seed(config.seed),
            sampler: config.sampler.code(),
            items: items as u32,
            tiles: tiles.count() as u32,
            pad0: 0,
            fraction: options.batch_fraction as f32,
            floor: options.floor as f32,
            max_per_batch: options.max_per_batch as f32,
        };
        let wgsl = format!("{ADAPT_WGSL}\n{}", crate::gpu::SAMPLER_WGSL);
        shaders::export::validate(&wgsl).map_err(|e| format!("adaptive sampling kernel: {e}"))?;
        let module =
            d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("adapt"), source: wgpu::ShaderSource::Wgsl(wgsl.into()) });
        let pipelines = ["tile_sigma", "sum_tiles", "select_items", "batch_args"].map(|e| compute_pipeline(d, &module, e));
        let buf = |label: &str, bytes: &[u8], usage: wgpu::BufferUsages| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE | usage,
            })
        };
        let none = wgpu::BufferUsages::empty();
        let copy = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let params_buf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("adapt params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let tile_items = buf("tile items", bytemuck::cast_slice(&tiles.order), none);
        let tile_start = buf("tile start", bytemuck::cast_slice(&tiles.start), none);
        let tile_mean = buf("tile mean", &vec![0u8; 4 * tiles.count().max(1)], none);
        let tile_sum = buf("tile sum", &vec![0u8; 4 * tiles.count().max(1)], none);
        let total = buf("tile total", &[0u8; 4], none);
        let info: Vec<[u32; 2]> = targets
            .items
            .iter()
            .zip(&tiles.tile_of)
            .map(|(&[_, _, id], t)| [*t, crate::accumulate::adaptive::join_seed(config.seed, id)])
            .collect();
        let item_info = buf("item info", bytemuck::cast_slice(&info), none);
        let iota: Vec<u32> = (0..items as u32).collect();
        let iota = buf("item indices", bytemuck::cast_slice(&iota), none);
        let flags = buf("join flags", &vec![0u8; 4 * items], copy);
        let offsets = buf("join offsets", &vec![0u8; 4 * items], copy);
        let selected = buf("batch items", &vec![0u8; 4 * items], copy);
        let count = buf("batch count", &[0u8; 4], copy);
        let args = buf("batch args", bytemuck::cast_slice(&[1u32, 1, 1]), wgpu::BufferUsages::INDIRECT);
        let batch_index = buf("batch index", &[0u8; 4], copy);
        let samples = buf("batch samples", &vec![0u8; 4 * items], copy);
        let entries = |k: usize, list: &[(u32, &wgpu::Buffer)]| {
            let entries: Vec<wgpu::BindGroupEntry> =
                list.iter().map(|(b, buffer)| wgpu::BindGroupEntry { binding: *b, resource: buffer.as_entire_binding() }).collect();
            d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("adapt"),
                layout: &pipelines[k].get_bind_group_layout(0),
                entries: &entries,
            })
        };
        let args_group = entries(3, &[(9, &count), (10, &args), (11, &batch_index)]);
        let variance_groups = matches!(source, BatchSource::Variance(_)).then(|| {
            [
                entries(0, &[(0, &params_buf), (1, moments), (2, &tile_items), (3, &tile_start), (4, &tile_mean), (5, &tile_sum)]),
                entries(1, &[(0, &params_buf), (5, &tile_sum), (6, &total)]),
                entries(
                    2,
                    &[(0, &params_buf), (4, &tile_mean), (6, &total), (7, &item_info), (8, &flags), (11, &batch_index), (12, &samples)],
                ),
            ]
        });
        let [tile_sigma, sum_tiles, select_items, args_pipeline] = pipelines;
        let (selector, pilot_passes) = match (source, variance_groups) {
            (BatchSource::Variance(o), Some(groups)) => (
                Selector::Variance { pipelines: [tile_sigma, sum_tiles, select_items], groups, items, tiles: tiles.count() },
                o.pilot_passes,
            ),
            (BatchSource::Camera(c, bvh), _) => {
                (Selector::Camera(Box::new(CameraGpu::new(d, targets, c, bvh, &flags, &samples)?)), c.pilot_passes)
            }
            (BatchSource::Variance(_), None) => unreachable!("variance groups are built for a variance source"),
        };
        let prims = Prims::new(d);
        let compact = prims.compact_plan(d, &iota, &flags, &offsets, &selected, items);
        Ok(AdaptGpu { pilot_passes, selector, args_pipeline, args_group, batch_index, compact, selected, count, samples, args, prims })
    }

    /// Batches one submission may hold: camera batches write their jitter from the CPU,
    /// one per submission; variance batches keep everything on the GPU.
    pub fn per_submission(&self) -> u64 {
        match self.selector {
            Selector::Variance { .. } => 16,
            Selector::Camera(_) => 1,
        }
    }

    /// Sets the index of the next batch recorded (before a submission of batches).
    pub fn set_batch(&self, q: &wgpu::Queue, batch: u64) {
        q.write_buffer(&self.batch_index, 0, &(batch as u32).to_le_bytes());
    }

    /// Records the next batch's selection into `enc` (`batch`: its index, for the camera's
    /// jitter): after it, `selected`, `count`, `samples` and `args` describe the batch,
    /// and the batch index has advanced.
    pub fn record_select(&self, q: &wgpu::Queue, enc: &mut wgpu::CommandEncoder, batch: u64) {
        let grid = |n: usize| {
            let n = n.max(1) as u32;
            if n <= 65535 {
                (n, 1)
            } else {
                (65535, n.div_ceil(65535))
            }
        };
        match &self.selector {
            Selector::Variance { pipelines, groups, items, tiles } => {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("adapt select"), timestamp_writes: None });
                let dispatches = [grid(*tiles), (1, 1), grid(items.div_ceil(64))];
                for (k, (x, y)) in dispatches.into_iter().enumerate() {
                    pass.set_pipeline(&pipelines[k]);
                    pass.set_bind_group(0, &groups[k], &[]);
                    pass.dispatch_workgroups(x, y, 1);
                }
            }
            Selector::Camera(c) => c.record(q, enc, batch),
        }
        self.prims.record_compact(enc, &self.compact);
        enc.copy_buffer_to_buffer(self.compact.total(), 0, &self.count, 0, 4);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("adapt args"), timestamp_writes: None });
        pass.set_pipeline(&self.args_pipeline);
        pass.set_bind_group(0, &self.args_group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
}

impl CameraGpu {
    #[allow(clippy::too_many_lines)] // To split: over the 120-line limit the crate holds (lib.rs).
    fn new(
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
        // Triangles with their atlas UVs (−1: not lightmapped), unindexed.
        let mut verts: Vec<[f32; 5]> = Vec::with_capacity(3 * bvh.tris.len());
        for t in &bvh.tris {
            let uv = targets.triangle_uv.get(t.mesh as usize).and_then(|m| m.get(t.prim as usize)).copied();
            for (k, p) in [t.v0(), t.v0() + t.e1(), t.v0() + t.e2()].iter().enumerate() {
                let w = uv.map_or([-1.0, -1.0], |uv| [uv[k].x, uv[k].y]);
                verts.push([p.x, p.y, p.z, w[0], w[1]]);
            }
        }
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
            pad0: 0,
            pad1: 0,
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
        let raster = d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("camera raster"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
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
                module: &module,
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
        });
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
    fn record(&self, q: &wgpu::Queue, enc: &mut wgpu::CommandEncoder, batch: u64) {
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

/// A compute pipeline of `module`'s `entry` with the layout its bindings imply.
pub(crate) fn compute_pipeline(d: &wgpu::Device, module: &wgpu::ShaderModule, entry: &str) -> wgpu::ComputePipeline {
    d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}
