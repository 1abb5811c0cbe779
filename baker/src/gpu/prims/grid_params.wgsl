// The parameters of scan.wgsl, compact.wgsl and offsets.wgsl: the item count and the
// workgroups per row of the 2D dispatch (counts above 65 535 blocks), padded to 16 bytes.

#define_import_path prims::grid

struct GridParams {
    n: u32,
    row: u32,
    pad_a: u32,
    pad_b: u32,
}
