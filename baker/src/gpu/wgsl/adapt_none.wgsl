// ---- no adaptive sampling in this bake ----
fn batch_item(v: u32) -> vec3<u32> {
    return vec3<u32>(NO_HIT, 0u, 0u);
}

fn batch_samples_of(i: u32) -> u32 {
    return 0u;
}
