// Shared by scan.wgsl and sort.wgsl (prepended to each): an in-place inclusive scan of the
// 256-entry workgroup array `block_tmp` (Hillis–Steele, log2 256 = 8 steps). Contains
// barriers: every invocation of the workgroup must call it.

var<workgroup> block_tmp: array<u32, 256>;

fn block_inclusive_scan(lane: u32) {
    for (var off = 1u; off < 256u; off = off * 2u) {
        var t = 0u;
        if (lane >= off) {
            t = block_tmp[lane - off];
        }
        workgroupBarrier();
        block_tmp[lane] = block_tmp[lane] + t;
        workgroupBarrier();
    }
}
