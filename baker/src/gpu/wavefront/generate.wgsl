// ---- wavefront pass: generate ([Roughton19 §5.1]) ----
// One thread per job of the dispatch (the megakernel's job_at): its samples take
// consecutive slots of the path pool (a workgroup scan of the counts, one atomic per
// workgroup); each slot gets the first segment of its point sample's path, and enters
// the first queue at its own position.

#import baker::bindings::{NO_HIT, P}
#import baker::jobs::job_at
#import baker::path::{PathState, path_start}
#import baker::vertex::first_vertex
#import baker::wave::{PATH_DONE, WAVE_OVERFLOW, WAVE_SLOTS, flat_id, jobs, path_keys, paths, queue, wave}

var<workgroup> wg_counts: array<u32, 64>;
var<workgroup> wg_base: u32;

@compute @workgroup_size(64)
fn wf_generate(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
    @builtin(num_workgroups) nwg: vec3<u32>,
) {
    let v = flat_id(gid, nwg);
    var job = vec3<u32>(NO_HIT, 0u, 0u);
    if (v < arrayLength(&jobs)) {
        job = job_at(v);
    }
    let count = select(job.z, 0u, job.x == NO_HIT);
    // Exclusive scan of the counts in workgroup memory (Hillis–Steele, inclusive, shifted).
    wg_counts[lid] = count;
    workgroupBarrier();
    for (var s = 1u; s < 64u; s = s << 1u) {
        var add = 0u;
        if (lid >= s) {
            add = wg_counts[lid - s];
        }
        workgroupBarrier();
        wg_counts[lid] += add;
        workgroupBarrier();
    }
    if (lid == 63u) {
        wg_base = atomicAdd(&wave[WAVE_SLOTS], wg_counts[63]);
    }
    let base = workgroupUniformLoad(&wg_base);
    if (v >= arrayLength(&jobs)) {
        return;
    }
    var first = base + wg_counts[lid] - count;
    var n = count;
    if (first + n > arrayLength(&paths)) {
        // The pool is full (the host sizes it so that this cannot happen): report.
        atomicAdd(&wave[WAVE_OVERFLOW], n);
        n = 0u;
        first = 0u;
    }
    jobs[v] = vec4<u32>(job.x, job.y, n, first);
    for (var j = 0u; j < n; j++) {
        let slot = first + j;
        let fv = first_vertex(job.x, job.y + j);
        var st: PathState;
        if (P.primary_only == 1u) {
            st = path_start(fv.origin, fv.dir, 0.0, false);
        } else {
            st = path_start(fv.origin, fv.dir, fv.p_s, true);
            if (!fv.traced) {
                st.flags |= PATH_DONE;
            }
        }
        paths[slot] = st;
        path_keys[slot] = vec2<u32>(fv.smp.key, fv.smp.index);
        queue[slot] = slot;
    }
}
