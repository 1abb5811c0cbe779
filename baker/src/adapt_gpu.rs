//! Adaptive sampling on the GPU (CPU twin [`crate::adapt`], WGSL `wgsl/adapt.wgsl`): per
//! batch, recorded into one command encoder before the bake's dispatch — the tiles' mean
//! σ (a workgroup per 8×8 tile), their sum (the distribution's normaliser), each texel's
//! join flag from its own Sobol' stream, the compaction of the flags into the batch's
//! item list (prefix sum + scatter, [`crate::gpu_prims`]) and the indirect dispatch
//! arguments from its length. The bake kernel then runs the batch by
//! `dispatch_workgroups_indirect`, each thread taking one listed texel at its own sample
//! index (`wgsl/adapt_batch.wgsl`). Nothing is read back between batches.
//!
//! A batch is one dispatch (about f·N texels): the frame-time load balancing of uniform
//! passes does not split it.

use crate::adapt::{AdaptiveOptions, Tiles};
use crate::bake::Targets;
use crate::gpu_prims::Prims;
use wgpu::util::DeviceExt;

const ADAPT_WGSL: &str = include_str!("../wgsl/adapt.wgsl");

/// WGSL `AdaptParams`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct AdaptParams {
    seed: u32,
    sampler: u32,
    items: u32,
    tiles: u32,
    batch: u32,
    fraction: f32,
    floor: f32,
    pad: u32,
}

/// The selection kernels, their buffers and bind groups.
#[derive(Debug)]
pub struct AdaptGpu {
    pub options: AdaptiveOptions,
    params: AdaptParams,
    params_buf: wgpu::Buffer,
    pipelines: [wgpu::ComputePipeline; 4],
    groups: [wgpu::BindGroup; 4],
    iota: wgpu::Buffer,
    flags: wgpu::Buffer,
    offsets: wgpu::Buffer,
    /// The batch's items (read by the bake kernel, binding 11).
    pub selected: wgpu::Buffer,
    /// The batch's length (binding 12).
    pub count: wgpu::Buffer,
    /// Indirect dispatch arguments of the bake kernel.
    pub args: wgpu::Buffer,
    prims: Prims,
    items: usize,
    tiles: usize,
}

impl AdaptGpu {
    /// Builds the selection for `targets` (lightmap texels) reading the bake's `moments`.
    pub fn new(
        d: &wgpu::Device,
        targets: &Targets,
        options: AdaptiveOptions,
        config: &crate::bake::BakeConfig,
        moments: &wgpu::Buffer,
    ) -> Result<AdaptGpu, String> {
        let tiles = Tiles::new(targets, targets.width)?;
        let items = targets.items.len();
        let params = AdaptParams {
            seed: crate::sampler::gpu_seed(config.seed),
            sampler: config.sampler.code(),
            items: items as u32,
            tiles: tiles.count() as u32,
            batch: 0,
            fraction: options.batch_fraction as f32,
            floor: options.floor as f32,
            pad: 0,
        };
        let source = format!("{ADAPT_WGSL}\n{}", crate::gpu::SAMPLER_WGSL);
        shaders::export::validate(&source).map_err(|e| format!("adaptive sampling kernel: {e}"))?;
        let module =
            d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("adapt"), source: wgpu::ShaderSource::Wgsl(source.into()) });
        let pipeline = |entry: &str| {
            d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipelines = ["tile_sigma", "sum_tiles", "select_items", "batch_args"].map(pipeline);
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
        let info: Vec<[u32; 2]> =
            targets.items.iter().zip(&tiles.tile_of).map(|(&[_, _, id], t)| [*t, crate::adapt::join_seed(config.seed, id)]).collect();
        let item_info = buf("item info", bytemuck::cast_slice(&info), none);
        let iota: Vec<u32> = (0..items as u32).collect();
        let iota = buf("item indices", bytemuck::cast_slice(&iota), none);
        let flags = buf("join flags", &vec![0u8; 4 * items], copy);
        let offsets = buf("join offsets", &vec![0u8; 4 * items], copy);
        let selected = buf("batch items", &vec![0u8; 4 * items], copy);
        let count = buf("batch count", &[0u8; 4], copy);
        let args = buf("batch args", bytemuck::cast_slice(&[1u32, 1, 1]), wgpu::BufferUsages::INDIRECT);
        let entries = |k: usize, list: &[(u32, &wgpu::Buffer)]| {
            let entries: Vec<wgpu::BindGroupEntry> =
                list.iter().map(|(b, buffer)| wgpu::BindGroupEntry { binding: *b, resource: buffer.as_entire_binding() }).collect();
            d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("adapt"),
                layout: &pipelines[k].get_bind_group_layout(0),
                entries: &entries,
            })
        };
        let groups = [
            entries(0, &[(0, &params_buf), (1, moments), (2, &tile_items), (3, &tile_start), (4, &tile_mean), (5, &tile_sum)]),
            entries(1, &[(0, &params_buf), (5, &tile_sum), (6, &total)]),
            entries(2, &[(0, &params_buf), (4, &tile_mean), (6, &total), (7, &item_info), (8, &flags)]),
            entries(3, &[(9, &count), (10, &args)]),
        ];
        Ok(AdaptGpu {
            options,
            params,
            params_buf,
            pipelines,
            groups,
            iota,
            flags,
            offsets,
            selected,
            count,
            args,
            prims: Prims::new(d),
            items,
            tiles: tiles.count(),
        })
    }

    /// Records batch `batch`'s selection into `enc`: after it, `selected`, `count` and
    /// `args` describe the batch.
    pub fn record_select(&mut self, d: &wgpu::Device, q: &wgpu::Queue, enc: &mut wgpu::CommandEncoder, batch: u64) {
        self.params.batch = batch as u32;
        q.write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&self.params));
        let grid = |n: usize| {
            let n = n.max(1) as u32;
            if n <= 65535 {
                (n, 1)
            } else {
                (65535, n.div_ceil(65535))
            }
        };
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("adapt select"), timestamp_writes: None });
            let dispatches = [grid(self.tiles), (1, 1), grid(self.items.div_ceil(64))];
            for (k, (x, y)) in dispatches.into_iter().enumerate() {
                pass.set_pipeline(&self.pipelines[k]);
                pass.set_bind_group(0, &self.groups[k], &[]);
                pass.dispatch_workgroups(x, y, 1);
            }
        }
        let total = self.prims.encode_compact(d, enc, &self.iota, &self.flags, &self.offsets, &self.selected, self.items);
        enc.copy_buffer_to_buffer(&total, 0, &self.count, 0, 4);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("adapt args"), timestamp_writes: None });
        pass.set_pipeline(&self.pipelines[3]);
        pass.set_bind_group(0, &self.groups[3], &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
}
