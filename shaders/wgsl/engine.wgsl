// engine.wgsl — the directional lightmap formats engines ship, decoded as each engine's
// published shader does; every function returns E/π (what the engine multiplies by albedo)
// at the unit shading normal n, in world space: the formats store world-space directions
// (the baker writes them so), so n is the world-space shading normal, normal map applied.
// Arguments are the textures' values as sampled: the HDR colour and "unit" textures in [0, 1].
// CPU twin and sources: sbf::recon::engine (decode; the encodes live there too).

// Godot 4.4 and later, LightmapGI with spherical harmonics (scene_forward_clustered.glsl,
// USE_LIGHTMAP): L0 and three layers holding L1/(8·L0) + 1/2 for y, z and x, each
// decoded to (s − 1/2)·2 and scaled by 4·L0. (Godot 4.0–4.3 stored signed coefficients:
// 0.282095·L0 + 0.32573·Σ l·n, not this; sbf::recon::engine has both.)
fn godot_l1_irradiance(l0: vec3<f32>, l1n1: vec3<f32>, l1_0: vec3<f32>, l1p1: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let s = l0 * 4.0;
    return l0 + (l1n1 - 0.5) * 2.0 * n.y * s + (l1_0 - 0.5) * 2.0 * n.z * s + (l1p1 - 0.5) * 2.0 * n.x * s;
}

// Bakery MonoSH (Bakery.cginc, BakeryMonoSH) with "SH non-linear mode" off: RGB L0 and one
// direction t with nL1 = 2t − 1; max(L0 + 2·L0·(nL1·n), 0). Bakery's default is the
// non-linear mode (Geomerics' curve of the channel sum): sbf::recon::engine's MonoSh.
fn monosh_irradiance(l0: vec3<f32>, dir: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
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
