#version 450
#extension GL_GOOGLE_include_directive : require
// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
#include "sbf_engine_lightmaps.glsl"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
vec3 sbf_example(vec3 n, vec3 v, float alpha, vec4 coefficients[36]) {
    {
        SbfLightmapTaps r = sbf_lightmap_bicubic_taps(vec2(0.5), vec2(0.5));
    }
    {
        vec4 r = sbf_lightmap_bspline_axis(0.5);
    }
    vec3 result = vec3(0.0);
    {
        vec3 r = sbf_godot_l1_irradiance(n, n, n, n, n);
        result += r;
    }
    {
        vec3 r = sbf_godot_l1_legacy_irradiance(n, n, n, n, n);
        result += r;
    }
    {
        vec3 r = sbf_monosh_irradiance(n, n, n);
        result += r;
    }
    {
        vec3 r = sbf_monosh_linear_irradiance(n, n, n);
        result += r;
    }
    {
        vec3 r = sbf_enlighten_irradiance(n, vec4(0.5), n);
        result += r;
    }
    {
        vec3 r = sbf_enlighten_rgb_irradiance(n, vec4(0.5), vec4(0.5), vec4(0.5), n);
        result += r;
    }
    return result;
}

layout(std140, set = 0, binding = 0) uniform Inputs {
    vec4 coefficients[36];
    vec4 view_alpha;
};
layout(location = 0) in vec3 normal;
layout(location = 0) out vec4 color;

void main() {
    color = vec4(sbf_example(normalize(normal), normalize(view_alpha.xyz), view_alpha.w, coefficients), 1.0);
}
