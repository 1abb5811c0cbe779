// sg.wgsl — spherical Gaussians G(v) = μ·exp(λ(v·p − 1)): evaluation, Lambert
// irradiance by Hill's fit (c0 from fitgen: HILL_C0, minimax re-fit over λ ∈ [2, 64]),
// and GGX specular by the anisotropic warp (Xu et al. 2013, "Anisotropic Spherical
// Gaussians"; Pettineo's SG series). CPU twins: sbf::Sg::eval,
// sbf::recon::sg::hill_curve (with fits::HILL_C0), sbf::recon::sg::AsgWarp.
// Runtime range: λ ≥ 2 for the irradiance fit (below, sbf switches to the exact zonal
// expansion, which is not in WGSL); every function stays finite for λ > 0.

// Unit-amplitude lobe value at unit direction v.
fn sg_eval(axis: vec3<f32>, sharpness: f32, v: vec3<f32>) -> f32 {
    return exp(sharpness * (dot(axis, v) - 1.0));
}

// ∫ G over the sphere for unit amplitude: 2π(1 − e^(−2λ))/λ, with its limit 4π at λ → 0.
fn sg_integral(sharpness: f32) -> f32 {
    if (sharpness < 1e-30) {
        return 4.0 * PI;
    }
    return 2.0 * PI * (-expm1_f32(-2.0 * sharpness)) / sharpness;
}

// e^x − 1 without cancellation for small |x| (WGSL has no expm1).
fn expm1_f32(x: f32) -> f32 {
    // Taylor to x⁴ below |x| = 1e-2 (truncation ~1e-10 relative); above, exp(x) − 1
    // loses at most ~6e-6 relative in f32.
    if (abs(x) < 1e-2) {
        return x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x / 24.0)));
    }
    return exp(x) - 1.0;
}

// E/π of a unit-amplitude lobe at unit normal n (Hill 2016's fitted curve).
fn sg_hill_irradiance(axis: vec3<f32>, sharpness: f32, n: vec3<f32>) -> f32 {
    let lam = max(sharpness, 1e-30);
    let c0 = HILL_C0;
    let c1 = 1.0 / (4.0 * c0);
    let e1 = exp(-lam);
    let e2 = e1 * e1;
    let r = 1.0 / lam;
    let scale = 1.0 + 2.0 * e2 - r;
    let bias = (e1 - e2) * r - e2;
    let xs = sqrt(max(1.0 - scale, 0.0));
    let x = clamp(dot(axis, n), -1.0, 1.0);
    let x0 = c0 * x;
    let x1 = c1 * xs;
    var y = clamp(x, 0.0, 1.0);
    if (abs(x0) <= x1 && xs > 0.0) {
        y = (x0 + x1) * (x0 + x1) / xs;
    }
    return (scale * y + bias) * sg_integral(lam) * INV_PI;
}

// Lower bound on n·v used by the warp (as sbf::recon::sg::NV_EPSILON).
const SG_NV_EPSILON: f32 = 1e-4;

// The per-pixel part of the ASG warp: warped NDF frame and bandwidths, and the
// visibility·Fresnel·cosine tail evaluated at the reflection direction.
struct SgAsgWarp {
    x: vec3<f32>,
    y: vec3<f32>,
    z: vec3<f32>,
    lx: f32,
    ly: f32,
    mu: f32,
    tail: f32,
}

fn sg_asg_warp(n: vec3<f32>, v: vec3<f32>, alpha_in: f32, f0: f32, f90: f32) -> SgAsgWarp {
    let alpha = clamp(alpha_in, 1e-4, 1.0);
    let a2 = alpha * alpha;
    let lam = 2.0 / a2;
    let mu = 1.0 / (PI * a2);
    let nv = max(dot(n, v), SG_NV_EPSILON);
    let z = reflect_about(v, n);
    let y0 = cross(n, z);
    var y = tangent_frame(z)[1];
    if (dot(y0, y0) > 1e-12) {
        y = normalize(y0);
    }
    let x = cross(y, z);
    // Tail: G2/(4 n·v n·l)·F·(n·l) at l = z, with Smith Λ in a frame where n = +Z.
    let nl = dot(n, z);
    var tail = 0.0;
    if (nl > 0.0) {
        let g2 = ggx_g2(vec3<f32>(sqrt(max(1.0 - nv * nv, 0.0)), 0.0, nv), vec3<f32>(sqrt(max(1.0 - nl * nl, 0.0)), 0.0, nl), alpha);
        let hv = v + z;
        let hl = length(hv);
        var fc = 0.0;
        if (hl > 0.0) {
            fc = schlick_weight(dot(v, hv / hl));
        }
        tail = g2 / (4.0 * nv) * (f0 * (1.0 - fc) + f90 * fc);
    }
    return SgAsgWarp(x, y, z, lam / (8.0 * nv * nv), lam / 8.0, mu, tail);
}

// Specular from one unit-amplitude SG light lobe: the ASG convolved with the SG.
fn sg_asg_lobe(w: SgAsgWarp, axis: vec3<f32>, sharpness: f32) -> f32 {
    let nu = 0.5 * sharpness;
    let lx2 = nu * w.lx / (nu + w.lx);
    let ly2 = nu * w.ly / (nu + w.ly);
    let amp = PI / sqrt((nu + w.lx) * (nu + w.ly));
    let px = dot(axis, w.x);
    let py = dot(axis, w.y);
    return w.mu * amp * max(dot(axis, w.z), 0.0) * exp(-lx2 * px * px - ly2 * py * py) * w.tail;
}
