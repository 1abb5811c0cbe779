// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
#include "sbf_engine_lightmaps.hlsl"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
float3 sbf_example(float3 n, float3 v, float alpha, float4 coefficients[36]) {
    {
        SbfLightmapTaps r = sbf_lightmap_bicubic_taps(((float2)0.5), ((float2)0.5));
    }
    {
        float4 r = sbf_lightmap_bspline_axis(0.5);
    }
    float3 result = ((float3)0.0);
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
        float3 r = sbf_enlighten_irradiance(n, ((float4)0.5), n);
        result += r;
    }
    {
        float3 r = sbf_enlighten_rgb_irradiance(n, ((float4)0.5), ((float4)0.5), ((float4)0.5), n);
        result += r;
    }
    return result;
}

cbuffer Inputs : register(b0) {
    float4 coefficients[36];
    float4 view_alpha;
};

float4 main(float3 normal : NORMAL) : SV_Target {
    return float4(sbf_example(normalize(normal), normalize(view_alpha.xyz), view_alpha.w, coefficients), 1.0);
}
