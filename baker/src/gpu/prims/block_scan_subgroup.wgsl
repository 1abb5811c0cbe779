// The subgroup variant of block_scan.wgsl (same function, same contract; the device needs
// Features::SUBGROUP): each subgroup scans its values with subgroupInclusiveAdd, then adds
// the totals of the subgroups before it, read from workgroup memory. Assumes what the
// tests check on each device: subgroups are equal runs of consecutive invocation indices
// (found from subgroupMin/subgroupMax of the index) in index order.

var<workgroup> block_tmp: array<u32, 256>;

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
