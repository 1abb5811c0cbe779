// The workgroup block scan of scan.wgsl and sort.wgsl: an in-place inclusive scan of the
// 256-entry workgroup array `block_tmp`. Contains barriers: every invocation of the
// workgroup must call it. Two variants, the shader def SUBGROUPS choosing:
// - workgroup memory (Hillis–Steele, log2 256 = 8 steps);
// - subgroups (the device needs Features::SUBGROUP): each subgroup scans its values with
//   subgroupInclusiveAdd, then adds the totals of the subgroups before it, read from
//   workgroup memory. Assumes what the tests check on each device: subgroups are equal runs
//   of consecutive invocation indices (found from subgroupMin/subgroupMax of the index) in
//   index order.

#define_import_path prims::block_scan

var<workgroup> block_tmp: array<u32, 256>;

#ifdef SUBGROUPS
fn block_inclusive_scan(lane: u32) {
    let v = block_tmp[lane];
    let incl = subgroupInclusiveAdd(v);
    let lo = subgroupMin(lane);
    let size = subgroupMax(lane) - lo + 1u;
    workgroupBarrier();
    block_tmp[lane] = incl;
    workgroupBarrier();
    // The last entry of every earlier subgroup is that subgroup's total.
    var base = 0u;
    for (var k = lo; k > 0u; k -= size) {
        base += block_tmp[k - 1u];
    }
    workgroupBarrier();
    block_tmp[lane] = incl + base;
    workgroupBarrier();
}
#else
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
#endif
