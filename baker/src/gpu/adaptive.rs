//! Adaptive sampling on the GPU (CPU twin [`crate::accumulate::adaptive`], WGSL `wgsl/adapt.wgsl`): per
//! batch, recorded into one command encoder before the bake's dispatch — the tiles' mean
//! σ (a workgroup per 8×8 tile), their sum (the distribution's normaliser), each texel's
//! samples in the batch (from its own Sobol' stream), the compaction of the texels with
//! samples into the batch's item list (prefix sum + scatter, [`crate::gpu::prims`]) and the indirect dispatch
//! arguments from its length. The bake kernel then runs the batch by
//! `dispatch_workgroups_indirect`, each thread taking one listed texel through its samples
//! from its own sample index (`wgsl/jobs.wgsl` with the shader def BATCH). Nothing is read back between batches, and nothing is
//! allocated per batch: the batch index lives on the GPU (advanced by each batch), so a
//! run of batches is recorded into one submission.
//!
//! A batch is one dispatch (about f·N texels): the frame-time load balancing of uniform
//! passes does not split it.

use super::camera::CameraGpu;
use crate::accumulate::adaptive::{AdaptiveOptions, Tiles};
use crate::accumulate::camera::CameraSampling;
use crate::accumulate::Targets;
use crate::gpu::prims::Prims;
use crate::scene::bvh::Bvh;
use wgpu::util::DeviceExt;

/// WGSL `AdaptParams`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct AdaptParams {
    seed: u32,
    sampler: u32,
    items: u32,
    tiles: u32,
    pad_a: u32,
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
            pad_a: 0,
            fraction: options.batch_fraction as f32,
            floor: options.floor as f32,
            max_per_batch: options.max_per_batch as f32,
        };
        let wgsl = super::kernel::adapt_kernel(config.sampler).map_err(|e| format!("adaptive sampling kernel: {e}"))?;
        let module =
            d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("adapt"), source: wgpu::ShaderSource::Wgsl(wgsl.into()) });
        let pipelines = ["tile_sigma", "sum_tiles", "select_items", "batch_args"].map(|e| super::compute_pipeline(d, &module, e));
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
