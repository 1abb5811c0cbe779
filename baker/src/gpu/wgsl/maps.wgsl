// maps.wgsl — material texture maps at a surface point on the GPU (CPU twin:
// baker::scene::Scene::material_at and scene/texture.rs): the factor times the map (glTF
// 2.0 §3.9.2), colour maps decoded from sRGB (IEC 61966-2-1) before filtering, nearest or
// bilinear (texel centres at (i + ½)/w) with repeat, clamp or mirror wrapping, mip 0, and
// KHR_texture_transform's affine map. Composed only into kernels of textured scenes (the
// shader def TEXTURES). Host side: baker::gpu::maps.

#define_import_path baker::maps

#import baker::bindings::{Material, Tri, load_material, luminance, max3}

// Words 0–3: where the materials, the texture headers, the triangles and the texels
// begin. Per material MAT_WORDS: base colour (3), metallic, roughness, specular,
// emission (3), whether it has a map, then per map (base colour, metallic-roughness,
// emissive) MAP_WORDS: texture + 1 (0: none), texcoord set, the transform's rows (2 × 3);
// then the alpha mask's cutoff (< 0: none) and the base colour factor's alpha.
// Per texture 4: first texel, width, height, wrap S | wrap T << 2 | nearest << 4 (wrap: 0
// repeat, 1 clamp, 2 mirror). Per BVH triangle TRI_WORDS: TEXCOORD_0 and _1 at its three
// corners, which sets it has (bits), the luminance of its mean emission (its NEE share).
// Texels RGBA8, R in the low byte. Floats as their bits.
@group(0) @binding(20) var<storage, read> maps: array<u32>;

const MAT_WORDS: u32 = 36u;
const MAP_WORDS: u32 = 8u;
const TRI_WORDS: u32 = 14u;

fn word_f(i: u32) -> f32 {
    return bitcast<f32>(maps[i]);
}

fn srgb_decode(c: f32) -> f32 {
    return select(pow((c + 0.055) / 1.055, 2.4), c / 12.92, c <= 0.04045);
}

fn wrap_index(i: i32, n: u32, mode: u32) -> u32 {
    let m = i32(n);
    if (mode == 1u) {
        return u32(clamp(i, 0, m - 1));
    }
    let k = ((i % (2 * m)) + 2 * m) % (2 * m);
    if (mode == 2u) {
        return u32(select(2 * m - 1 - k, k, k < m));
    }
    return u32(k % m);
}

fn texel(first: u32, w: u32, x: u32, y: u32, srgb: bool) -> vec4<f32> {
    let v = unpack4x8unorm(maps[maps[3] + first + y * w + x]);
    if (srgb) {
        return vec4<f32>(srgb_decode(v.x), srgb_decode(v.y), srgb_decode(v.z), v.w);
    }
    return v;
}

// Texture t's filtered value at uv.
fn sample_texture(t: u32, uv: vec2<f32>, srgb: bool) -> vec4<f32> {
    let h = maps[1] + 4u * t;
    let first = maps[h];
    let w = maps[h + 1u];
    let ht = maps[h + 2u];
    let flags = maps[h + 3u];
    let ws = flags & 3u;
    let wt = (flags >> 2u) & 3u;
    let x = uv.x * f32(w);
    let y = uv.y * f32(ht);
    if ((flags & 16u) != 0u) {
        return texel(first, w, wrap_index(i32(floor(x)), w, ws), wrap_index(i32(floor(y)), ht, wt), srgb);
    }
    let fx = x - 0.5;
    let fy = y - 0.5;
    let i = i32(floor(fx));
    let j = i32(floor(fy));
    let tx = fx - floor(fx);
    let ty = fy - floor(fy);
    let x0 = wrap_index(i, w, ws);
    let x1 = wrap_index(i + 1, w, ws);
    let y0 = wrap_index(j, ht, wt);
    let y1 = wrap_index(j + 1, ht, wt);
    let top = mix(texel(first, w, x0, y0, srgb), texel(first, w, x1, y0, srgb), tx);
    let bottom = mix(texel(first, w, x0, y1, srgb), texel(first, w, x1, y1, srgb), tx);
    return mix(top, bottom, ty);
}

// Map k of material m at barycentric b of BVH triangle tri (1 where the material has no
// such map or the mesh lacks its coordinate set).
fn map_value(m: u32, k: u32, tri: u32, b: vec2<f32>, srgb: bool) -> vec4<f32> {
    let r = maps[0] + MAT_WORDS * m + 10u + MAP_WORDS * k;
    let t = maps[r];
    let uv_set = maps[r + 1u];
    let tr = maps[2] + TRI_WORDS * tri;
    if (t == 0u || (maps[tr + 12u] & (1u << uv_set)) == 0u) {
        return vec4<f32>(1.0);
    }
    let c = tr + 6u * uv_set;
    let a = vec2<f32>(word_f(c), word_f(c + 1u));
    let e = vec2<f32>(word_f(c + 2u), word_f(c + 3u));
    let f = vec2<f32>(word_f(c + 4u), word_f(c + 5u));
    let uv = a * (1.0 - b.x - b.y) + e * b.x + f * b.y;
    let u = word_f(r + 2u) * uv.x + word_f(r + 3u) * uv.y + word_f(r + 4u);
    let v = word_f(r + 5u) * uv.x + word_f(r + 6u) * uv.y + word_f(r + 7u);
    return sample_texture(t - 1u, vec2<f32>(u, v), srgb);
}

// Barycentric (u, v) of point p on tri (p = corner + u·edge_u + v·edge_v).
fn barycentrics(tri: Tri, p: vec3<f32>) -> vec2<f32> {
    let q = p - tri.corner;
    let d00 = dot(tri.edge_u, tri.edge_u);
    let d01 = dot(tri.edge_u, tri.edge_v);
    let d11 = dot(tri.edge_v, tri.edge_v);
    let d20 = dot(q, tri.edge_u);
    let d21 = dot(q, tri.edge_v);
    let den = d00 * d11 - d01 * d01;
    return vec2<f32>(d11 * d20 - d01 * d21, d00 * d21 - d01 * d20) / den;
}

// Material m of BVH triangle tri at barycentric b: the factors times the maps, the layer
// weights as baker::scene::Material derives them (diffuse = base·(1 − metallic), F0 =
// mix(0.04·specular, base, metallic), α = max(roughness², 10⁻³), the GGX layer's sampling
// probability as estimator::trace::specular_probability).
fn textured_material(m: u32, tri: u32, b: vec2<f32>) -> Material {
    let o = maps[0] + MAT_WORDS * m;
    let plain = load_material(m);
    if (maps[o + 9u] == 0u) {
        return plain;
    }
    let base = vec3<f32>(word_f(o), word_f(o + 1u), word_f(o + 2u)) * map_value(m, 0u, tri, b, true).xyz;
    let mr = map_value(m, 1u, tri, b, false);
    let roughness = word_f(o + 4u) * mr.y;
    let metallic = word_f(o + 3u) * mr.z;
    let specular = word_f(o + 5u);
    let emissive = vec3<f32>(word_f(o + 6u), word_f(o + 7u), word_f(o + 8u)) * map_value(m, 2u, tri, b, true).xyz;
    let diffuse = base * (1.0 - metallic);
    let f0 = mix(vec3<f32>(0.04 * specular), base, metallic);
    let glossy = max3(f0) > 0.0 || (maps[o + 10u + MAP_WORDS] != 0u && specular > 0.0);
    let p = select(0.0, select(1.0, 0.5, max3(diffuse) > 0.0), glossy);
    return Material(diffuse, p, f0, max(roughness * roughness, 1e-3), emissive, glossy, plain.double_sided);
}

// An emission whose luminance is emitter triangle tri's share of NEE over its area (the
// map's mean where it has one; `le` itself otherwise), for emitter_pdf.
fn select_emission(m: u32, tri: u32, le: vec3<f32>) -> vec3<f32> {
    if (maps[maps[0] + MAT_WORDS * m + 10u + 2u * MAP_WORDS] == 0u) {
        return le;
    }
    return vec3<f32>(word_f(maps[2] + TRI_WORDS * tri + 13u));
}

// Whether rays pass through BVH triangle k (`tri`) at point p: its material's alpha mask,
// the base colour factor's alpha × the map's, is below the cutoff (CPU twin:
// Scene::is_hole).
fn is_hole(k: u32, tri: Tri, p: vec3<f32>) -> bool {
    let o = maps[0] + MAT_WORDS * tri.material;
    let cutoff = word_f(o + 34u);
    if (cutoff < 0.0) {
        return false;
    }
    return word_f(o + 35u) * map_value(tri.material, 0u, k, barycentrics(tri, p), false).w < cutoff;
}
