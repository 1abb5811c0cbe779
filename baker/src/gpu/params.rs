//! What the bake kernel reads besides the items: the uniform parameters of a pass
//! (`TraceParams`, checked against its WGSL twin) and the scene's materials, lights,
//! emitters and environment packed as vec4s (`aux`).

use crate::accumulate::{BakeConfig, Targets};
use crate::estimator::trace::{specular_probability, Tracer};
use crate::scene::{Environment, Light};
use sbf::glam::Vec3;

/// The partition block of a single-device bake (any positive value is the identity).
pub(crate) const PART_BLOCK_DEFAULT: u32 = 64;

/// Uniform parameters of a pass (WGSL `TraceParams`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TraceParams {
    pub pass_index: u32,
    pub seed: u32,
    pub item_count: u32,
    pub max_bounces: u32,
    pub emitter_count: u32,
    pub light_count: u32,
    pub env_kind: u32,
    pub mode: u32,
    pub env_cells_offset: u32,
    pub inv_total_power: f32,
    pub count_rays: u32,
    pub primary_only: u32,
    pub light_offset: u32,
    pub emitter_offset: u32,
    pub env_offset: u32,
    pub env_width: u32,
    pub env_rows_offset: u32,
    pub env_cdf_width: u32,
    pub env_cdf_height: u32,
    pub guide_phase: u32,
    /// Ray guiding: the pass's stage and the stage's first pass (`guiding::stage`).
    pub guide_stage: u32,
    pub guide_start: u32,
    /// The items of this dispatch, [item_offset, item_end) (a pass may take several), as
    /// positions in this device's share of the items.
    pub item_offset: u32,
    pub item_end: u32,
    /// Multi-GPU partition ([`crate::gpu::multi`]): the items are dealt out in blocks of
    /// `part_block`, block b to device b mod `part_count`; this device is `part_index`.
    /// Position v of its share is item (v / B)·B·count + index·B + v mod B (one device: v).
    pub part_block: u32,
    pub part_count: u32,
    pub part_index: u32,
    /// Passes this dispatch runs, from `pass_index` (each thread takes its item through
    /// them in order, so an item's state sees exactly the one-pass-per-dispatch updates).
    pub pass_count: u32,
    /// [`crate::sampling::sequence::Sequence::code`].
    pub sampler: u32,
    /// 1: the dispatch runs an adaptive batch (indirect, its items listed).
    pub batch_mode: u32,
    /// Sample points in the first points binding; the rest are in the second
    /// (`points_hi`), so the points may exceed one storage binding ([`crate::gpu::buffers`]).
    pub point_split: u32,
    /// 1: indirect light only (`Tracer::indirect_only`).
    pub indirect_only: u32,
    pub env_zenith: [f32; 4],
    pub env_horizon: [f32; 4],
    pub env_ground: [f32; 4],
}
shaders::gpu_struct!(
    TraceParams,
    "TraceParams",
    [
        pass_index,
        seed,
        item_count,
        max_bounces,
        emitter_count,
        light_count,
        env_kind,
        mode,
        env_cells_offset,
        inv_total_power,
        count_rays,
        primary_only,
        light_offset,
        emitter_offset,
        env_offset,
        env_width,
        env_rows_offset,
        env_cdf_width,
        env_cdf_height,
        guide_phase,
        guide_stage,
        guide_start,
        item_offset,
        item_end,
        part_block,
        part_count,
        part_index,
        pass_count,
        sampler,
        batch_mode,
        point_split,
        indirect_only,
        env_zenith,
        env_horizon,
        env_ground
    ]
);
shaders::gpu_struct!(crate::scene::bvh::Node, "Node", [min, left_first, max, count]);
shaders::gpu_struct!(crate::scene::bvh::Tri, "Tri", [corner, material, edge_u, mesh, edge_v, prim]);

/// Offsets (in vec4s) of the parts of `aux` (see bindings.wgsl).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct AuxLayout {
    pub(crate) lights: u32,
    pub(crate) emitters: u32,
    pub(crate) emitter_count: u32,
    pub(crate) env_texels: u32,
    pub(crate) env_rows: u32,
    pub(crate) env_cells: u32,
    pub(crate) env_cdf: (u32, u32),
}

/// Materials, lights, emitters, the environment map and its sampler packed as vec4s
/// (see `aux` in bindings.wgsl).
pub(crate) fn aux_data(tracer: &Tracer) -> (Vec<[f32; 4]>, AuxLayout) {
    let mut aux = Vec::new();
    let mut at = AuxLayout::default();
    for m in &tracer.scene.materials {
        let (d, f0, e) = (m.diffuse_albedo(), m.specular_f0(), m.emissive);
        let flags = m.is_glossy() as u32 | (m.double_sided as u32) << 1;
        aux.push([d.x, d.y, d.z, specular_probability(m) as f32]);
        aux.push([f0.x, f0.y, f0.z, m.alpha()]);
        aux.push([e.x, e.y, e.z, flags as f32]);
    }
    at.lights = aux.len() as u32;
    for l in &tracer.scene.lights {
        // 4 vec4 per light: (position or direction, kind), (colour, range),
        // (spot axis, cos inner), (cos outer, 0, 0, 0).
        let (a, kind, c, range, axis, ci, co) = match *l {
            Light::Directional { direction, irradiance } => (direction, 0.0, irradiance, f32::INFINITY, Vec3::Z, 1.0, -1.0),
            Light::Point { position, intensity, range } => (position, 1.0, intensity, range, Vec3::Z, 1.0, -1.0),
            Light::Spot { position, direction, intensity, cos_inner, cos_outer, range } => {
                (position, 2.0, intensity, range, direction, cos_inner, cos_outer)
            }
        };
        aux.push([a.x, a.y, a.z, kind]);
        aux.push([c.x, c.y, c.z, if range.is_finite() { range } else { -1.0 }]);
        aux.push([axis.x, axis.y, axis.z, ci]);
        aux.push([co, 0.0, 0.0, 0.0]);
    }
    at.emitters = aux.len() as u32;
    for (tri, cdf) in tracer.emitter_table() {
        aux.push([f32::from_bits(tri), cdf as f32, 0.0, 0.0]);
        at.emitter_count += 1;
    }
    // The last CDF entry is 1 up to rounding; the search clamps to the last emitter.
    at.env_texels = aux.len() as u32;
    if let Environment::Map(m) = &tracer.scene.environment {
        aux.extend(m.texels.iter().map(|t| [t[0], t[1], t[2], 0.0]));
    }
    if let Some(env) = &tracer.env {
        at.env_rows = aux.len() as u32;
        aux.extend(env.row_cdf.iter().map(|c| [*c, 0.0, 0.0, 0.0]));
        at.env_cells = aux.len() as u32;
        aux.extend(env.col_cdf.iter().zip(&env.cell_p).map(|(c, p)| [*c, *p, 0.0, 0.0]));
        at.env_cdf = (env.width as u32, env.height as u32);
    }
    if aux.is_empty() {
        aux.push([0.0; 4]);
    }
    (aux, at)
}

/// The parameters of pass 0 of a bake of `targets` with `config` (the environment's kind
/// and colours, the offsets of `aux`'s parts `at`, one partition, one pass per dispatch).
pub(crate) fn trace_params(tracer: &Tracer, targets: &Targets, config: &BakeConfig, at: &AuxLayout) -> TraceParams {
    let items = targets.items.len() as u32;
    TraceParams {
        item_count: items,
        mode: targets.sphere as u32,
        item_end: items,
        indirect_only: config.indirect_only as u32,
        ..scene_params(tracer, at, config.max_bounces, crate::sampling::sequence::gpu_seed(config.seed), config.sampler.code())
    }
}

/// The parameters of the scene, its lights and environment, the bounce count, the seed
/// and the sequence (`Sequence::code`), for no items.
pub(crate) fn scene_params(tracer: &Tracer, at: &AuxLayout, max_bounces: u32, seed: u32, sampler: u32) -> TraceParams {
    let (env_kind, env) = match tracer.scene.environment {
        Environment::Black => (0, [[0.0; 4]; 3]),
        Environment::Constant(c) => (1, [[c.x, c.y, c.z, 0.0], [0.0; 4], [0.0; 4]]),
        Environment::Sky { zenith: z, horizon: h, ground: g } => (2, [[z.x, z.y, z.z, 0.0], [h.x, h.y, h.z, 0.0], [g.x, g.y, g.z, 0.0]]),
        Environment::Map(_) => (3, [[0.0; 4]; 3]),
    };
    let env_width = match &tracer.scene.environment {
        Environment::Map(m) => m.geometry.width as u32,
        _ => 0,
    };
    TraceParams {
        pass_index: 0,
        seed,
        item_count: 0,
        max_bounces,
        emitter_count: at.emitter_count,
        light_count: tracer.scene.lights.len() as u32,
        env_kind,
        mode: 0,
        env_cells_offset: at.env_cells,
        inv_total_power: if tracer.total_power > 0.0 { (1.0 / tracer.total_power) as f32 } else { 0.0 },
        count_rays: 0,
        primary_only: 0,
        light_offset: at.lights,
        emitter_offset: at.emitters,
        env_offset: at.env_texels,
        env_width,
        env_rows_offset: at.env_rows,
        env_cdf_width: at.env_cdf.0,
        env_cdf_height: at.env_cdf.1,
        guide_phase: 0,
        guide_stage: 0,
        guide_start: 0,
        item_offset: 0,
        item_end: 0,
        part_block: PART_BLOCK_DEFAULT,
        part_count: 1,
        part_index: 0,
        pass_count: 1,
        sampler,
        batch_mode: 0,
        point_split: u32::MAX,
        indirect_only: tracer.indirect_only as u32,
        env_zenith: env[0],
        env_horizon: env[1],
        env_ground: env[2],
    }
}
