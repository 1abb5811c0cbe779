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
    pad_a: u32,
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

@compute @workgroup_size(64)
fn reference_pass(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let j = gid.x + gid.y * nwg.x * 64u;
    if (j >= R.count) {
        return;
    }
    let a = surfaces[3u * j];
    let b = surfaces[3u * j + 1u];
    let c = surfaces[3u * j + 2u];
    let pixel = bitcast<u32>(a.w);
    let mi = bitcast<u32>(b.w);
    var sd = vec3<f32>(0.0);
    var ss = vec3<f32>(0.0);
    var st = vec3<f32>(0.0);
    var qd = vec3<f32>(0.0);
    var qs = vec3<f32>(0.0);
    var qt = vec3<f32>(0.0);
    var n = 0u;
    for (var i = 0u; i < R.samples; i++) {
        let r = reference_sample(a.xyz, b.xyz, c.xyz, mi, pixel, R.first + i);
        if (r.accepted) {
            let t = r.d + r.s;
            sd += r.d;
            ss += r.s;
            st += t;
            qd += r.d * r.d;
            qs += r.s * r.s;
            qt += t * t;
            n += 1u;
        }
    }
    let o = 7u * j;
    sums[o] = vec4<f32>(sd, 0.0);
    sums[o + 1u] = vec4<f32>(ss, 0.0);
    sums[o + 2u] = vec4<f32>(st, 0.0);
    sums[o + 3u] = vec4<f32>(qd, 0.0);
    sums[o + 4u] = vec4<f32>(qs, 0.0);
    sums[o + 5u] = vec4<f32>(qt, 0.0);
    sums[o + 6u] = vec4<f32>(f32(n), 0.0, 0.0, 0.0);
}
