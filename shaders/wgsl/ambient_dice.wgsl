// ambient_dice.wgsl — Ambient Dice cosine-lobe SRBFs ([Roughton19 §8.3]): lobe value
// B(c) = c²(0.35 + 0.25c²) for c = v·p > 0, Lambert irradiance per lobe by the
// minimax quadratic of the exact quartic (fitgen: AD_DIFFUSE_QUADRATIC, max error
// 6.5e-4), and GGX specular by Listing 8.1's blend (fitgen: AD_SPECULAR_PARAMS,
// AD_SPECULAR_DIFFUSE) times Listing 8.2's LUT (lut2_sample of ad_specular_2d).
// Lobe axes come from the generated layout constants (AD12_AXES, AD9_AXES).
// CPU twins: sbf::basis::ambient_dice::srbf_lobe_f32, sbf::recon::runtime::ad_irradiance,
// sbf::recon::ambient_dice::SpecularFit, sbf::recon::runtime::ad_specular.

fn ad_srbf_lobe(c: f32) -> f32 {
    let x = max(c, 0.0);
    let x2 = x * x;
    return x2 * (0.35 + 0.25 * x2);
}

// One Ambient Dice SRBF lobe with unit axis `axis` evaluated at unit direction v.
fn ad_srbf_eval(axis: vec3<f32>, v: vec3<f32>) -> f32 {
    return ad_srbf_lobe(dot(axis, v));
}

// E/π of a unit-coefficient lobe at unit normal n.
fn ad_lobe_irradiance(axis: vec3<f32>, n: vec3<f32>) -> f32 {
    let x = clamp(dot(axis, n), -1.0, 1.0);
    let p = AD_DIFFUSE_QUADRATIC;
    return p.x + x * (p.y + x * p.z);
}

// Per-pixel part of Listing 8.1: reflection vector and the two blend weights.
struct AdSpecularFit {
    n: vec3<f32>,
    r: vec3<f32>,
    focus: f32,
    alpha_lerp: f32,
}

fn ad_specular_fit(n: vec3<f32>, v: vec3<f32>, alpha: f32) -> AdSpecularFit {
    let k = AD_SPECULAR_PARAMS;
    let sa = sqrt(alpha);
    let focus = clamp(k[0] * sa + k[1] * alpha + k[2] * sa * alpha + k[3] * alpha * alpha, 0.0, 1.0);
    let alpha_lerp = clamp(k[4] * sa + k[5] * alpha + k[6] * sa * alpha + k[7] * alpha * alpha, 0.0, 1.0);
    return AdSpecularFit(n, reflect_about(v, n), focus, alpha_lerp);
}

// The fit's value for one lobe axis (before the LUT factor).
fn ad_specular_lobe(f: AdSpecularFit, axis: vec3<f32>) -> f32 {
    let r_dot = dot(f.r, axis);
    let n_dot = dot(f.n, axis);
    let mirror = ad_srbf_lobe(r_dot);
    let c = r_dot + (n_dot - r_dot) * f.focus;
    let p = AD_SPECULAR_DIFFUSE;
    let d = p.x + c * (p.y + c * p.z);
    return mirror + (d - mirror) * f.alpha_lerp;
}

// LUT factor f0·L.x + f90·L.y at (n·v, α).
fn ad_specular_scale(lut: texture_2d<f32>, n_dot_v: f32, alpha: f32, f0: f32, f90: f32) -> f32 {
    let l = lut2_sample(lut, clamp(n_dot_v, 0.0, 1.0), alpha);
    return f0 * l.x + f90 * l.y;
}

// E/π at unit normal n from 12 RGB Ambient Dice radiance coefficients c on the icosahedron
// axes AD12_AXES (the probes' sphere; n in the same frame as the axes, world space).
fn ad12_irradiance(c: array<vec3<f32>, 12>, n: vec3<f32>) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    for (var i = 0; i < 12; i++) {
        e += c[i] * ad_lobe_irradiance(AD12_AXES[i], n);
    }
    return e;
}

// E/π at unit normal n from 9 RGB Ambient Dice radiance coefficients c on the hemisphere
// axes AD9_AXES, which live in the lightmap texel's tangent frame (+Z the texel's normal): n
// in that frame (+Z for the texel's own normal).
fn ad9_irradiance(c: array<vec3<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    for (var i = 0; i < 9; i++) {
        e += c[i] * ad_lobe_irradiance(AD9_AXES[i], n);
    }
    return e;
}

// GGX specular radiance from 12 RGB Ambient Dice coefficients c (axes AD12_AXES, world
// space): [Roughton19 Listing 8.1]'s fit per lobe times the table `lut` (luts/ad_specular_2d.sbflut,
// rg32float; u = n·v, v = GGX α) at (n·v, α), for unit n and v in the axes' frame, GGX α
// (= perceptual roughness²) and Fresnel f0, f90.
fn ad12_specular(c: array<vec3<f32>, 12>, lut: texture_2d<f32>, n: vec3<f32>, v: vec3<f32>, alpha: f32, f0: f32, f90: f32) -> vec3<f32> {
    let f = ad_specular_fit(n, v, alpha);
    var s = vec3<f32>(0.0);
    for (var i = 0; i < 12; i++) {
        s += c[i] * ad_specular_lobe(f, AD12_AXES[i]);
    }
    return s * ad_specular_scale(lut, dot(n, v), alpha, f0, f90);
}

// GGX specular radiance from 9 RGB Ambient Dice coefficients c (axes AD9_AXES, the texel's
// tangent frame): as `ad12_specular`, with n and v in that frame.
fn ad9_specular(c: array<vec3<f32>, 9>, lut: texture_2d<f32>, n: vec3<f32>, v: vec3<f32>, alpha: f32, f0: f32, f90: f32) -> vec3<f32> {
    let f = ad_specular_fit(n, v, alpha);
    var s = vec3<f32>(0.0);
    for (var i = 0; i < 9; i++) {
        s += c[i] * ad_specular_lobe(f, AD9_AXES[i]);
    }
    return s * ad_specular_scale(lut, dot(n, v), alpha, f0, f90);
}
