// ---- no filtered accumulation in this bake: samples feed their own texel only ----
fn filter_record(i: u32, fv: FirstVertex, l: vec3<f32>, e: vec3<f32>, w: f32) {
}
