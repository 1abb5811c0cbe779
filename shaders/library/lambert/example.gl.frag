#version 450 core
// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
// OpenGL has no #include directive: the engine's include step, or a paste, puts
// sbf_lambert.gl.glsl here.
#include "sbf_lambert.gl.glsl"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
vec3 sbf_example(vec3 n, vec3 v, float alpha, vec4 coefficients[36]) {
    vec3 result = vec3(0.0);
    {
        vec3 sh_l2_irradiance_c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 9u; k++) {
            sh_l2_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sh_l2_irradiance(sh_l2_irradiance_c, n);
        result += r;
    }
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
        vec3 ad9_irradiance_c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 9u; k++) {
            ad9_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_ad9_irradiance(ad9_irradiance_c, n);
        result += r;
    }
    {
        vec3 ad12_irradiance_c[12] = vec3[12](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 12u; k++) {
            ad12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_ad12_irradiance(ad12_irradiance_c, n);
        result += r;
    }
    return result;
}

layout(std140, binding = 0) uniform Inputs {
    vec4 coefficients[36];
    vec4 view_alpha;
};
layout(location = 0) in vec3 normal;
layout(location = 0) out vec4 color;

void main() {
    color = vec4(sbf_example(normalize(normal), normalize(view_alpha.xyz), view_alpha.w, coefficients), 1.0);
}
