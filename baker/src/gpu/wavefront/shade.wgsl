// ---- wavefront pass: shade ([Roughton19 §5.1]) ----
// One thread per active path of the queue: its hit handled by the megakernel's own
// path_step (environment or emission, next-event estimation with its shadow rays, the
// BSDF sample, Russian roulette); the flag says whether the path stays in the queue.

#import baker::bindings::Hit
#import baker::path::path_step
#import baker::sequence::Sampler
#import baker::wave::{PATH_DONE, WAVE_LENGTH, flat_id, hits, path_flags, path_keys, paths, queue, wave}

@compute @workgroup_size(64)
fn wf_shade(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let q = flat_id(gid, nwg);
    if (q >= atomicLoad(&wave[WAVE_LENGTH])) {
        return;
    }
    let slot = queue[q];
    var st = paths[slot];
    var goes_on = false;
    if ((st.flags & PATH_DONE) == 0u) {
        let h = hits[slot];
        let k = path_keys[slot];
        goes_on = path_step(&st, Hit(bitcast<f32>(h.x), h.y), Sampler(k.x, k.y, 0u));
        if (!goes_on) {
            st.flags |= PATH_DONE;
        }
        paths[slot] = st;
    }
    path_flags[q] = select(0u, 1u, goes_on);
}
