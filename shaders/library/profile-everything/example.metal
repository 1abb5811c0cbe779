// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
#include "sbf_profile_everything.metal"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
inline float3 sbf_example(float3 n, float3 v, float alpha, array<float4, 36> coefficients, texture2d<float> lut, texture3d<float> lobe_volume, sampler lobe_sampler) {
    float3 result = float3(0.0f);
    {
        array<float3, 4> sh_l1_irradiance_c = array<float3, 4>{};
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l1_irradiance(sh_l1_irradiance_c, n);
        result += r;
    }
    {
        array<float3, 9> sh_l2_irradiance_c = array<float3, 9>{};
        for (uint k = 0u; k < 9u; k++) {
            sh_l2_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l2_irradiance(sh_l2_irradiance_c, n);
        result += r;
    }
    {
        array<float3, 4> sh_l1_specular_c = array<float3, 4>{};
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l1_specular(sh_l1_specular_c, lut, n, v, alpha, 0.04f, 1.0f);
        result += r;
    }
    {
        array<float3, 9> sh_l2_specular_c = array<float3, 9>{};
        for (uint k = 0u; k < 9u; k++) {
            sh_l2_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l2_specular(sh_l2_specular_c, lut, n, v, alpha, 0.04f, 1.0f);
        result += r;
    }
    {
        float r = sbf_sg_hill_irradiance(n, 0.5f, n);
        result += float3(r);
    }
    {
        array<float3, 9> sg9_irradiance_c = array<float3, 9>{};
        for (uint k = 0u; k < 9u; k++) {
            sg9_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sg9_irradiance(sg9_irradiance_c, 0.5f, n);
        result += r;
    }
    {
        array<float3, 12> sg12_irradiance_c = array<float3, 12>{};
        for (uint k = 0u; k < 12u; k++) {
            sg12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sg12_irradiance(sg12_irradiance_c, 0.5f, n);
        result += r;
    }
    {
        SbfSgSplitSum r = sbf_sg_split_sum_setup(lut, n, v, alpha, 0.04f, 1.0f);
    }
    {
        SbfSgSplitSum sg_split_sum_lobe_w = sbf_sg_split_sum_setup(lut, n, v, alpha, 0.04f, 1.0f);
        float r = sbf_sg_split_sum_lobe(sg_split_sum_lobe_w, n, 0.5f);
        result += float3(r);
    }
    {
        array<float3, 9> sg9_specular_c = array<float3, 9>{};
        for (uint k = 0u; k < 9u; k++) {
            sg9_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sg9_specular(sg9_specular_c, 0.5f, lut, n, v, alpha, 0.04f, 1.0f);
        result += r;
    }
    {
        array<float3, 12> sg12_specular_c = array<float3, 12>{};
        for (uint k = 0u; k < 12u; k++) {
            sg12_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sg12_specular(sg12_specular_c, 0.5f, lut, n, v, alpha, 0.04f, 1.0f);
        result += r;
    }
    {
        array<float3, 9> ad9_irradiance_c = array<float3, 9>{};
        for (uint k = 0u; k < 9u; k++) {
            ad9_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad9_irradiance(ad9_irradiance_c, n);
        result += r;
    }
    {
        array<float3, 12> ad12_irradiance_c = array<float3, 12>{};
        for (uint k = 0u; k < 12u; k++) {
            ad12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad12_irradiance(ad12_irradiance_c, n);
        result += r;
    }
    {
        array<float3, 9> ad9_specular_c = array<float3, 9>{};
        for (uint k = 0u; k < 9u; k++) {
            ad9_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad9_specular(ad9_specular_c, lut, n, v, alpha, 0.04f, 1.0f);
        result += r;
    }
    {
        array<float3, 12> ad12_specular_c = array<float3, 12>{};
        for (uint k = 0u; k < 12u; k++) {
            ad12_specular_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad12_specular(ad12_specular_c, lut, n, v, alpha, 0.04f, 1.0f);
        result += r;
    }
    {
        SbfLobeGgxFilteredPixel r = sbf_lobe_ggx_filtered_pixel(lobe_volume, n, v, alpha);
    }
    {
        SbfLobeGgxFilteredPixel lobe_ggx_filtered_lobe_px = sbf_lobe_ggx_filtered_pixel(lobe_volume, n, v, alpha);
        float2 r = sbf_lobe_ggx_filtered_lobe(lobe_volume, lobe_sampler, lobe_ggx_filtered_lobe_px, n);
        result += float3(r, 0.0f);
    }
    {
        float r = sbf_ggx_energy_compensation(float2(0.5f), 0.04f);
        result += float3(r);
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

fragment float4 fs_main(FragmentIn frag [[stage_in]], constant Inputs& inputs [[buffer(0)]], texture2d<float> lut [[texture(0)]], texture3d<float> lobe_volume [[texture(2)]], sampler lobe_sampler [[sampler(0)]]) {
    return float4(sbf_example(normalize(frag.normal), normalize(inputs.view_alpha.xyz), inputs.view_alpha.w, inputs.coefficients, lut, lobe_volume, lobe_sampler), 1.0f);
}
