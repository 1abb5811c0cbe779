// Exclusive prefix sum of u32 (wrapping), one 256-element block per workgroup
// (block_scan.wgsl), block totals written out for the next level;
// then the scanned totals added back. Every invocation reaches every barrier (no early
// return): the control flow around barriers is uniform.

#import prims::block_scan::{block_inclusive_scan, block_tmp}
#import prims::grid::GridParams

@group(0) @binding(0) var<storage, read_write> data: array<u32>;
@group(0) @binding(1) var<storage, read_write> sums: array<u32>;
@group(0) @binding(2) var<uniform> params: GridParams;

const BLOCK: u32 = 256u;

@compute @workgroup_size(256)
fn scan_blocks(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let block = wid.x + wid.y * params.row;
    let i = block * BLOCK + lid.x;
    var v = 0u;
    if (i < params.n) {
        v = data[i];
    }
    block_tmp[lid.x] = v;
    workgroupBarrier();
    block_inclusive_scan(lid.x);
    if (i < params.n) {
        data[i] = block_tmp[lid.x] - v;
    }
    if (lid.x == BLOCK - 1u && block * BLOCK < params.n) {
        sums[block] = block_tmp[BLOCK - 1u];
    }
}

@compute @workgroup_size(256)
fn add_offsets(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let block = wid.x + wid.y * params.row;
    let i = block * BLOCK + lid.x;
    if (i < params.n) {
        data[i] = data[i] + sums[block];
    }
}
