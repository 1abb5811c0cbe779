// megakernel.wgsl — the bake's passes as one kernel: a thread per job takes its item
// through whole paths (the default pipeline; the wavefront runs the same functions as
// separate passes, gpu/wavefront/).

#import baker::bindings::{NO_HIT, P, moments}
#import baker::item::finish_item
#import baker::jobs::job_at
#import baker::path::{PathResult, path}
#import baker::vertex::first_vertex

// One pass: one point sample per item (texel or probe) plus its light samples, added to
// the moments and to every configured basis's progressive encoder (`encode` and
// `project`, bases.wgsl). CPU twin: Tracer::sample_point + Targets::item_sample.
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
