// glossy.wgsl — the GGX layer of the baker's material (seed 004 §6.3.1) in tangent space
// (normal +Z): f = F(v·h)·D·G2/(4 v_z l_z) with Schlick's F, sampled from the
// distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution of
// Visible Normals"), pdf D_v(h)/(4 v·h) (eq. 17). CPU twins: baker::trace::eval_bsdf's
// GGX term, sbf::ggx::{sample_vndf, vndf_reflected_pdf}. D, G1, G2 and the Schlick weight
// come from the `shaders` GGX module. Left out of the kernel (see glossy_none.wgsl) when
// no material in the scene is glossy.

fn glossy_eval(v: vec3<f32>, l: vec3<f32>, alpha: f32, f0: vec3<f32>) -> BsdfValue {
    let hs = v + l;
    if (v.z <= 0.0 || l.z <= 0.0 || dot(hs, hs) <= 0.0) {
        return BsdfValue(vec3<f32>(0.0), 0.0);
    }
    let h = normalize(hs);
    let d = ggx_d(h, alpha);
    let dg = d * ggx_g2(v, l, alpha) / (4.0 * v.z * l.z);
    let vh = dot(v, h);
    let fw = schlick_weight(vh);
    let f = (f0 + (vec3<f32>(1.0) - f0) * fw) * dg;
    var pdf = 0.0;
    if (vh > 0.0) {
        pdf = ggx_g1(v, alpha) * vh * d / v.z / (4.0 * vh);
    }
    return BsdfValue(f, pdf);
}

fn glossy_sample(v: vec3<f32>, alpha: f32, u: vec2<f32>) -> vec3<f32> {
    // Stretch the view vector to the hemisphere configuration.
    let vh = normalize(vec3<f32>(alpha * v.x, alpha * v.y, v.z));
    let lensq = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if (lensq > 0.0) {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(lensq);
    }
    let t2 = cross(vh, t1);
    // Uniform disk sample, warped towards the visible half.
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    // Unstretch, then reflect v about h.
    let h = normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(nh.z, 0.0)));
    return 2.0 * dot(v, h) * h - v;
}
