// bindings.wgsl — the bake kernel's parameters and buffers (group 0, bindings 0–8; Rust
// twins baker::gpu::TraceParams and the BVH's Node/Tri), the material record, and small
// helpers every stage uses.

#define_import_path baker::bindings

#import sbf::runtime::EncoderState

struct Node {
    min: vec3<f32>,
    left_first: u32,
    max: vec3<f32>,
    count: u32,
}

struct Tri {
    corner: vec3<f32>,
    material: u32,
    edge_u: vec3<f32>,
    mesh: u32,
    edge_v: vec3<f32>,
    prim: u32,
}

// Bake parameters (uniform; Rust twin baker::gpu::TraceParams).
struct TraceParams {
    pass_index: u32,
    seed: u32,
    item_count: u32,
    max_bounces: u32,
    emitter_count: u32,
    light_count: u32,
    env_kind: u32,
    // 0: lightmap texels (hemisphere about the normal), 1: probes (whole sphere).
    mode: u32,
    // The environment sampler's cells (col CDF, probability) in `aux` from here.
    env_cells_offset: u32,
    inv_total_power: f32,
    // 1: count rays into `counters`.
    count_rays: u32,
    // 1: trace only the first segment (primary-ray timing).
    primary_only: u32,
    // Offsets into `aux` (in vec4s) of the lights and the emitters.
    light_offset: u32,
    emitter_offset: u32,
    // ENV_MAP: the lat-long map's texels in `aux` from env_offset, env_width × env_width/2.
    env_offset: u32,
    env_width: u32,
    // The sampler's row CDF in `aux` from env_rows_offset; its grid (0 × 0: none).
    env_rows_offset: u32,
    env_cdf_width: u32,
    env_cdf_height: u32,
    // Ray guiding: 0 none, 1 learning (uniform samples recorded), 2 guided (and recorded).
    guide_phase: u32,
    // Ray guiding: the pass's stage and the stage's first pass (baker::guiding::stage).
    guide_stage: u32,
    guide_start: u32,
    // The items of this dispatch: [item_offset, item_end) (a pass may take several), as
    // positions in this device's share of the items.
    item_offset: u32,
    item_end: u32,
    // Multi-GPU partition (baker::multi_gpu): blocks of part_block items, block b to device
    // b mod part_count; this device is part_index.
    part_block: u32,
    part_count: u32,
    part_index: u32,
    // Passes of this dispatch, from pass_index: each thread takes its item through them in
    // order (the item's state sees exactly the one-pass-per-dispatch updates).
    pass_count: u32,
    // Sample sequences (baker::sampler::Sequence::code): 0 Sobol', 1 independent.
    sampler: u32,
    // 1: this dispatch runs an adaptive batch (its items listed by jobs.wgsl, BATCH).
    batch_mode: u32,
    // Sample points in `points`; the rest are in `points_hi`.
    point_split: u32,
    // 1: indirect light only — no light samples at the baked (or visible) point, no
    // emitter or sky hit on its first segment (baker::estimator::trace::Tracer::indirect_only).
    indirect_only: u32,
    env_zenith: vec4<f32>,
    env_horizon: vec4<f32>,
    env_ground: vec4<f32>,
}

struct Hit {
    t: f32,
    tri: u32,
}

const NO_HIT: u32 = 0xffffffffu;
const T_FAR: f32 = 3.0e38;
const ENV_BLACK: u32 = 0u;
const ENV_CONSTANT: u32 = 1u;
const ENV_SKY: u32 = 2u;
const ENV_MAP: u32 = 3u;
const LIGHT_DIRECTIONAL: u32 = 0u;
const LIGHT_POINT: u32 = 1u;
const LIGHT_SPOT: u32 = 2u;

@group(0) @binding(0) var<uniform> P: TraceParams;
@group(0) @binding(1) var<storage, read> nodes: array<Node>;
@group(0) @binding(2) var<storage, read> tris: array<Tri>;
// Materials (3 vec4 each: diffuse albedo + GGX probability, F0 + α, emission + flags
// (1 glossy, 2 double-sided)), then lights (4 vec4 each: position/direction + kind,
// colour + range (< 0: none), spot axis + cos inner, cos outer), then emitters (1 vec4
// each: triangle index as bits, CDF of power), then the environment map's texels
// (ENV_MAP), then its sampler's row CDF and cells; offsets in TraceParams.
@group(0) @binding(3) var<storage, read> aux: array<vec4<f32>>;
// Per item: (first point, point count, output index, 0); points are (position, shading
// normal, geometric normal) triples.
@group(0) @binding(4) var<storage, read> items: array<vec4<u32>>;
@group(0) @binding(5) var<storage, read> points: array<vec4<f32>>;
// The sample points past P.point_split (one storage binding holds at most the adapter's
// limit; a one-point placeholder when all fit in `points`).
@group(0) @binding(19) var<storage, read> points_hi: array<vec4<f32>>;
// Per item, 3 vec4: (Σ E/π (or Σ L for probes), accepted count), (Σ of squares,
// back-face count), (non-finite count, 0, 0, 0). Counts are exact up to 2²⁴ passes.
@group(0) @binding(6) var<storage, read_write> moments: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> states: array<EncoderState>;
// Rays traced: primary, extension, shadow (only when P.count_rays = 1); then the
// traversals the driver cut short (CUT_TRAVERSALS; always counted, never expected).
@group(0) @binding(8) var<storage, read_write> counters: array<atomic<u32>, 4>;
const CUT_TRAVERSALS: u32 = 3u;

struct Material {
    diffuse: vec3<f32>,
    specular_probability: f32,
    reflectance: vec3<f32>,
    alpha: f32,
    emissive: vec3<f32>,
    glossy: bool,
    double_sided: bool,
}

fn load_material(m: u32) -> Material {
    let a = aux[3u * m];
    let b = aux[3u * m + 1u];
    let c = aux[3u * m + 2u];
    let flags = u32(c.w);
    return Material(a.xyz, a.w, b.xyz, b.w, c.xyz, (flags & 1u) != 0u, (flags & 2u) != 0u);
}

fn power2(a: f32, b: f32) -> f32 {
    return a * a / (a * a + b * b);
}

fn max3(v: vec3<f32>) -> f32 {
    return max(v.x, max(v.y, v.z));
}

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}
