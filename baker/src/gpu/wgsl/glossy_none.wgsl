// glossy_none.wgsl — composed instead of glossy.wgsl when no material in the scene has a
// GGX layer ("leave out what the scene does not need"): every material's GGX
// probability and `glossy` flag are then 0, so neither function is reached; they exist
// so the kernel type-checks without the GGX module.

fn glossy_eval(v: vec3<f32>, l: vec3<f32>, alpha: f32, f0: vec3<f32>) -> BsdfValue {
    return BsdfValue(vec3<f32>(0.0), 0.0);
}

fn glossy_sample(v: vec3<f32>, alpha: f32, u: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(0.0, 0.0, 1.0);
}
