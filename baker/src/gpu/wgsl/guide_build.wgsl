// One thread per cluster adds this pass's records of its items, in item order (three per
// item): the same sums on every run (no atomics).
#import baker::guide_common::{BINS, BIN_COUNT, CDF_LEN, G, cluster_items, guide_dist, guide_rec, guide_sums, relax, rows, value}

@compute @workgroup_size(64)
fn guide_gather(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let c = gid.x + gid.y * nwg.x * 64u;
    if (c >= G.cluster_count) {
        return;
    }
    let first = cluster_items[c];
    let last = cluster_items[c + 1u];
    for (var k = first; k < last; k++) {
        let item = cluster_items[G.cluster_count + 1u + k];
        // The point sample's record, then the emitter's and the environment's.
        for (var slot = 0u; slot < 3u; slot++) {
            let r = guide_rec[3u * item + slot];
            if (r.x != 0xffffffffu) {
                guide_sums[c * BIN_COUNT + r.x] += bitcast<f32>(r.y);
            }
        }
    }
}

// One workgroup per cluster: quadtree relaxation, then the conditional and marginal CDFs
// by serial sums in workgroup memory (the fallback where subgroups are missing or
// narrower than a row of 16 bins).
@compute @workgroup_size(256)
fn guide_build(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) b: u32) {
    let c = wid.x + wid.y * nwg.x;
    let live = c < G.cluster_count;
    value[b] = relax(c, b);
    workgroupBarrier();
    let at = min(c, max(G.cluster_count, 1u) - 1u) * CDF_LEN;
    if (live && b < BINS) {
        var acc = 0.0;
        for (var k = 0u; k < BINS; k++) {
            acc += value[b * BINS + k];
            value[b * BINS + k] = acc;
        }
        rows[b] = acc;
        for (var k = 0u; k < BINS; k++) {
            var o = f32(k + 1u) / f32(BINS);
            if (k == BINS - 1u) {
                o = 1.0;
            } else if (acc > 0.0) {
                o = value[b * BINS + k] / acc;
            }
            guide_dist[at + b * BINS + k] = o;
        }
    }
    workgroupBarrier();
    if (live && b == 0u) {
        var acc = 0.0;
        for (var k = 0u; k < BINS; k++) {
            acc += rows[k];
            value[k] = acc;
        }
        for (var k = 0u; k < BINS; k++) {
            guide_dist[at + BIN_COUNT + k] = select(value[k] / acc, 1.0, k == BINS - 1u);
        }
    }
}
