// reference.wgsl — the path-traced reference on the GPU (CPU twin:
// baker::render::reference::sample). At each pixel's visible surface x, viewed along ω_o:
// L_o = ∫ (f_d + f_s)(ω_o, ω_i) L_in(x, ω_i) cos θ_i dω_i, with L_in from the bake's own
// estimator at x — every delta light, one emitter point by power and one environment
// direction, MIS-weighted (power heuristic, Veach 1997 §9.2) against the point sample,
// which is drawn from the visible material's BSDF and traced by the bake's path
// (`path`, path.wgsl). Lambert and GGX parts are kept apart. Per (pixel, sample)
// independent random numbers (the bake's white-noise sequence: SEQUENCE = 1), so the
// sample variance estimates the noise. A point sample whose first hit is the back of a
// single-sided surface rejects the sample, as the bake rejects it.
// One thread per (surface, sample): a dispatch lays each surface's samples in a slot of
// SLOT consecutive threads (a power of two dividing the workgroup) and sums them in
// workgroup memory, so no thread loops over samples. (llvmpipe/lavapipe give each
// invocation 65 535 loop iterations in all — gallivm's loop limiter — and then end every
// loop early: a thread that looped over 64 samples of a deep BVH lost its last samples,
// eight lanes at a time, and cut the traversal of the sample it was in.)
// Group 0: the bake's bindings (bindings.wgsl); group 1: the surfaces and the sums.

#import baker::bindings::{P, load_material, max3, power2}
#import baker::bsdf::{eval_bsdf, sample_bsdf}
#import baker::lights::{area_sample, delta_at, offset_towards, visible_area, visible_delta}
#import baker::path::path
#import baker::sequence::{USE_DIRECTION, sample4, sampler_new}
#import sbf::runtime::INV_PI

struct RefParams {
    eye: vec3<f32>,
    // Surfaces in this dispatch (one thread each).
    count: u32,
    // Samples [first, first + samples) of every surface.
    first: u32,
    samples: u32,
    // Threads per surface: a power of two ≥ samples, dividing 64.
    slot: u32,
    pad_b: u32,
}

@group(1) @binding(0) var<uniform> R: RefParams;
// Per surface, 3 vec4: (position, pixel index as bits), (shading normal, material as
// bits), (geometric normal, 0).
@group(1) @binding(1) var<storage, read> surfaces: array<vec4<f32>>;
// Per surface, 7 vec4 over this dispatch's samples: Σ diffuse, Σ specular, Σ total, then
// their squares, then (accepted samples, 0, 0, 0).
@group(1) @binding(2) var<storage, read_write> sums: array<vec4<f32>>;

struct Split {
    d: vec3<f32>,
    s: vec3<f32>,
}

// (Lambert part, GGX part) of the material's f for (ω_o, ω_i): 0 below either horizon.
fn split_bsdf(m_index: u32, ns: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> Split {
    let m = load_material(m_index);
    if (dot(wi, ns) <= 0.0 || dot(wo, ns) <= 0.0) {
        return Split(vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let f = eval_bsdf(m, ns, wo, wi).f;
    let fd = m.diffuse * INV_PI;
    return Split(fd, f - fd);
}

struct RefSample {
    d: vec3<f32>,
    s: vec3<f32>,
    accepted: bool,
}

// One sample of (diffuse, specular) reflected radiance (CPU twin: reference::sample).
fn reference_sample(x: vec3<f32>, ns: vec3<f32>, ng: vec3<f32>, mi: u32, pixel: u32, index: u32) -> RefSample {
    var r = RefSample(vec3<f32>(0.0), vec3<f32>(0.0), true);
    let wo = normalize(R.eye - x);
    if (dot(wo, ng) <= 0.0 || dot(wo, ns) <= 0.0) {
        return r;
    }
    let m = load_material(mi);
    let smp = sampler_new(P.seed, pixel, index);
    let drawn = sample_bsdf(m, ns, wo, sample4(smp, USE_DIRECTION).xyz);
    // Light samples at x: inside the hemisphere of both normals, shadow rays from the
    // point offset to the side they leave.
    let lights = select(P.light_count, 0u, P.indirect_only != 0u);
    for (var k = 0u; k < lights; k++) {
        let dl = delta_at(k, x);
        if (dot(dl.wi, ns) > 0.0 && dot(dl.wi, ng) > 0.0 && max3(dl.e) > 0.0 && visible_delta(k, offset_towards(x, ng, dl.wi))) {
            let b = split_bsdf(mi, ns, wo, dl.wi);
            let w = dl.e * dot(dl.wi, ns);
            r.d += b.d * w;
            r.s += b.s * w;
        }
    }
    let areas = select(2u, 0u, P.indirect_only != 0u);
    for (var a_k = 0u; a_k < areas; a_k++) {
        let a = area_sample(a_k, x, smp);
        if (a.pdf > 0.0 && dot(a.wi, ns) > 0.0 && dot(a.wi, ng) > 0.0 && visible_area(offset_towards(x, ng, a.wi), a)) {
            let c = a.radiance * (power2(a.pdf, eval_bsdf(m, ns, wo, a.wi).pdf) / a.pdf);
            let b = split_bsdf(mi, ns, wo, a.wi);
            let w = c * dot(a.wi, ns);
            r.d += b.d * w;
            r.s += b.s * w;
        }
    }
    // The point sample: none drawn, or between the shading and the geometric horizon
    // (the surface occludes), adds nothing.
    if (drawn.pdf > 0.0 && dot(drawn.wi, ng) > 0.0) {
        let pr = path(offset_towards(x, ng, drawn.wi), drawn.wi, drawn.pdf, true, smp);
        if (pr.back) {
            r.accepted = false;
            return r;
        }
        let b = split_bsdf(mi, ns, wo, drawn.wi);
        let w = pr.radiance * (dot(drawn.wi, ns) / drawn.pdf);
        r.d += b.d * w;
        r.s += b.s * w;
    }
    return r;
}

// The seven sums of each thread's sample, then of its slot (tree reduction).
var<workgroup> partial: array<vec4<f32>, 448>;

@compute @workgroup_size(64)
fn reference_pass(@builtin(local_invocation_index) lid: u32, @builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let t = lid + 64u * (wg.x + wg.y * nwg.x);
    let j = t / R.slot;
    let i = t % R.slot;
    var v: array<vec4<f32>, 7>;
    for (var c = 0u; c < 7u; c++) {
        v[c] = vec4<f32>(0.0);
    }
    if (j < R.count && i < R.samples) {
        let a = surfaces[3u * j];
        let b = surfaces[3u * j + 1u];
        let c = surfaces[3u * j + 2u];
        let r = reference_sample(a.xyz, b.xyz, c.xyz, bitcast<u32>(b.w), bitcast<u32>(a.w), R.first + i);
        if (r.accepted) {
            let tot = r.d + r.s;
            v[0] = vec4<f32>(r.d, 0.0);
            v[1] = vec4<f32>(r.s, 0.0);
            v[2] = vec4<f32>(tot, 0.0);
            v[3] = vec4<f32>(r.d * r.d, 0.0);
            v[4] = vec4<f32>(r.s * r.s, 0.0);
            v[5] = vec4<f32>(tot * tot, 0.0);
            v[6] = vec4<f32>(1.0, 0.0, 0.0, 0.0);
        }
    }
    for (var c = 0u; c < 7u; c++) {
        partial[64u * c + lid] = v[c];
    }
    for (var stride = R.slot / 2u; stride > 0u; stride /= 2u) {
        workgroupBarrier();
        if (i < stride) {
            for (var c = 0u; c < 7u; c++) {
                partial[64u * c + lid] += partial[64u * c + lid + stride];
            }
        }
    }
    if (i == 0u && j < R.count) {
        for (var c = 0u; c < 7u; c++) {
            sums[7u * j + c] = partial[64u * c + lid];
        }
    }
}
