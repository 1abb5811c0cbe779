// ---- wavefront pass: baked_lights ----
// One thread per sample of the wave (the first queue: every slot): the shadow rays of its
// light samples at the baked point (trace.wgsl's baked_visibility), whose visibility mask
// accumulate then reads — so those rays run in parallel over all samples instead of one
// after another in each job's accumulate thread (measured: accumulate was 36–62% of the
// wavefront's GPU time on the H200 before).

@compute @workgroup_size(64)
fn wf_baked_lights(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let q = flat_id(gid, nwg);
    if (q >= atomicLoad(&wave[WAVE_LENGTH])) {
        return;
    }
    let slot = queue[q];
    let job = slot_jobs[slot];
    baked_vis[slot] = baked_visibility(first_vertex(job.x, job.y));
}
