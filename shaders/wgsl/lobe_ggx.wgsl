// lobe_ggx.wgsl — GGX specular from radial lobes (SG λ 6, Ambient Dice SRBF) through their
// per-lobe response tables (luts/lobe_ggx_*.sbflut), uploaded as an rg32float
// texture_2d_array: x = ψ node, y = γ node, layer = n·v node × LOBE_GGX_SQRT_ALPHA_NODES
// + √α node; every axis's nodes span its range edge to edge (n·v, √α ∈ [0, 1]; γ, ψ ∈ [0, π]).
// γ is the angle of the lobe axis from the mirror direction r, ψ its azimuth about r from
// the normal's side. Multilinear by hand from textureLoad (hardware filtering has 8-bit
// weights on many GPUs; see lut.wgsl). Per pixel `lobe_ggx_pixel`, per lobe
// `lobe_ggx_lobe` → (R₀, R₁): the lobe reflects c·(f0·R₀ + f90·R₁).
// CPU twins: sbf::recon::runtime::lobe_ggx_specular (f32), sbf::recon::lobe_ggx (f64).

struct LobeGgxPixel {
    r: vec3<f32>,
    t: vec3<f32>,
    layer: vec4<i32>,
    w: vec4<f32>,
}

// acos by Abramowitz & Stegun 4.4.46 (|error| ≤ 2e-8 rad on [−1, 1]): Vulkan only bounds
// the built-in acos through atan's 4096 ulp (≈ 3e-4 rad measured on lavapipe), which moves
// a lookup by up to 0.1% of its value.
fn lobe_ggx_acos(x: f32) -> f32 {
    let a = abs(x);
    let p = 1.5707963050 + a * (-0.2145988016 + a * (0.0889789874 + a * (-0.0501743046 + a * (0.0308918810 + a * (-0.0170881256 + a * (0.0066700901 - a * 0.0012624911))))));
    let r = sqrt(max(1.0 - a, 0.0)) * p;
    return select(r, PI - r, x < 0.0);
}

// (lower node, fraction) of x ∈ [0, 1] on `size` nodes, clamped.
fn lobe_ggx_locate(x: f32, size: i32) -> vec2<f32> {
    let t = clamp(x, 0.0, 1.0) * f32(size - 1);
    let i = min(floor(t), f32(size - 2));
    return vec2<f32>(i, t - i);
}

// Per pixel: where (n·v, √α) falls in the per-lobe table `tab` (texture_2d_array, rg32float,
// the layout above) for unit normal n and view v in the frame the lobe axes live in, and GGX α
// (= perceptual roughness², clamped to the table). Feed the result to `lobe_ggx_lobe` per lobe.
fn lobe_ggx_pixel(tab: texture_2d_array<f32>, n: vec3<f32>, v: vec3<f32>, alpha: f32) -> LobeGgxPixel {
    let na = LOBE_GGX_SQRT_ALPHA_NODES;
    let nv_nodes = i32(textureNumLayers(tab)) / na;
    let a = lobe_ggx_locate(dot(n, v), nv_nodes);
    let b = lobe_ggx_locate(sqrt(clamp(alpha, 0.0, 1.0)), na);
    let i = i32(a.x);
    let j = i32(b.x);
    let layer = vec4<i32>(i * na + j, i * na + j + 1, (i + 1) * na + j, (i + 1) * na + j + 1);
    let w = vec4<f32>((1.0 - a.y) * (1.0 - b.y), (1.0 - a.y) * b.y, a.y * (1.0 - b.y), a.y * b.y);
    let r = 2.0 * dot(v, n) * n - v;
    let t0 = n - dot(n, r) * r;
    var t = vec3<f32>(0.0);
    if (dot(t0, t0) > 1e-12) {
        t = normalize(t0);
    }
    return LobeGgxPixel(r, t, layer, w);
}

// (R₀, R₁) of one unit lobe with axis `axis`.
fn lobe_ggx_lobe(tab: texture_2d_array<f32>, px: LobeGgxPixel, axis: vec3<f32>) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(tab));
    let rp = clamp(dot(px.r, axis), -1.0, 1.0);
    let st2 = max(1.0 - rp * rp, 0.0);
    var psi = 0.0;
    if (st2 > 1e-12 && dot(px.t, px.t) > 0.0) {
        psi = lobe_ggx_acos(clamp(dot(px.t, axis) / sqrt(st2), -1.0, 1.0));
    }
    let g = lobe_ggx_locate(lobe_ggx_acos(rp) / PI, size.y);
    let p = lobe_ggx_locate(psi / PI, size.x);
    let k = i32(g.x);
    let l = i32(p.x);
    var e = vec2<f32>(0.0);
    for (var c = 0; c < 4; c++) {
        let lay = px.layer[c];
        let lo = textureLoad(tab, vec2<i32>(l, k), lay, 0).xy * (1.0 - p.y) + textureLoad(tab, vec2<i32>(l + 1, k), lay, 0).xy * p.y;
        let hi = textureLoad(tab, vec2<i32>(l, k + 1), lay, 0).xy * (1.0 - p.y) + textureLoad(tab, vec2<i32>(l + 1, k + 1), lay, 0).xy * p.y;
        e += px.w[c] * (lo * (1.0 - g.y) + hi * g.y);
    }
    return e;
}

// ---- The same table through the texture unit's filter ----
// A texture_3d, rg16float (the table's f16 values as committed, filterable on every WebGPU
// device): x = √α node × N_ψ + ψ node, y = γ node, z = n·v node, sampled at mip 0 with a
// linear, clamp-to-edge sampler. One fetch interpolates ψ, γ and n·v; the shader blends
// the two √α tiles: 2 fetches per lobe instead of 16 loads, the same multilinear function.
// A tile is read between its edge texels' centres, so the filter never reaches the next
// tile. The filter's weights are fixed point (8 fractional bits on NVIDIA, AMD and Intel;
// Vulkan's subTexelPrecisionBits): each 1D fraction moves by ≤ 2⁻⁹, i.e. by ≤ 2⁻⁹ × the
// difference between neighbouring nodes along that axis. Per pixel
// `lobe_ggx_filtered_pixel`, per lobe `lobe_ggx_filtered_lobe` → (R₀, R₁), as `lobe_ggx_lobe`.
// CPU twin (the exact multilinear lookup): sbf::recon::runtime::lobe_ggx_specular.

struct LobeGgxFilteredPixel {
    r: vec3<f32>,
    t: vec3<f32>,
    // Texture coordinates: x of ψ = 0 in the two √α tiles, x per unit ψ/π, y of γ = 0, y
    // per unit γ/π, z of this n·v.
    x0: f32,
    x1: f32,
    sx: f32,
    y0: f32,
    sy: f32,
    z: f32,
    // Weight of the upper √α tile.
    wa: f32,
}

// Per pixel: the filtered table's texture coordinates (texture_3d, rg16float, the layout
// above) for unit normal n and view v in the lobe axes' frame, and GGX α (= perceptual
// roughness²). Feed the result to `lobe_ggx_filtered_lobe` per lobe.
fn lobe_ggx_filtered_pixel(tab: texture_3d<f32>, n: vec3<f32>, v: vec3<f32>, alpha: f32) -> LobeGgxFilteredPixel {
    let size = vec3<f32>(textureDimensions(tab));
    let na = LOBE_GGX_SQRT_ALPHA_NODES;
    let npsi = size.x / f32(na);
    let b = lobe_ggx_locate(sqrt(clamp(alpha, 0.0, 1.0)), na);
    let x0 = (b.x * npsi + 0.5) / size.x;
    let z = (clamp(dot(n, v), 0.0, 1.0) * (size.z - 1.0) + 0.5) / size.z;
    let r = 2.0 * dot(v, n) * n - v;
    let t0 = n - dot(n, r) * r;
    var t = vec3<f32>(0.0);
    if (dot(t0, t0) > 1e-12) {
        t = normalize(t0);
    }
    return LobeGgxFilteredPixel(r, t, x0, x0 + npsi / size.x, (npsi - 1.0) / size.x, 0.5 / size.y, (size.y - 1.0) / size.y, z, b.y);
}

// (R₀, R₁) of one unit lobe with axis `axis`.
fn lobe_ggx_filtered_lobe(tab: texture_3d<f32>, smp: sampler, px: LobeGgxFilteredPixel, axis: vec3<f32>) -> vec2<f32> {
    let rp = clamp(dot(px.r, axis), -1.0, 1.0);
    let st2 = max(1.0 - rp * rp, 0.0);
    var psi = 0.0;
    if (st2 > 1e-12 && dot(px.t, px.t) > 0.0) {
        psi = lobe_ggx_acos(clamp(dot(px.t, axis) / sqrt(st2), -1.0, 1.0));
    }
    let xp = clamp(psi / PI, 0.0, 1.0) * px.sx;
    let y = px.y0 + clamp(lobe_ggx_acos(rp) / PI, 0.0, 1.0) * px.sy;
    let lo = textureSampleLevel(tab, smp, vec3<f32>(px.x0 + xp, y, px.z), 0.0).xy;
    let hi = textureSampleLevel(tab, smp, vec3<f32>(px.x1 + xp, y, px.z), 0.0).xy;
    return mix(lo, hi, px.wa);
}
