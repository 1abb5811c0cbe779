// Ray guiding's gather and build kernels (baker::guiding, CPU twins `record`/`build`).

struct GuideParams {
    cluster_count: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var<uniform> G: GuideParams;
// CSR: cluster_count + 1 offsets, then the items of every cluster in ascending order.
@group(0) @binding(1) var<storage, read> cluster_items: array<u32>;
@group(0) @binding(2) var<storage, read> guide_rec: array<vec2<u32>>;
@group(0) @binding(3) var<storage, read_write> guide_sums: array<f32>;
@group(0) @binding(4) var<storage, read_write> guide_dist: array<f32>;

const BINS: u32 = 16u;
const BIN_COUNT: u32 = 256u;
const CDF_LEN: u32 = 272u;

// One thread per cluster adds this pass's records of its items, in item order (three per
// item): the same sums on every run (no atomics).
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

var<workgroup> lv0: array<f32, 256>;
var<workgroup> lv1: array<f32, 64>;
var<workgroup> lv2: array<f32, 16>;
var<workgroup> lv3: array<f32, 4>;
var<workgroup> lv4: array<f32, 1>;
var<workgroup> value: array<f32, 256>;
var<workgroup> rows: array<f32, 16>;

// Mean of the 2×2 children of cell (x, y) at a level of side `side` (children side 2·side).
fn quad(b: u32, side: u32, level: u32) -> f32 {
    let x = b % side;
    let y = b / side;
    let s = 2u * side;
    let i = 2u * y * s + 2u * x;
    switch level {
        case 1u: {
            return ((lv0[i] + lv0[i + 1u]) + (lv0[i + s] + lv0[i + s + 1u])) * 0.25;
        }
        case 2u: {
            return ((lv1[i] + lv1[i + 1u]) + (lv1[i + s] + lv1[i + s + 1u])) * 0.25;
        }
        case 3u: {
            return ((lv2[i] + lv2[i + 1u]) + (lv2[i + s] + lv2[i + s + 1u])) * 0.25;
        }
        default: {
            return ((lv3[i] + lv3[i + 1u]) + (lv3[i + s] + lv3[i + s + 1u])) * 0.25;
        }
    }
}

// One workgroup per cluster: quadtree relaxation, conditional and marginal CDFs.
@compute @workgroup_size(256)
fn guide_build(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) b: u32) {
    let c = wid.x + wid.y * nwg.x;
    let live = c < G.cluster_count;
    let cc = min(c, max(G.cluster_count, 1u) - 1u);
    lv0[b] = max(guide_sums[cc * BIN_COUNT + b], 0.0);
    workgroupBarrier();
    if (b < 64u) {
        lv1[b] = quad(b, 8u, 1u);
    }
    workgroupBarrier();
    if (b < 16u) {
        lv2[b] = quad(b, 4u, 2u);
    }
    workgroupBarrier();
    if (b < 4u) {
        lv3[b] = quad(b, 2u, 3u);
    }
    workgroupBarrier();
    if (b == 0u) {
        lv4[0] = quad(0u, 1u, 4u);
    }
    workgroupBarrier();
    let total = lv4[0];
    let x = b % BINS;
    let y = b / BINS;
    var v = 1.0;
    if (total > 0.0) {
        v = 0.5 * lv0[b] + 0.25 * lv1[(y >> 1u) * 8u + (x >> 1u)] + 0.125 * lv2[(y >> 2u) * 4u + (x >> 2u)]
            + 0.0625 * lv3[(y >> 3u) * 2u + (x >> 3u)] + 0.0625 * lv4[0];
    }
    value[b] = v;
    workgroupBarrier();
    let at = cc * CDF_LEN;
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
