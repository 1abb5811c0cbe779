// Stream compaction: items whose flag is non-zero, in order, to the front of `outp`;
// `offsets` is the exclusive prefix sum of the flags (scan.wgsl).

#import prims::grid::GridParams

@group(0) @binding(0) var<storage, read> items: array<u32>;
@group(0) @binding(1) var<storage, read> flags: array<u32>;
@group(0) @binding(2) var<storage, read> offsets: array<u32>;
@group(0) @binding(3) var<storage, read_write> outp: array<u32>;
@group(0) @binding(4) var<uniform> params: GridParams;

@compute @workgroup_size(256)
fn scatter(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let i = (wid.x + wid.y * params.row) * 256u + lid.x;
    if (i < params.n && flags[i] != 0u) {
        outp[offsets[i]] = items[i];
    }
}
