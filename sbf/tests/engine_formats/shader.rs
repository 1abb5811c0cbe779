//! The engines' lightmap decodes transcribed line by line from their shader sources, in f32
//! as a GPU runs them — an oracle written from the sources, not from `sbf`'s decoder. Texture
//! reads are the function arguments (the values a texture returns).
#![allow(dead_code)]

pub type V3 = [f32; 3];

fn dot(a: V3, b: V3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn mul(a: V3, b: V3) -> V3 {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}
fn scale(a: V3, s: f32) -> V3 {
    a.map(|v| v * s)
}
fn normalize(a: V3) -> V3 {
    scale(a, 1.0 / dot(a, a).sqrt())
}
fn saturate(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

/// Godot ≥ 4.4, `scene_forward_clustered.glsl` (USE_LIGHTMAP, uses_sh), the four layers as
/// sampled; `en` (exposure normalisation) 1.
pub fn godot_4_4(l0_tex: V3, l1n1_tex: V3, l1_0_tex: V3, l1p1_tex: V3, n: V3) -> V3 {
    let lm_light_l0 = l0_tex;
    let lm_light_l1n1 = scale(add(l1n1_tex, [-0.5; 3]), 2.0);
    let lm_light_l1_0 = scale(add(l1_0_tex, [-0.5; 3]), 2.0);
    let lm_light_l1p1 = scale(add(l1p1_tex, [-0.5; 3]), 2.0);
    let en = 1.0f32;
    let mut ambient_light = [0.0f32; 3];
    ambient_light = add(ambient_light, scale(lm_light_l0, en));
    ambient_light = add(ambient_light, mul(scale(lm_light_l1n1, n[1]), scale(lm_light_l0, en * 4.0)));
    ambient_light = add(ambient_light, mul(scale(lm_light_l1_0, n[2]), scale(lm_light_l0, en * 4.0)));
    ambient_light = add(ambient_light, mul(scale(lm_light_l1p1, n[0]), scale(lm_light_l0, en * 4.0)));
    ambient_light
}

/// Godot 4.0–4.3, the same shader before the packing: `ambient_light += lm_light_l0 *
/// 0.282095f * en; ambient_light += lm_light_l1n1 * 0.32573 * n.y * en; …`.
pub fn godot_4_0(l0: V3, l1n1: V3, l1_0: V3, l1p1: V3, n: V3) -> V3 {
    let en = 1.0f32;
    let mut ambient_light = [0.0f32; 3];
    ambient_light = add(ambient_light, scale(l0, 0.282095 * en));
    ambient_light = add(ambient_light, scale(l1n1, 0.32573 * n[1] * en));
    ambient_light = add(ambient_light, scale(l1_0, 0.32573 * n[2] * en));
    ambient_light = add(ambient_light, scale(l1p1, 0.32573 * n[0] * en));
    ambient_light
}

/// Bakery.cginc `shEvaluateDiffuseL1Geomerics` (no guards: R₁ = 0 or R₀ = 0 give NaN, as on
/// a GPU; callers keep away from them).
pub fn sh_evaluate_diffuse_l1_geomerics(l0: f32, l1: V3, n: V3) -> f32 {
    let r0 = l0;
    let r1 = scale(l1, 0.5);
    let len_r1 = dot(r1, r1).sqrt();
    let q = dot(normalize(r1), n) * 0.5 + 0.5;
    let p = 1.0 + 2.0 * len_r1 / r0;
    let a = (1.0 - len_r1 / r0) / (1.0 + len_r1 / r0);
    r0 * (a + (1.0 - a) * (p + 1.0) * q.powf(p))
}

/// Bakery.cginc `BakeryMonoSH`, diffuse: `dominant_dir` the direction texture as sampled,
/// `l0` the decoded lightmap; `nonlinear`: `#if BAKERY_SHNONLINEAR` (Bakery's default).
pub fn bakery_mono_sh(l0: V3, dominant_dir: V3, n: V3, nonlinear: bool) -> V3 {
    let nl1 = add(scale(dominant_dir, 2.0), [-1.0; 3]);
    let l1x = scale(l0, nl1[0] * 2.0);
    let l1y = scale(l0, nl1[1] * 2.0);
    let l1z = scale(l0, nl1[2] * 2.0);
    let mut sh;
    if nonlinear {
        let luma_l0 = dot(l0, [1.0; 3]);
        let luma_l1x = dot(l1x, [1.0; 3]);
        let luma_l1y = dot(l1y, [1.0; 3]);
        let luma_l1z = dot(l1z, [1.0; 3]);
        let luma_sh = sh_evaluate_diffuse_l1_geomerics(luma_l0, [luma_l1x, luma_l1y, luma_l1z], n);
        sh = add(add(add(l0, scale(l1x, n[0])), scale(l1y, n[1])), scale(l1z, n[2]));
        let regular_luma_sh = dot(sh, [1.0; 3]);
        sh = scale(sh, lerp(1.0, luma_sh / regular_luma_sh, saturate(regular_luma_sh * 16.0)));
    } else {
        sh = add(add(add(l0, scale(l1x, n[0])), scale(l1y, n[1])), scale(l1z, n[2]));
    }
    sh.map(|v| v.max(0.0))
}

/// UnityCG.cginc `DecodeDirectionalLightmap(color, dirTex, normalWorld)`.
pub fn unity_decode_directional_lightmap(color: V3, dir_tex: [f32; 4], normal_world: V3) -> V3 {
    let half_lambert = dot(normal_world, add([dir_tex[0], dir_tex[1], dir_tex[2]], [-0.5; 3])) + 0.5;
    scale(color, half_lambert / dir_tex[3].max(1e-4))
}
