// item.wgsl — the rest of a pass once its point sample's path radiance is known (the
// megakernel's tail and the wavefront's accumulate pass): light samples at the baked
// point, moments, encoders, ray guiding's records and (FILTERED) the filter's record.

#define_import_path baker::item

#import baker::bases::{encode, project, project_reset}
#import baker::bindings::{P, items, luminance, max3, moments, power2}
#import baker::bsdf::to_local
#import baker::lights::{area_sample, delta_at, offset_towards, visible_area, visible_delta}
#import baker::path::PathResult
#import baker::vertex::FirstVertex
#import sbf::runtime::{INV_PI, tangent_frame}
#ifdef GUIDING
#import baker::guide::{guide_clear, guide_pdf, guide_record}
#endif
#ifdef FILTERED
#import baker::filter_bindings::{FP, fsamples}
#import baker::bases::filter_store_q
#endif

fn finite3(v: vec3<f32>) -> bool {
    // NaN fails every comparison; ±∞ exceeds the largest finite f32 (3.40282346e38 is it
    // exactly; 3.4028235e38 lies above it, which tint rejects).
    return all(abs(v) <= vec3<f32>(3.40282346e38));
}

#ifdef FILTERED
// The record of pass fv.pass_index of item i; w = 0 marks a sample that is not gathered
// (back face, not finite).
fn filter_record(i: u32, fv: FirstVertex, l: vec3<f32>, e: vec3<f32>, w: f32) {
    var slot = fv.pass_index - P.pass_index;
    if (P.batch_mode == 1u) {
        slot = fv.pass_index % FP.slots;
    }
    let at = slot * FP.items + i;
    let plane = FP.slots * FP.items;
    fsamples[at] = vec4<f32>(fv.local, w);
    fsamples[at + plane] = vec4<f32>(l, fv.uv.x);
    fsamples[at + 2u * plane] = vec4<f32>(e, fv.uv.y);
    if (w > 0.0) {
        filter_store_q(at, plane);
    }
}
#endif

// A rejected sample (back face, not finite) leaves no guiding record and a filter record
// of weight 0 (not gathered); the caller counts it in the item's moments.
fn reject_sample(i: u32, fv: FirstVertex) {
#ifdef GUIDING
    guide_clear(i);
#endif
#ifdef FILTERED
    filter_record(i, fv, vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
#endif
}

// The rest of a pass of item i once its point sample's path radiance is known (the
// megakernel's tail and the wavefront's accumulate pass): the light samples at the baked
// point, then the moments, the encoders and ray guiding's records.
fn finish_item(i: u32, fv: FirstVertex, pr: PathResult) {
    project_reset();
#ifdef GUIDING
    guide_clear(i);
#endif
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
    let lights = select(P.light_count, 0u, P.indirect_only != 0u);
    for (var k = 0u; k < lights; k++) {
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
    let areas = select(2u, 0u, P.indirect_only != 0u);
    for (var a_k = 0u; a_k < areas; a_k++) {
        let a = area_sample(a_k, pos, fv.smp);
        if (a.pdf > 0.0 && (!texel || (dot(a.wi, nrm) > 0.0 && dot(a.wi, ng) > 0.0))) {
            if (visible_area(select(pos, offset_towards(pos, ng, a.wi), texel), a)) {
                let ld = select(a.wi, to_local(a.wi, fr, nrm), texel);
                // MIS against the point-sample strategy's pdf at ω_l.
#ifdef GUIDING
                let p_point = select(p_s, guide_pdf(it.w, ld), fv.guided);
#else
                let p_point = p_s;
#endif
                let c = a.radiance * (power2(a.pdf, p_point) / a.pdf);
#ifdef GUIDING
                if (texel) {
                    // Learning: this sample's estimate of the bin's (1/2π)·∫L cosθ.
                    guide_record(i, 1u + a_k, ld, luminance(c) * 0.5 * INV_PI);
                }
#endif
                e_lights += c * select(p_s, max(ld.z, 0.0) * INV_PI, texel);
                finite = finite && finite3(c);
                project(ld, c * p_s);
            }
        }
    }
    if (pr.back) {
        moments[3u * out + 1u].w += 1.0;
        reject_sample(i, fv);
        return;
    }
    let e = pr.radiance * fv.weight + e_lights;
    if (!(finite && finite3(pr.radiance) && finite3(e) && finite3(e * e))) {
        moments[3u * out + 2u].x += 1.0;
        reject_sample(i, fv);
        return;
    }
    moments[3u * out] += vec4<f32>(e, 1.0);
    moments[3u * out + 1u] += vec4<f32>(e * e, 0.0);
    encode(out, fv.local, pr.radiance, fv.w_enc);
#ifdef FILTERED
    filter_record(i, fv, pr.radiance, e, fv.w_enc);
#endif
#ifdef GUIDING
    if (texel) {
        guide_record(i, 0u, fv.local, luminance(pr.radiance) * fv.w_enc);
    }
#endif
}
