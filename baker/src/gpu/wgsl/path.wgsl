// path.wgsl — the GPU twin of baker::estimator::trace ([Roughton19 ch. 6]): BVH traversal of the
// CPU-built nodes (no hardware ray queries), and the path-traced estimator of incoming
// radiance. At the baked point: the point sample plus next-event estimation of every
// delta light (directional, point, spot), one emitter by power and one environment
// direction by luminance × solid angle, both MIS-weighted (power heuristic, Veach 1997
// §9.2) against the point sample; the light samples reach the encoders as known
// projections (`project`, bases.wgsl). Along the path: the same NEE with MIS
// against BSDF sampling, Russian roulette from the third bounce. Shadow rays start at
// the offset point (offset_ray) and aim from it. Material: Lambert + GGX layers added
// (§6.3.1), layer chosen with the stored probability, mixture pdf. A point sample whose
// first hit is a single-sided back face is rejected and counted (validity).
// Needs from `shaders`: tangent_frame, PI, INV_PI.

#define_import_path baker::path

#import baker::bindings::{Hit, Material, NO_HIT, P, T_FAR, load_material, max3, power2, tris}
#import baker::bsdf::{eval_bsdf, sample_bsdf}
#import baker::lights::{area_sample, delta_at, emitter_pdf, env_pdf, environment, offset_ray, visible_area, visible_delta}
#import baker::sequence::{Sampler, USE_DIRECTION, sample4}
#import baker::traverse::{count_ray, traverse}
#ifdef TEXTURES
#import baker::maps::{barycentrics, select_emission, textured_material}
#endif

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
        if (bounce > 0u || P.indirect_only == 0u) {
            (*st).radiance += (*st).throughput * environment(d) * w;
        }
        return false;
    }
    if (P.primary_only == 1u) {
        // Timing mode: the first segment only (its hit distance keeps the work live).
        (*st).radiance += vec3<f32>(hit.t);
        return false;
    }
    let tri = tris[hit.tri];
#ifdef TEXTURES
    let m = textured_material(tri.material, hit.tri, barycentrics(tri, (*st).o + d * hit.t));
    let le_share = select_emission(tri.material, hit.tri, m.emissive);
#else
    let m = load_material(tri.material);
    let le_share = m.emissive;
#endif
    let ng = normalize(cross(tri.edge_u, tri.edge_v));
    let front = dot(d, ng) < 0.0;
    if (bounce == 0u && ((*st).flags & PATH_REJECT_BACK) != 0u && !front && !m.double_sided) {
        (*st).radiance = vec3<f32>(0.0);
        (*st).flags |= PATH_BACK;
        return false;
    }
    if (front && max3(m.emissive) > 0.0 && (bounce > 0u || P.indirect_only == 0u)) {
        var w = 1.0;
        if ((*st).prev_pdf > 0.0) {
            w = power2((*st).prev_pdf, emitter_pdf(le_share, hit.t, -dot(d, ng)));
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
