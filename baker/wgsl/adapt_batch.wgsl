// ---- adaptive sampling: this dispatch runs a batch (baker::adapt) ----
// The batch's items (compacted by adapt.wgsl's selection) and their number.
@group(0) @binding(11) var<storage, read> batch_items: array<u32>;
@group(0) @binding(12) var<storage, read> batch_count: array<u32>;

// Position v of the batch → (item, its sample index: the samples it has had).
fn batch_item(v: u32) -> vec2<u32> {
    if (v >= batch_count[0]) {
        return vec2<u32>(NO_HIT, 0u);
    }
    let i = batch_items[v];
    let n = moments[3u * i].w + moments[3u * i + 1u].w + moments[3u * i + 2u].x;
    return vec2<u32>(i, u32(n));
}
