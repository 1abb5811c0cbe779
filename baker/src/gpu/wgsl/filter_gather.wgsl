// ---- filtered gather-based accumulation ([Roughton19 §3.2, Listing 3.2]; CPU twin
// baker::filter::gather_batch) ----
// The bake kernel writes one record per sample — the point sample's direction and
// encoder weight, its radiance, its plain estimate, its continuous atlas position and the
// light samples' known projections Q_k — into the item's own `slots` records: slot
// pass − first pass of the dispatch (uniform passes), or sample index mod slots (a batch
// of adaptive or camera-based sampling, whose samples of an item are consecutive and at
// most `slots`). The records are thus grouped by item (the paths sorted by texel) and
// item i's start at i·slots with its sample count known (the dispatch's passes, or the
// batch's per-item count): the offset buffer of Listing 3.1 for this layout.
// filter_gather then runs one thread per gather target (every texel a chart overlaps):
// the texels of its chart within the filter's reach in row-major order — per pass for
// uniform passes; once, each neighbour's samples in order, for a batch — each record
// weighted by the separable filter of its position's offset from the target's centre
// into the target's own encoders (weight × filter weight) and weighted Welford moments.
// The encoders' side (Q_k ↔ record, a target's states ↔ private variables, the update on
// them) is in bases.wgsl.


#import baker::bases::{encode_filtered, filter_load_q, filtered_load, filtered_store}
#import baker::bindings::moments
#import baker::filter_bindings::{FILTER_NONE, FP, fmoments, fsamples, ftables}
#import baker::filter_kernel::filter_kernel_1d
#ifdef BATCH
#import baker::jobs::batch_samples_of
#endif

@compute @workgroup_size(64)
fn filter_gather(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let j = (wid.x + wid.y * FP.row) * 64u + lid.x;
    if (j >= FP.target_count) {
        return;
    }
    let t = ftables[j];
    let chart = ftables[FP.charts_offset + t];
    let x = i32(t % FP.width);
    let y = i32(t / FP.width);
    let centre = vec2<f32>(f32(x) + 0.5, f32(y) + 0.5);
    let reach = i32(FP.reach);
    let plane = FP.slots * FP.items;
    filtered_load(j);
    var m0 = fmoments[3u * j];
    var m1 = fmoments[3u * j + 1u];
    var m2 = fmoments[3u * j + 2u];
    let rounds = select(FP.passes, 1u, FP.batch == 1u);
    for (var q = 0u; q < rounds; q++) {
        for (var ny = max(y - reach, 0); ny <= min(y + reach, i32(FP.height) - 1); ny++) {
            for (var nx = max(x - reach, 0); nx <= min(x + reach, i32(FP.width) - 1); nx++) {
                let n = u32(ny) * FP.width + u32(nx);
                let item = ftables[FP.items_offset + n];
                if (ftables[FP.charts_offset + n] != chart || item == FILTER_NONE) {
                    continue;
                }
                // Uniform passes: the record of pass q. A batch: the item's samples in it,
                // in order — its first is its sample count before the batch.
                var first = q;
                var count = 1u;
#ifdef BATCH
                if (FP.batch == 1u) {
                    count = batch_samples_of(item);
                    let had = moments[3u * item].w + moments[3u * item + 1u].w + moments[3u * item + 2u].x;
                    first = u32(had) - count;
                }
#endif
                for (var s = 0u; s < count; s++) {
                    let at = ((first + s) % FP.slots) * FP.items + item;
                    let r0 = fsamples[at];
                    if (!(r0.w > 0.0)) {
                        continue;
                    }
                    let r1 = fsamples[at + plane];
                    let r2 = fsamples[at + 2u * plane];
                    let d = vec2<f32>(r1.w, r2.w) - centre;
                    let wf = filter_kernel_1d(FP.kernel, FP.radius, d.x) * filter_kernel_1d(FP.kernel, FP.radius, d.y);
                    if (wf == 0.0) {
                        continue;
                    }
                    if (wf < 0.0) {
                        // Mitchell's negative lobes: not gathered (baker::filter says why).
                        m2.y += 1.0;
                        continue;
                    }
                    // Weighted Welford (West 1979): W += w; δ = x − mean; mean += (w/W)·δ;
                    // M2 += w·δ·(x − mean').
                    m2.x += 1.0;
                    m0.w += wf;
                    m1.w += wf * wf;
                    let delta = r2.xyz - m0.xyz;
                    let mean = m0.xyz + (wf / m0.w) * delta;
                    m1 = vec4<f32>(m1.xyz + wf * delta * (r2.xyz - mean), m1.w);
                    m0 = vec4<f32>(mean, m0.w);
                    filter_load_q(at, plane);
                    encode_filtered(r0.xyz, r1.xyz, r0.w * wf);
                }
            }
        }
    }
    filtered_store(j);
    fmoments[3u * j] = m0;
    fmoments[3u * j + 1u] = m1;
    fmoments[3u * j + 2u] = m2;
}
