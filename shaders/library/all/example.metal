// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
#include "sbf_all.metal"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
// Not called here (they need state or data from the host): progressive_update (a pointer to state the caller keeps).
inline float3 sbf_example(float3 n, float3 v, float alpha, array<float4, 36> coefficients, texture2d<float> lut, texture2d_array<float> lobe_table, texture3d<float> lobe_volume, sampler lobe_sampler) {
    float3 result = float3(0.0f);
    {
        array<float, 4> r = sbf_sh_eval_l1(n);
        result += float3(r[0]);
    }
    {
        array<float, 9> r = sbf_sh_eval_l2(n);
        result += float3(r[0]);
    }
    {
        array<float, 25> r = sbf_sh_eval_l4(n);
        result += float3(r[0]);
    }
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
        array<float3, 25> sh_l4_irradiance_c = array<float3, 25>{};
        for (uint k = 0u; k < 25u; k++) {
            sh_l4_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l4_irradiance(sh_l4_irradiance_c, n);
        result += r;
    }
    {
        array<float3, 4> sh_l1_geomerics_irradiance_c = array<float3, 4>{};
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_geomerics_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l1_geomerics_irradiance(sh_l1_geomerics_irradiance_c, n);
        result += r;
    }
    {
        array<float3, 4> sh_l1_zh3_irradiance_c = array<float3, 4>{};
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_zh3_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l1_zh3_irradiance(sh_l1_zh3_irradiance_c, n);
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
        array<float3, 4> sh_rotate_l1_c = array<float3, 4>{};
        for (uint k = 0u; k < 4u; k++) {
            sh_rotate_l1_c[k] = coefficients[k % 36u].xyz;
        }
        array<float3, 4> r = sbf_sh_rotate_l1(sh_rotate_l1_c, float3x3(float3(1.0f, 0.0f, 0.0f), float3(0.0f, 1.0f, 0.0f), float3(0.0f, 0.0f, 1.0f)));
        result += r[0];
    }
    {
        array<float3, 9> sh_rotate_l2_c = array<float3, 9>{};
        for (uint k = 0u; k < 9u; k++) {
            sh_rotate_l2_c[k] = coefficients[k % 36u].xyz;
        }
        array<float3, 9> r = sbf_sh_rotate_l2(sh_rotate_l2_c, float3x3(float3(1.0f, 0.0f, 0.0f), float3(0.0f, 1.0f, 0.0f), float3(0.0f, 0.0f, 1.0f)));
        result += r[0];
    }
    {
        array<float3, 25> sh_rotate_l4_c = array<float3, 25>{};
        for (uint k = 0u; k < 25u; k++) {
            sh_rotate_l4_c[k] = coefficients[k % 36u].xyz;
        }
        array<float3, 25> r = sbf_sh_rotate_l4(sh_rotate_l4_c, float3x3(float3(1.0f, 0.0f, 0.0f), float3(0.0f, 1.0f, 0.0f), float3(0.0f, 0.0f, 1.0f)));
        result += r[0];
    }
    {
        float r = sbf_sg_eval(n, 0.5f, v);
        result += float3(r);
    }
    {
        float r = sbf_sg_integral(0.5f);
        result += float3(r);
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
        SbfSgAsgWarp r = sbf_sg_asg_warp(n, v, alpha, 0.04f, 1.0f);
    }
    {
        SbfSgAsgWarp sg_asg_lobe_w = sbf_sg_asg_warp(n, v, alpha, 0.04f, 1.0f);
        float r = sbf_sg_asg_lobe(sg_asg_lobe_w, n, 0.5f);
        result += float3(r);
    }
    {
        float r = sbf_ad_srbf_eval(n, v);
        result += float3(r);
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
        SbfLobeGgxPixel r = sbf_lobe_ggx_pixel(lobe_table, n, v, alpha);
    }
    {
        SbfLobeGgxPixel lobe_ggx_lobe_px = sbf_lobe_ggx_pixel(lobe_table, n, v, alpha);
        float2 r = sbf_lobe_ggx_lobe(lobe_table, lobe_ggx_lobe_px, n);
        result += float3(r, 0.0f);
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
        float r = sbf_ggx_d(n, alpha);
        result += float3(r);
    }
    {
        float r = sbf_ggx_g1(n, alpha);
        result += float3(r);
    }
    {
        float r = sbf_ggx_g2(v, v, alpha);
        result += float3(r);
    }
    {
        float r = sbf_ggx_lambda(n, alpha);
        result += float3(r);
    }
    {
        float r = sbf_schlick_weight(0.5f);
        result += float3(r);
    }
    {
        float r = sbf_ggx_energy_compensation(float2(0.5f), 0.04f);
        result += float3(r);
    }
    {
        SbfAdBezierWeights r = sbf_ad_bezier_weights(n);
    }
    {
        array<float3, 36> ad_bezier_eval_c = array<float3, 36>{};
        for (uint k = 0u; k < 36u; k++) {
            ad_bezier_eval_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad_bezier_eval(ad_bezier_eval_c, n);
        result += r;
    }
    {
        array<float, 36> ad_ycocg_eval_y = array<float, 36>{};
        for (uint k = 0u; k < 36u; k++) {
            ad_ycocg_eval_y[k] = coefficients[k % 36u].x;
        }
        array<float, 12> ad_ycocg_eval_co = array<float, 12>{};
        for (uint k = 0u; k < 12u; k++) {
            ad_ycocg_eval_co[k] = coefficients[k % 36u].x;
        }
        array<float, 12> ad_ycocg_eval_cg = array<float, 12>{};
        for (uint k = 0u; k < 12u; k++) {
            ad_ycocg_eval_cg[k] = coefficients[k % 36u].x;
        }
        float3 r = sbf_ad_ycocg_eval(ad_ycocg_eval_y, ad_ycocg_eval_co, ad_ycocg_eval_cg, n);
        result += r;
    }
    {
        SbfLightmapTaps r = sbf_lightmap_bicubic_taps(float2(0.5f), float2(0.5f));
    }
    {
        float4 r = sbf_lightmap_bspline_axis(0.5f);
    }
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
    {
        float r = sbf_slc_acceptance(0.5f, 0.5f, 0.5f);
        result += float3(r);
    }
    {
        float r = sbf_slc_random_range(0.5f, 0.5f, 0.5f);
        result += float3(r);
    }
    {
        float r = sbf_slc_culled_estimate(0.5f, 0.5f, 0.5f);
        result += float3(r);
    }
    {
        float r = sbf_slc_schlick_max(0.04f, 0.5f);
        result += float3(r);
    }
    {
        float r = sbf_slc_dielectric_max(0.5f, 0.5f);
        result += float3(r);
    }
    {
        float r = sbf_slc_g1_dist(0.5f, alpha);
        result += float3(r);
    }
    {
        float r = sbf_slc_spheroid_scale(0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f);
        result += float3(r);
    }
    {
        float r = sbf_slc_bound_surface(0.5f, 0.5f, alpha);
        result += float3(r);
    }
    {
        SbfSlcEllipsoid r = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5f);
    }
    {
        SbfSlcSphere r = sbf_slc_diffuse_sphere(n, n, 0.5f, 0.5f, 0.5f);
    }
    {
        float r = sbf_slc_diffuse_intensity_bound(0.5f, 0.5f);
        result += float3(r);
    }
    {
        SbfSlcSphere r = sbf_slc_point_sphere(n, 0.5f, 0.5f, 0.5f);
    }
    {
        SbfSlcSphere slc_ray_sphere_s = sbf_slc_diffuse_sphere(n, n, 0.5f, 0.5f, 0.5f);
        float3 r = sbf_slc_ray_sphere(n, n, slc_ray_sphere_s);
        result += r;
    }
    {
        float2 r = sbf_slc_equiangular_sample(0.5f, 0.5f, 0.5f, 0.5f, 0.5f);
        result += float3(r, 0.0f);
    }
    {
        float r = sbf_slc_equiangular_pdf(0.5f, 0.5f, 0.5f, 0.5f, 0.5f);
        result += float3(r);
    }
    {
        SbfSlcEllipsoid slc_cull_transform_e = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5f);
        SbfSlcCullEllipsoid r = sbf_slc_cull_transform(slc_cull_transform_e, float3x3(float3(1.0f, 0.0f, 0.0f), float3(0.0f, 1.0f, 0.0f), float3(0.0f, 0.0f, 1.0f)), n);
    }
    {
        array<float3, 8> r = sbf_slc_tile_corners(0.5f, 0.5f, 0.5f, 0.5f, float2(0.5f), float2(0.5f), 0.5f, 0.5f);
        result += r[0];
    }
    {
        SbfSlcEllipsoid slc_cull_transform_e = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5f);
        SbfSlcCullEllipsoid slc_ellipsoid_hits_corners_e = sbf_slc_cull_transform(slc_cull_transform_e, float3x3(float3(1.0f, 0.0f, 0.0f), float3(0.0f, 1.0f, 0.0f), float3(0.0f, 0.0f, 1.0f)), n);
        array<float3, 8> slc_ellipsoid_hits_corners_corners = array<float3, 8>{};
        for (uint k = 0u; k < 8u; k++) {
            slc_ellipsoid_hits_corners_corners[k] = coefficients[k % 36u].xyz;
        }
        bool r = sbf_slc_ellipsoid_hits_corners(slc_ellipsoid_hits_corners_e, slc_ellipsoid_hits_corners_corners);
        result += r ? float3(1.0f) : float3(0.0f);
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

fragment float4 fs_main(FragmentIn frag [[stage_in]], constant Inputs& inputs [[buffer(0)]], texture2d<float> lut [[texture(0)]], texture2d_array<float> lobe_table [[texture(1)]], texture3d<float> lobe_volume [[texture(2)]], sampler lobe_sampler [[sampler(0)]]) {
    return float4(sbf_example(normalize(frag.normal), normalize(inputs.view_alpha.xyz), inputs.view_alpha.w, inputs.coefficients, lut, lobe_table, lobe_volume, lobe_sampler), 1.0f);
}
