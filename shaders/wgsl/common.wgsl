// common.wgsl — shared constants. Conventions: right-handed, +Y up in world space,
// tangent space normal +Z; irradiance is E/π; coefficients are RGB vec3<f32>.

const PI: f32 = 3.14159265358979;
const INV_PI: f32 = 0.318309886183791;

// Orthonormal tangent and bitangent for unit n (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited"). CPU twin: sbf::basis::ambient_dice_bezier::tangent_frame.
fn tangent_frame(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return array<vec3<f32>, 2>(vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x), vec3<f32>(b, s + n.y * n.y * a, -n.y));
}

// reflect(v, n) in the BRDF convention (v points away from the surface): 2(v·n)n − v.
fn reflect_about(v: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return 2.0 * dot(v, n) * n - v;
}
