// Shared by scan.wgsl, compact.wgsl and offsets.wgsl (prepended): the item count and the
// workgroups per row of the 2D dispatch (counts above 65 535 blocks), padded to 16 bytes.

struct GridParams {
    n: u32,
    row: u32,
    _pad0: u32,
    _pad1: u32,
}
