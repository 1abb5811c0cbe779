// render.wgsl — the scene rasterised and shaded from its bake ([Roughton19 §8.4.3]). Appended
// after the runtime library the `shaders` crate composes (the same functions it exports
// to HLSL/GLSL/MSL). Per pixel: the lightmap's lobes, bilinear at the interpolated
// lightmap UV (atlas texels; centres at i + ½, indices clamped), the tangent frame of the
// interpolated normal (tangent_frame, the frame the bake encoded in), then diffuse =
// albedo·E/π and GGX specular by the configured basis and path — SH through the
// runtime's array functions, SG and AD in one pass over the lobes through its per-lobe
// functions (each lobe read once; no coefficient array, which GPUs keep in slow local
// memory past ~9 vec3s). CPU twin: baker::render::shade (f64) with
// baker::render::atlas::footprint.
// Pipeline-overridable constants pick the configuration, so the driver folds the switch.
// Two paths shade with the same `shade`: forward (fs_frame, fs_terms: the raster pass's
// fragments) and deferred (fs_gbuffer writes the fragments' inputs, then cs_frame or
// cs_terms shade them in a compute pass over 8×8 tiles; baker::render::deferred).

// 0: plain E/π (diffuse only), else the basis' GPU slot kind + 1 (sbf::registry): 1 SH L1,
// 2 SH L2, 3 SG 9, 4 SG 12, 5 AD 9, 6 AD 12, 7 SH L1 + ZH3.
override ENCODING: u32 = 0u;
// Specular through the per-lobe tables (lobe_ggx_filtered: the texture unit interpolates
// three of their four axes) instead of the fits.
override TABLES: bool = false;
// Lobes per texel (1 for the plain E/π; the lightmap texture may hold a padding layer).
override LOBES: u32 = 1u;
// Read the lightmap through the sampler's bilinear filter (as engines do: one fetch per
// lobe, the weights at the GPU's sub-texel precision) instead of four loads weighted in f32.
override HW_FILTER: bool = false;
// The cubic B-spline instead, by four bilinear taps of the sampler (Sigg and Hadwiger 2005;
// the library's lightmap_bspline_axis, CPU twin sbf::recon::lut::bspline_taps).
override BICUBIC: bool = false;
// Timing only: fetch every lobe (the same bilinear lookups) and sum them, no runtime — the
// configuration's lightmap-bandwidth floor.
override FETCH_ONLY: bool = false;

struct Frame {
    view_proj: mat4x4<f32>,
    // xyz: the eye; w: SG sharpness λ.
    eye: vec4<f32>,
    // Atlas size in texels (x, y).
    atlas: vec4<u32>,
    // Lobe axes in the tangent frame (SG, AD).
    axes: array<vec4<f32>, 12>,
    // The probe lattice: probes along x, y, z (w: probe count, 0 without probes) and the
    // positions of its first and last probe.
    grid_dims: vec4<u32>,
    grid_first: vec4<f32>,
    grid_last: vec4<f32>,
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
@group(0) @binding(4) var lobe_tab: texture_3d<f32>;
// SH L2 probes (world frame), 9 RGB rows per probe, x fastest; row 0's w: 1 valid, 0 inside geometry.
@group(0) @binding(5) var<storage, read> probes: array<vec4<f32>>;
@group(0) @binding(6) var dfg: texture_2d<f32>;
// Bilinear, clamped to the edge (HW_FILTER only).
@group(0) @binding(7) var lightmap_sampler: sampler;
// Trilinear, clamped to the edge: the lobe table's.
@group(0) @binding(8) var lobe_sampler: sampler;

// The material index's high bits: the surface has a lightmap, or is a dynamic object
// shaded from the probes.
const LIGHTMAPPED: u32 = 0x80000000u;
const PROBED: u32 = 0x40000000u;

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

// The bilinear footprint at atlas position uv (texels; baker::render::atlas::footprint):
// the lower and upper texel (clamped to the atlas) and the fractional position; and the
// normalised position the sampler reads (the same texel centres and clamping).
struct Footprint {
    i0: vec2<i32>,
    i1: vec2<i32>,
    f: vec2<f32>,
    uv: vec2<f32>,
    // BICUBIC: the taps' normalised positions (x₀, x₁, y₀, y₁) and weights (gx₀, gx₁, gy₀, gy₁).
    tap: vec4<f32>,
    g: vec4<f32>,
}

fn lightmap_footprint(uv: vec2<f32>) -> Footprint {
    let size = vec2<i32>(frame.atlas.xy);
    let x = uv - vec2<f32>(0.5);
    let fl = floor(x);
    let i = vec2<i32>(fl);
    var fp = Footprint(clamp(i, vec2<i32>(0), size - 1), clamp(i + 1, vec2<i32>(0), size - 1), x - fl, uv / vec2<f32>(frame.atlas.xy), vec4<f32>(0.0), vec4<f32>(0.0));
    if (BICUBIC) {
        let ax = lightmap_bspline_axis(uv.x);
        let ay = lightmap_bspline_axis(uv.y);
        let s = vec2<f32>(frame.atlas.xy);
        fp.tap = vec4<f32>(ax.xy / s.x, ay.xy / s.y);
        fp.g = vec4<f32>(ax.zw, ay.zw);
    }
    return fp;
}

// Lobe l's RGB value at the footprint, bilinear.
fn lightmap_lobe(fp: Footprint, l: u32) -> vec3<f32> {
    if (HW_FILTER) {
        return textureSampleLevel(lightmap, lightmap_sampler, fp.uv, l, 0.0).xyz;
    }
    if (BICUBIC) {
        let a = textureSampleLevel(lightmap, lightmap_sampler, fp.tap.xz, l, 0.0).xyz * fp.g.x + textureSampleLevel(lightmap, lightmap_sampler, fp.tap.yz, l, 0.0).xyz * fp.g.y;
        let b = textureSampleLevel(lightmap, lightmap_sampler, fp.tap.xw, l, 0.0).xyz * fp.g.x + textureSampleLevel(lightmap, lightmap_sampler, fp.tap.yw, l, 0.0).xyz * fp.g.y;
        return a * fp.g.z + b * fp.g.w;
    }
    let a = textureLoad(lightmap, fp.i0, l, 0).xyz * (1.0 - fp.f.x) + textureLoad(lightmap, vec2<i32>(fp.i1.x, fp.i0.y), l, 0).xyz * fp.f.x;
    let b = textureLoad(lightmap, vec2<i32>(fp.i0.x, fp.i1.y), l, 0).xyz * (1.0 - fp.f.x) + textureLoad(lightmap, fp.i1, l, 0).xyz * fp.f.x;
    return a * (1.0 - fp.f.y) + b * fp.f.y;
}

struct Terms {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

// What the specular of one surface needs: GGX α, Schlick F0 (f90 = 1), whether F0 is grey
// (one evaluation with (F0, 1)) or coloured (F0·S(1, 0) + S(0, 1), by linearity).
struct Gloss {
    alpha: f32,
    f0: vec3<f32>,
    grey: bool,
    on: bool,
}

// SH (bands ≤ 2): the runtime's array functions on the lobes read once.
fn shade_sh(fp: Footprint, vt: vec3<f32>, g: Gloss) -> Terms {
    let n = vec3<f32>(0.0, 0.0, 1.0);
    var t = Terms(vec3<f32>(0.0), vec3<f32>(0.0));
    if (ENCODING == 1u || ENCODING == 7u) {
        let c = array<vec3<f32>, 4>(lightmap_lobe(fp, 0u), lightmap_lobe(fp, 1u), lightmap_lobe(fp, 2u), lightmap_lobe(fp, 3u));
        if (ENCODING == 7u) {
            t.diffuse = sh_l1_zh3_irradiance(c, n);
        } else {
            t.diffuse = sh_l1_irradiance(c, n);
        }
        if (g.on) {
            if (g.grey) {
                t.specular = sh_l1_specular(c, lut, n, vt, g.alpha, g.f0.x, 1.0);
            } else {
                t.specular = g.f0 * sh_l1_specular(c, lut, n, vt, g.alpha, 1.0, 0.0) + sh_l1_specular(c, lut, n, vt, g.alpha, 0.0, 1.0);
            }
        }
        return t;
    }
    // Built from constant indices, as for L1: a loop filling the array leaves it in local
    // memory on some GPUs.
    let c = array<vec3<f32>, 9>(
        lightmap_lobe(fp, 0u), lightmap_lobe(fp, 1u), lightmap_lobe(fp, 2u), lightmap_lobe(fp, 3u), lightmap_lobe(fp, 4u),
        lightmap_lobe(fp, 5u), lightmap_lobe(fp, 6u), lightmap_lobe(fp, 7u), lightmap_lobe(fp, 8u),
    );
    t.diffuse = sh_l2_irradiance(c, n);
    if (g.on) {
        if (g.grey) {
            t.specular = sh_l2_specular(c, lut, n, vt, g.alpha, g.f0.x, 1.0);
        } else {
            t.specular = g.f0 * sh_l2_specular(c, lut, n, vt, g.alpha, 1.0, 0.0) + sh_l2_specular(c, lut, n, vt, g.alpha, 0.0, 1.0);
        }
    }
    return t;
}

// SG and AD: one pass over the lobes, each read once and weighted by the runtime's per-lobe
// functions (the per-pixel parts set up before the loop) — no coefficient array.
fn shade_lobes(fp: Footprint, vt: vec3<f32>, g: Gloss) -> Terms {
    let n = vec3<f32>(0.0, 0.0, 1.0);
    let lambda = frame.eye.w;
    let sg = ENCODING == 3u || ENCODING == 4u;
    // Per-pixel parts of each specular runtime ((1, 0) and (0, 1) Fresnel for a coloured F0).
    let f0a = select(1.0, g.f0.x, g.grey);
    let f90a = select(0.0, 1.0, g.grey);
    var warp_a: SgSplitSum;
    var warp_b: SgSplitSum;
    var fit: AdSpecularFit;
    var scale = vec3<f32>(0.0);
    var px: LobeGgxFilteredPixel;
    if (g.on) {
        if (TABLES) {
            px = lobe_ggx_filtered_pixel(lobe_tab, n, vt, g.alpha);
        } else if (sg) {
            warp_a = sg_split_sum_setup(dfg, n, vt, g.alpha, f0a, f90a);
            warp_b = sg_split_sum_setup(dfg, n, vt, g.alpha, 0.0, 1.0);
        } else {
            fit = ad_specular_fit(n, vt, g.alpha);
            if (g.grey) {
                scale = vec3<f32>(ad_specular_scale(lut, vt.z, g.alpha, g.f0.x, 1.0));
            } else {
                scale = g.f0 * ad_specular_scale(lut, vt.z, g.alpha, 1.0, 0.0) + vec3<f32>(ad_specular_scale(lut, vt.z, g.alpha, 0.0, 1.0));
            }
        }
    }
    var t = Terms(vec3<f32>(0.0), vec3<f32>(0.0));
    for (var l = 0u; l < LOBES; l++) {
        let c = lightmap_lobe(fp, l);
        let axis = frame.axes[l].xyz;
        if (sg) {
            t.diffuse += c * sg_hill_irradiance(axis, lambda, n);
        } else {
            t.diffuse += c * ad_lobe_irradiance(axis, n);
        }
        if (g.on) {
            var w: vec3<f32>;
            if (TABLES) {
                let r = lobe_ggx_filtered_lobe(lobe_tab, lobe_sampler, px, axis);
                w = select(g.f0 * r.x + vec3<f32>(r.y), vec3<f32>(g.f0.x * r.x + r.y), g.grey);
            } else if (sg) {
                let a = sg_split_sum_lobe(warp_a, axis, lambda);
                w = select(g.f0 * a + vec3<f32>(sg_split_sum_lobe(warp_b, axis, lambda)), vec3<f32>(a), g.grey);
            } else {
                w = ad_specular_lobe(fit, axis) * scale;
            }
            t.specular += c * w;
        }
    }
    return t;
}

// What a pixel shades: 1 the lit side of a lightmapped surface (the lightmap holds the light
// arriving at the side its face normal points to); 2 the front of a dynamic object; 0
// neither (the back of a surface, an emitter, no surface): black. The rest is what the
// rasteriser interpolated — the forward pass's fragment inputs, or the deferred path's
// G-buffer.
struct Surface {
    kind: u32,
    // The material's index (flags removed).
    material: u32,
    position: vec3<f32>,
    // Interpolated, not normalised.
    normal: vec3<f32>,
    uv: vec2<f32>,
}

fn surface_kind(vo: VertexOut) -> u32 {
    if (dot(frame.eye.xyz - vo.position, vo.face) <= 0.0) {
        return 0u;
    }
    if ((vo.material & LIGHTMAPPED) != 0u) {
        return 1u;
    }
    return select(0u, 2u, (vo.material & PROBED) != 0u);
}

fn surface_of(vo: VertexOut) -> Surface {
    return Surface(surface_kind(vo), vo.material & ~(LIGHTMAPPED | PROBED), vo.position, vo.normal, vo.uv);
}

struct ProbeSample {
    c: array<vec3<f32>, 9>,
    // Σ of the valid probes' trilinear weights (0: none valid).
    w: f32,
}

// SH L2 at p: trilinear over the lattice cell (clamped), invalid probes left out and the
// rest renormalised (baker::render::probes::ProbeField::at).
fn probe_sample(p: vec3<f32>) -> ProbeSample {
    var out: ProbeSample;
    let dims = vec3<i32>(frame.grid_dims.xyz);
    let span = max(frame.grid_last.xyz - frame.grid_first.xyz, vec3<f32>(1e-30));
    let t = clamp((p - frame.grid_first.xyz) / span * vec3<f32>(max(dims - 1, vec3<i32>(0))), vec3<f32>(0.0), vec3<f32>(max(dims - 1, vec3<i32>(0))));
    let i = min(vec3<i32>(floor(t)), max(dims - 2, vec3<i32>(0)));
    let f = select(vec3<f32>(0.0), t - vec3<f32>(i), dims >= vec3<i32>(2));
    for (var corner = 0; corner < 8; corner++) {
        let d = vec3<i32>(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        let idx = min(i + d, dims - 1);
        let wv = select(vec3<f32>(1.0) - f, f, d == vec3<i32>(1));
        let w = wv.x * wv.y * wv.z;
        let k = u32(idx.x + dims.x * (idx.y + dims.y * idx.z));
        if (w > 0.0 && probes[k * 9u].w > 0.5) {
            for (var l = 0u; l < 9u; l++) {
                out.c[l] += w * probes[k * 9u + l].xyz;
            }
            out.w += w;
        }
    }
    if (out.w > 0.0) {
        for (var l = 0u; l < 9u; l++) {
            out.c[l] /= out.w;
        }
    }
    return out;
}

// A dynamic object: SH L2 probes in the world frame (baker::render::shade::probe_terms).
fn shade_probed(p: vec3<f32>, n: vec3<f32>, v: vec3<f32>, g: Gloss) -> Terms {
    var t = Terms(vec3<f32>(0.0), vec3<f32>(0.0));
    if (frame.grid_dims.w == 0u) {
        return t;
    }
    let s = probe_sample(p);
    if (s.w <= 0.0) {
        return t;
    }
    t.diffuse = sh_l2_irradiance(s.c, n);
    if (g.on) {
        if (g.grey) {
            t.specular = sh_l2_specular(s.c, dfg, n, v, g.alpha, g.f0.x, 1.0);
        } else {
            t.specular = g.f0 * sh_l2_specular(s.c, dfg, n, v, g.alpha, 1.0, 0.0) + sh_l2_specular(s.c, dfg, n, v, g.alpha, 0.0, 1.0);
        }
    }
    return t;
}

fn shade(s: Surface) -> Terms {
    let kind = s.kind;
    if (kind == 0u) {
        return Terms(vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let m = materials[s.material];
    let n = normalize(s.normal);
    let v = normalize(frame.eye.xyz - s.position);
    let f0 = m.f0.xyz;
    let glossy = max(f0.x, max(f0.y, f0.z)) > 0.0;
    var t: Terms;
    if (kind == 2u) {
        t = shade_probed(s.position, n, v, Gloss(m.albedo_alpha.w, f0, f0.x == f0.y && f0.y == f0.z, glossy && dot(n, v) > 0.0));
    } else {
        let tb = tangent_frame(n);
        let vt = vec3<f32>(dot(v, tb[0]), dot(v, tb[1]), dot(v, n));
        let fp = lightmap_footprint(s.uv);
        let g = Gloss(m.albedo_alpha.w, f0, f0.x == f0.y && f0.y == f0.z, ENCODING != 0u && glossy && vt.z > 0.0);
        if (FETCH_ONLY) {
            var c = vec3<f32>(0.0);
            for (var l = 0u; l < LOBES; l++) {
                c += lightmap_lobe(fp, l);
            }
            return Terms(c * m.albedo_alpha.xyz, vec3<f32>(0.0));
        }
        switch ENCODING {
            case 1u, 2u, 7u: {
                t = shade_sh(fp, vt, g);
            }
            case 3u, 4u, 5u, 6u: {
                t = shade_lobes(fp, vt, g);
            }
            default: {
                t = Terms(lightmap_lobe(fp, 0u), vec3<f32>(0.0));
            }
        }
    }
    t.diffuse *= m.albedo_alpha.xyz;
    return t;
}

// The frame as an engine draws it: reflected radiance, one target.
@fragment
fn fs_frame(vo: VertexOut) -> @location(0) vec4<f32> {
    let t = shade(surface_of(vo));
    return vec4<f32>(t.diffuse + t.specular, 1.0);
}

// The analysis targets are rgba32uint holding f32 bits (rgba32float is not renderable
// on every adapter).
struct TermsOut {
    // xyz: diffuse; w: material index (+ 0.5), −1 where not shaded (surface_kind 0).
    @location(0) diffuse: vec4<u32>,
    // xyz: specular; w: surface_kind.
    @location(1) specular: vec4<u32>,
}

// Diffuse and specular apart (analysis).
@fragment
fn fs_terms(vo: VertexOut) -> TermsOut {
    return terms_out(surface_of(vo));
}

fn terms_out(s: Surface) -> TermsOut {
    let t = shade(s);
    let id = select(-1.0, f32(s.material) + 0.5, s.kind != 0u);
    return TermsOut(bitcast<vec4<u32>>(vec4<f32>(t.diffuse, id)), bitcast<vec4<u32>>(vec4<f32>(t.specular, f32(s.kind))));
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

// ---- The deferred path: a G-buffer from the raster pass, then shading in a compute pass
// over 8×8-pixel tiles (how current engines light a frame). The G-buffer keeps what the
// forward pass's fragments are given, in f32, so that both paths shade the same inputs.

struct GBufferOut {
    // xyz: interpolated normal (unnormalised); w: lightmap u (f32 bits).
    @location(0) normal_u: vec4<u32>,
    // xyz: world position; w: lightmap v (f32 bits).
    @location(1) position_v: vec4<u32>,
    // The material's index | kind << 30 (0: nothing to shade; the clear value).
    @location(2) surface: u32,
}

@fragment
fn fs_gbuffer(vo: VertexOut) -> GBufferOut {
    let s = surface_of(vo);
    return GBufferOut(
        bitcast<vec4<u32>>(vec4<f32>(vo.normal, vo.uv.x)),
        bitcast<vec4<u32>>(vec4<f32>(vo.position, vo.uv.y)),
        select(0u, s.material | (s.kind << 30u), s.kind != 0u),
    );
}

@group(1) @binding(0) var gbuffer_normal_u: texture_2d<u32>;
@group(1) @binding(1) var gbuffer_position_v: texture_2d<u32>;
@group(1) @binding(2) var gbuffer_surface: texture_2d<u32>;
// cs_frame's target (the engine's frame) and cs_terms' (diffuse and specular apart, as
// fs_terms writes them).
@group(1) @binding(3) var frame_out: texture_storage_2d<rgba16float, write>;
@group(1) @binding(4) var diffuse_out: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(5) var specular_out: texture_storage_2d<rgba32uint, write>;

// The surface the G-buffer holds at pixel p.
fn gbuffer_surface_at(p: vec2<i32>) -> Surface {
    let word = textureLoad(gbuffer_surface, p, 0).x;
    let nu = bitcast<vec4<f32>>(textureLoad(gbuffer_normal_u, p, 0));
    let pv = bitcast<vec4<f32>>(textureLoad(gbuffer_position_v, p, 0));
    return Surface(word >> 30u, word & 0x3fffffffu, pv.xyz, nu.xyz, vec2<f32>(nu.w, pv.w));
}

// One invocation per pixel, a workgroup per 8×8 tile.
@compute @workgroup_size(8, 8)
fn cs_frame(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(gbuffer_surface);
    if (any(id.xy >= size)) {
        return;
    }
    let t = shade(gbuffer_surface_at(vec2<i32>(id.xy)));
    textureStore(frame_out, vec2<i32>(id.xy), vec4<f32>(t.diffuse + t.specular, 1.0));
}

// Diffuse and specular apart (analysis; the same words fs_terms writes).
@compute @workgroup_size(8, 8)
fn cs_terms(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(gbuffer_surface);
    if (any(id.xy >= size)) {
        return;
    }
    let o = terms_out(gbuffer_surface_at(vec2<i32>(id.xy)));
    textureStore(diffuse_out, vec2<i32>(id.xy), o.diffuse);
    textureStore(specular_out, vec2<i32>(id.xy), o.specular);
}
