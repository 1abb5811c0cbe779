// Ray guiding's kernels (baker::guiding, CPU twins `record`/`build`): the parts shared by
// the gather, the workgroup build (guide_build.wgsl) and the subgroup build
// (guide_build_subgroup.wgsl).

#define_import_path baker::guide_common

struct GuideParams {
    cluster_count: u32,
    pad_a: u32,
    pad_b: u32,
    pad_c: u32,
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

// The quadtree relaxation of cluster c's sums (c clamped to a real cluster), every
// invocation b one bin: its smoothed value (1 everywhere for a cluster without light).
// Call from uniform control flow (barriers).
fn relax(c: u32, b: u32) -> f32 {
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
    return v;
}
