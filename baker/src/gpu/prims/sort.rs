//! The stable LSD radix sort of (key, value) u32 pairs and the offset buffer of paths
//! sorted by texel ([Roughton19 Listing 3.1]), with their CPU twins. Compiled only by a caller
//! that asks for them ([`SortPrims::new`]); no bake does.

use super::{bind, dispatch, grid, padded, pipeline, read_u32, storage_layout_entry, uniform_layout_entry, Params, Prims, ScanPlan, BLOCK};
use wgpu::util::DeviceExt;

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
/// `[offsets[t], offsets[t + 1])`, empty where either is the sentinel or they are equal
/// ([Roughton19 §3.2]).
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

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SortParams {
    n: u32,
    row: u32,
    shift: u32,
    blocks: u32,
}

/// The sort and offset-buffer kernels of one device; the sort's per-pass scans run on a
/// [`Prims`].
#[derive(Debug)]
pub struct SortPrims {
    sort_layout: wgpu::BindGroupLayout,
    sort_histogram: wgpu::ComputePipeline,
    sort_scatter: wgpu::ComputePipeline,
    offsets_layout: wgpu::BindGroupLayout,
    offsets: wgpu::ComputePipeline,
}

impl SortPrims {
    /// The kernels for `d`, with the block scan variant of `prims`.
    pub fn new(d: &wgpu::Device, prims: &Prims) -> SortPrims {
        let subgroups = prims.subgroups;
        let sort_source = super::composed("sort.wgsl", include_str!("sort.wgsl"), subgroups);
        let sort = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sort.wgsl"),
            source: wgpu::ShaderSource::Wgsl(sort_source.into()),
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
            source: wgpu::ShaderSource::Wgsl(super::composed("offsets.wgsl", include_str!("offsets.wgsl"), subgroups).into()),
        });
        let offsets_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("offsets"),
            entries: &[storage_layout_entry(0, true), storage_layout_entry(1, false), uniform_layout_entry(2)],
        });
        SortPrims {
            sort_histogram: pipeline(d, &sort_layout, &sort, "histogram"),
            sort_scatter: pipeline(d, &sort_layout, &sort, "scatter"),
            sort_layout,
            offsets: pipeline(d, &offsets_layout, &offsets, "generate_offsets"),
            offsets_layout,
        }
    }
}

/// A radix sort's scratch buffers, scans and bind groups ([`SortPrims::sort_plan`]), for
/// recording it repeatedly ([`SortPrims::record_sort`]).
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

impl SortPrims {
    /// Plans a stable LSD radix sort of the first `n` (key, value) pairs of `keys`, `vals`
    /// by the low `bits` key bits (⌈bits/4⌉ passes, ping-ponging with two scratch buffers
    /// allocated here).
    pub fn sort_plan(&self, d: &wgpu::Device, prims: &Prims, keys: &wgpu::Buffer, vals: &wgpu::Buffer, n: usize, bits: u32) -> SortPlan {
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
            list.push((g, prims.scan_plan(d, &counts, 16 * blocks)));
            std::mem::swap(&mut src, &mut dst);
        }
        SortPlan { passes: list, grid: (x, y), sorted: src }
    }

    /// Records a planned sort; [`SortPlan::sorted`] then holds the result.
    pub fn record_sort(&self, enc: &mut wgpu::CommandEncoder, prims: &Prims, plan: &SortPlan) {
        for (g, scan) in &plan.passes {
            dispatch(enc, "sort histogram", &self.sort_histogram, g, plan.grid);
            prims.record_scan(enc, scan);
            dispatch(enc, "sort scatter", &self.sort_scatter, g, plan.grid);
        }
    }

    /// Records a stable radix sort of the first `n` (key, value) pairs by the low `bits` key
    /// bits (see [`SortPrims::sort_plan`]); returns the buffers holding the sorted keys and
    /// values (the inputs themselves after an even number of passes, the scratch ones
    /// otherwise).
    pub fn encode_sort(
        &self,
        d: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        prims: &Prims,
        keys: wgpu::Buffer,
        vals: wgpu::Buffer,
        n: usize,
        bits: u32,
    ) -> (wgpu::Buffer, wgpu::Buffer) {
        let plan = self.sort_plan(d, prims, &keys, &vals, n, bits);
        self.record_sort(enc, prims, &plan);
        plan.sorted
    }
}

impl SortPrims {
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

/// Host convenience: the offset buffer (`texels + 1` entries) of sorted path texels.
pub fn offsets(d: &wgpu::Device, q: &wgpu::Queue, sp: &SortPrims, sorted: &[u32], texels: usize) -> Vec<u32> {
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
    sp.encode_offsets(d, &mut enc, &pt, &ob, sorted.len());
    q.submit([enc.finish()]);
    read_u32(d, q, &ob, texels + 1)
}

/// Host convenience: sorts (key, value) pairs by the low `bits` key bits on the GPU.
pub fn sort_pairs(
    d: &wgpu::Device,
    q: &wgpu::Queue,
    prims: &Prims,
    sp: &SortPrims,
    keys: &[u32],
    vals: &[u32],
    bits: u32,
) -> (Vec<u32>, Vec<u32>) {
    assert_eq!(keys.len(), vals.len(), "one value per key");
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let buf = |v: &[u32], label| {
        d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytemuck::cast_slice(&padded(v)), usage })
    };
    let mut enc = d.create_command_encoder(&Default::default());
    let (k, v) = sp.encode_sort(d, &mut enc, prims, buf(keys, "keys"), buf(vals, "values"), keys.len(), bits);
    q.submit([enc.finish()]);
    (read_u32(d, q, &k, keys.len()), read_u32(d, q, &v, keys.len()))
}
