//! Filtered gather-based accumulation on the GPU ([Roughton19 §3.2]; `wgsl/filter_gather.wgsl`, `wgsl/filter_bindings.wgsl`): the
//! record buffer the bake kernel writes (one record per item and pass of a dispatch), the
//! gather targets' encoder states and weighted moments, and the gather pass recorded after
//! each dispatch's last range. The CPU twin is [`crate::accumulate::filter::gather_batch`].

use crate::accumulate::filter::{FilteredState, GatherLayout, WeightedMoments};
use crate::accumulate::{BakeConfig, Targets};
use shaders::progressive::EncoderState;
use wgpu::util::DeviceExt;

/// The filters' 1D weight in WGSL (`filter_kernel_1d(kernel, radius, d)`, kernel codes as
/// [`crate::accumulate::filter::GatherFilter`]'s; its CPU twin is `GatherFilter::weight_1d`).
pub const FILTER_KERNEL_WGSL: &str = include_str!("wgsl/filter_kernel.wgsl");

/// `FilterParams` of `wgsl/filter_bindings.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FilterParams {
    pub width: u32,
    pub height: u32,
    pub target_count: u32,
    pub kernel: u32,
    pub radius: f32,
    pub reach: u32,
    pub passes: u32,
    pub charts_offset: u32,
    pub items_offset: u32,
    pub row: u32,
    pub slots: u32,
    pub batch: u32,
    pub items: u32,
    pub pad_a: u32,
    pub pad_b: u32,
    pub pad_c: u32,
}
shaders::gpu_struct!(
    FilterParams,
    "FilterParams",
    [
        width,
        height,
        target_count,
        kernel,
        radius,
        reach,
        passes,
        charts_offset,
        items_offset,
        row,
        slots,
        batch,
        items,
        pad_a,
        pad_b,
        pad_c
    ]
);

/// The GPU side of a filtered bake.
#[derive(Debug)]
pub struct FilterGpu {
    /// Binding 14 of the bake kernel: the records the passes write.
    pub records: wgpu::Buffer,
    states: wgpu::Buffer,
    moments: wgpu::Buffer,
    /// Binding 18 of the bake kernel too (the record slots).
    pub params_buf: wgpu::Buffer,
    params: FilterParams,
    gather: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    /// Passes per dispatch the record buffer holds.
    pub max_passes: u64,
}

/// Bytes of one record: 3 vec4 of header, then a vec4 per lobe of every basis (stored
/// component-major: `wgsl/item.wgsl`'s `filter_record`).
pub fn record_bytes(config: &BakeConfig) -> u64 {
    16 * (3 + config.bases.iter().map(|b| b.lobes()).sum::<usize>()) as u64
}

impl FilterGpu {
    /// The buffers and the gather pass for `targets` under `config` (whose filter is
    /// set) from the composed `filter_gather.wgsl` (`source`), at most `max_passes` passes
    /// per dispatch within the storage-binding limit `limit`; `bake` lists the bake's
    /// buffers by binding (the gather reads the items' moments and, in adaptive or
    /// camera-based bakes, the batch's per-item sample counts).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        d: &wgpu::Device,
        source: &str,
        targets: &Targets,
        config: &BakeConfig,
        max_passes: u64,
        limit: u64,
        bake: &[(u32, &wgpu::Buffer)],
    ) -> Result<FilterGpu, String> {
        let f = config.filter.ok_or("no filter configured")?;
        let layout = GatherLayout::new(targets, &f)?;
        let items = targets.items.len() as u64;
        let per_pass = items * record_bytes(config);
        // A batch's samples of one item are consecutive and at most max_per_batch.
        let per_batch = config.adaptive.map(|a| a.max_per_batch).or(config.camera.map(|c| c.max_per_batch)).unwrap_or(1) as u64;
        let max_passes = max_passes.min(limit / per_pass.max(1));
        let slots = max_passes.max(per_batch);
        if max_passes == 0 || slots * per_pass > limit {
            return Err(format!(
                "filtered records: {} bytes ({slots} per item) exceed the adapter's storage-buffer binding limit of {limit} bytes (fewer bases, texels or samples per batch, or --device cpu)",
                slots.max(1) * per_pass
            ));
        }
        let n = layout.targets.len();
        let states_len = (config.bases.len() * n).max(1) * std::mem::size_of::<EncoderState>();
        crate::gpu::check_bindings(&[("filtered encoder states", states_len as u64), ("filtered moments", (n * 48) as u64)], limit)?;
        let mut tables = layout.targets.clone();
        let charts_offset = tables.len() as u32;
        tables.extend_from_slice(&layout.charts);
        let items_offset = tables.len() as u32;
        tables.extend_from_slice(&layout.item_of);
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let zeroed = |label, bytes: u64| {
            d.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: bytes.max(16), usage, mapped_at_creation: false })
        };
        let records = zeroed("filtered records", per_pass * slots);
        let states = zeroed("filtered states", states_len as u64);
        let moments = zeroed("filtered moments", (n * 48) as u64);
        let tables = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("filter tables"),
            contents: bytemuck::cast_slice(&tables),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let groups = (n as u32).div_ceil(64).max(1);
        let params = FilterParams {
            width: layout.width as u32,
            height: layout.height as u32,
            target_count: n as u32,
            kernel: f.kernel.code(),
            radius: f.radius,
            reach: layout.reach as u32,
            passes: 1,
            charts_offset,
            items_offset,
            row: groups.min(65535),
            slots: slots as u32,
            batch: 0,
            items: items as u32,
            pad_a: 0,
            pad_b: 0,
            pad_c: 0,
        };
        let params_buf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("filter params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let naga = shaders::export::validate(source).map_err(|e| format!("filter_gather.wgsl: {e}"))?;
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("filter_gather.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let gather = super::compute_pipeline(d, &module, "filter_gather");
        let buffer_of = |b: u32| -> Result<&wgpu::Buffer, String> {
            Ok(match b {
                14 => &records,
                15 => &states,
                16 => &moments,
                17 => &tables,
                18 => &params_buf,
                _ => match bake.iter().find(|(k, _)| *k == b) {
                    Some((_, buf)) => buf,
                    None => return Err(format!("filter_gather uses binding {b}, which neither the filter nor the bake provides")),
                },
            })
        };
        let used = crate::gpu::wavefront::bindings_used(&naga.0, &naga.1, "filter_gather")?;
        let entries = used
            .iter()
            .map(|&(_, b)| Ok(wgpu::BindGroupEntry { binding: b, resource: buffer_of(b)?.as_entire_binding() }))
            .collect::<Result<Vec<_>, String>>()?;
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("filter gather"),
            layout: &gather.get_bind_group_layout(0),
            entries: &entries,
        });
        Ok(FilterGpu { records, states, moments, params_buf, params, gather, group, max_passes })
    }

    /// Records the gather of a dispatch's `passes` passes (after its last range), or of
    /// a `batch` of adaptive or camera-based sampling (after its bake pass).
    pub fn record(&mut self, q: &wgpu::Queue, enc: &mut wgpu::CommandEncoder, passes: u32, batch: bool) {
        self.params.passes = passes;
        self.params.batch = batch as u32;
        q.write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&self.params));
        let groups = self.params.target_count.div_ceil(64).max(1);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("filter gather"), timestamp_writes: None });
        pass.set_pipeline(&self.gather);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(self.params.row, groups.div_ceil(self.params.row), 1);
    }

    /// The filtered state as the GPU holds it (moments as f64, encoders exactly).
    pub fn state(&self, gpu: &shaders::gpu::Gpu, config: &BakeConfig) -> Result<FilteredState, String> {
        let n = self.params.target_count as usize;
        let m: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&gpu.read_back(&self.moments)?);
        let mut negative_weights = 0;
        let moments = (0..n)
            .map(|j| {
                let [a, b, c] = [m[3 * j], m[3 * j + 1], m[3 * j + 2]];
                negative_weights += c[1] as u64;
                WeightedMoments {
                    weight: a[3] as f64,
                    weight_sq: b[3] as f64,
                    mean: [a[0] as f64, a[1] as f64, a[2] as f64],
                    m2: [b[0] as f64, b[1] as f64, b[2] as f64],
                    samples: c[0] as u64,
                }
            })
            .collect();
        let raw: Vec<EncoderState> = bytemuck::pod_collect_to_vec(&gpu.read_back(&self.states)?);
        let encoders = crate::gpu::encoders::encoders_from_raw(&raw, n, config, false)?;
        Ok(FilteredState { encoders, moments, negative_weights })
    }

    /// Replaces the GPU's filtered state (resuming a checkpoint).
    pub fn upload(&self, q: &wgpu::Queue, state: &FilteredState) -> Result<(), String> {
        let n = self.params.target_count as usize;
        if state.moments.len() != n {
            return Err(format!("the saved state has {} filtered targets, this bake {n}", state.moments.len()));
        }
        let m: Vec<[f32; 4]> = state
            .moments
            .iter()
            .enumerate()
            .flat_map(|(j, m)| {
                // The negative-weight count is per target on the GPU: the total goes to
                // the first (state() sums them).
                let neg = if j == 0 { state.negative_weights as f32 } else { 0.0 };
                [
                    [m.mean[0] as f32, m.mean[1] as f32, m.mean[2] as f32, m.weight as f32],
                    [m.m2[0] as f32, m.m2[1] as f32, m.m2[2] as f32, m.weight_sq as f32],
                    [m.samples as f32, neg, 0.0, 0.0],
                ]
            })
            .collect();
        q.write_buffer(&self.moments, 0, bytemuck::cast_slice(&m));
        let raw = crate::gpu::encoders::raw_from_encoders(&state.encoders);
        if !raw.is_empty() {
            q.write_buffer(&self.states, 0, bytemuck::cast_slice(&raw));
        }
        Ok(())
    }
}
