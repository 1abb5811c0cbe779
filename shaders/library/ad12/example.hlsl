// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
#include "sbf_ad12.hlsl"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
float3 sbf_example(float3 n, float3 v, float alpha, float4 coefficients[36], Texture2D<float2> lut) {
    float3 result = ((float3)0.0);
    {
        float3 ad12_irradiance_c[12] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 12u; k++) {
            ad12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad12_irradiance(ad12_irradiance_c, n);
        result += r;
    }
    {
        float3 ad12_specular_c[12] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 12u; k++) {
            ad12_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad12_specular(ad12_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    return result;
}

cbuffer Inputs : register(b0) {
    float4 coefficients[36];
    float4 view_alpha;
};
Texture2D<float2> lut : register(t0);

float4 main(float3 normal : NORMAL) : SV_Target {
    return float4(sbf_example(normalize(normal), normalize(view_alpha.xyz), view_alpha.w, coefficients, lut), 1.0);
}
