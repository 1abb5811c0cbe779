// Offset buffer ([Roughton19], §3.2, Listing 3.1): for paths sorted by texel, offsets[t] is the
// index of the first path of texel t, for every texel that has paths; `offsets` (texel
// count + 1 entries) must be filled with the sentinel 0xFFFFFFFF first. Thread j compares
// its path's texel with the previous one: at a change it writes j at its own texel and at
// the previous texel + 1 (which closes the previous range when texels are skipped); the
// last thread closes its range with the path count. Reading: texel t has no paths if
// offsets[t] or offsets[t + 1] is the sentinel or they are equal; else its paths are
// [offsets[t], offsets[t + 1]).

#import prims::grid::GridParams

@group(0) @binding(0) var<storage, read> path_texels: array<u32>;
@group(0) @binding(1) var<storage, read_write> offsets: array<u32>;
@group(0) @binding(2) var<uniform> params: GridParams;

@compute @workgroup_size(256)
fn generate_offsets(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let j = (wid.x + wid.y * params.row) * 256u + lid.x;
    if (j >= params.n) {
        return;
    }
    let t = path_texels[j];
    if (j == 0u) {
        offsets[t] = 0u;
    } else {
        let prev = path_texels[j - 1u];
        if (t > prev) {
            offsets[t] = j;
            offsets[prev + 1u] = j;
        }
    }
    if (j + 1u == params.n) {
        offsets[t + 1u] = params.n;
    }
}
