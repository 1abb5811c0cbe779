// ---- wavefront pass: ray direction sorting (seed 004 §5.4) ----
// Per queue position: the octant of its path's next direction (3 bits, the thesis' choice:
// finer buckets cost a second 4-bit sort pass and did not pay there); positions past the
// queue's length get 8, so the stable radix sort (gpu_prims) keeps the active paths first,
// in their order within each octant.

@compute @workgroup_size(64)
fn wf_sort_keys(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let q = flat_id(gid, nwg);
    if (q >= arrayLength(&ray_keys)) {
        return;
    }
    var key = 8u;
    if (q < atomicLoad(&wave[WAVE_LENGTH])) {
        let d = paths[queue[q]].d;
        key = select(0u, 1u, d.x < 0.0) | select(0u, 2u, d.y < 0.0) | select(0u, 4u, d.z < 0.0);
    }
    ray_keys[q] = key;
}
