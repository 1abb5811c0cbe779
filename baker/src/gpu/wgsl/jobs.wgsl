// jobs.wgsl — a dispatch's thread → its job (item, first sample index, samples): a range
// of passes of this device's share of the items, or, with the shader def BATCH (adaptive
// or camera-based sampling), an entry of the batch's item list.

#define_import_path baker::jobs

#import baker::bindings::{NO_HIT, P}
#ifdef BATCH
#import baker::bindings::moments
#endif

// Thread position v of a dispatch → its job: (item, first sample index, samples) — a
// pass range, or an adaptive batch's entry; item NO_HIT past the end.
fn job_at(v: u32) -> vec3<u32> {
#ifdef BATCH
    if (P.batch_mode == 1u) {
        return batch_item(v);
    }
#endif
    let w = P.item_offset + v;
    // Position w of this device's share → the item (the identity on one device).
    let i = (w / P.part_block) * P.part_block * P.part_count + P.part_index * P.part_block + w % P.part_block;
    return vec3<u32>(select(i, NO_HIT, w >= P.item_end), P.pass_index, P.pass_count);
}

#ifdef BATCH
// The batch's items (compacted by adapt.wgsl's selection), their number, and per item
// its samples in the batch.
@group(0) @binding(11) var<storage, read> batch_items: array<u32>;
@group(0) @binding(12) var<storage, read> batch_count: array<u32>;
@group(0) @binding(13) var<storage, read> batch_samples: array<u32>;

// Position v of the batch → (item, its first sample index: the samples it has had, its
// samples in this batch); item NO_HIT past the end.
fn batch_item(v: u32) -> vec3<u32> {
    if (v >= batch_count[0]) {
        return vec3<u32>(NO_HIT, 0u, 0u);
    }
    let i = batch_items[v];
    let n = moments[3u * i].w + moments[3u * i + 1u].w + moments[3u * i + 2u].x;
    return vec3<u32>(i, u32(n), batch_samples[i]);
}

// Item i's samples in the current batch (0: not in it).
fn batch_samples_of(i: u32) -> u32 {
    return batch_samples[i];
}
#endif
