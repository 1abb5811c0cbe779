// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
#include "sbf_profile_everything.hlsl"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
float3 sbf_example(float3 n, float3 v, float alpha, float4 coefficients[36], Texture2D<float2> lut, Texture3D<float2> lobe_volume, SamplerState lobe_sampler) {
    float3 result = ((float3)0.0);
    {
        float3 sh_l1_irradiance_c[4] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l1_irradiance(sh_l1_irradiance_c, n);
        result += r;
    }
    {
        float3 sh_l2_irradiance_c[9] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 9u; k++) {
            sh_l2_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l2_irradiance(sh_l2_irradiance_c, n);
        result += r;
    }
    {
        float3 sh_l1_specular_c[4] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l1_specular(sh_l1_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        float3 sh_l2_specular_c[9] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 9u; k++) {
            sh_l2_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l2_specular(sh_l2_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        float r = sbf_sg_hill_irradiance(n, 0.5, n);
        result += ((float3)r);
    }
    {
        float3 sg9_irradiance_c[9] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 9u; k++) {
            sg9_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sg9_irradiance(sg9_irradiance_c, 0.5, n);
        result += r;
    }
    {
        float3 sg12_irradiance_c[12] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 12u; k++) {
            sg12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sg12_irradiance(sg12_irradiance_c, 0.5, n);
        result += r;
    }
    {
        SbfSgSplitSum r = sbf_sg_split_sum_setup(lut, n, v, alpha, 0.04, 1.0);
    }
    {
        SbfSgSplitSum sg_split_sum_lobe_w = sbf_sg_split_sum_setup(lut, n, v, alpha, 0.04, 1.0);
        float r = sbf_sg_split_sum_lobe(sg_split_sum_lobe_w, n, 0.5);
        result += ((float3)r);
    }
    {
        float3 sg9_specular_c[9] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 9u; k++) {
            sg9_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sg9_specular(sg9_specular_c, 0.5, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        float3 sg12_specular_c[12] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 12u; k++) {
            sg12_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sg12_specular(sg12_specular_c, 0.5, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        float3 ad9_irradiance_c[9] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 9u; k++) {
            ad9_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad9_irradiance(ad9_irradiance_c, n);
        result += r;
    }
    {
        float3 ad12_irradiance_c[12] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 12u; k++) {
            ad12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad12_irradiance(ad12_irradiance_c, n);
        result += r;
    }
    {
        float3 ad9_specular_c[9] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 9u; k++) {
            ad9_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad9_specular(ad9_specular_c, lut, n, v, alpha, 0.04, 1.0);
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
    {
        SbfLobeGgxFilteredPixel r = sbf_lobe_ggx_filtered_pixel(lobe_volume, n, v, alpha);
    }
    {
        SbfLobeGgxFilteredPixel lobe_ggx_filtered_lobe_px = sbf_lobe_ggx_filtered_pixel(lobe_volume, n, v, alpha);
        float2 r = sbf_lobe_ggx_filtered_lobe(lobe_volume, lobe_sampler, lobe_ggx_filtered_lobe_px, n);
        result += float3(r, 0.0);
    }
    {
        float r = sbf_ggx_energy_compensation(((float2)0.5), 0.04);
        result += ((float3)r);
    }
    return result;
}

cbuffer Inputs : register(b0) {
    float4 coefficients[36];
    float4 view_alpha;
};
Texture2D<float2> lut : register(t0);
Texture3D<float2> lobe_volume : register(t2);
SamplerState lobe_sampler : register(s0);

float4 main(float3 normal : NORMAL) : SV_Target {
    return float4(sbf_example(normalize(normal), normalize(view_alpha.xyz), view_alpha.w, coefficients, lut, lobe_volume, lobe_sampler), 1.0);
}
