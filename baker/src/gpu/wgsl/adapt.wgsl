// Adaptive sampling's batch selection (CPU twin: baker::adapt). Per batch: tile_sigma
// (one workgroup per 8×8 tile: the mean per-sample σ of its texels and their sum),
// sum_tiles (one workgroup: Σ over tiles, the distribution's normaliser), select_items
// (per texel: its samples in the batch from λ = min(L, f·((1 − m)·N·s/Σ + m)) — ⌊λ⌋ plus
// one with probability λ − ⌊λ⌋ by its own Sobol' stream), then the texels with samples
// are compacted (gpu_prims) and batch_args writes the indirect dispatch.

#import baker::sequence::group_point

struct AdaptParams {
    seed: u32,
    sampler: u32,
    items: u32,
    tiles: u32,
    pad_a: u32,
    fraction: f32,
    floor: f32,
    max_per_batch: f32,
}

@group(0) @binding(0) var<uniform> P: AdaptParams;
@group(0) @binding(1) var<storage, read> moments: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> tile_items: array<u32>;
@group(0) @binding(3) var<storage, read> tile_start: array<u32>;
@group(0) @binding(4) var<storage, read_write> tile_mean: array<f32>;
@group(0) @binding(5) var<storage, read_write> tile_sum: array<f32>;
@group(0) @binding(6) var<storage, read_write> total: array<f32>;
// Per item: (tile, seed of its join stream).
@group(0) @binding(7) var<storage, read> item_info: array<vec2<u32>>;
@group(0) @binding(8) var<storage, read_write> flags: array<u32>;
// Per item, its samples in this batch (read by the bake kernel).
@group(0) @binding(12) var<storage, read_write> batch_samples: array<u32>;

// The compacted batch's length (copied from the compaction's total) and the indirect
// dispatch arguments written from it.
@group(0) @binding(9) var<storage, read> batch_len: array<u32>;
@group(0) @binding(10) var<storage, read_write> args: array<u32>;
// The batch index, advanced on the GPU by batch_args so that consecutive batches can be
// recorded into one submission.
@group(0) @binding(11) var<storage, read_write> batch_index: array<u32>;

var<workgroup> partial: array<f32, 256>;

// A texel's per-sample σ of E/π, RMS over the channels (0 below 2 samples; CPU twin
// adapt::sigma).
fn sigma(i: u32) -> f32 {
    let s = moments[3u * i];
    let q = moments[3u * i + 1u];
    let n = s.w;
    if (n < 2.0) {
        return 0.0;
    }
    let mean = s.xyz / n;
    let var3 = max(q.xyz / n - mean * mean, vec3<f32>(0.0)) * (n / (n - 1.0));
    return sqrt((var3.x + var3.y + var3.z) / 3.0);
}

@compute @workgroup_size(64)
fn tile_sigma(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let t = wid.x + wid.y * nwg.x;
    var s = 0.0;
    var n = 0u;
    if (t < P.tiles) {
        let a = tile_start[t];
        n = tile_start[t + 1u] - a;
        for (var k = lid.x; k < n; k += 64u) {
            s += sigma(tile_items[a + k]);
        }
    }
    partial[lid.x] = s;
    workgroupBarrier();
    for (var w = 32u; w > 0u; w = w >> 1u) {
        if (lid.x < w) {
            partial[lid.x] += partial[lid.x + w];
        }
        workgroupBarrier();
    }
    if (lid.x == 0u && t < P.tiles) {
        tile_sum[t] = partial[0];
        tile_mean[t] = select(0.0, partial[0] / f32(n), n > 0u);
    }
}

@compute @workgroup_size(256)
fn sum_tiles(@builtin(local_invocation_id) lid: vec3<u32>) {
    var s = 0.0;
    for (var t = lid.x; t < P.tiles; t += 256u) {
        s += tile_sum[t];
    }
    partial[lid.x] = s;
    workgroupBarrier();
    for (var w = 128u; w > 0u; w = w >> 1u) {
        if (lid.x < w) {
            partial[lid.x] += partial[lid.x + w];
        }
        workgroupBarrier();
    }
    if (lid.x == 0u) {
        total[0] = partial[0];
    }
}

@compute @workgroup_size(64)
fn select_items(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = gid.x + gid.y * nwg.x * 64u;
    if (i >= P.items) {
        return;
    }
    let info = item_info[i];
    var share = 1.0;
    if (total[0] > 0.0) {
        share = tile_mean[info.x] * f32(P.items) / total[0];
    }
    let rate = min(P.max_per_batch, P.fraction * ((1.0 - P.floor) * share + P.floor));
    let u = f32(group_point(info.y, batch_index[0]).x >> 8u) * (1.0 / 16777216.0);
    let whole = floor(rate);
    let n = u32(whole) + select(0u, 1u, u < rate - whole);
    batch_samples[i] = n;
    flags[i] = select(0u, 1u, n > 0u);
}

// Indirect dispatch of the batch: ⌈len/64⌉ workgroups as a 2D grid (x ≤ 65 535); the
// next batch's index.
@compute @workgroup_size(1)
fn batch_args() {
    batch_index[0] += 1u;
    let groups = (batch_len[0] + 63u) / 64u;
    let x = min(groups, 65535u);
    args[0] = max(x, 1u);
    args[1] = max((groups + 65534u) / 65535u, 1u);
    args[2] = 1u;
}
