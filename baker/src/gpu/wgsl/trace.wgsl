// trace.wgsl — the GPU twin of baker::trace (seed 004 ch. 6): BVH traversal of the
// CPU-built nodes (no hardware ray queries), and the path-traced estimator of incoming
// radiance. At the baked point: the point sample plus next-event estimation of every
// delta light (directional, point, spot), one emitter by power and one environment
// direction by luminance × solid angle, both MIS-weighted (power heuristic, Veach 1997
// §9.2) against the point sample; the light samples reach the encoders as known
// projections (`project`, generated per bake). Along the path: the same NEE with MIS
// against BSDF sampling, Russian roulette from the third bounce. Shadow rays start at
// the offset point (offset_ray) and aim from it. Material: Lambert + GGX layers added
// (§6.3.1), layer chosen with the stored probability, mixture pdf. A point sample whose
// first hit is a single-sided back face is rejected and counted (validity).
// Needs from `shaders`: tangent_frame, PI, INV_PI; the GGX layer's functions come from
// glossy.wgsl (or its leave-out twin when no material in the scene is glossy).

struct Node {
    min: vec3<f32>,
    left_first: u32,
    max: vec3<f32>,
    count: u32,
}

struct Tri {
    v0: vec3<f32>,
    material: u32,
    e1: vec3<f32>,
    mesh: u32,
    e2: vec3<f32>,
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
    // 1: this dispatch runs an adaptive batch (its items listed by adapt_batch.wgsl).
    batch_mode: u32,
    pad1: u32,
    pad2: u32,
    env0: vec4<f32>,
    env1: vec4<f32>,
    env2: vec4<f32>,
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
// Per item, 3 vec4: (Σ E/π (or Σ L for probes), accepted count), (Σ of squares,
// back-face count), (non-finite count, 0, 0, 0). Counts are exact up to 2²⁴ passes.
@group(0) @binding(6) var<storage, read_write> moments: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> states: array<EncoderState>;
// Rays traced: primary, extension, shadow (only when P.count_rays = 1).
@group(0) @binding(8) var<storage, read_write> counters: array<atomic<u32>, 4>;

struct Material {
    diffuse: vec3<f32>,
    specular_probability: f32,
    f0: vec3<f32>,
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

// ---- random numbers: sampler.wgsl (composed after this file) ----


// ---- traversal ----

fn slab(n: Node, o: vec3<f32>, inv: vec3<f32>, tmax: f32) -> f32 {
    let t0 = (n.min - o) * inv;
    let t1 = (n.max - o) * inv;
    let lo = min(t0, t1);
    let hi = max(t0, t1);
    let near = max(max(lo.x, lo.y), max(lo.z, 0.0));
    let far = min(min(hi.x, hi.y), min(hi.z, tmax));
    return select(T_FAR, near, near <= far);
}

// Möller–Trumbore, two-sided; t in (0, tmax) or T_FAR (CPU twin: bvh::intersect_tri).
fn intersect_tri(tri: Tri, o: vec3<f32>, d: vec3<f32>, tmax: f32) -> f32 {
    let p = cross(d, tri.e2);
    let det = dot(tri.e1, p);
    if (abs(det) < 1e-12) {
        return T_FAR;
    }
    let inv = 1.0 / det;
    let s = o - tri.v0;
    let u = dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) {
        return T_FAR;
    }
    let q = cross(s, tri.e1);
    let v = dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) {
        return T_FAR;
    }
    let t = dot(tri.e2, q) * inv;
    return select(T_FAR, t, t > 0.0 && t < tmax);
}

// Closest hit (any = false) or any hit (any = true) within (0, tmax).
fn traverse(o: vec3<f32>, d: vec3<f32>, tmax: f32, any: bool) -> Hit {
    var best = Hit(tmax, NO_HIT);
    // Guard 1/d against zero components (the CPU's IEEE ∞ gives the same slabs).
    let dd = select(d, vec3<f32>(1e-30), abs(d) < vec3<f32>(1e-30));
    let inv = 1.0 / dd;
    var stack: array<u32, 64>;
    var sp = 1u;
    stack[0] = 0u;
    while (sp > 0u) {
        sp -= 1u;
        let n = nodes[stack[sp]];
        if (n.count > 0u) {
            for (var k = n.left_first; k < n.left_first + n.count; k++) {
                let t = intersect_tri(tris[k], o, d, best.t);
                if (t < best.t) {
                    best = Hit(t, k);
                    if (any) {
                        return best;
                    }
                }
            }
            continue;
        }
        let a = n.left_first;
        let b = a + 1u;
        let ta = slab(nodes[a], o, inv, best.t);
        let tb = slab(nodes[b], o, inv, best.t);
        let hit_a = ta < T_FAR;
        let hit_b = tb < T_FAR;
        if (hit_a && hit_b) {
            let near_a = ta <= tb;
            stack[sp] = select(a, b, near_a);
            stack[sp + 1u] = select(b, a, near_a);
            sp += 2u;
        } else if (hit_a) {
            stack[sp] = a;
            sp += 1u;
        } else if (hit_b) {
            stack[sp] = b;
            sp += 1u;
        }
    }
    return best;
}

fn count_ray(k: u32) {
    if (P.count_rays == 1u) {
        atomicAdd(&counters[k], 1u);
    }
}

// ---- scene ----

fn environment(d: vec3<f32>) -> vec3<f32> {
    switch P.env_kind {
        case ENV_CONSTANT: {
            return P.env0.xyz;
        }
        case ENV_SKY: {
            if (d.y >= 0.0) {
                return mix(P.env1.xyz, P.env0.xyz, sqrt(d.y));
            }
            return P.env2.xyz;
        }
        case ENV_MAP: {
            // Nearest texel (CPU twin: scene::latlong_texel).
            let w = P.env_width;
            let h = w / 2u;
            let u = 0.5 * (1.0 + atan2(d.x, -d.z) / PI);
            let v = acos(clamp(d.y, -1.0, 1.0)) / PI;
            let i = min(u32(u * f32(w)), w - 1u);
            let j = min(u32(v * f32(h)), h - 1u);
            return aux[P.env_offset + j * w + i].xyz;
        }
        default: {
            return vec3<f32>(0.0);
        }
    }
}

// Ray origin moved off a surface towards the side of unit n (Wächter & Binder, Ray
// Tracing Gems ch. 6): 256 ulps per coordinate along n, 1/65536 of n near the origin.
// CPU twin: baker::lights::offset_ray.
fn offset_ray(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let k = vec3<i32>(n * 256.0);
    let pi = bitcast<vec3<f32>>(bitcast<vec3<i32>>(p) + select(k, -k, p < vec3<f32>(0.0)));
    return select(pi, p + n * (1.0 / 65536.0), abs(p) < vec3<f32>(1.0 / 32.0));
}

fn offset_towards(p: vec3<f32>, n: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    return offset_ray(p, select(-n, n, dot(dir, n) >= 0.0));
}

// ---- lights ----

// A delta light seen from o: direction towards it, irradiance at normal incidence, and
// the shadow-ray length, all from o (CPU twin: baker::lights::delta_at); e = 0: nothing.
struct DeltaLight {
    wi: vec3<f32>,
    e: vec3<f32>,
    dist: f32,
}

fn delta_at(k: u32, o: vec3<f32>) -> DeltaLight {
    let a = aux[P.light_offset + 4u * k];
    let c = aux[P.light_offset + 4u * k + 1u];
    let kind = u32(a.w);
    if (kind == LIGHT_DIRECTIONAL) {
        return DeltaLight(a.xyz, c.xyz, T_FAR);
    }
    let to = a.xyz - o;
    let d2 = dot(to, to);
    if (!(d2 > 0.0)) {
        return DeltaLight(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0);
    }
    let d = sqrt(d2);
    let wi = to / d;
    // KHR_lights_punctual range window clamp(1 − (d/range)⁴, 0, 1)², none if range < 0.
    var w = 1.0;
    if (c.w > 0.0) {
        let r = pow(d / c.w, 4.0);
        w = pow(clamp(1.0 - r, 0.0, 1.0), 2.0);
    }
    if (kind == LIGHT_SPOT) {
        let s = aux[P.light_offset + 4u * k + 2u];
        let co = aux[P.light_offset + 4u * k + 3u].x;
        let scale = 1.0 / max(s.w - co, 1e-3);
        let t = clamp((dot(-wi, s.xyz) - co) * scale, 0.0, 1.0);
        w *= t * t;
    }
    return DeltaLight(wi, c.xyz * (w / d2), d);
}

// Whether a shadow ray from offset origin o reaches delta light k (aimed and measured
// from o; CPU twin: Tracer::visible_delta).
fn visible_delta(k: u32, o: vec3<f32>) -> bool {
    let a = aux[P.light_offset + 4u * k];
    count_ray(2u);
    if (u32(a.w) == LIGHT_DIRECTIONAL) {
        return traverse(o, a.xyz, T_FAR, true).tri == NO_HIT;
    }
    let to = a.xyz - o;
    let d = length(to);
    return traverse(o, to / d, d * (1.0 - 1e-4), true).tri == NO_HIT;
}

// Whether a shadow ray from offset origin o reaches point q (stopped 1e-4 relative short
// of q; CPU twin: Tracer::visible_point).
fn visible_point(o: vec3<f32>, q: vec3<f32>) -> bool {
    let to = q - o;
    let d = length(to);
    count_ray(2u);
    return d > 0.0 && traverse(o, to / d, d * (1.0 - 1e-4), true).tri == NO_HIT;
}

// An emitter point chosen by power: triangle index and point (CPU twin: pick_emitter).
struct EmitterPoint {
    tri: u32,
    q: vec3<f32>,
}

// An emitter by power (u.x) and a point uniform on it (u.y, u.z).
fn pick_emitter(u3: vec3<f32>) -> EmitterPoint {
    let u = u3.x;
    var a = u3.y;
    var b = u3.z;
    // Binary search of the CDF (first entry ≥ u).
    var lo = 0u;
    var hi = P.emitter_count - 1u;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (aux[P.emitter_offset + mid].y < u) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let ti = bitcast<u32>(aux[P.emitter_offset + lo].x);
    let tri = tris[ti];
    if (a + b > 1.0) {
        a = 1.0 - a;
        b = 1.0 - b;
    }
    return EmitterPoint(ti, tri.v0 + tri.e1 * a + tri.e2 * b);
}

// Solid-angle pdf of NEE reaching a point of emitter `le` at distance t, cosine cos_l:
// selection pdf / area = luminance / total power (the area cancels).
fn emitter_pdf(le: vec3<f32>, t: f32, cos_l: f32) -> f32 {
    return max(luminance(le), 1e-12) * P.inv_total_power * t * t / cos_l;
}

// Environment importance sampling (CPU twin: baker::lights::EnvSampler).
fn env_cell_solid_angle(j: u32) -> f32 {
    let h = f32(P.env_cdf_height);
    return 2.0 * PI / f32(P.env_cdf_width) * (cos(PI * f32(j) / h) - cos(PI * f32(j + 1u) / h));
}

struct EnvSample {
    wi: vec3<f32>,
    pdf: f32,
}

fn env_sample(u: vec3<f32>) -> EnvSample {
    let w = P.env_cdf_width;
    let h = P.env_cdf_height;
    if (w == 0u) {
        return EnvSample(vec3<f32>(0.0, 1.0, 0.0), 0.0);
    }
    // First row (then column) whose CDF exceeds u.
    var lo = 0u;
    var hi = h - 1u;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (aux[P.env_rows_offset + mid].x <= u.x) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let j = lo;
    let row = P.env_cells_offset + j * w;
    lo = 0u;
    hi = w - 1u;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (aux[row + mid].x <= u.y) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let i = lo;
    let c_lo = select(0.0, aux[row + i - 1u].x, i > 0u);
    let c_hi = aux[row + i].x;
    let f = select(0.5, clamp((u.y - c_lo) / (c_hi - c_lo), 0.0, 1.0), c_hi > c_lo);
    let c0 = cos(PI * f32(j) / f32(h));
    let c1 = cos(PI * f32(j + 1u) / f32(h));
    let ct = c0 + (c1 - c0) * u.z;
    let phi = (2.0 * (f32(i) + f) / f32(w) - 1.0) * PI;
    let st = sqrt(max(1.0 - ct * ct, 0.0));
    let wi = vec3<f32>(st * sin(phi), ct, -st * cos(phi));
    return EnvSample(wi, aux[row + i].y / env_cell_solid_angle(j));
}

fn env_pdf(d: vec3<f32>) -> f32 {
    let w = P.env_cdf_width;
    if (w == 0u) {
        return 0.0;
    }
    let h = P.env_cdf_height;
    let u = 0.5 * (1.0 + atan2(d.x, -d.z) / PI);
    let v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    let i = min(u32(u * f32(w)), w - 1u);
    let j = min(u32(v * f32(h)), h - 1u);
    return aux[P.env_cells_offset + j * w + i].y / env_cell_solid_angle(j);
}

// A next-event sample of an area light seen from x (CPU twin: Tracer::area_samples):
// direction, radiance, solid-angle pdf (0: none), the emitter point (goal) a shadow ray must
// reach, and whether that target is a point (else the unbounded environment).
struct AreaSample {
    wi: vec3<f32>,
    radiance: vec3<f32>,
    pdf: f32,
    goal: vec3<f32>,
    bounded: bool,
}

// k = 0: an emitter point by power; k = 1: an environment direction — from the vertex's
// emitter and environment groups.
fn area_sample(k: u32, x: vec3<f32>, smp: Sampler) -> AreaSample {
    if (k == 0u) {
        if (P.emitter_count == 0u) {
            return AreaSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, vec3<f32>(0.0), true);
        }
        let em = pick_emitter(sample4(smp, USE_EMITTER).xyz);
        let tri = tris[em.tri];
        let to = em.q - x;
        let dist = length(to);
        let wi = to / dist;
        let cos_l = -dot(wi, normalize(cross(tri.e1, tri.e2)));
        if (!(cos_l > 0.0)) {
            return AreaSample(wi, vec3<f32>(0.0), 0.0, em.q, true);
        }
        let le = load_material(tri.material).emissive;
        return AreaSample(wi, le, emitter_pdf(le, dist, cos_l), em.q, true);
    }
    let es = env_sample(sample4(smp, USE_ENVIRONMENT).xyz);
    if (!(es.pdf > 0.0)) {
        return AreaSample(es.wi, vec3<f32>(0.0), 0.0, vec3<f32>(0.0), false);
    }
    return AreaSample(es.wi, environment(es.wi), es.pdf, vec3<f32>(0.0), false);
}

// Whether a shadow ray from offset origin o reaches an area sample (CPU twin: visible).
fn visible_area(o: vec3<f32>, a: AreaSample) -> bool {
    if (a.bounded) {
        return visible_point(o, a.goal);
    }
    count_ray(2u);
    return traverse(o, a.wi, T_FAR, true).tri == NO_HIT;
}

fn to_local(w: vec3<f32>, f: array<vec3<f32>, 2>, n: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(w, f[0]), dot(w, f[1]), dot(w, n));
}

// Concentric disk → cosine-weighted hemisphere (Shirley & Chiu 1997; CPU twin
// sbf::sampling::cosine_hemisphere).
fn cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let a = 2.0 * u - vec2<f32>(1.0);
    var p = vec2<f32>(0.0);
    if (a.x != 0.0 || a.y != 0.0) {
        if (abs(a.x) > abs(a.y)) {
            let phi = (PI / 4.0) * (a.y / a.x);
            p = a.x * vec2<f32>(cos(phi), sin(phi));
        } else {
            let phi = PI / 2.0 - (PI / 4.0) * (a.x / a.y);
            p = a.y * vec2<f32>(cos(phi), sin(phi));
        }
    }
    return vec3<f32>(p, sqrt(max(1.0 - dot(p, p), 0.0)));
}

// (f, pdf) of the layered material for unit wo, wi about shading normal ns.
struct BsdfValue {
    f: vec3<f32>,
    pdf: f32,
}

fn eval_bsdf(m: Material, ns: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> BsdfValue {
    let ci = dot(wi, ns);
    let co = dot(wo, ns);
    if (ci <= 0.0 || co <= 0.0) {
        return BsdfValue(vec3<f32>(0.0), 0.0);
    }
    var f = m.diffuse * INV_PI;
    var pdf = (1.0 - m.specular_probability) * ci * INV_PI;
    if (m.glossy) {
        let fr = tangent_frame(ns);
        let g = glossy_eval(to_local(wo, fr, ns), to_local(wi, fr, ns), m.alpha, m.f0);
        f += g.f;
        pdf += m.specular_probability * g.pdf;
    }
    return BsdfValue(f, pdf);
}

struct BsdfSample {
    wi: vec3<f32>,
    f: vec3<f32>,
    pdf: f32,
}

// Samples wi (pdf 0 when the sample is lost: below the surface or zero throughput).
// u = (layer choice, 2D direction).
fn sample_bsdf(m: Material, ns: vec3<f32>, wo: vec3<f32>, u3: vec3<f32>) -> BsdfSample {
    let choose = u3.x;
    let u = u3.yz;
    let fr = tangent_frame(ns);
    var local: vec3<f32>;
    if (choose < m.specular_probability) {
        local = glossy_sample(to_local(wo, fr, ns), m.alpha, u);
    } else if (m.specular_probability < 1.0) {
        local = cosine_hemisphere(u);
    } else {
        return BsdfSample(vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    }
    let wi = normalize(fr[0] * local.x + fr[1] * local.y + ns * local.z);
    let e = eval_bsdf(m, ns, wo, wi);
    if (!(e.pdf > 0.0) || max3(e.f) <= 0.0) {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0);
    }
    return BsdfSample(wi, e.f, e.pdf);
}

// Next-event estimation at p (shading normal ns facing wo): one emitter by power and one
// environment direction, MIS against the BSDF; every delta light. Shadow rays start at
// the offset point and aim from it.
fn direct(p: vec3<f32>, ns: vec3<f32>, wo: vec3<f32>, m: Material, smp: Sampler) -> vec3<f32> {
    var l = vec3<f32>(0.0);
    let o = offset_ray(p, ns);
    for (var k = 0u; k < 2u; k++) {
        let a = area_sample(k, p, smp);
        let cos_i = dot(a.wi, ns);
        if (a.pdf > 0.0 && cos_i > 0.0) {
            let e = eval_bsdf(m, ns, wo, a.wi);
            if (max3(e.f) > 0.0 && visible_area(o, a)) {
                l += e.f * a.radiance * (cos_i * power2(a.pdf, e.pdf) / a.pdf);
            }
        }
    }
    for (var k = 0u; k < P.light_count; k++) {
        let dl = delta_at(k, p);
        let cos_i = dot(dl.wi, ns);
        if (cos_i <= 0.0 || max3(dl.e) <= 0.0) {
            continue;
        }
        let f = eval_bsdf(m, ns, wo, dl.wi).f;
        if (max3(f) > 0.0) {
            if (visible_delta(k, o)) {
                l += f * dl.e * cos_i;
            }
        }
    }
    return l;
}

// A path's state between its segments (also the wavefront's per-path record, 64 bytes):
// the next segment's origin and direction, the pdf of the sample that chose it (≤ 0:
// counted fully), the hit index of that segment (bounce), throughput and gathered
// radiance, and the flags below.
struct PathState {
    o: vec3<f32>,
    prev_pdf: f32,
    d: vec3<f32>,
    bounce: u32,
    throughput: vec3<f32>,
    flags: u32,
    radiance: vec3<f32>,
    pad: u32,
}

// A first hit on a single-sided back face ends the path and sets PATH_BACK.
const PATH_REJECT_BACK: u32 = 1u;
const PATH_BACK: u32 = 2u;

// The path from origin o along unit dir. first_pdf > 0: the pdf of the strategy that
// chose dir (MIS at the first hit); reject_back: see PATH_REJECT_BACK.
fn path_start(origin: vec3<f32>, dir: vec3<f32>, first_pdf: f32, reject_back: bool) -> PathState {
    return PathState(origin, first_pdf, dir, 0u, vec3<f32>(1.0), select(0u, PATH_REJECT_BACK, reject_back), vec3<f32>(0.0), 0u);
}

struct PathResult {
    radiance: vec3<f32>,
    back: bool,
}

// One segment's hit (or miss) handled: environment or emission (MIS), then at a surface
// vertex next-event estimation, the BSDF sample and Russian roulette. Hit k (bounce
// k − 1) draws from vertex k of the sampler. Returns whether the path goes on (its next
// segment in st.o, st.d). Shared by the megakernel's loop (`path`) and the wavefront's
// shade pass, so both run the same estimator.
fn path_step(st: ptr<function, PathState>, hit: Hit, smp0: Sampler) -> bool {
    let bounce = (*st).bounce;
    let d = (*st).d;
    if (hit.tri == NO_HIT) {
        var w = 1.0;
        if ((*st).prev_pdf > 0.0 && P.env_cdf_width > 0u) {
            w = power2((*st).prev_pdf, env_pdf(d));
        }
        (*st).radiance += (*st).throughput * environment(d) * w;
        return false;
    }
    if (P.primary_only == 1u) {
        // Timing mode: the first segment only (its hit distance keeps the work live).
        (*st).radiance += vec3<f32>(hit.t);
        return false;
    }
    let tri = tris[hit.tri];
    let m = load_material(tri.material);
    let ng = normalize(cross(tri.e1, tri.e2));
    let front = dot(d, ng) < 0.0;
    if (bounce == 0u && ((*st).flags & PATH_REJECT_BACK) != 0u && !front && !m.double_sided) {
        (*st).radiance = vec3<f32>(0.0);
        (*st).flags |= PATH_BACK;
        return false;
    }
    if (front && max3(m.emissive) > 0.0) {
        var w = 1.0;
        if ((*st).prev_pdf > 0.0) {
            w = power2((*st).prev_pdf, emitter_pdf(m.emissive, hit.t, -dot(d, ng)));
        }
        (*st).radiance += (*st).throughput * m.emissive * w;
    }
    if (bounce == P.max_bounces) {
        return false;
    }
    let p = (*st).o + d * hit.t;
    let ns = select(-ng, ng, front);
    let wo = -d;
    var smp = smp0;
    smp.vertex = bounce + 1u;
    (*st).radiance += (*st).throughput * direct(p, ns, wo, m, smp);
    // BSDF: layer choice, direction; Russian roulette: the fourth number.
    let ub = sample4(smp, USE_DIRECTION);
    let s = sample_bsdf(m, ns, wo, ub.xyz);
    if (!(s.pdf > 0.0)) {
        return false;
    }
    var throughput = (*st).throughput * s.f * (dot(s.wi, ns) / s.pdf);
    if (!(max3(throughput) > 0.0) || max3(throughput) > 3.0e38) {
        return false;
    }
    if (bounce >= 2u) {
        let q = min(max3(throughput), 0.95);
        if (ub.w >= q) {
            return false;
        }
        throughput /= q;
    }
    (*st).throughput = throughput;
    (*st).prev_pdf = s.pdf;
    (*st).o = offset_ray(p, ns);
    (*st).d = s.wi;
    (*st).bounce = bounce + 1u;
    return true;
}

// The whole path in one thread (the megakernel).
fn path(origin: vec3<f32>, dir: vec3<f32>, first_pdf: f32, reject_back: bool, smp: Sampler) -> PathResult {
    var st = path_start(origin, dir, first_pdf, reject_back);
    loop {
        count_ray(select(1u, 0u, st.bounce == 0u));
        let hit = traverse(st.o, st.d, T_FAR, false);
        if (!path_step(&st, hit, smp)) {
            break;
        }
    }
    return PathResult(st.radiance, (st.flags & PATH_BACK) != 0u);
}

fn finite3(v: vec3<f32>) -> bool {
    // NaN fails every comparison; ±∞ exceeds the largest finite f32.
    return all(abs(v) <= vec3<f32>(3.4028235e38));
}

// Thread position v of a dispatch → its job: (item, first sample index, samples) — a
// pass range, or an adaptive batch's entry; item NO_HIT past the end.
fn job_at(v: u32) -> vec3<u32> {
    if (P.batch_mode == 1u) {
        return batch_item(v);
    }
    let w = P.item_offset + v;
    // Position w of this device's share → the item (the identity on one device).
    let i = (w / P.part_block) * P.part_block * P.part_count + P.part_index * P.part_block + w % P.part_block;
    return vec3<u32>(select(i, NO_HIT, w >= P.item_end), P.pass_index, P.pass_count);
}

// One pass: one point sample per item (texel or probe) plus its light samples, added to
// the moments and to every configured basis's progressive encoder (`encode` and
// `project`, generated per bake). CPU twin: Tracer::sample_point + Targets::item_sample.
// The megakernel: each thread takes its job through whole paths.
@compute @workgroup_size(64)
fn bake_pass(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    // One call site of bake_item keeps the kernel's code (and registers) single.
    let job = job_at(gid.x + gid.y * nwg.x * 64u);
    if (job.x == NO_HIT) {
        return;
    }
    for (var j = 0u; j < job.z; j++) {
        bake_item(job.x, job.y + j);
    }
}

// The baked point of pass `pass_index` of item i and its point sample's direction
// (CPU twin: Tracer::sample_point + Targets::item_sample).
struct FirstVertex {
    smp: Sampler,
    pos: vec3<f32>,
    // Shading normal (the texel's hemisphere and frame) and geometric normal (offsets and
    // the surface's own horizon: directions below it see the surface, radiance 0).
    nrm: vec3<f32>,
    ng: vec3<f32>,
    texel: bool,
    guided: bool,
    // The direction in the normal's frame (texels) or world space (probes), and in world.
    local: vec3<f32>,
    dir: vec3<f32>,
    // The plain estimate's weight of the path radiance, the point sample's pdf, and the
    // encoders' sample weight: 1, or (1/2π)/p for a guided point sample.
    weight: f32,
    p_s: f32,
    w_enc: f32,
    // The path's origin, and whether it is traced at all (texels: dir above the surface).
    origin: vec3<f32>,
    traced: bool,
    // The pass, and the point's continuous atlas position (filtered accumulation).
    pass_index: u32,
    uv: vec2<f32>,
}

fn first_vertex(i: u32, pass_index: u32) -> FirstVertex {
    let it = items[i];
    var smp = sampler_new(it.z, pass_index);
    if (P.guide_phase != 0u) {
        // A guided bake's numbers: the stage's own.
        smp = sampler_staged(smp, P.guide_stage, P.guide_start);
    }
    // The baked point's direction group (u₀, u₁ direction, u₃ guided mixture choice); the
    // sub-texel point from the sample index.
    let u4 = sample4(smp, USE_DIRECTION);
    let k = it.x + pass_index % it.y;
    let pos = points[3u * k].xyz;
    let nrm = points[3u * k + 1u].xyz;
    let ng = points[3u * k + 2u].xyz;
    let uv = vec2<f32>(points[3u * k + 1u].w, points[3u * k + 2u].w);
    let texel = P.mode == 0u;
    var local: vec3<f32>;
    var dir: vec3<f32>;
    var weight: f32;
    var p_s: f32;
    var w_enc = 1.0;
    let guided = texel && P.guide_phase == 2u;
    if (texel) {
        let fr = tangent_frame(nrm);
        let ud = u4.xy;
        let choice = u4.w;
        if (guided && choice < GUIDED_FRACTION) {
            // The guided component of the mixture.
            local = guide_sample(it.w, ud);
        } else {
            // Uniform hemisphere about the normal (pdf 1/2π).
            let z = 1.0 - ud.x;
            let r = sqrt(max(1.0 - z * z, 0.0));
            let phi = 2.0 * PI * ud.y;
            local = vec3<f32>(r * cos(phi), r * sin(phi), z);
        }
        dir = normalize(fr[0] * local.x + fr[1] * local.y + nrm * local.z);
        // E/π sample = L·cosθ/(π·p): 2·L·cosθ for the uniform pdf.
        weight = 2.0 * local.z;
        p_s = 0.5 * INV_PI;
        if (guided) {
            p_s = guide_pdf(it.w, local);
            weight = local.z * INV_PI / p_s;
            w_enc = 0.5 * INV_PI / p_s;
        }
    } else {
        // Uniform sphere in world space (probes): the sample is L itself.
        let z = 1.0 - 2.0 * u4.x;
        let r = sqrt(max(1.0 - z * z, 0.0));
        let phi = 2.0 * PI * u4.y;
        local = vec3<f32>(r * cos(phi), r * sin(phi), z);
        dir = local;
        weight = 1.0;
        p_s = 0.25 * INV_PI;
    }
    let origin = select(pos, offset_towards(pos, ng, dir), texel);
    let traced = !texel || dot(dir, ng) > 0.0;
    return FirstVertex(smp, pos, nrm, ng, texel, guided, local, dir, weight, p_s, w_enc, origin, traced, pass_index, uv);
}

// Pass `pass_index` of item i: the point sample's path, then the rest (megakernel).
fn bake_item(i: u32, pass_index: u32) {
    let fv = first_vertex(i, pass_index);
    if (P.primary_only == 1u) {
        // Timing mode: the first segment only; keep the result live with one write.
        let l = path(fv.origin, fv.dir, 0.0, false, fv.smp).radiance;
        moments[3u * i] += vec4<f32>(l, 0.0);
        return;
    }
    var pr = PathResult(vec3<f32>(0.0), false);
    if (fv.traced) {
        pr = path(fv.origin, fv.dir, fv.p_s, true, fv.smp);
    }
    finish_item(i, fv, pr);
}

// The rest of a pass of item i once its point sample's path radiance is known (the
// megakernel's tail and the wavefront's accumulate pass): the light samples at the baked
// point, then the moments, the encoders and ray guiding's records.
fn finish_item(i: u32, fv: FirstVertex, pr: PathResult) {
    project_reset();
    guide_clear(i);
    let it = items[i];
    let texel = fv.texel;
    let pos = fv.pos;
    let nrm = fv.nrm;
    let ng = fv.ng;
    let p_s = fv.p_s;
    let fr = tangent_frame(nrm);
    let out = i;
    // Light samples at the baked point: (ω_l, c = L·w/p·V) → the plain estimate gains
    // c·cosθ/π (texels) or c·p_s (probes); the encoders gain p_s·c at ω_l.
    var e_lights = vec3<f32>(0.0);
    var finite = true;
    for (var k = 0u; k < P.light_count; k++) {
        let dl = delta_at(k, pos);
        if (max3(dl.e) <= 0.0 || (texel && (dot(dl.wi, nrm) <= 0.0 || dot(dl.wi, ng) <= 0.0))) {
            continue;
        }
        if (visible_delta(k, select(pos, offset_towards(pos, ng, dl.wi), texel))) {
            let ld = select(dl.wi, to_local(dl.wi, fr, nrm), texel);
            e_lights += dl.e * select(p_s, max(ld.z, 0.0) * INV_PI, texel);
            finite = finite && finite3(dl.e);
            project(ld, dl.e * p_s);
        }
    }
    // One emitter point by power and one environment direction, MIS against the point
    // sample.
    for (var a_k = 0u; a_k < 2u; a_k++) {
        let a = area_sample(a_k, pos, fv.smp);
        if (a.pdf > 0.0 && (!texel || (dot(a.wi, nrm) > 0.0 && dot(a.wi, ng) > 0.0))) {
            if (visible_area(select(pos, offset_towards(pos, ng, a.wi), texel), a)) {
                let ld = select(a.wi, to_local(a.wi, fr, nrm), texel);
                // MIS against the point-sample strategy's pdf at ω_l.
                let p_point = select(p_s, guide_pdf(it.w, ld), fv.guided);
                let c = a.radiance * (power2(a.pdf, p_point) / a.pdf);
                if (texel) {
                    // Learning: this sample's estimate of the bin's (1/2π)·∫L cosθ.
                    guide_record(i, 1u + a_k, ld, luminance(c) * 0.5 * INV_PI);
                }
                e_lights += c * select(p_s, max(ld.z, 0.0) * INV_PI, texel);
                finite = finite && finite3(c);
                project(ld, c * p_s);
            }
        }
    }
    if (pr.back) {
        moments[3u * out + 1u].w += 1.0;
        guide_clear(i);
        filter_record(i, fv, vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
        return;
    }
    let e = pr.radiance * fv.weight + e_lights;
    if (!(finite && finite3(pr.radiance) && finite3(e) && finite3(e * e))) {
        moments[3u * out + 2u].x += 1.0;
        guide_clear(i);
        filter_record(i, fv, vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
        return;
    }
    moments[3u * out] += vec4<f32>(e, 1.0);
    moments[3u * out + 1u] += vec4<f32>(e * e, 0.0);
    encode(out, fv.local, pr.radiance, fv.w_enc);
    filter_record(i, fv, pr.radiance, e, fv.w_enc);
    if (texel) {
        guide_record(i, 0u, fv.local, luminance(pr.radiance) * fv.w_enc);
    }
}
