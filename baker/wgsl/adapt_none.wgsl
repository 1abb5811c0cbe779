// ---- no adaptive sampling in this bake ----
fn batch_item(v: u32) -> vec2<u32> {
    return vec2<u32>(NO_HIT, 0u);
}
