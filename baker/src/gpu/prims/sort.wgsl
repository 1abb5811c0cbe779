// One pass of a stable LSD radix sort of (key, value) u32 pairs by the 4-bit digit at
// `shift`: `histogram` counts each 256-element block's digits into counts[digit · blocks +
// block]; those counts are scanned (scan.wgsl) into global offsets; `scatter` writes each
// pair to offset[digit, block] + its rank among the block's pairs with that digit (a
// workgroup scan per digit, block_scan.wgsl: stable). Workgroup memory only (no
// subgroup operations).

#import prims::block_scan::{block_inclusive_scan, block_tmp}

struct SortParams {
    n: u32,
    row: u32,
    shift: u32,
    blocks: u32,
}

@group(0) @binding(0) var<storage, read> keys_in: array<u32>;
@group(0) @binding(1) var<storage, read> vals_in: array<u32>;
@group(0) @binding(2) var<storage, read_write> keys_out: array<u32>;
@group(0) @binding(3) var<storage, read_write> vals_out: array<u32>;
@group(0) @binding(4) var<storage, read_write> counts: array<u32>;
@group(0) @binding(5) var<uniform> params: SortParams;

const BLOCK: u32 = 256u;
const RADIX: u32 = 16u;
var<workgroup> hist: array<atomic<u32>, 16>;

@compute @workgroup_size(256)
fn histogram(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let block = wid.x + wid.y * params.row;
    if (lid.x < RADIX) {
        atomicStore(&hist[lid.x], 0u);
    }
    workgroupBarrier();
    let i = block * BLOCK + lid.x;
    if (i < params.n) {
        atomicAdd(&hist[(keys_in[i] >> params.shift) & 15u], 1u);
    }
    workgroupBarrier();
    if (lid.x < RADIX && block < params.blocks) {
        counts[lid.x * params.blocks + block] = atomicLoad(&hist[lid.x]);
    }
}

@compute @workgroup_size(256)
fn scatter(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let block = wid.x + wid.y * params.row;
    let i = block * BLOCK + lid.x;
    let live = i < params.n;
    var digit = RADIX;
    if (live) {
        digit = (keys_in[i] >> params.shift) & 15u;
    }
    for (var d = 0u; d < RADIX; d = d + 1u) {
        let f = select(0u, 1u, digit == d);
        block_tmp[lid.x] = f;
        workgroupBarrier();
        block_inclusive_scan(lid.x);
        if (f == 1u && block < params.blocks) {
            let dst = counts[d * params.blocks + block] + block_tmp[lid.x] - 1u;
            keys_out[dst] = keys_in[i];
            vals_out[dst] = vals_in[i];
        }
        workgroupBarrier();
    }
}
