// vertex.wgsl — the baked point of a pass and its point sample's direction: uniform over
// the texel's hemisphere or the probe's sphere, or with the shader def GUIDING from the
// learned mixture (CPU twin: Tracer::sample_point + Targets::item_sample).

#define_import_path baker::vertex

#import baker::bindings::{P, items, points, points_hi}
#import baker::lights::offset_towards
#import baker::sequence::{Sampler, USE_DIRECTION, sample4, sampler_new, sampler_staged}
#import sbf::runtime::{INV_PI, PI, tangent_frame}
#ifdef GUIDING
#import baker::guide::{guide_pdf, guide_sample, guided_fraction}
#endif

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

// Part c (0 position, 1 shading normal + u, 2 geometric normal + v) of sample point k, from
// whichever of the two bindings holds it.
fn point_part(k: u32, c: u32) -> vec4<f32> {
    if (k < P.point_split) {
        return points[3u * k + c];
    }
    return points_hi[3u * (k - P.point_split) + c];
}

fn first_vertex(i: u32, pass_index: u32) -> FirstVertex {
    let it = items[i];
    var smp = sampler_new(P.seed, it.z, pass_index);
    if (P.guide_phase != 0u) {
        // A guided bake's numbers: the stage's own.
        smp = sampler_staged(smp, P.guide_stage, P.guide_start);
    }
    // The baked point's direction group (u₀, u₁ direction, u₃ guided mixture choice); the
    // sub-texel point from the sample index.
    let u4 = sample4(smp, USE_DIRECTION);
    let k = it.x + pass_index % it.y;
    let p0 = point_part(k, 0u);
    let p1 = point_part(k, 1u);
    let p2 = point_part(k, 2u);
    let pos = p0.xyz;
    let nrm = p1.xyz;
    let ng = p2.xyz;
    let uv = vec2<f32>(p1.w, p2.w);
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
        var uniform = true;
#ifdef GUIDING
        if (guided && choice < guided_fraction()) {
            // The guided component of the mixture.
            local = guide_sample(it.w, ud);
            uniform = false;
        }
#endif
        if (uniform) {
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
#ifdef GUIDING
        if (guided) {
            p_s = guide_pdf(it.w, local);
            weight = local.z * INV_PI / p_s;
            w_enc = 0.5 * INV_PI / p_s;
        }
#endif
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
