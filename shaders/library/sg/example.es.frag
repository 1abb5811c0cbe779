#version 300 es
precision highp float;
precision highp int;
// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
// OpenGL has no #include directive: the engine's include step, or a paste, puts
// sbf_sg.es.glsl here.
#include "sbf_sg.es.glsl"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
vec3 sbf_example(vec3 n, vec3 v, float alpha, vec4 coefficients[36], highp sampler2D lut) {
    vec3 result = vec3(0.0);
    {
        float r = sbf_sg_hill_irradiance(n, 0.5, n);
        result += vec3(r);
    }
    {
        vec3 sg9_irradiance_c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 9u; k++) {
            sg9_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sg9_irradiance(sg9_irradiance_c, 0.5, n);
        result += r;
    }
    {
        vec3 sg12_irradiance_c[12] = vec3[12](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 12u; k++) {
            sg12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sg12_irradiance(sg12_irradiance_c, 0.5, n);
        result += r;
    }
    {
        SbfSgSplitSum r = sbf_sg_split_sum_setup(lut, n, v, alpha, 0.04, 1.0);
    }
    {
        SbfSgSplitSum sg_split_sum_lobe_w = sbf_sg_split_sum_setup(lut, n, v, alpha, 0.04, 1.0);
        float r = sbf_sg_split_sum_lobe(sg_split_sum_lobe_w, n, 0.5);
        result += vec3(r);
    }
    {
        vec3 sg9_specular_c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 9u; k++) {
            sg9_specular_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sg9_specular(sg9_specular_c, 0.5, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        vec3 sg12_specular_c[12] = vec3[12](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 12u; k++) {
            sg12_specular_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sg12_specular(sg12_specular_c, 0.5, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    return result;
}

layout(std140) uniform Inputs {
    vec4 coefficients[36];
    vec4 view_alpha;
};
uniform highp sampler2D lut;
in vec3 normal;
layout(location = 0) out vec4 color;

void main() {
    color = vec4(sbf_example(normalize(normal), normalize(view_alpha.xyz), view_alpha.w, coefficients, lut), 1.0);
}
