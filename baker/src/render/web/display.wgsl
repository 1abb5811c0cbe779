// display.wgsl — the bake viewer's WebGPU display pass: render.wgsl's fs_terms targets
// (f32 bits in rgba32uint: diffuse, specular) or, right of the split, the reference's, as
// the diffuse, specular or total term (term 0, 1, 2) × exposure, the report's tone curve
// x/(1 + x), sRGB (render::report::tonemap_rgb, output::srgb8) — the same as viewer.es.glsl's
// `display` section.

struct Display {
    exposure: f32,
    term: u32,
    // The split's x in pixels (≥ the width: no reference shown).
    split: f32,
    has_reference: u32,
}

@group(0) @binding(0) var<uniform> display: Display;
@group(0) @binding(1) var shaded_diffuse: texture_2d<u32>;
@group(0) @binding(2) var shaded_specular: texture_2d<u32>;
// Diffuse in rows [0, h), specular in rows [h, 2h), from the top.
@group(0) @binding(3) var reference: texture_2d<f32>;

@vertex
fn vs_display(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u);
    let y = f32(i & 2u);
    return vec4<f32>(x * 2.0 - 1.0, y * 2.0 - 1.0, 0.0, 1.0);
}

fn srgb(v: f32) -> f32 {
    let x = clamp(v, 0.0, 1.0);
    return select(1.055 * pow(x, 1.0 / 2.4) - 0.055, 12.92 * x, x <= 0.0031308);
}

fn pick(d: vec3<f32>, s: vec3<f32>) -> vec3<f32> {
    if (display.term == 0u) {
        return d;
    }
    if (display.term == 1u) {
        return s;
    }
    return d + s;
}

@fragment
fn fs_display(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let h = i32(textureDimensions(shaded_diffuse).y);
    var c: vec3<f32>;
    if (display.has_reference != 0u && frag.x >= display.split) {
        c = pick(textureLoad(reference, p, 0).xyz, textureLoad(reference, vec2<i32>(p.x, p.y + h), 0).xyz);
    } else {
        c = pick(bitcast<vec4<f32>>(textureLoad(shaded_diffuse, p, 0)).xyz, bitcast<vec4<f32>>(textureLoad(shaded_specular, p, 0)).xyz);
    }
    var e = max(c, vec3<f32>(0.0)) * display.exposure;
    e = e / (vec3<f32>(1.0) + e);
    return vec4<f32>(srgb(e.x), srgb(e.y), srgb(e.z), 1.0);
}
