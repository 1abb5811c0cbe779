//! The buffers every bake binds: parameters, BVH, scene data (`aux`), items, sample points,
//! per-item moments, encoder states and ray counters, uploaded once.

use super::params::TraceParams;
use crate::accumulate::Targets;
use crate::estimator::trace::Tracer;
use wgpu::util::DeviceExt;

/// The buffers of a bake (bindings 0–8 of the bake kernel).
#[derive(Debug)]
pub(crate) struct BakeBuffers {
    pub(crate) params: wgpu::Buffer,
    pub(crate) nodes: wgpu::Buffer,
    pub(crate) tris: wgpu::Buffer,
    pub(crate) aux: wgpu::Buffer,
    pub(crate) items: wgpu::Buffer,
    pub(crate) points: wgpu::Buffer,
    pub(crate) points_hi: wgpu::Buffer,
    pub(crate) moments: wgpu::Buffer,
    pub(crate) states: wgpu::Buffer,
    pub(crate) counters: wgpu::Buffer,
    /// The materials' texture maps (binding 20; [`crate::gpu::maps`]) of a textured scene.
    pub(crate) maps: Option<wgpu::Buffer>,
}

/// Bytes of one sample point on the GPU (position, shading normal + u, geometric normal + v).
pub(crate) const POINT_BYTES: u64 = 48;

/// How many of `points` sample points go to the first points binding: all when they fit
/// in one binding of `limit` bytes, else as many as fit (the rest go to the second).
pub(crate) fn point_split(points: usize, limit: u64) -> u32 {
    (points as u64).min(limit / POINT_BYTES).min(u32::MAX as u64) as u32
}

/// Uploads the scene, BVH, targets and zeroed state (`states_len` bytes of encoder states);
/// the sample points go to two bindings at `params.point_split`.
pub(crate) fn upload(
    d: &wgpu::Device,
    tracer: &Tracer,
    targets: &Targets,
    params: &TraceParams,
    aux: &[[f32; 4]],
    states_len: usize,
    maps: Option<&[u32]>,
) -> BakeBuffers {
    let items = targets.items.len();
    let storage = |label: &str, bytes: &[u8], extra| storage(d, label, bytes, extra);
    let rw = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let params_buf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("params"),
        contents: bytemuck::bytes_of(params),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    let nodes = storage("nodes", bytemuck::cast_slice(&tracer.bvh.nodes), wgpu::BufferUsages::empty());
    let tris = storage("tris", bytemuck::cast_slice(&tracer.bvh.tris), wgpu::BufferUsages::empty());
    let auxb = storage("aux", bytemuck::cast_slice(aux), wgpu::BufferUsages::empty());
    let item_data: Vec<[u32; 4]> = targets.items.iter().zip(&targets.clusters).map(|(&[a, b, c], k)| [a, b, c, *k]).collect();
    let itemb = storage("items", bytemuck::cast_slice(&item_data), wgpu::BufferUsages::empty());
    // The w components of the normals: the point's atlas position (filtered gather).
    let pts: Vec<[f32; 4]> = targets
        .points
        .iter()
        .enumerate()
        .flat_map(|(k, p)| {
            let uv = targets.point_uv.get(k).copied().unwrap_or([0.0; 2]);
            [p.position.extend(1.0).to_array(), p.normal.extend(uv[0]).to_array(), p.geometric.extend(uv[1]).to_array()]
        })
        .collect();
    let split = (params.point_split as usize).min(targets.points.len());
    let pointb = storage("points", bytemuck::cast_slice(&pts[..3 * split]), wgpu::BufferUsages::empty());
    // A binding may not be empty: one placeholder point when every point is in the first.
    let hi: &[[f32; 4]] = if split < targets.points.len() { &pts[3 * split..] } else { &[[0.0; 4]; 3] };
    let points_hi = storage("points (second binding)", bytemuck::cast_slice(hi), wgpu::BufferUsages::empty());
    let moments_buf = storage("moments", &vec![0u8; items * 48], rw);
    let states_buf = storage("states", &vec![0u8; states_len], rw);
    let counters_buf = storage("counters", &[0u8; 16], rw);
    BakeBuffers {
        params: params_buf,
        nodes,
        tris,
        aux: auxb,
        items: itemb,
        points: pointb,
        points_hi,
        moments: moments_buf,
        states: states_buf,
        counters: counters_buf,
        maps: maps.map(|m| storage("material maps", bytemuck::cast_slice(m), wgpu::BufferUsages::empty())),
    }
}

/// A storage buffer holding `bytes`, with `extra` usages.
pub(crate) fn storage(d: &wgpu::Device, label: &str, bytes: &[u8], extra: wgpu::BufferUsages) -> wgpu::Buffer {
    d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: wgpu::BufferUsages::STORAGE | extra,
    })
}

/// The ray counters' slot of traversals the driver cut short (bindings.wgsl
/// `CUT_TRAVERSALS`).
const CUT_TRAVERSALS: usize = 3;

/// Refuses results whose kernels had a BVH traversal ended early by the driver: llvmpipe
/// and lavapipe end every loop of an invocation after 65 535 iterations in all (gallivm's
/// loop limiter), which returns a wrong hit, not an error. `counters` is the ray counters'
/// buffer (readable).
pub(crate) fn check_cut_traversals(gpu: &shaders::gpu::Gpu, counters: &wgpu::Buffer) -> Result<(), String> {
    let c: [u32; 4] = bytemuck::pod_read_unaligned(&gpu.read_back(counters)?);
    match c[CUT_TRAVERSALS] {
        0 => Ok(()),
        n => Err(format!(
            "the GPU driver ended {n} BVH traversals early (a loop-iteration cap per invocation, as llvmpipe's 65 535): \
             the results would hold wrong hits; on a software adapter use fewer samples per dispatch or --device cpu"
        )),
    }
}

/// Every storage buffer of a bake against the adapter's binding limit, before upload.
pub(crate) fn check_sizes(
    tracer: &Tracer,
    targets: &Targets,
    aux: usize,
    states_len: usize,
    clusters: usize,
    pool: usize,
    limit: u64,
) -> Result<(), String> {
    let split = point_split(targets.points.len(), limit);
    check_bindings(
        &[
            ("BVH nodes", std::mem::size_of_val(&tracer.bvh.nodes[..]) as u64),
            ("triangles", std::mem::size_of_val(&tracer.bvh.tris[..]) as u64),
            ("materials, lights and environment", (aux * 16) as u64),
            ("sample points (first binding)", split as u64 * POINT_BYTES),
            ("sample points (second binding)", (targets.points.len() as u64 - split as u64) * POINT_BYTES),
            ("encoder states", states_len as u64),
            ("moments", (targets.items.len() * 48) as u64),
            ("ray-guiding distributions", (clusters * crate::sampling::guiding::CDF_LEN * 4) as u64),
            ("ray-guiding records", (if clusters > 0 { targets.items.len() * 24 } else { 0 }) as u64),
            ("wavefront path pool", (pool * 64) as u64),
        ],
        limit,
    )
}

/// Checks every storage buffer of a bake against the adapter's binding limit before
/// anything is uploaded ([`shaders::gpu::check_bindings`]); the error names the buffer,
/// both sizes and what to do.
pub fn check_bindings(buffers: &[(&str, u64)], max_binding: u64) -> Result<(), String> {
    shaders::gpu::check_bindings(buffers, max_binding)
        .map_err(|e| format!("{e} (bake on the CPU with --device cpu, fewer bases or texels, or a simpler scene)"))
}
