//! Reusable GPU primitives for the wavefront pipeline (issue 15 item 2/10), each with a
//! CPU twin that its tests compare against:
//!
//! | primitive | WGSL | CPU twin |
//! |---|---|---|
//! | exclusive prefix sum of u32 (wrapping), any length | `scan.wgsl` | [`exclusive_scan_cpu`] |
//! | stream compaction by 0/1 flags (order kept) | `compact.wgsl` (+ the scan) | [`compact_cpu`] |
//! | stable LSD radix sort of (key, value) u32 pairs by the low `bits` key bits, 4 per pass | `sort.wgsl` (+ the scan) | [`sort_pairs_cpu`] |
//! | offset buffer of paths sorted by texel (seed 004 Listing 3.1: sentinel fill + one pass) | `offsets.wgsl` | [`texel_ranges_cpu`], read by [`texel_range`] |
//! | tile-format index of a texel and its inverse (seed 004 eq. 5.2/5.3) | `tile.wgsl` ([`TILE_WGSL`]) | [`tile_index`], [`tile_coords`] |
//! | filtered gather of sorted paths into texels through the offset buffer (seed 004 §3.2.2, Listing 3.2; box, Gaussian, Mitchell; within a chart) | `gather.wgsl` | [`gather_cpu`] |
//!
//! The scan is the classic multi-level one: each 256-element block is scanned in
//! workgroup memory and writes its total; the totals are scanned the same way (recursively,
//! one level per factor of 256), then added back level by level. The block scan (shared by
//! the prefix sum and the radix sort's stable ranks) has two variants: subgroup
//! (`subgroupInclusiveAdd` per subgroup plus the earlier subgroups' totals,
//! `block_scan_subgroup.wgsl`) where the device has `Features::SUBGROUP`, and
//! workgroup memory (Hillis–Steele, `block_scan.wgsl`) elsewhere; [`Prims::with_subgroups`]
//! picks one explicitly so tests run both.
//! Dispatches are 2D (≤ 65 535 workgroups per row).

use wgpu::util::DeviceExt;

/// Elements per workgroup block (the WGSL `BLOCK`).
pub const BLOCK: usize = 256;
/// Workgroups per dispatch row.
const ROW: usize = 65_535;

/// The CPU twin of the scan: out[i] = Σ_{k<i} v[k] (wrapping), and the total.
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

/// The CPU twin of the radix sort: pairs stably ordered by the low `bits` bits of the key.
pub fn sort_pairs_cpu(keys: &[u32], vals: &[u32], bits: u32) -> (Vec<u32>, Vec<u32>) {
    assert_eq!(keys.len(), vals.len(), "one value per key");
    let mask = if bits >= 32 { u32::MAX } else { (1u32 << bits) - 1 };
    let mut pairs: Vec<(u32, u32)> = keys.iter().copied().zip(vals.iter().copied()).collect();
    pairs.sort_by_key(|p| p.0 & mask);
    pairs.into_iter().unzip()
}

/// The offset buffer's sentinel (an unwritten entry).
pub const SENTINEL: u32 = u32::MAX;

/// The paths of texel `t` from an offset buffer (`texel count + 1` entries): the range
/// [offsets[t], offsets[t + 1]), empty where either is the sentinel or they are equal
/// (seed 004 §3.2).
pub fn texel_range(offsets: &[u32], t: usize) -> std::ops::Range<usize> {
    let (a, b) = (offsets[t], offsets[t + 1]);
    if a == SENTINEL || b == SENTINEL || a >= b {
        0..0
    } else {
        a as usize..b as usize
    }
}

/// The CPU oracle for the offset buffer: each texel's range of paths in `sorted` (path
/// texel indices in non-decreasing order), by counting.
pub fn texel_ranges_cpu(sorted: &[u32], texels: usize) -> Vec<std::ops::Range<usize>> {
    assert!(sorted.windows(2).all(|w| w[0] <= w[1]), "paths sorted by texel");
    let mut count = vec![0usize; texels];
    for t in sorted {
        count[*t as usize] += 1;
    }
    let mut start = 0;
    count
        .iter()
        .map(|c| {
            let r = if *c == 0 { 0..0 } else { start..start + c };
            start += c;
            r
        })
        .collect()
}

/// The WGSL of the tile-format index functions (`tile_index`, `tile_coords`).
pub const TILE_WGSL: &str = include_str!("tile.wgsl");

/// Tile-format index of texel (x, y) (seed 004 eq. 5.2): tiles of 2^log2_n texels a side,
/// `tiles_per_row` = ⌈width / n⌉.
pub fn tile_index(x: u32, y: u32, log2_n: u32, tiles_per_row: u32) -> u32 {
    let n = 1u32 << log2_n;
    let tile = (x >> log2_n) + tiles_per_row * (y >> log2_n);
    (tile << (2 * log2_n)) | ((x & (n - 1)) + n * (y & (n - 1)))
}

/// The texel of a tile-format index (the inverse of [`tile_index`]; eq. 5.3 for the
/// tile's origin).
pub fn tile_coords(i: u32, log2_n: u32, tiles_per_row: u32) -> (u32, u32) {
    let n = 1u32 << log2_n;
    let tile = i >> (2 * log2_n);
    let within = i & (n * n - 1);
    (n * (tile % tiles_per_row) + (within & (n - 1)), n * (tile / tiles_per_row) + (within >> log2_n))
}

/// The reconstruction filter of the gather: separable, w(d) = f(d.x)·f(d.y) for the offset
/// d of a path's continuous atlas position from the texel centre, zero from `radius` on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GatherFilter {
    /// 1 inside the radius.
    Box,
    /// exp(−d²/2σ²) − exp(−r²/2σ²), σ = r/2, clamped at 0 (zero at the radius).
    Gaussian,
    /// Mitchell–Netravali with B = C = 1/3 over [−r, r] (negative lobes included).
    Mitchell,
}

impl GatherFilter {
    /// The kernel code of `filter_kernel.wgsl`.
    pub fn code(self) -> u32 {
        match self {
            GatherFilter::Box => 0,
            GatherFilter::Gaussian => 1,
            GatherFilter::Mitchell => 2,
        }
    }
    /// The 1D weight at offset `d` for radius `r` (the WGSL `filter_1d`, same f32 steps).
    pub fn weight_1d(self, r: f32, d: f32) -> f32 {
        let a = d.abs();
        match self {
            GatherFilter::Box => (a < r) as u32 as f32,
            GatherFilter::Gaussian => {
                let s2 = 2.0 * (0.5 * r) * (0.5 * r);
                ((-d * d / s2).exp() - (-r * r / s2).exp()).max(0.0)
            }
            GatherFilter::Mitchell => {
                let x = 2.0 * a / r;
                let (b, c) = (1.0f32 / 3.0, 1.0f32 / 3.0);
                if x < 1.0 {
                    ((12.0 - 9.0 * b - 6.0 * c) * x * x * x + (-18.0 + 12.0 * b + 6.0 * c) * x * x + (6.0 - 2.0 * b)) / 6.0
                } else if x < 2.0 {
                    ((-b - 6.0 * c) * x * x * x + (6.0 * b + 30.0 * c) * x * x + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)) / 6.0
                } else {
                    0.0
                }
            }
        }
    }
}

/// The filters' 1D weight in WGSL (`filter_kernel_1d(kernel, radius, d)`, kernel codes as
/// [`GatherFilter`]'s), shared by the gather and the bake's filtered accumulation.
pub const FILTER_KERNEL_WGSL: &str = include_str!("filter_kernel.wgsl");

/// The chart id of a texel that neither gathers nor is gathered from.
pub const INVALID_CHART: u32 = u32::MAX;

/// Texels on each side a gather of radius `r` must visit: a path of texel x + k lies at
/// least k − ½ from the centre of x, so k < r + ½.
pub fn gather_reach(r: f32) -> u32 {
    ((r + 0.5).ceil() as u32).saturating_sub(1)
}

/// The gather's inputs: a `width` × `height` atlas (row-major texel indices), the offset
/// buffer of the paths sorted by texel (`width·height + 1` entries), each path's continuous
/// atlas position (inside its texel) and value (RGB, fourth component unused), each
/// texel's chart ([`INVALID_CHART`]: left alone).
#[derive(Debug, Clone, Copy)]
pub struct GatherInput<'a> {
    pub width: usize,
    pub height: usize,
    pub offsets: &'a [u32],
    pub positions: &'a [[f32; 2]],
    pub values: &'a [[f32; 4]],
    pub charts: &'a [u32],
    pub filter: GatherFilter,
    pub radius: f32,
}

impl GatherInput<'_> {
    /// Checks sizes and the radius (finite, in (0, 16]).
    pub fn validate(&self, acc_len: usize) -> Result<(), String> {
        let texels = self.width * self.height;
        if self.offsets.len() != texels + 1 || self.charts.len() != texels || acc_len != texels {
            return Err(format!(
                "gather: {} offsets, {} charts and {acc_len} accumulators for {texels} texels (need texels + 1, texels, texels)",
                self.offsets.len(),
                self.charts.len()
            ));
        }
        if self.positions.len() != self.values.len() {
            return Err(format!("gather: {} positions but {} values", self.positions.len(), self.values.len()));
        }
        if !(self.radius > 0.0 && self.radius <= 16.0) {
            return Err(format!("gather: filter radius must be in (0, 16] texels, not {}", self.radius));
        }
        Ok(())
    }
}

/// The CPU twin of the gather: adds (Σ w·v, Σ w) of every texel's neighbourhood to `acc`
/// (same order and f32 steps as `gather.wgsl`).
pub fn gather_cpu(g: &GatherInput, acc: &mut [[f32; 4]]) -> Result<(), String> {
    g.validate(acc.len())?;
    let reach = gather_reach(g.radius) as i64;
    for (t, a) in acc.iter_mut().enumerate() {
        let chart = g.charts[t];
        if chart == INVALID_CHART {
            continue;
        }
        let (x, y) = ((t % g.width) as i64, (t / g.width) as i64);
        let centre = [x as f32 + 0.5, y as f32 + 0.5];
        let (mut sum, mut weight) = ([0f32; 3], 0f32);
        for ny in (y - reach).max(0)..=(y + reach).min(g.height as i64 - 1) {
            for nx in (x - reach).max(0)..=(x + reach).min(g.width as i64 - 1) {
                let n = ny as usize * g.width + nx as usize;
                if g.charts[n] != chart {
                    continue;
                }
                for p in texel_range(g.offsets, n) {
                    let d = [g.positions[p][0] - centre[0], g.positions[p][1] - centre[1]];
                    let w = g.filter.weight_1d(g.radius, d[0]) * g.filter.weight_1d(g.radius, d[1]);
                    if w != 0.0 {
                        for c in 0..3 {
                            sum[c] += w * g.values[p][c];
                        }
                        weight += w;
                    }
                }
            }
        }
        for c in 0..3 {
            a[c] += sum[c];
        }
        a[3] += weight;
    }
    Ok(())
}

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GatherParams {
    width: u32,
    height: u32,
    row: u32,
    kernel: u32,
    radius: f32,
    reach: u32,
    _pad: [u32; 2],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SortParams {
    n: u32,
    row: u32,
    shift: u32,
    blocks: u32,
}

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    n: u32,
    row: u32,
    _pad: [u32; 2],
}

fn grid(blocks: usize) -> (u32, u32) {
    let blocks = blocks.max(1);
    (blocks.min(ROW) as u32, blocks.div_ceil(ROW) as u32)
}

fn storage_layout_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
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

fn uniform_layout_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

fn pipeline(d: &wgpu::Device, layout: &wgpu::BindGroupLayout, module: &wgpu::ShaderModule, entry: &str) -> wgpu::ComputePipeline {
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
fn bind(d: &wgpu::Device, layout: &wgpu::BindGroupLayout, label: &str, buffers: &[&wgpu::Buffer], params: &[u8]) -> wgpu::BindGroup {
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
fn dispatch(enc: &mut wgpu::CommandEncoder, label: &str, pipeline: &wgpu::ComputePipeline, group: &wgpu::BindGroup, (x, y): (u32, u32)) {
    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: None });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(x, y, 1);
}

/// The compiled kernels of one device.
#[derive(Debug)]
pub struct Prims {
    /// The block scans (prefix sum, radix sort) use subgroup operations.
    pub subgroups: bool,
    scan_layout: wgpu::BindGroupLayout,
    scan_blocks: wgpu::ComputePipeline,
    add_offsets: wgpu::ComputePipeline,
    compact_layout: wgpu::BindGroupLayout,
    scatter: wgpu::ComputePipeline,
    sort_layout: wgpu::BindGroupLayout,
    sort_histogram: wgpu::ComputePipeline,
    sort_scatter: wgpu::ComputePipeline,
    offsets_layout: wgpu::BindGroupLayout,
    offsets: wgpu::ComputePipeline,
    gather_layout: wgpu::BindGroupLayout,
    gather: wgpu::ComputePipeline,
}

/// The workgroup block scan of the prefix sum and the radix sort: subgroup or
/// workgroup-memory variant.
fn block_scan_source(subgroups: bool) -> &'static str {
    if subgroups {
        include_str!("block_scan_subgroup.wgsl")
    } else {
        include_str!("block_scan.wgsl")
    }
}

/// The WGSL of the prefix sum and the radix sort, for validation: (workgroup variant,
/// subgroup variant) of each.
pub fn block_scan_sources() -> [(String, String); 2] {
    let scan = |sg| format!("{}{}{}", include_str!("grid_params.wgsl"), block_scan_source(sg), include_str!("scan.wgsl"));
    let sort = |sg| format!("{}{}", block_scan_source(sg), include_str!("sort.wgsl"));
    [(scan(false), scan(true)), (sort(false), sort(true))]
}

impl Prims {
    /// The kernels for `d`, with the subgroup block scan where the device has subgroups.
    pub fn new(d: &wgpu::Device) -> Prims {
        Prims::with_subgroups(d, d.features().contains(wgpu::Features::SUBGROUP))
    }

    /// The kernels with the subgroup (`true`, the device must have `Features::SUBGROUP`) or
    /// the workgroup-memory block scan — tests run both where they can.
    pub fn with_subgroups(d: &wgpu::Device, subgroups: bool) -> Prims {
        let [(scan_wg, scan_sg), (sort_wg, sort_sg)] = block_scan_sources();
        let scan = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scan.wgsl"),
            source: wgpu::ShaderSource::Wgsl(if subgroups { scan_sg } else { scan_wg }.into()),
        });
        let compact = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("compact.wgsl"),
            source: wgpu::ShaderSource::Wgsl(concat!(include_str!("grid_params.wgsl"), include_str!("compact.wgsl")).into()),
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
        let sort = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sort.wgsl"),
            source: wgpu::ShaderSource::Wgsl(if subgroups { sort_sg } else { sort_wg }.into()),
        });
        let sort_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sort"),
            entries: &[
                storage_layout_entry(0, true),
                storage_layout_entry(1, true),
                storage_layout_entry(2, false),
                storage_layout_entry(3, false),
                storage_layout_entry(4, false),
                uniform_layout_entry(5),
            ],
        });
        let offsets = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("offsets.wgsl"),
            source: wgpu::ShaderSource::Wgsl(concat!(include_str!("grid_params.wgsl"), include_str!("offsets.wgsl")).into()),
        });
        let offsets_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("offsets"),
            entries: &[storage_layout_entry(0, true), storage_layout_entry(1, false), uniform_layout_entry(2)],
        });
        let gather = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("gather.wgsl"),
            source: wgpu::ShaderSource::Wgsl(format!("{FILTER_KERNEL_WGSL}\n{}", include_str!("gather.wgsl")).into()),
        });
        let gather_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gather"),
            entries: &[
                storage_layout_entry(0, true),
                storage_layout_entry(1, true),
                storage_layout_entry(2, true),
                storage_layout_entry(3, true),
                storage_layout_entry(4, false),
                uniform_layout_entry(5),
            ],
        });
        Prims {
            subgroups,
            gather: pipeline(d, &gather_layout, &gather, "gather"),
            gather_layout,
            offsets: pipeline(d, &offsets_layout, &offsets, "generate_offsets"),
            offsets_layout,
            sort_histogram: pipeline(d, &sort_layout, &sort, "histogram"),
            sort_scatter: pipeline(d, &sort_layout, &sort, "scatter"),
            sort_layout,
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

/// A radix sort's scratch buffers, scans and bind groups ([`Prims::sort_plan`]), for
/// recording it repeatedly ([`Prims::record_sort`]).
#[derive(Debug)]
pub struct SortPlan {
    passes: Vec<(wgpu::BindGroup, ScanPlan)>,
    grid: (u32, u32),
    /// The sorted keys and values once the sort ran.
    sorted: (wgpu::Buffer, wgpu::Buffer),
}

impl SortPlan {
    /// The buffers holding the sorted (keys, values) after the sort ran: the inputs
    /// themselves after an even number of 4-bit passes, the scratch ones otherwise.
    pub fn sorted(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (&self.sorted.0, &self.sorted.1)
    }
}

impl Prims {
    /// Plans a stable LSD radix sort of the first `n` (key, value) pairs of `keys`, `vals`
    /// by the low `bits` key bits (⌈bits/4⌉ passes, ping-ponging with two scratch buffers
    /// allocated here).
    pub fn sort_plan(&self, d: &wgpu::Device, keys: &wgpu::Buffer, vals: &wgpu::Buffer, n: usize, bits: u32) -> SortPlan {
        let passes = bits.min(32).div_ceil(4);
        let blocks = n.div_ceil(BLOCK).max(1);
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let scratch = |label| {
            d.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: (4 * n.max(1)) as u64, usage, mapped_at_creation: false })
        };
        let counts = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sort counts"),
            size: (4 * 16 * blocks) as u64,
            usage,
            mapped_at_creation: false,
        });
        let (mut src, mut dst) = ((keys.clone(), vals.clone()), (scratch("sort keys"), scratch("sort values")));
        let (x, y) = grid(blocks);
        let mut list = Vec::new();
        for p in 0..passes {
            let params = SortParams { n: n as u32, row: x, shift: 4 * p, blocks: blocks as u32 };
            let g = bind(d, &self.sort_layout, "sort pass", &[&src.0, &src.1, &dst.0, &dst.1, &counts], bytemuck::bytes_of(&params));
            list.push((g, self.scan_plan(d, &counts, 16 * blocks)));
            std::mem::swap(&mut src, &mut dst);
        }
        SortPlan { passes: list, grid: (x, y), sorted: src }
    }

    /// Records a planned sort; [`SortPlan::sorted`] then holds the result.
    pub fn record_sort(&self, enc: &mut wgpu::CommandEncoder, plan: &SortPlan) {
        for (g, scan) in &plan.passes {
            dispatch(enc, "sort histogram", &self.sort_histogram, g, plan.grid);
            self.record_scan(enc, scan);
            dispatch(enc, "sort scatter", &self.sort_scatter, g, plan.grid);
        }
    }

    /// Records a stable radix sort of the first `n` (key, value) pairs by the low `bits` key
    /// bits (see [`Prims::sort_plan`]); returns the buffers holding the sorted keys and
    /// values (the inputs themselves after an even number of passes, the scratch ones
    /// otherwise).
    pub fn encode_sort(
        &self,
        d: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        keys: wgpu::Buffer,
        vals: wgpu::Buffer,
        n: usize,
        bits: u32,
    ) -> (wgpu::Buffer, wgpu::Buffer) {
        let plan = self.sort_plan(d, &keys, &vals, n, bits);
        self.record_sort(enc, &plan);
        plan.sorted
    }
}

impl Prims {
    /// Records the offset buffer of `paths` path texel indices (sorted) into `offsets`
    /// (`texels + 1` u32): the sentinel fill (a copy-side clear to 0xFF bytes) and one
    /// thread per path.
    pub fn encode_offsets(
        &self,
        d: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        path_texels: &wgpu::Buffer,
        offsets: &wgpu::Buffer,
        paths: usize,
    ) {
        let fill = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sentinels"),
            contents: &vec![0xFFu8; offsets.size() as usize],
            usage: wgpu::BufferUsages::COPY_SRC,
        });
        enc.copy_buffer_to_buffer(&fill, 0, offsets, 0, offsets.size());
        if paths == 0 {
            return;
        }
        let (x, y) = grid(paths.div_ceil(BLOCK));
        let p = Params { n: paths as u32, row: x, _pad: [0; 2] };
        let g = bind(d, &self.offsets_layout, "offsets", &[path_texels, offsets], bytemuck::bytes_of(&p));
        dispatch(enc, "offsets", &self.offsets, &g, (x, y));
    }
}

impl Prims {
    /// Records the filtered gather of `width` × `height` texels into `acc` (one vec4 per
    /// texel: Σ w·v, Σ w added): buffers as in [`GatherInput`] (positions as vec2<f32>,
    /// values and `acc` as vec4<f32>).
    #[allow(clippy::too_many_arguments)]
    pub fn encode_gather(
        &self,
        d: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        [offsets, positions, values, charts, acc]: [&wgpu::Buffer; 5],
        (width, height): (usize, usize),
        filter: GatherFilter,
        radius: f32,
    ) {
        let texels = width * height;
        if texels == 0 {
            return;
        }
        let (x, y) = grid(texels.div_ceil(BLOCK));
        let p = GatherParams {
            width: width as u32,
            height: height as u32,
            row: x,
            kernel: filter.code(),
            radius,
            reach: gather_reach(radius),
            _pad: [0; 2],
        };
        let g = bind(d, &self.gather_layout, "gather", &[offsets, positions, values, charts, acc], bytemuck::bytes_of(&p));
        dispatch(enc, "gather", &self.gather, &g, (x, y));
    }
}

/// Host convenience: the GPU gather of `g` added to `acc` (returned).
pub fn gather(d: &wgpu::Device, q: &wgpu::Queue, prims: &Prims, g: &GatherInput, acc: &[[f32; 4]]) -> Result<Vec<[f32; 4]>, String> {
    g.validate(acc.len())?;
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let buf = |bytes: &[u8], label| {
        let contents = if bytes.is_empty() { &[0u8; 16][..] } else { bytes };
        d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
    };
    let b = [
        buf(bytemuck::cast_slice(g.offsets), "gather offsets"),
        buf(bytemuck::cast_slice(g.positions), "gather positions"),
        buf(bytemuck::cast_slice(g.values), "gather values"),
        buf(bytemuck::cast_slice(g.charts), "gather charts"),
        buf(bytemuck::cast_slice(acc), "gather accumulators"),
    ];
    let mut enc = d.create_command_encoder(&Default::default());
    prims.encode_gather(d, &mut enc, [&b[0], &b[1], &b[2], &b[3], &b[4]], (g.width, g.height), g.filter, g.radius);
    q.submit([enc.finish()]);
    let raw = read_u32(d, q, &b[4], 4 * acc.len());
    Ok(bytemuck::cast_slice::<u32, f32>(&raw).chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect())
}

/// Host convenience: the offset buffer (`texels + 1` entries) of sorted path texels.
pub fn offsets(d: &wgpu::Device, q: &wgpu::Queue, prims: &Prims, sorted: &[u32], texels: usize) -> Vec<u32> {
    assert!(sorted.iter().all(|t| (*t as usize) < texels), "texel indices below the texel count");
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let pt = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("path texels"),
        contents: bytemuck::cast_slice(&padded(sorted)),
        usage,
    });
    let ob = d.create_buffer(&wgpu::BufferDescriptor {
        label: Some("offsets"),
        size: (4 * (texels + 1)) as u64,
        usage,
        mapped_at_creation: false,
    });
    let mut enc = d.create_command_encoder(&Default::default());
    prims.encode_offsets(d, &mut enc, &pt, &ob, sorted.len());
    q.submit([enc.finish()]);
    read_u32(d, q, &ob, texels + 1)
}

/// Host convenience: sorts (key, value) pairs by the low `bits` key bits on the GPU.
pub fn sort_pairs(d: &wgpu::Device, q: &wgpu::Queue, prims: &Prims, keys: &[u32], vals: &[u32], bits: u32) -> (Vec<u32>, Vec<u32>) {
    assert_eq!(keys.len(), vals.len(), "one value per key");
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let buf = |v: &[u32], label| {
        d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytemuck::cast_slice(&padded(v)), usage })
    };
    let mut enc = d.create_command_encoder(&Default::default());
    let (k, v) = prims.encode_sort(d, &mut enc, buf(keys, "keys"), buf(vals, "values"), keys.len(), bits);
    q.submit([enc.finish()]);
    (read_u32(d, q, &k, keys.len()), read_u32(d, q, &v, keys.len()))
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
