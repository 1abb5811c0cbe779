// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
#include "sbf_engine_lightmaps.metal"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
inline float3 sbf_example(float3 n, float3 v, float alpha, array<float4, 36> coefficients) {
    {
        SbfLightmapTaps r = sbf_lightmap_bicubic_taps(float2(0.5f), float2(0.5f));
    }
    {
        float4 r = sbf_lightmap_bspline_axis(0.5f);
    }
    float3 result = float3(0.0f);
    {
        float3 r = sbf_godot_l1_irradiance(n, n, n, n, n);
        result += r;
    }
    {
        float3 r = sbf_godot_l1_legacy_irradiance(n, n, n, n, n);
        result += r;
    }
    {
        float3 r = sbf_monosh_irradiance(n, n, n);
        result += r;
    }
    {
        float3 r = sbf_monosh_linear_irradiance(n, n, n);
        result += r;
    }
    {
        float3 r = sbf_enlighten_irradiance(n, float4(0.5f), n);
        result += r;
    }
    {
        float3 r = sbf_enlighten_rgb_irradiance(n, float4(0.5f), float4(0.5f), float4(0.5f), n);
        result += r;
    }
    return result;
}

struct Inputs {
    array<float4, 36> coefficients;
    float4 view_alpha;
};

struct FragmentIn {
    float3 normal [[user(locn0)]];
};

fragment float4 fs_main(FragmentIn frag [[stage_in]], constant Inputs& inputs [[buffer(0)]]) {
    return float4(sbf_example(normalize(frag.normal), normalize(inputs.view_alpha.xyz), inputs.view_alpha.w, inputs.coefficients), 1.0f);
}
