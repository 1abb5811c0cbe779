// engine.wgsl — the directional lightmap formats engines ship, decoded as each engine's
// published shader does; every function returns E/π (what the engine multiplies by albedo)
// at the unit shading normal n, in world space: the formats store world-space directions
// (the baker writes them so), so n is the world-space shading normal, normal map applied.
// Arguments are the textures' values as sampled: the HDR colour and "unit" textures in [0, 1].
// CPU twin and sources: sbf::recon::engine (decode; the encodes live there too).

// Godot 4.4 and later, LightmapGI with spherical harmonics (scene_forward_clustered.glsl,
// USE_LIGHTMAP): L0 and three layers holding L1/(8·L0) + 1/2 for y, z and x, each
// decoded to (s − 1/2)·2 and scaled by 4·L0. (Godot 4.0–4.3: godot_l1_legacy_irradiance.)
fn godot_l1_irradiance(l0: vec3<f32>, l1n1: vec3<f32>, l1_0: vec3<f32>, l1p1: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let s = l0 * 4.0;
    return l0 + (l1n1 - 0.5) * 2.0 * n.y * s + (l1_0 - 0.5) * 2.0 * n.z * s + (l1p1 - 0.5) * 2.0 * n.x * s;
}

// Godot 4.0–4.3, LightmapGI with spherical harmonics (scene_forward_clustered.glsl of those
// versions): four layers of signed SH L1 coefficients — L0, then L1 for y, z and x — as
// sampled (no offset, no scale); 0.282095·L0 + 0.32573·(l1n1·n.y + l1_0·n.z + l1p1·n.x).
fn godot_l1_legacy_irradiance(l0: vec3<f32>, l1n1: vec3<f32>, l1_0: vec3<f32>, l1p1: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return l0 * 0.282095 + (l1n1 * n.y + l1_0 * n.z + l1p1 * n.x) * 0.32573;
}

// Geomerics' L1 irradiance curve, as Bakery.cginc's shEvaluateDiffuseL1Geomerics(L0, L1, n)
// (one channel: L0 = a₀, L1 = a₁ of the linear irradiance a₀ + a₁·n): R₀ = L0, R₁ = L1/2,
// q = (1 + n·R̂₁)/2, p = 1 + 2|R₁|/R₀, a = (1 − |R₁|/R₀)/(1 + |R₁|/R₀),
// R₀·(a + (1 − a)(p + 1)·q^p). Where |R₁| = 0 or R₀ ≤ 0 the shader divides by zero; this
// returns the linear value a₀ + a₁·n there (the formula's limit at |R₁| → 0). CPU twin:
// sbf::recon::sh::geomerics_l1.
fn geomerics_l1(l0: f32, l1: vec3<f32>, n: vec3<f32>) -> f32 {
    let r1 = 0.5 * l1;
    let len = length(r1);
    if (l0 <= 0.0 || len <= 0.0) {
        return l0 + dot(l1, n);
    }
    let q = clamp(0.5 * (1.0 + dot(n, r1 / len)), 0.0, 1.0);
    let ratio = len / l0;
    let p = 1.0 + 2.0 * ratio;
    let a = (1.0 - ratio) / (1.0 + ratio);
    return l0 * (a + (1.0 - a) * (p + 1.0) * pow(q, p));
}

// Bakery MonoSH (Bakery.cginc, BakeryMonoSH), "SH non-linear mode" on — Bakery's default
// (BAKERY_SHNONLINEAR): RGB L0 and one direction t with nL1 = 2t − 1 give the linear value
// sh = L0 + 2·L0·(nL1·n) per channel; Geomerics' curve of the channel sums rescales it:
// sh·lerp(1, geomerics(ΣL0, 2·ΣL0·nL1, n)/Σsh, saturate(16·Σsh)), then max(·, 0). Where
// the weight is 0 the shader's ratio is 0/0 and the factor is 1.
fn monosh_irradiance(l0: vec3<f32>, dir: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let nl1 = dir * 2.0 - 1.0;
    let sh = l0 + 2.0 * l0 * dot(nl1, n);
    let luma_l0 = l0.x + l0.y + l0.z;
    let luma_sh = geomerics_l1(luma_l0, nl1 * (2.0 * luma_l0), n);
    let regular = sh.x + sh.y + sh.z;
    let w = clamp(16.0 * regular, 0.0, 1.0);
    var factor = 1.0;
    if (w > 0.0) {
        factor = 1.0 + w * (luma_sh / regular - 1.0);
    }
    return max(sh * factor, vec3<f32>(0.0));
}

// Bakery MonoSH with "SH non-linear mode" off (the #else branch of BakeryMonoSH): the same
// textures; max(L0 + 2·L0·(nL1·n), 0).
fn monosh_linear_irradiance(l0: vec3<f32>, dir: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let nl1 = dir * 2.0 - 1.0;
    return max(l0 + 2.0 * l0 * dot(nl1, n), vec3<f32>(0.0));
}

// Enlighten directional irradiance, one channel's half-Lambert term over its rescaling
// factor (UnityCG.cginc DecodeDirectionalLightmap): (n·(t.xyz − 1/2) + 1/2)/max(t.w, 1e-4).
fn enlighten_factor(dir: vec4<f32>, n: vec3<f32>) -> f32 {
    let half_lambert = dot(n, dir.xyz - 0.5) + 0.5;
    return half_lambert / max(dir.w, 1e-4);
}

// Enlighten directional irradiance, one luminance direction: the irradiance colour times
// its factor.
fn enlighten_irradiance(colour: vec3<f32>, dir: vec4<f32>, n: vec3<f32>) -> vec3<f32> {
    return colour * enlighten_factor(dir, n);
}

// Enlighten directional irradiance, one direction per colour channel.
fn enlighten_rgb_irradiance(colour: vec3<f32>, dir_r: vec4<f32>, dir_g: vec4<f32>, dir_b: vec4<f32>, n: vec3<f32>) -> vec3<f32> {
    return colour * vec3<f32>(enlighten_factor(dir_r, n), enlighten_factor(dir_g, n), enlighten_factor(dir_b, n));
}
