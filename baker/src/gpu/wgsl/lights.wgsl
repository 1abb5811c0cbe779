// lights.wgsl — the environment, ray offsets, delta lights, emitters by power and the
// environment's importance sampler (CPU twins in baker::scene::lights and
// baker::sampling::environment), and the area samples next-event estimation draws.

#define_import_path baker::lights

#import baker::bindings::{ENV_CONSTANT, ENV_MAP, ENV_SKY, LIGHT_DIRECTIONAL, LIGHT_SPOT, NO_HIT, P, T_FAR, aux, load_material, luminance, tris}
#import baker::sequence::{Sampler, USE_EMITTER, USE_ENVIRONMENT, sample4}
#import baker::traverse::{count_ray, traverse}
#ifdef TEXTURES
#import baker::maps::{select_emission, textured_material}
#endif
#import sbf::runtime::PI

fn environment(d: vec3<f32>) -> vec3<f32> {
    switch P.env_kind {
        case ENV_CONSTANT: {
            return P.env_zenith.xyz;
        }
        case ENV_SKY: {
            if (d.y >= 0.0) {
                return mix(P.env_horizon.xyz, P.env_zenith.xyz, sqrt(d.y));
            }
            return P.env_ground.xyz;
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
    // Barycentric coordinates of q.
    b: vec2<f32>,
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
    return EmitterPoint(ti, tri.corner + tri.edge_u * a + tri.edge_v * b, vec2<f32>(a, b));
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
        let cos_l = -dot(wi, normalize(cross(tri.edge_u, tri.edge_v)));
        if (!(cos_l > 0.0)) {
            return AreaSample(wi, vec3<f32>(0.0), 0.0, em.q, true);
        }
#ifdef TEXTURES
        let le = textured_material(tri.material, em.tri, em.b).emissive;
        return AreaSample(wi, le, emitter_pdf(select_emission(tri.material, em.tri, le), dist, cos_l), em.q, true);
#else
        let le = load_material(tri.material).emissive;
        return AreaSample(wi, le, emitter_pdf(le, dist, cos_l), em.q, true);
#endif
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
