// ---- wavefront pass: accumulate ([Roughton19 §5.1]) ----
// One thread per job of the dispatch: its samples in order (the progressive encoder's
// ordering, §7.3.1), each the megakernel's finish_item with the path radiance its slot
// gathered — the light samples at the baked point, the moments, the encoders, guiding.

#import baker::bindings::NO_HIT
#import baker::item::finish_item
#import baker::path::{PATH_BACK, PathResult}
#import baker::vertex::first_vertex
#import baker::wave::{flat_id, jobs, paths}

@compute @workgroup_size(64)
fn wf_accumulate(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let v = flat_id(gid, nwg);
    if (v >= arrayLength(&jobs)) {
        return;
    }
    let job = jobs[v];
    if (job.x == NO_HIT) {
        return;
    }
    for (var j = 0u; j < job.z; j++) {
        let st = paths[job.w + j];
        let fv = first_vertex(job.x, job.y + j);
        finish_item(job.x, fv, PathResult(st.radiance, (st.flags & PATH_BACK) != 0u));
    }
}
