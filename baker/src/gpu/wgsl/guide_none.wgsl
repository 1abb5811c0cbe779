// ---- no ray guiding in this bake: the point sample is uniform ----
const GUIDED_FRACTION: f32 = 0.0;

fn guide_sample(c: u32, u: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(0.0, 0.0, 1.0);
}

fn guide_pdf(c: u32, local: vec3<f32>) -> f32 {
    return 0.5 * INV_PI;
}

fn guide_record(i: u32, slot: u32, local: vec3<f32>, lum: f32) {
}

fn guide_clear(i: u32) {
}
