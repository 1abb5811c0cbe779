// sh_specular.wgsl — GGX specular from SH radiance (bands ≤ 2) by zonal convolution about
// the GGX dominant direction R_d (Lagarde & de Rousiers 2014, as [Roughton19 Listing 8.2]):
// the lobe of f_r·cos is taken as the zonal SG of sharpness λ = (2/α²)/(4·max(n·v, 1e-4))
// with unit integral; its zonal ratios g_l/g_0 filter the bands (g₁ = coth λ − 1/λ,
// g₂ = 1 − 3g₁/λ: the modified spherical Bessel ratios i_l(λ)/i_0(λ)), and the split-sum
// term f0·dfg.x + f90·dfg.y (the dfg table at (n·v, α), lut2_sample) carries the BRDF's
// energy: a constant radiance L gives exactly L·(f0·dfg.x + f90·dfg.y).
// Approximation (stated): the warp's anisotropy and the horizon are ignored.
// CPU twin: sbf::recon::sh::specular_zonal_rgb with specular_zonal_filter (f64).

// (g₁/g₀, g₂/g₀) of the unit-integral SG of sharpness λ ≥ 0.5 (n·v ≤ 1, α ≤ 1). With
// e = e^(−2λ), coth λ = (1 + e)/(1 − e); 1 − e ≥ 0.63 here, so no cancellation there;
// g₁ loses ≤ 4 bits to the subtraction at λ = 0.5 and g₂ ≤ 6 (≈ 1e-5 relative).
fn sh_specular_ratios(lambda: f32) -> vec2<f32> {
    let e = exp(-2.0 * lambda);
    let g1 = (1.0 + e) / (1.0 - e) - 1.0 / lambda;
    return vec2<f32>(g1, 1.0 - 3.0 * g1 / lambda);
}

// The dominant direction normalize(mix(n, r, s(√s + α))), s = saturate(1 − α)
// (sbf::ggx::dominant_direction).
fn sh_specular_dominant(n: vec3<f32>, r: vec3<f32>, alpha: f32) -> vec3<f32> {
    let s = clamp(1.0 - alpha, 0.0, 1.0);
    let f = s * (sqrt(s) + alpha);
    return normalize(n + (r - n) * f);
}

// The filter sharpness λ and the split-sum scale for (n, v, α, f0, f90).
fn sh_specular_setup(dfg: texture_2d<f32>, n: vec3<f32>, v: vec3<f32>, alpha_in: f32, f0: f32, f90: f32) -> vec4<f32> {
    let alpha = clamp(alpha_in, 1e-4, 1.0);
    let nv = dot(n, v);
    let lambda = 2.0 / (alpha * alpha) / (4.0 * max(nv, 1e-4));
    let g = sh_specular_ratios(lambda);
    let d = lut2_sample(dfg, clamp(nv, 0.0, 1.0), alpha_in);
    return vec4<f32>(g, f0 * d.x + f90 * d.y, alpha);
}

// Specular radiance towards v from L1 RGB radiance coefficients.
fn sh_l1_specular(c: array<vec3<f32>, 4>, dfg: texture_2d<f32>, n: vec3<f32>, v: vec3<f32>, alpha: f32, f0: f32, f90: f32) -> vec3<f32> {
    let s = sh_specular_setup(dfg, n, v, alpha, f0, f90);
    let y = sh_eval_l1(sh_specular_dominant(n, reflect_about(v, n), s.w));
    let l = c[0] * y[0] + s.x * (c[1] * y[1] + c[2] * y[2] + c[3] * y[3]);
    return l * s.z;
}

// Specular radiance towards v from L2 RGB radiance coefficients.
fn sh_l2_specular(c: array<vec3<f32>, 9>, dfg: texture_2d<f32>, n: vec3<f32>, v: vec3<f32>, alpha: f32, f0: f32, f90: f32) -> vec3<f32> {
    let s = sh_specular_setup(dfg, n, v, alpha, f0, f90);
    let y = sh_eval_l2(sh_specular_dominant(n, reflect_about(v, n), s.w));
    let b1 = c[1] * y[1] + c[2] * y[2] + c[3] * y[3];
    let b2 = c[4] * y[4] + c[5] * y[5] + c[6] * y[6] + c[7] * y[7] + c[8] * y[8];
    return (c[0] * y[0] + s.x * b1 + s.y * b2) * s.z;
}
