// Ray guiding's build with subgroup prefix sums ([HWRTL]: WavePrefixSum per row, then
// over the row totals). Prepended: guide_common.wgsl (naga 30 takes subgroup built-ins
// without `enable subgroups;`; the device needs `Features::SUBGROUP`). Used where
// every subgroup holds whole rows: sizes ≥ 16 (the host checks the adapter's minimum), a
// row being 16 consecutive invocations of the 1D workgroup.
#import baker::guide_common::{BINS, BIN_COUNT, CDF_LEN, G, guide_dist, relax, rows}


@compute @workgroup_size(256)
fn guide_build(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_index) b: u32,
    @builtin(subgroup_invocation_id) lane: u32,
) {
    let c = wid.x + wid.y * nwg.x;
    let live = c < G.cluster_count;
    let v = relax(c, b);
    let at = min(c, max(G.cluster_count, 1u) - 1u) * CDF_LEN;
    let x = b % BINS;
    let y = b / BINS;
    // Row prefix sums: the subgroup's inclusive scan minus its value just before the row.
    let incl = subgroupInclusiveAdd(v);
    let first = lane - x;
    let before = subgroupShuffle(incl, max(first, 1u) - 1u);
    let prefix = incl - select(0.0, before, first > 0u);
    let row_total = subgroupShuffle(prefix, first + BINS - 1u);
    if (live) {
        var o = f32(x + 1u) / f32(BINS);
        if (x == BINS - 1u) {
            o = 1.0;
        } else if (row_total > 0.0) {
            o = prefix / row_total;
        }
        guide_dist[at + b] = o;
    }
    if (x == BINS - 1u) {
        rows[y] = row_total;
    }
    workgroupBarrier();
    // The marginal: a scan of the 16 row totals in the first subgroup (invocations 0–15).
    let r = select(0.0, rows[min(b, BINS - 1u)], b < BINS);
    let m = subgroupInclusiveAdd(r);
    let total = subgroupShuffle(m, BINS - 1u);
    if (live && b < BINS) {
        guide_dist[at + BIN_COUNT + b] = select(m / total, 1.0, b == BINS - 1u);
    }
}
