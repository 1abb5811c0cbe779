//! Reusable GPU primitives, each with a CPU twin that its tests compare against:
//!
//! | primitive | WGSL | CPU twin |
//! |---|---|---|
//! | exclusive prefix sum of u32 (wrapping), any length | `scan.wgsl` | [`exclusive_scan_cpu`] |
//! | stream compaction by 0/1 flags (order kept) | `compact.wgsl` (+ the scan) | [`compact_cpu`] |
//! | stable LSD radix sort of (key, value) u32 pairs by the low `bits` key bits, 4 per pass | `sort.wgsl` (+ the scan) | [`sort::sort_pairs_cpu`] |
//! | offset buffer of paths sorted by texel ([Roughton19 Listing 3.1]: sentinel fill + one pass) | `offsets.wgsl` | [`sort::texel_ranges_cpu`], read by [`sort::texel_range`] |
//! | tile-format index of a texel and its inverse ([Roughton19 eq. 5.2]/5.3) | `tile.wgsl` ([`TILE_WGSL`]) | [`crate::layout::tiles::tile_index`], [`crate::layout::tiles::tile_coords`] |
//!
//! The scan is the classic multi-level one: each 256-element block is scanned in
//! workgroup memory and writes its total; the totals are scanned the same way (recursively,
//! one level per factor of 256), then added back level by level. The block scan (shared by
//! the prefix sum and the radix sort's stable ranks) has two variants in one module,
//! `block_scan.wgsl`, chosen by the shader def SUBGROUPS: subgroup (`subgroupInclusiveAdd`
//! per subgroup plus the earlier subgroups' totals) where the device has
//! `Features::SUBGROUP`, and workgroup memory (Hillis–Steele) elsewhere;
//! [`Prims::with_subgroups`] picks one explicitly so tests run both. The entry shaders
//! (`scan`, `compact`, `offsets`, `sort`) import it and `grid_params.wgsl` through the
//! composer ([`crate::gpu::compose`]).
//! Dispatches are 2D (≤ 65 535 workgroups per row).
//!
//! [`Prims`] compiles the scan and the compaction (the wavefront pipeline and adaptive
//! batches use them); [`sort::SortPrims`] the radix sort and the offset buffer, which no
//! bake uses (ray sorting measured slower on every scene; the filtered accumulation
//! gathers by atlas neighbourhood), only where a caller asks for them.

pub mod sort;

use wgpu::util::DeviceExt;

/// Elements per workgroup block (the WGSL `BLOCK`).
pub const BLOCK: usize = 256;
/// Workgroups per dispatch row.
const ROW: usize = 65_535;

/// The CPU twin of the scan: `out[i] = Σ_{k<i} v[k]` (wrapping), and the total.
pub fn exclusive_scan_cpu(v: &[u32]) -> (Vec<u32>, u32) {
    let mut acc = 0u32;
    let out = v
        .iter()
        .map(|x| {
            let o = acc;
            acc = acc.wrapping_add(*x);
            o
        })
        .collect();
    (out, acc)
}

/// The CPU twin of compaction: the items whose flag is 1, in order. Panics on a flag
/// other than 0 or 1 (the GPU version's contract).
pub fn compact_cpu(items: &[u32], flags: &[u32]) -> Vec<u32> {
    assert_eq!(items.len(), flags.len(), "one flag per item");
    items
        .iter()
        .zip(flags)
        .filter(|(_, f)| {
            assert!(**f <= 1, "flags are 0 or 1");
            **f == 1
        })
        .map(|(i, _)| *i)
        .collect()
}

/// The WGSL of the tile-format index functions (`tile_index`, `tile_coords`).
pub const TILE_WGSL: &str = include_str!("tile.wgsl");

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    n: u32,
    row: u32,
    _pad: [u32; 2],
}

pub(crate) fn grid(blocks: usize) -> (u32, u32) {
    let blocks = blocks.max(1);
    (blocks.min(ROW) as u32, blocks.div_ceil(ROW) as u32)
}

pub(crate) fn storage_layout_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub(crate) fn uniform_layout_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

pub(crate) fn pipeline(
    d: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    let pl = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(entry),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: Some(&pl),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// A bind group of `buffers` at bindings 0, 1, … and a uniform buffer holding `params` at the
/// next binding (the layout of every kernel here).
pub(crate) fn bind(
    d: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    label: &str,
    buffers: &[&wgpu::Buffer],
    params: &[u8],
) -> wgpu::BindGroup {
    let ub = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: params,
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let mut entries: Vec<wgpu::BindGroupEntry> =
        buffers.iter().enumerate().map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() }).collect();
    entries.push(wgpu::BindGroupEntry { binding: buffers.len() as u32, resource: ub.as_entire_binding() });
    d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(label), layout, entries: &entries })
}

/// One compute pass with one dispatch of `pipeline` over the 2D workgroup grid `(x, y)`.
pub(crate) fn dispatch(
    enc: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    group: &wgpu::BindGroup,
    (x, y): (u32, u32),
) {
    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: None });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(x, y, 1);
}

/// The compiled scan and compaction kernels of one device (what the wavefront and
/// adaptive bakes use; the sort and the offset buffer are [`sort::SortPrims`], compiled
/// only where asked for).
#[derive(Debug)]
pub struct Prims {
    /// The block scans (prefix sum, radix sort) use subgroup operations.
    pub subgroups: bool,
    scan_layout: wgpu::BindGroupLayout,
    scan_blocks: wgpu::ComputePipeline,
    add_offsets: wgpu::ComputePipeline,
    compact_layout: wgpu::BindGroupLayout,
    scatter: wgpu::ComputePipeline,
}

/// Composes a primitive's entry shader (`file`, `source`) with the block scan's variant:
/// subgroup operations or workgroup memory.
fn shader(file: &str, source: &str, subgroups: bool) -> Result<String, String> {
    use crate::gpu::compose::{add_module, compose, composer, Defs};
    let mut c = composer();
    add_module(&mut c, "grid_params.wgsl", include_str!("grid_params.wgsl"), None)?;
    add_module(&mut c, "block_scan.wgsl", include_str!("block_scan.wgsl"), None)?;
    let mut defs = Defs::new();
    if subgroups {
        defs.insert("SUBGROUPS".into(), naga_oil::compose::ShaderDefValue::Bool(true));
    }
    compose(&mut c, (file, source), &defs)
}

/// The WGSL of the prefix sum and the radix sort, for validation: (workgroup variant,
/// subgroup variant) of each.
pub fn block_scan_sources() -> Result<[(String, String); 2], String> {
    let both =
        |file: &str, source: &str| -> Result<(String, String), String> { Ok((shader(file, source, false)?, shader(file, source, true)?)) };
    Ok([both("scan.wgsl", include_str!("scan.wgsl"))?, both("sort.wgsl", include_str!("sort.wgsl"))?])
}

/// A primitive's composed WGSL: the sources are this crate's and their composition is
/// tested (`primitive_shaders_compose_in_both_variants` in `tests/gpu_prims.rs`), so a failure is a build defect.
pub(crate) fn composed(file: &str, source: &str, subgroups: bool) -> String {
    shader(file, source, subgroups).unwrap_or_else(|e| panic!("the GPU primitives' WGSL does not compose: {e}"))
}

impl Prims {
    /// The kernels for `d`, with the subgroup block scan where the device has subgroups.
    pub fn new(d: &wgpu::Device) -> Prims {
        Prims::with_subgroups(d, d.features().contains(wgpu::Features::SUBGROUP))
    }

    /// The kernels with the subgroup (`true`, the device must have `Features::SUBGROUP`) or
    /// the workgroup-memory block scan — tests run both where they can.
    pub fn with_subgroups(d: &wgpu::Device, subgroups: bool) -> Prims {
        let scan = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scan.wgsl"),
            source: wgpu::ShaderSource::Wgsl(composed("scan.wgsl", include_str!("scan.wgsl"), subgroups).into()),
        });
        let compact = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("compact.wgsl"),
            source: wgpu::ShaderSource::Wgsl(composed("compact.wgsl", include_str!("compact.wgsl"), subgroups).into()),
        });
        let scan_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scan"),
            entries: &[storage_layout_entry(0, false), storage_layout_entry(1, false), uniform_layout_entry(2)],
        });
        let compact_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("compact"),
            entries: &[
                storage_layout_entry(0, true),
                storage_layout_entry(1, true),
                storage_layout_entry(2, true),
                storage_layout_entry(3, false),
                uniform_layout_entry(4),
            ],
        });
        Prims {
            subgroups,
            scan_blocks: pipeline(d, &scan_layout, &scan, "scan_blocks"),
            add_offsets: pipeline(d, &scan_layout, &scan, "add_offsets"),
            scatter: pipeline(d, &compact_layout, &compact, "scatter"),
            scan_layout,
            compact_layout,
        }
    }

    /// Records an in-place exclusive scan of the first `n` u32 of `data` (a storage buffer)
    /// into `enc`; returns the one-element buffer that will hold the total. Allocates the
    /// per-level block-total buffers it needs ([`Prims::scan_plan`] keeps them for reuse).
    pub fn encode_scan(&self, d: &wgpu::Device, enc: &mut wgpu::CommandEncoder, data: &wgpu::Buffer, n: usize) -> wgpu::Buffer {
        let plan = self.scan_plan(d, data, n);
        self.record_scan(enc, &plan);
        plan.sums.into_iter().last().expect("at least one level")
    }

    /// The buffers and bind groups of a scan of the first `n` u32 of `data`, for recording
    /// it any number of times without allocating ([`Prims::record_scan`]).
    pub fn scan_plan(&self, d: &wgpu::Device, data: &wgpu::Buffer, n: usize) -> ScanPlan {
        // Level sizes: n, ⌈n/256⌉, … down to 1 (the total).
        let mut sizes = vec![n];
        while *sizes.last().expect("non-empty") > 1 || sizes.len() == 1 {
            let next = sizes.last().expect("non-empty").div_ceil(BLOCK).max(1);
            sizes.push(next);
            if next == 1 {
                break;
            }
        }
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let sums: Vec<wgpu::Buffer> = sizes[1..]
            .iter()
            .map(|s| {
                d.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("scan totals"),
                    size: (4 * s.max(&1)) as u64,
                    usage,
                    mapped_at_creation: false,
                })
            })
            .collect();
        let level_data = |k: usize| if k == 0 { data } else { &sums[k - 1] };
        let bind_level = |k: usize| {
            let p = Params { n: sizes[k] as u32, row: grid(sizes[k + 1]).0, _pad: [0; 2] };
            bind(d, &self.scan_layout, "scan level", &[level_data(k), &sums[k]], bytemuck::bytes_of(&p))
        };
        let groups: Vec<wgpu::BindGroup> = (0..sizes.len() - 1).map(bind_level).collect();
        ScanPlan { sizes, sums, groups }
    }

    /// Records a planned scan into `enc`; the plan's [`ScanPlan::total`] then holds the sum.
    pub fn record_scan(&self, enc: &mut wgpu::CommandEncoder, plan: &ScanPlan) {
        let (sizes, groups) = (&plan.sizes, &plan.groups);
        // A zero total for n = 0 (no block writes it).
        enc.clear_buffer(&plan.sums[0], 0, None);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("scan"), timestamp_writes: None });
        for (k, g) in groups.iter().enumerate() {
            let (x, y) = grid(sizes[k + 1]);
            pass.set_pipeline(&self.scan_blocks);
            pass.set_bind_group(0, g, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        // Top level down: each level's blocks get their scanned totals added.
        for k in (0..groups.len().saturating_sub(1)).rev() {
            let (x, y) = grid(sizes[k + 1]);
            pass.set_pipeline(&self.add_offsets);
            pass.set_bind_group(0, &groups[k], &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
    }

    /// Records the compaction of the first `n` items by their 0/1 flags into `out` (at least
    /// `n` u32): `offsets` receives the flags' exclusive scan; returns the buffer holding the
    /// number kept.
    #[allow(clippy::too_many_arguments)]
    pub fn encode_compact(
        &self,
        d: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        items: &wgpu::Buffer,
        flags: &wgpu::Buffer,
        offsets: &wgpu::Buffer,
        out: &wgpu::Buffer,
        n: usize,
    ) -> wgpu::Buffer {
        let plan = self.compact_plan(d, items, flags, offsets, out, n);
        self.record_compact(enc, &plan);
        plan.scan.sums.into_iter().last().expect("at least one level")
    }

    /// A compaction's buffers and bind groups (see [`Prims::encode_compact`]) for
    /// recording it repeatedly ([`Prims::record_compact`]).
    pub fn compact_plan(
        &self,
        d: &wgpu::Device,
        items: &wgpu::Buffer,
        flags: &wgpu::Buffer,
        offsets: &wgpu::Buffer,
        out: &wgpu::Buffer,
        n: usize,
    ) -> CompactPlan {
        let (x, y) = grid(n.div_ceil(BLOCK));
        let p = Params { n: n as u32, row: x, _pad: [0; 2] };
        let group = bind(d, &self.compact_layout, "compact", &[items, flags, offsets, out], bytemuck::bytes_of(&p));
        CompactPlan { scan: self.scan_plan(d, offsets, n), group, flags: flags.clone(), offsets: offsets.clone(), n, grid: (x, y) }
    }

    /// Records a planned compaction; [`CompactPlan::total`] then holds the number kept.
    pub fn record_compact(&self, enc: &mut wgpu::CommandEncoder, plan: &CompactPlan) {
        if plan.n > 0 {
            enc.copy_buffer_to_buffer(&plan.flags, 0, &plan.offsets, 0, (4 * plan.n) as u64);
        }
        self.record_scan(enc, &plan.scan);
        dispatch(enc, "compact", &self.scatter, &plan.group, plan.grid);
    }
}

/// A scan's level buffers and bind groups ([`Prims::scan_plan`]).
#[derive(Debug)]
pub struct ScanPlan {
    sizes: Vec<usize>,
    sums: Vec<wgpu::Buffer>,
    groups: Vec<wgpu::BindGroup>,
}

impl ScanPlan {
    /// The one-element buffer that holds the total after the scan ran.
    pub fn total(&self) -> &wgpu::Buffer {
        self.sums.last().expect("at least one level")
    }
}

/// A compaction's scan plan and scatter bind group ([`Prims::compact_plan`]).
#[derive(Debug)]
pub struct CompactPlan {
    scan: ScanPlan,
    group: wgpu::BindGroup,
    flags: wgpu::Buffer,
    offsets: wgpu::Buffer,
    n: usize,
    grid: (u32, u32),
}

impl CompactPlan {
    /// The one-element buffer that holds the number kept after the compaction ran.
    pub fn total(&self) -> &wgpu::Buffer {
        self.scan.total()
    }
}

/// Host convenience for tests and small inputs: uploads `v`, scans it on the GPU, reads
/// the result and the total back.
pub fn exclusive_scan(d: &wgpu::Device, q: &wgpu::Queue, prims: &Prims, v: &[u32]) -> (Vec<u32>, u32) {
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let data = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("scan data"),
        contents: bytemuck::cast_slice(&padded(v)),
        usage,
    });
    let mut enc = d.create_command_encoder(&Default::default());
    let total = prims.encode_scan(d, &mut enc, &data, v.len());
    q.submit([enc.finish()]);
    (read_u32(d, q, &data, v.len()), read_u32(d, q, &total, 1)[0])
}

/// Host convenience: compacts `items` by `flags` (0/1) on the GPU.
pub fn compact(d: &wgpu::Device, q: &wgpu::Queue, prims: &Prims, items: &[u32], flags: &[u32]) -> Vec<u32> {
    assert_eq!(items.len(), flags.len(), "one flag per item");
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let buf = |v: &[u32], label| {
        d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytemuck::cast_slice(&padded(v)), usage })
    };
    let (ib, fb, ob, out) =
        (buf(items, "items"), buf(flags, "flags"), buf(&vec![0; items.len()], "offsets"), buf(&vec![0; items.len()], "compacted"));
    let mut enc = d.create_command_encoder(&Default::default());
    let total = prims.encode_compact(d, &mut enc, &ib, &fb, &ob, &out, items.len());
    q.submit([enc.finish()]);
    let kept = read_u32(d, q, &total, 1)[0] as usize;
    read_u32(d, q, &out, kept)
}

/// At least one element (wgpu buffers cannot be empty).
fn padded(v: &[u32]) -> Vec<u32> {
    if v.is_empty() {
        vec![0]
    } else {
        v.to_vec()
    }
}

fn read_u32(d: &wgpu::Device, q: &wgpu::Queue, src: &wgpu::Buffer, n: usize) -> Vec<u32> {
    if n == 0 {
        return Vec::new();
    }
    let staging = d.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: (4 * n) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = d.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(src, 0, &staging, 0, (4 * n) as u64);
    q.submit([enc.finish()]);
    let slice = staging.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    d.poll(wgpu::PollType::wait_indefinitely()).expect("device poll");
    let bytes = slice.get_mapped_range().expect("mapped read-back").to_vec();
    bytemuck::pod_collect_to_vec::<u8, u32>(&bytes)
}
