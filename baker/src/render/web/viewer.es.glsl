// viewer.es.glsl — the bake viewer's WebGL 2 stages (GLSL ES 3.0). viewer.js compiles
// each section (`//--- name`) behind `#version 300 es`, precision and its #defines; the
// fragment stage also behind the library's GLSL ES export (sbf.es.glsl). The fragment
// stage is `render.wgsl`'s shading (baker/src/render/wgsl/render.wgsl) in GLSL ES: the same
// footprint, the same per-basis loop over the lobes, the same `sbf_*` runtime calls; storage
// buffers (which WebGL 2 lacks) are RGBA32F textures read by texelFetch.

//--- vertex
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 uv;
layout(location = 3) in uint material;
layout(location = 4) in vec3 face;
uniform mat4 view_proj;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
flat out uint v_material;
flat out vec3 v_face;

void main() {
    // view_proj maps depth to [0, w] (wgpu's, WebGPU's); GL clips to [-w, w]: remapped so
    // that both APIs clip at the same near plane.
    vec4 p = view_proj * vec4(position, 1.0);
    gl_Position = vec4(p.xy, 2.0 * p.z - p.w, p.w);
    v_position = position;
    v_normal = normal;
    v_uv = uv;
    v_material = material;
    v_face = face;
}

//--- fragment
// #defines: ENCODING (0 plain E/π; 1 SH L1, 2 SH L2, 3 SG 9, 4 SG 12, 5 AD 9, 6 AD 12,
// 7 SH L1 + ZH3), LOBES, BICUBIC (0/1).
in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
flat in uint v_material;
flat in vec3 v_face;
// xyz: the eye; w: SG sharpness λ.
uniform vec4 eye;
uniform uvec2 atlas;
uniform vec4 axes[12];
uniform uvec4 grid_dims;
uniform vec4 grid_first;
uniform vec4 grid_last;
uniform highp sampler2DArray lightmap;
uniform highp sampler2D lut;
uniform highp sampler2D dfg;
// Two texels per material: (albedo, α), (F0, 0).
uniform highp sampler2D materials;
// Nine texels per probe, probes_per_row probes a row: SH L2 RGB, w of the first: valid.
uniform highp sampler2D probes;
uniform int probes_per_row;
layout(location = 0) out vec4 out_diffuse;
layout(location = 1) out vec4 out_specular;

const uint LIGHTMAPPED = 0x80000000u;
const uint PROBED = 0x40000000u;

struct Footprint {
    ivec2 i0;
    ivec2 i1;
    vec2 f;
    vec4 tap;
    vec4 g;
};

Footprint lightmap_footprint(vec2 uv) {
    ivec2 size = ivec2(atlas);
    vec2 x = uv - vec2(0.5);
    vec2 fl = floor(x);
    ivec2 i = ivec2(fl);
    Footprint fp = Footprint(clamp(i, ivec2(0), size - 1), clamp(i + 1, ivec2(0), size - 1), x - fl, vec4(0.0), vec4(0.0));
#if BICUBIC
    vec4 ax = sbf_lightmap_bspline_axis(uv.x);
    vec4 ay = sbf_lightmap_bspline_axis(uv.y);
    vec2 s = vec2(atlas);
    fp.tap = vec4(ax.xy / s.x, ay.xy / s.y);
    fp.g = vec4(ax.zw, ay.zw);
#endif
    return fp;
}

vec3 lightmap_lobe(Footprint fp, int l) {
#if BICUBIC
    float fl = float(l);
    vec3 a = texture(lightmap, vec3(fp.tap.xz, fl)).xyz * fp.g.x + texture(lightmap, vec3(fp.tap.yz, fl)).xyz * fp.g.y;
    vec3 b = texture(lightmap, vec3(fp.tap.xw, fl)).xyz * fp.g.x + texture(lightmap, vec3(fp.tap.yw, fl)).xyz * fp.g.y;
    return a * fp.g.z + b * fp.g.w;
#else
    vec3 a = texelFetch(lightmap, ivec3(fp.i0, l), 0).xyz * (1.0 - fp.f.x) + texelFetch(lightmap, ivec3(fp.i1.x, fp.i0.y, l), 0).xyz * fp.f.x;
    vec3 b = texelFetch(lightmap, ivec3(fp.i0.x, fp.i1.y, l), 0).xyz * (1.0 - fp.f.x) + texelFetch(lightmap, ivec3(fp.i1, l), 0).xyz * fp.f.x;
    return a * (1.0 - fp.f.y) + b * fp.f.y;
#endif
}

struct Terms {
    vec3 diffuse;
    vec3 specular;
};

struct Gloss {
    float alpha;
    vec3 f0;
    bool grey;
    bool on;
};

#if ENCODING == 1 || ENCODING == 2 || ENCODING == 7
Terms shade_sh(Footprint fp, vec3 vt, Gloss g) {
    vec3 n = vec3(0.0, 0.0, 1.0);
    Terms t = Terms(vec3(0.0), vec3(0.0));
#if ENCODING == 2
    vec3 c[9] = vec3[9](lightmap_lobe(fp, 0), lightmap_lobe(fp, 1), lightmap_lobe(fp, 2), lightmap_lobe(fp, 3), lightmap_lobe(fp, 4),
        lightmap_lobe(fp, 5), lightmap_lobe(fp, 6), lightmap_lobe(fp, 7), lightmap_lobe(fp, 8));
    t.diffuse = sbf_sh_l2_irradiance(c, n);
    if (g.on) {
        if (g.grey) {
            t.specular = sbf_sh_l2_specular(c, lut, n, vt, g.alpha, g.f0.x, 1.0);
        } else {
            t.specular = g.f0 * sbf_sh_l2_specular(c, lut, n, vt, g.alpha, 1.0, 0.0) + sbf_sh_l2_specular(c, lut, n, vt, g.alpha, 0.0, 1.0);
        }
    }
#else
    vec3 c[4] = vec3[4](lightmap_lobe(fp, 0), lightmap_lobe(fp, 1), lightmap_lobe(fp, 2), lightmap_lobe(fp, 3));
#if ENCODING == 7
    t.diffuse = sbf_sh_l1_zh3_irradiance(c, n);
#else
    t.diffuse = sbf_sh_l1_irradiance(c, n);
#endif
    if (g.on) {
        if (g.grey) {
            t.specular = sbf_sh_l1_specular(c, lut, n, vt, g.alpha, g.f0.x, 1.0);
        } else {
            t.specular = g.f0 * sbf_sh_l1_specular(c, lut, n, vt, g.alpha, 1.0, 0.0) + sbf_sh_l1_specular(c, lut, n, vt, g.alpha, 0.0, 1.0);
        }
    }
#endif
    return t;
}
#endif

#if ENCODING >= 3 && ENCODING <= 6
Terms shade_lobes(Footprint fp, vec3 vt, Gloss g) {
    vec3 n = vec3(0.0, 0.0, 1.0);
    float lambda = eye.w;
    float f0a = g.grey ? g.f0.x : 1.0;
    float f90a = g.grey ? 1.0 : 0.0;
#if ENCODING <= 4
    SbfSgSplitSum warp_a;
    SbfSgSplitSum warp_b;
    if (g.on) {
        warp_a = sbf_sg_split_sum_setup(dfg, n, vt, g.alpha, f0a, f90a);
        warp_b = sbf_sg_split_sum_setup(dfg, n, vt, g.alpha, 0.0, 1.0);
    }
#else
    SbfAdSpecularFit fit;
    vec3 scale = vec3(0.0);
    if (g.on) {
        fit = sbf_ad_specular_fit(n, vt, g.alpha);
        if (g.grey) {
            scale = vec3(sbf_ad_specular_scale(lut, vt.z, g.alpha, g.f0.x, 1.0));
        } else {
            scale = g.f0 * sbf_ad_specular_scale(lut, vt.z, g.alpha, 1.0, 0.0) + vec3(sbf_ad_specular_scale(lut, vt.z, g.alpha, 0.0, 1.0));
        }
    }
#endif
    Terms t = Terms(vec3(0.0), vec3(0.0));
    for (int l = 0; l < LOBES; l++) {
        vec3 c = lightmap_lobe(fp, l);
        vec3 axis = axes[l].xyz;
#if ENCODING <= 4
        t.diffuse += c * sbf_sg_hill_irradiance(axis, lambda, n);
        if (g.on) {
            float a = sbf_sg_split_sum_lobe(warp_a, axis, lambda);
            vec3 w = g.grey ? vec3(a) : g.f0 * a + vec3(sbf_sg_split_sum_lobe(warp_b, axis, lambda));
            t.specular += c * w;
        }
#else
        t.diffuse += c * sbf_ad_lobe_irradiance(axis, n);
        if (g.on) {
            t.specular += c * (sbf_ad_specular_lobe(fit, axis) * scale);
        }
#endif
    }
    return t;
}
#endif

// SH L2 at p: trilinear over the lattice cell, invalid probes left out and the rest
// renormalised (render.wgsl's probe_sample).
Terms shade_probed(vec3 p, vec3 n, vec3 v, Gloss g) {
    Terms t = Terms(vec3(0.0), vec3(0.0));
    if (grid_dims.w == 0u) {
        return t;
    }
    ivec3 dims = ivec3(grid_dims.xyz);
    vec3 span = max(grid_last.xyz - grid_first.xyz, vec3(1e-30));
    vec3 top = vec3(max(dims - 1, ivec3(0)));
    vec3 tt = clamp((p - grid_first.xyz) / span * top, vec3(0.0), top);
    ivec3 i = min(ivec3(floor(tt)), max(dims - 2, ivec3(0)));
    vec3 f = mix(vec3(0.0), tt - vec3(i), greaterThanEqual(dims, ivec3(2)));
    vec3 c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
    float wsum = 0.0;
    for (int corner = 0; corner < 8; corner++) {
        ivec3 d = ivec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        ivec3 idx = min(i + d, dims - 1);
        vec3 wv = mix(vec3(1.0) - f, f, equal(d, ivec3(1)));
        float w = wv.x * wv.y * wv.z;
        int k = idx.x + dims.x * (idx.y + dims.y * idx.z);
        ivec2 at = ivec2(9 * (k % probes_per_row), k / probes_per_row);
        if (w > 0.0 && texelFetch(probes, at, 0).w > 0.5) {
            for (int l = 0; l < 9; l++) {
                c[l] += w * texelFetch(probes, at + ivec2(l, 0), 0).xyz;
            }
            wsum += w;
        }
    }
    if (wsum <= 0.0) {
        return t;
    }
    for (int l = 0; l < 9; l++) {
        c[l] /= wsum;
    }
    t.diffuse = sbf_sh_l2_irradiance(c, n);
    if (g.on) {
        if (g.grey) {
            t.specular = sbf_sh_l2_specular(c, dfg, n, v, g.alpha, g.f0.x, 1.0);
        } else {
            t.specular = g.f0 * sbf_sh_l2_specular(c, dfg, n, v, g.alpha, 1.0, 0.0) + sbf_sh_l2_specular(c, dfg, n, v, g.alpha, 0.0, 1.0);
        }
    }
    return t;
}

void main() {
    out_diffuse = vec4(0.0, 0.0, 0.0, -1.0);
    out_specular = vec4(0.0);
    if (dot(eye.xyz - v_position, v_face) <= 0.0) {
        return;
    }
    uint kind = (v_material & LIGHTMAPPED) != 0u ? 1u : ((v_material & PROBED) != 0u ? 2u : 0u);
    if (kind == 0u) {
        return;
    }
    int m = int(v_material & ~(LIGHTMAPPED | PROBED));
    vec4 albedo_alpha = texelFetch(materials, ivec2(2 * m, 0), 0);
    vec3 f0 = texelFetch(materials, ivec2(2 * m + 1, 0), 0).xyz;
    vec3 n = normalize(v_normal);
    vec3 v = normalize(eye.xyz - v_position);
    bool glossy = max(f0.x, max(f0.y, f0.z)) > 0.0;
    bool grey = f0.x == f0.y && f0.y == f0.z;
    Terms t;
    if (kind == 2u) {
        t = shade_probed(v_position, n, v, Gloss(albedo_alpha.w, f0, grey, glossy && dot(n, v) > 0.0));
    } else {
        vec3 tb[2] = sbf_tangent_frame(n);
        vec3 vt = vec3(dot(v, tb[0]), dot(v, tb[1]), dot(v, n));
        Footprint fp = lightmap_footprint(v_uv);
        Gloss g = Gloss(albedo_alpha.w, f0, grey, ENCODING != 0 && glossy && vt.z > 0.0);
#if ENCODING == 1 || ENCODING == 2 || ENCODING == 7
        t = shade_sh(fp, vt, g);
#elif ENCODING >= 3 && ENCODING <= 6
        t = shade_lobes(fp, vt, g);
#else
        t = Terms(lightmap_lobe(fp, 0), vec3(0.0));
#endif
    }
    out_diffuse = vec4(t.diffuse * albedo_alpha.xyz, float(m) + 0.5);
    out_specular = vec4(t.specular, float(kind));
}

//--- display
// The frame to the canvas: the diffuse, specular or total term (TERM 0, 1, 2) of the shaded
// targets left of the split and the reference's right of it, × exposure, the report's tone
// curve x/(1 + x), sRGB (render::report::tonemap_rgb, output::srgb8).
uniform highp sampler2D shaded_diffuse;
uniform highp sampler2D shaded_specular;
uniform highp sampler2D reference;
uniform float exposure;
uniform int term;
// The split's x in pixels (≥ the width: no reference shown); has_reference 0: none.
uniform float split;
uniform int has_reference;
layout(location = 0) out vec4 color;

float srgb(float v) {
    float x = clamp(v, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(shaded_diffuse, 0);
    // Row 0 of the targets is the frame's bottom (GL); the reference is stored from the top.
    vec3 c;
    if (has_reference != 0 && gl_FragCoord.x >= split) {
        ivec2 q = ivec2(p.x, size.y - 1 - p.y);
        vec3 d = texelFetch(reference, ivec2(q.x, q.y), 0).xyz;
        vec3 s = texelFetch(reference, ivec2(q.x, q.y + size.y), 0).xyz;
        c = term == 0 ? d : (term == 1 ? s : d + s);
    } else {
        vec3 d = texelFetch(shaded_diffuse, p, 0).xyz;
        vec3 s = texelFetch(shaded_specular, p, 0).xyz;
        c = term == 0 ? d : (term == 1 ? s : d + s);
    }
    vec3 e = max(c, vec3(0.0)) * exposure;
    e = e / (vec3(1.0) + e);
    color = vec4(srgb(e.x), srgb(e.y), srgb(e.z), 1.0);
}
