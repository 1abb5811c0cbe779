// bsdf.wgsl — the baker's layered material ([Roughton19 §6.3.1]): Lambert plus, with the
// shader def GLOSSY (a material in the scene is glossy), a GGX layer in tangent space
// (normal +Z): f = F(v·h)·D·G2/(4 v_z l_z) with Schlick's F, sampled from the
// distribution of visible normals (Heitz 2018), pdf D_v(h)/(4 v·h) (eq. 17). CPU twins:
// baker::estimator::trace::{eval_bsdf, sample_bsdf}, sbf::ggx::{sample_vndf,
// vndf_reflected_pdf}. D, G1, G2 and the Schlick weight come from the `shaders` GGX module.

#define_import_path baker::bsdf

#import baker::bindings::{Material, max3}
#import sbf::runtime::{INV_PI, PI, tangent_frame}
#ifdef GLOSSY
#import sbf::runtime::{ggx_d, ggx_g1, ggx_g2, schlick_weight}
#endif

fn to_local(w: vec3<f32>, f: array<vec3<f32>, 2>, n: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(w, f[0]), dot(w, f[1]), dot(w, n));
}

// Concentric disk → cosine-weighted hemisphere (Shirley & Chiu 1997; CPU twin
// sbf::sampling::cosine_hemisphere).
fn cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let a = 2.0 * u - vec2<f32>(1.0);
    var p = vec2<f32>(0.0);
    if (a.x != 0.0 || a.y != 0.0) {
        if (abs(a.x) > abs(a.y)) {
            let phi = (PI / 4.0) * (a.y / a.x);
            p = a.x * vec2<f32>(cos(phi), sin(phi));
        } else {
            let phi = PI / 2.0 - (PI / 4.0) * (a.x / a.y);
            p = a.y * vec2<f32>(cos(phi), sin(phi));
        }
    }
    return vec3<f32>(p, sqrt(max(1.0 - dot(p, p), 0.0)));
}

// (f, pdf) of the layered material for unit wo, wi about shading normal ns.
struct BsdfValue {
    f: vec3<f32>,
    pdf: f32,
}

fn eval_bsdf(m: Material, ns: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> BsdfValue {
    let ci = dot(wi, ns);
    let co = dot(wo, ns);
    if (ci <= 0.0 || co <= 0.0) {
        return BsdfValue(vec3<f32>(0.0), 0.0);
    }
    var f = m.diffuse * INV_PI;
    var pdf = (1.0 - m.specular_probability) * ci * INV_PI;
#ifdef GLOSSY
    if (m.glossy) {
        let fr = tangent_frame(ns);
        let g = glossy_eval(to_local(wo, fr, ns), to_local(wi, fr, ns), m.alpha, m.reflectance);
        f += g.f;
        pdf += m.specular_probability * g.pdf;
    }
#endif
    return BsdfValue(f, pdf);
}

struct BsdfSample {
    wi: vec3<f32>,
    f: vec3<f32>,
    pdf: f32,
}

// Samples wi (pdf 0 when the sample is lost: below the surface or zero throughput).
// u = (layer choice, 2D direction).
fn sample_bsdf(m: Material, ns: vec3<f32>, wo: vec3<f32>, u3: vec3<f32>) -> BsdfSample {
    let choose = u3.x;
    let u = u3.yz;
    let fr = tangent_frame(ns);
    var local: vec3<f32>;
#ifdef GLOSSY
    if (choose < m.specular_probability) {
        local = glossy_sample(to_local(wo, fr, ns), m.alpha, u);
    } else if (m.specular_probability < 1.0) {
#else
    // No glossy material: every material's GGX probability is 0.
    if (m.specular_probability < 1.0) {
#endif
        local = cosine_hemisphere(u);
    } else {
        return BsdfSample(vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    }
    let wi = normalize(fr[0] * local.x + fr[1] * local.y + ns * local.z);
    let e = eval_bsdf(m, ns, wo, wi);
    if (!(e.pdf > 0.0) || max3(e.f) <= 0.0) {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0);
    }
    return BsdfSample(wi, e.f, e.pdf);
}

#ifdef GLOSSY
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
#endif
