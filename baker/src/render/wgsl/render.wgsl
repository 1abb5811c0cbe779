// render.wgsl — the scene rasterised and shaded from its bake (seed 004 §8.4.3). Appended
// after the runtime library the `shaders` crate composes (the same functions it exports
// to HLSL/GLSL/MSL). Per pixel: the lightmap's lobes, bilinear at the interpolated
// lightmap UV (atlas texels; centres at i + ½, indices clamped), the tangent frame of the
// interpolated normal (tangent_frame, the frame the bake encoded in), then diffuse =
// albedo·E/π and GGX specular by the configured basis and path. CPU twin:
// baker::render::shade (f64) with baker::render::atlas::footprint.
// Pipeline-overridable constants pick the configuration, so the driver folds the switch.

// 0: plain E/π (diffuse only), 1: SH L1, 2: SH L2, 3: SG, 4: AD 9, 5: AD 12.
override ENCODING: u32 = 0u;
// Specular through the per-lobe tables (lobe_ggx) instead of the fits.
override TABLES: bool = false;
// Lobes per texel (1 for the plain E/π; the lightmap texture may hold a padding layer).
override LOBES: u32 = 1u;

struct Frame {
    view_proj: mat4x4<f32>,
    // xyz: the eye; w: SG sharpness λ.
    eye: vec4<f32>,
    // Atlas size in texels (x, y).
    atlas: vec4<u32>,
    // Lobe axes in the tangent frame (SG, AD).
    axes: array<vec4<f32>, 12>,
}

struct MaterialGpu {
    // xyz: Lambert albedo; w: GGX α.
    albedo_alpha: vec4<f32>,
    // xyz: Schlick F0 (f90 = 1).
    f0: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> materials: array<MaterialGpu>;
@group(0) @binding(2) var lightmap: texture_2d_array<f32>;
@group(0) @binding(3) var lut: texture_2d<f32>;
@group(0) @binding(4) var lobe_tab: texture_2d_array<f32>;

// The material index's high bit: the surface has a lightmap.
const LIGHTMAPPED: u32 = 0x80000000u;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) material: u32,
    // The triangle's face normal (its winding), the same at its three vertices.
    @location(4) face: vec3<f32>,
}

struct VertexOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) material: u32,
    @location(4) @interpolate(flat) face: vec3<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    return VertexOut(frame.view_proj * vec4<f32>(v.position, 1.0), v.position, v.normal, v.uv, v.material, v.face);
}

// The lobes at atlas position uv (texels), bilinear (baker::render::atlas::footprint).
fn lightmap_fetch(uv: vec2<f32>) -> array<vec3<f32>, 12> {
    let size = vec2<i32>(frame.atlas.xy);
    let x = uv - vec2<f32>(0.5);
    let f0 = floor(x);
    let f = x - f0;
    let i0 = clamp(vec2<i32>(f0), vec2<i32>(0), size - 1);
    let i1 = clamp(vec2<i32>(f0) + 1, vec2<i32>(0), size - 1);
    var c: array<vec3<f32>, 12>;
    for (var l = 0u; l < LOBES; l++) {
        let a = textureLoad(lightmap, vec2<i32>(i0.x, i0.y), l, 0).xyz * (1.0 - f.x) + textureLoad(lightmap, vec2<i32>(i1.x, i0.y), l, 0).xyz * f.x;
        let b = textureLoad(lightmap, vec2<i32>(i0.x, i1.y), l, 0).xyz * (1.0 - f.x) + textureLoad(lightmap, vec2<i32>(i1.x, i1.y), l, 0).xyz * f.x;
        c[l] = a * (1.0 - f.y) + b * f.y;
    }
    return c;
}

fn first4(c: array<vec3<f32>, 12>) -> array<vec3<f32>, 4> {
    return array<vec3<f32>, 4>(c[0], c[1], c[2], c[3]);
}

fn first9(c: array<vec3<f32>, 12>) -> array<vec3<f32>, 9> {
    return array<vec3<f32>, 9>(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]);
}

// E/π at the tangent-frame normal +Z.
fn lightmap_irradiance(c: array<vec3<f32>, 12>) -> vec3<f32> {
    let n = vec3<f32>(0.0, 0.0, 1.0);
    switch ENCODING {
        case 1u: {
            return sh_l1_irradiance(first4(c), n);
        }
        case 2u: {
            return sh_l2_irradiance(first9(c), n);
        }
        case 3u: {
            var e = vec3<f32>(0.0);
            for (var l = 0u; l < LOBES; l++) {
                e += c[l] * sg_hill_irradiance(frame.axes[l].xyz, frame.eye.w, n);
            }
            return e;
        }
        case 4u: {
            return ad9_irradiance(first9(c), n);
        }
        case 5u: {
            return ad12_irradiance(c, n);
        }
        default: {
            return c[0];
        }
    }
}

// Σ_l c_l·(f0·R₀ + f90·R₁)(axis_l) through the per-lobe tables.
fn lightmap_tables(c: array<vec3<f32>, 12>, lobes: u32, vt: vec3<f32>, alpha: f32, f0: f32, f90: f32) -> vec3<f32> {
    let px = lobe_ggx_pixel(lobe_tab, vec3<f32>(0.0, 0.0, 1.0), vt, alpha);
    var s = vec3<f32>(0.0);
    for (var l = 0u; l < lobes; l++) {
        let r = lobe_ggx_lobe(lobe_tab, px, frame.axes[l].xyz);
        s += c[l] * (f0 * r.x + f90 * r.y);
    }
    return s;
}

// Specular radiance towards the tangent-frame view vt (vt.z > 0), Schlick (f0, f90).
fn lightmap_specular(c: array<vec3<f32>, 12>, vt: vec3<f32>, alpha: f32, f0: f32, f90: f32) -> vec3<f32> {
    let n = vec3<f32>(0.0, 0.0, 1.0);
    switch ENCODING {
        case 1u: {
            return sh_l1_specular(first4(c), lut, n, vt, alpha, f0, f90);
        }
        case 2u: {
            return sh_l2_specular(first9(c), lut, n, vt, alpha, f0, f90);
        }
        case 3u: {
            if (TABLES) {
                return lightmap_tables(c, LOBES, vt, alpha, f0, f90);
            }
            let w = sg_asg_warp(n, vt, alpha, f0, f90);
            var s = vec3<f32>(0.0);
            for (var l = 0u; l < LOBES; l++) {
                s += c[l] * sg_asg_lobe(w, frame.axes[l].xyz, frame.eye.w);
            }
            return s;
        }
        case 4u: {
            if (TABLES) {
                return lightmap_tables(c, 9u, vt, alpha, f0, f90);
            }
            return ad9_specular(first9(c), lut, n, vt, alpha, f0, f90);
        }
        case 5u: {
            if (TABLES) {
                return lightmap_tables(c, 12u, vt, alpha, f0, f90);
            }
            return ad12_specular(c, lut, n, vt, alpha, f0, f90);
        }
        default: {
            return vec3<f32>(0.0);
        }
    }
}

struct Terms {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

// Whether the pixel sees the lit side of a lightmapped surface (the lightmap holds the
// light arriving at the side its face normal points to; the back of a surface is black).
fn lit_side(vo: VertexOut) -> bool {
    return (vo.material & LIGHTMAPPED) != 0u && dot(frame.eye.xyz - vo.position, vo.face) > 0.0;
}

fn shade(vo: VertexOut) -> Terms {
    var t = Terms(vec3<f32>(0.0), vec3<f32>(0.0));
    if (!lit_side(vo)) {
        return t;
    }
    let m = materials[vo.material & ~LIGHTMAPPED];
    let n = normalize(vo.normal);
    let tb = tangent_frame(n);
    let v = normalize(frame.eye.xyz - vo.position);
    let vt = vec3<f32>(dot(v, tb[0]), dot(v, tb[1]), dot(v, n));
    let c = lightmap_fetch(vo.uv);
    t.diffuse = m.albedo_alpha.xyz * lightmap_irradiance(c);
    let f0 = m.f0.xyz;
    if (ENCODING != 0u && max(f0.x, max(f0.y, f0.z)) > 0.0 && vt.z > 0.0) {
        let alpha = m.albedo_alpha.w;
        if (f0.x == f0.y && f0.y == f0.z) {
            t.specular = lightmap_specular(c, vt, alpha, f0.x, 1.0);
        } else {
            t.specular = f0 * lightmap_specular(c, vt, alpha, 1.0, 0.0) + lightmap_specular(c, vt, alpha, 0.0, 1.0);
        }
    }
    return t;
}

// The frame as an engine draws it: reflected radiance, one target.
@fragment
fn fs_frame(vo: VertexOut) -> @location(0) vec4<f32> {
    let t = shade(vo);
    return vec4<f32>(t.diffuse + t.specular, 1.0);
}

// The analysis targets are rgba32uint holding f32 bits (rgba32float is not renderable
// on every adapter).
struct TermsOut {
    // xyz: diffuse; w: material index (+ 0.5), −1 where nothing lightmapped.
    @location(0) diffuse: vec4<u32>,
    @location(1) specular: vec4<u32>,
}

// Diffuse and specular apart (analysis).
@fragment
fn fs_terms(vo: VertexOut) -> TermsOut {
    let t = shade(vo);
    let id = select(-1.0, f32(vo.material & ~LIGHTMAPPED) + 0.5, lit_side(vo));
    return TermsOut(bitcast<vec4<u32>>(vec4<f32>(t.diffuse, id)), bitcast<vec4<u32>>(vec4<f32>(t.specular, 0.0)));
}

struct SurfaceOut {
    // xyz: interpolated normal (unnormalised); w: lightmap u.
    @location(0) normal_u: vec4<u32>,
    // xyz: world position; w: lightmap v.
    @location(1) position_v: vec4<u32>,
}

// What the rasteriser interpolated (analysis: the CPU twin shades the same inputs).
@fragment
fn fs_surface(vo: VertexOut) -> SurfaceOut {
    return SurfaceOut(bitcast<vec4<u32>>(vec4<f32>(vo.normal, vo.uv.x)), bitcast<vec4<u32>>(vec4<f32>(vo.position, vo.uv.y)));
}
