// ---- wavefront pass: intersect ([Roughton19 §5.1]) ----
// One thread per active path of the queue: the closest hit of its next segment.

#import baker::bindings::T_FAR
#import baker::traverse::{count_ray, traverse}
#import baker::wave::{PATH_DONE, WAVE_LENGTH, flat_id, hits, paths, queue, wave}

@compute @workgroup_size(64)
fn wf_intersect(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let q = flat_id(gid, nwg);
    if (q >= atomicLoad(&wave[WAVE_LENGTH])) {
        return;
    }
    let slot = queue[q];
    let st = paths[slot];
    if ((st.flags & PATH_DONE) != 0u) {
        return;
    }
    count_ray(select(1u, 0u, st.bounce == 0u));
    let hit = traverse(st.o, st.d, T_FAR, false);
    hits[slot] = vec2<u32>(bitcast<u32>(hit.t), hit.tri);
}
