// sg.wgsl — spherical Gaussians G(v) = μ·exp(λ(v·p − 1)): evaluation, Lambert
// irradiance by Hill's fit (c0 from fitgen: HILL_C0, minimax re-fit over λ ∈ [2, 64]),
// and GGX specular two ways: the split sum over the warped NDF (sg_split_sum_*, the
// feature sg-specular; Karis 2013) and the anisotropic warp (sg_asg_*, the feature
// sg-specular-asg; Xu et al. 2013, "Anisotropic Spherical Gaussians"; Pettineo's SG
// series), which loses up to half the light of rough surfaces (sbf::recon::sg's docs).
// CPU twins: sbf::Sg::eval, sbf::recon::sg::hill_curve (with fits::HILL_C0),
// sbf::recon::sg::SplitSumWarp, sbf::recon::sg::AsgWarp.
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
    return sg_hill_cos(dot(axis, n), sharpness);
}

// sg_hill_irradiance for x = cos(axis, normal).
fn sg_hill_cos(x_in: f32, sharpness: f32) -> f32 {
    let lam = max(sharpness, 1e-30);
    let c0 = HILL_C0;
    let c1 = 1.0 / (4.0 * c0);
    let e1 = exp(-lam);
    let e2 = e1 * e1;
    let r = 1.0 / lam;
    let scale = 1.0 + 2.0 * e2 - r;
    let bias = (e1 - e2) * r - e2;
    // 1 − scale = 1/λ − 2e^(−2λ), without f32 cancellation at large λ.
    let xs = sqrt(max(r - 2.0 * e2, 0.0));
    let x = clamp(x_in, -1.0, 1.0);
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

// Per pixel for the ASG-warp specular: unit normal n and view v in the lobes' frame, GGX
// α_in (= perceptual roughness², held ≥ 1e-4) and Fresnel f0, f90. Then `sg_asg_lobe` per
// light lobe; the result is radiance reflected per unit lobe amplitude.
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

// The per-pixel part of the split-sum SG specular (Karis 2013, "Real Shading in Unreal
// Engine 4"; CPU twins sbf::recon::sg::SplitSumWarp, sbf::recon::runtime::sg_specular_split_sum):
// the GGX NDF as an SG about n (λ = 2/α², Wang et al. 2009) warped to the reflection
// direction R with λ/(4 n·v) (held ≥ 2, Hill's range), and the BRDF's energy
// f0·dfg.x + f90·dfg.y (the dfg table at (n·v, α)) over the warped lobe's E/π at n.
struct SgSplitSum {
    n: vec3<f32>,
    r: vec3<f32>,
    nv: f32,
    sharpness: f32,
    scale: f32,
}

// Per pixel for the split-sum SG specular: `dfg` the split-sum table (rg32float, see
// lut.wgsl: u = n·v, v = GGX α), unit normal n and view v in the lobes' frame, GGX α_in
// (= perceptual roughness²) and Fresnel f0, f90. Then `sg_split_sum_lobe` per light lobe.
fn sg_split_sum_setup(dfg: texture_2d<f32>, n: vec3<f32>, v: vec3<f32>, alpha_in: f32, f0: f32, f90: f32) -> SgSplitSum {
    let alpha = clamp(alpha_in, 1e-4, 1.0);
    let nv = max(dot(n, v), SG_NV_EPSILON);
    let lw = max(0.5 / (alpha * alpha * nv), 2.0);
    let r = reflect_about(v, n);
    let d = lut2_sample(dfg, clamp(dot(n, v), 0.0, 1.0), alpha_in);
    // n·R = n·v: from the inputs, not from R's rounding (λ_D magnifies it at grazing view).
    let den = sg_hill_cos(dot(n, v), lw);
    var scale = 0.0;
    if (den > 0.0) {
        scale = (f0 * d.x + f90 * d.y) / den;
    }
    return SgSplitSum(n, r, dot(n, v), lw, scale);
}

// Specular from one unit-amplitude SG light lobe: the radiance prefiltered by the warped
// NDF with the n·l weight, E/π(D·G) / E/π(D), times the BRDF's energy. D·G is one SG
// (axis λ_D R + λ p normalised, sharpness |λ_D R + λ p|, amplitude
// exp(−λ_D λ |R − p|² / (λ_D + λ + |λ_D R + λ p|)): the exponent without cancellation).
fn sg_split_sum_lobe(w: SgSplitSum, axis: vec3<f32>, sharpness: f32) -> f32 {
    let pm = w.sharpness * w.r + sharpness * axis;
    let d = length(pm);
    let q = w.r - axis;
    let amp = exp(-w.sharpness * sharpness * dot(q, q) / (w.sharpness + sharpness + d));
    // The product's axis·n = (λ_D n·v + λ p·n)/|λ_D R + λ p| (n·v as in the setup).
    var x = w.nv;
    if (d > 0.0) {
        x = (w.sharpness * w.nv + sharpness * dot(axis, w.n)) / d;
    }
    // Below λ 2 (outside Hill's range; amplitude < e^(−2)): Hill's curve at λ 2 with the
    // product lobe's own integral, as sbf::recon::sg::SplitSumWarp::lobe.
    let e = sg_hill_cos(x, max(d, 2.0)) * sg_integral(d) / sg_integral(max(d, 2.0));
    return amp * e * w.scale;
}

// E/π at unit normal n from 9 RGB SG lightmap lobe amplitudes c on SG9_AXES (the baker's SG 9
// layout, in the lightmap texel's tangent frame: n in that frame, +Z the texel's normal) of
// sharpness λ ≥ 2 (bake.json `sg_sharpness`; the baker's default is 6). Once per texel.
fn sg9_irradiance(c: array<vec3<f32>, 9>, sharpness: f32, n: vec3<f32>) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    for (var i = 0; i < 9; i++) {
        e += c[i] * sg_hill_irradiance(SG9_AXES[i], sharpness, n);
    }
    return e;
}

// As sg9_irradiance, for 12 lobes on SG12_AXES.
fn sg12_irradiance(c: array<vec3<f32>, 12>, sharpness: f32, n: vec3<f32>) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    for (var i = 0; i < 12; i++) {
        e += c[i] * sg_hill_irradiance(SG12_AXES[i], sharpness, n);
    }
    return e;
}

// GGX specular radiance from 9 RGB SG lightmap lobe amplitudes c on SG9_AXES (the texel's
// tangent frame, as sg9_irradiance) of sharpness λ, by the split sum above: `dfg` the
// split-sum table (see lut.wgsl), unit n and v in the texel's tangent frame, GGX α
// (= perceptual roughness²) and Fresnel f0, f90. Once per texel.
fn sg9_specular(c: array<vec3<f32>, 9>, sharpness: f32, dfg: texture_2d<f32>, n: vec3<f32>, v: vec3<f32>, alpha: f32, f0: f32, f90: f32) -> vec3<f32> {
    let w = sg_split_sum_setup(dfg, n, v, alpha, f0, f90);
    var s = vec3<f32>(0.0);
    for (var i = 0; i < 9; i++) {
        s += c[i] * sg_split_sum_lobe(w, SG9_AXES[i], sharpness);
    }
    return s;
}

// As sg9_specular, for 12 lobes on SG12_AXES.
fn sg12_specular(c: array<vec3<f32>, 12>, sharpness: f32, dfg: texture_2d<f32>, n: vec3<f32>, v: vec3<f32>, alpha: f32, f0: f32, f90: f32) -> vec3<f32> {
    let w = sg_split_sum_setup(dfg, n, v, alpha, f0, f90);
    var s = vec3<f32>(0.0);
    for (var i = 0; i < 12; i++) {
        s += c[i] * sg_split_sum_lobe(w, SG12_AXES[i], sharpness);
    }
    return s;
}
