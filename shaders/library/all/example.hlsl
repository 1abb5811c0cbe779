// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
#include "sbf_all.hlsl"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
// Not called here (they need state or data from the host): progressive_update (a pointer to state the caller keeps).
float3 sbf_example(float3 n, float3 v, float alpha, float4 coefficients[36], Texture2D<float2> lut, Texture2DArray<float2> lobe_table, Texture3D<float2> lobe_volume, SamplerState lobe_sampler) {
    float3 result = ((float3)0.0);
    {
        float r[4] = sbf_sh_eval_l1(n);
        result += ((float3)r[0]);
    }
    {
        float r[9] = sbf_sh_eval_l2(n);
        result += ((float3)r[0]);
    }
    {
        float r[25] = sbf_sh_eval_l4(n);
        result += ((float3)r[0]);
    }
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
        float3 sh_l4_irradiance_c[25] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 25u; k++) {
            sh_l4_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l4_irradiance(sh_l4_irradiance_c, n);
        result += r;
    }
    {
        float3 sh_l1_geomerics_irradiance_c[4] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_geomerics_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l1_geomerics_irradiance(sh_l1_geomerics_irradiance_c, n);
        result += r;
    }
    {
        float3 sh_l1_zh3_irradiance_c[4] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_zh3_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_sh_l1_zh3_irradiance(sh_l1_zh3_irradiance_c, n);
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
        float3 sh_rotate_l1_c[4] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 4u; k++) {
            sh_rotate_l1_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r[4] = sbf_sh_rotate_l1(sh_rotate_l1_c, float3x3(float3(1.0, 0.0, 0.0), float3(0.0, 1.0, 0.0), float3(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        float3 sh_rotate_l2_c[9] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 9u; k++) {
            sh_rotate_l2_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r[9] = sbf_sh_rotate_l2(sh_rotate_l2_c, float3x3(float3(1.0, 0.0, 0.0), float3(0.0, 1.0, 0.0), float3(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        float3 sh_rotate_l4_c[25] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 25u; k++) {
            sh_rotate_l4_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r[25] = sbf_sh_rotate_l4(sh_rotate_l4_c, float3x3(float3(1.0, 0.0, 0.0), float3(0.0, 1.0, 0.0), float3(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        float r = sbf_sg_eval(n, 0.5, v);
        result += ((float3)r);
    }
    {
        float r = sbf_sg_integral(0.5);
        result += ((float3)r);
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
        SbfSgAsgWarp r = sbf_sg_asg_warp(n, v, alpha, 0.04, 1.0);
    }
    {
        SbfSgAsgWarp sg_asg_lobe_w = sbf_sg_asg_warp(n, v, alpha, 0.04, 1.0);
        float r = sbf_sg_asg_lobe(sg_asg_lobe_w, n, 0.5);
        result += ((float3)r);
    }
    {
        float r = sbf_ad_srbf_eval(n, v);
        result += ((float3)r);
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
        SbfLobeGgxPixel r = sbf_lobe_ggx_pixel(lobe_table, n, v, alpha);
    }
    {
        SbfLobeGgxPixel lobe_ggx_lobe_px = sbf_lobe_ggx_pixel(lobe_table, n, v, alpha);
        float2 r = sbf_lobe_ggx_lobe(lobe_table, lobe_ggx_lobe_px, n);
        result += float3(r, 0.0);
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
        float r = sbf_ggx_d(n, alpha);
        result += ((float3)r);
    }
    {
        float r = sbf_ggx_g1(n, alpha);
        result += ((float3)r);
    }
    {
        float r = sbf_ggx_g2(v, v, alpha);
        result += ((float3)r);
    }
    {
        float r = sbf_ggx_lambda(n, alpha);
        result += ((float3)r);
    }
    {
        float r = sbf_schlick_weight(0.5);
        result += ((float3)r);
    }
    {
        float r = sbf_ggx_energy_compensation(((float2)0.5), 0.04);
        result += ((float3)r);
    }
    {
        SbfAdBezierWeights r = sbf_ad_bezier_weights(n);
    }
    {
        float3 ad_bezier_eval_c[36] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 36u; k++) {
            ad_bezier_eval_c[k] = coefficients[k % 36u].xyz;
        }
        float3 r = sbf_ad_bezier_eval(ad_bezier_eval_c, n);
        result += r;
    }
    {
        float ad_ycocg_eval_y[36] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
        for (uint k = 0u; k < 36u; k++) {
            ad_ycocg_eval_y[k] = coefficients[k % 36u].x;
        }
        float ad_ycocg_eval_co[12] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
        for (uint k = 0u; k < 12u; k++) {
            ad_ycocg_eval_co[k] = coefficients[k % 36u].x;
        }
        float ad_ycocg_eval_cg[12] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
        for (uint k = 0u; k < 12u; k++) {
            ad_ycocg_eval_cg[k] = coefficients[k % 36u].x;
        }
        float3 r = sbf_ad_ycocg_eval(ad_ycocg_eval_y, ad_ycocg_eval_co, ad_ycocg_eval_cg, n);
        result += r;
    }
    {
        SbfLightmapTaps r = sbf_lightmap_bicubic_taps(((float2)0.5), ((float2)0.5));
    }
    {
        float4 r = sbf_lightmap_bspline_axis(0.5);
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
        float3 r = sbf_enlighten_irradiance(n, ((float4)0.5), n);
        result += r;
    }
    {
        float3 r = sbf_enlighten_rgb_irradiance(n, ((float4)0.5), ((float4)0.5), ((float4)0.5), n);
        result += r;
    }
    {
        float r = sbf_slc_acceptance(0.5, 0.5, 0.5);
        result += ((float3)r);
    }
    {
        float r = sbf_slc_random_range(0.5, 0.5, 0.5);
        result += ((float3)r);
    }
    {
        float r = sbf_slc_culled_estimate(0.5, 0.5, 0.5);
        result += ((float3)r);
    }
    {
        float r = sbf_slc_schlick_max(0.04, 0.5);
        result += ((float3)r);
    }
    {
        float r = sbf_slc_dielectric_max(0.5, 0.5);
        result += ((float3)r);
    }
    {
        float r = sbf_slc_g1_dist(0.5, alpha);
        result += ((float3)r);
    }
    {
        float r = sbf_slc_spheroid_scale(0.5, 0.5, 0.5, 0.5, 0.5, 0.5);
        result += ((float3)r);
    }
    {
        float r = sbf_slc_bound_surface(0.5, 0.5, alpha);
        result += ((float3)r);
    }
    {
        SbfSlcEllipsoid r = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
    }
    {
        SbfSlcSphere r = sbf_slc_diffuse_sphere(n, n, 0.5, 0.5, 0.5);
    }
    {
        float r = sbf_slc_diffuse_intensity_bound(0.5, 0.5);
        result += ((float3)r);
    }
    {
        SbfSlcSphere r = sbf_slc_point_sphere(n, 0.5, 0.5, 0.5);
    }
    {
        SbfSlcSphere slc_ray_sphere_s = sbf_slc_diffuse_sphere(n, n, 0.5, 0.5, 0.5);
        float3 r = sbf_slc_ray_sphere(n, n, slc_ray_sphere_s);
        result += r;
    }
    {
        float2 r = sbf_slc_equiangular_sample(0.5, 0.5, 0.5, 0.5, 0.5);
        result += float3(r, 0.0);
    }
    {
        float r = sbf_slc_equiangular_pdf(0.5, 0.5, 0.5, 0.5, 0.5);
        result += ((float3)r);
    }
    {
        SbfSlcEllipsoid slc_cull_transform_e = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
        SbfSlcCullEllipsoid r = sbf_slc_cull_transform(slc_cull_transform_e, float3x3(float3(1.0, 0.0, 0.0), float3(0.0, 1.0, 0.0), float3(0.0, 0.0, 1.0)), n);
    }
    {
        float3 r[8] = sbf_slc_tile_corners(0.5, 0.5, 0.5, 0.5, ((float2)0.5), ((float2)0.5), 0.5, 0.5);
        result += r[0];
    }
    {
        SbfSlcEllipsoid slc_cull_transform_e = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
        SbfSlcCullEllipsoid slc_ellipsoid_hits_corners_e = sbf_slc_cull_transform(slc_cull_transform_e, float3x3(float3(1.0, 0.0, 0.0), float3(0.0, 1.0, 0.0), float3(0.0, 0.0, 1.0)), n);
        float3 slc_ellipsoid_hits_corners_corners[8] = { ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0), ((float3)0) };
        for (uint k = 0u; k < 8u; k++) {
            slc_ellipsoid_hits_corners_corners[k] = coefficients[k % 36u].xyz;
        }
        bool r = sbf_slc_ellipsoid_hits_corners(slc_ellipsoid_hits_corners_e, slc_ellipsoid_hits_corners_corners);
        result += r ? ((float3)1.0) : ((float3)0.0);
    }
    return result;
}

cbuffer Inputs : register(b0) {
    float4 coefficients[36];
    float4 view_alpha;
};
Texture2D<float2> lut : register(t0);
Texture2DArray<float2> lobe_table : register(t1);
Texture3D<float2> lobe_volume : register(t2);
SamplerState lobe_sampler : register(s0);

float4 main(float3 normal : NORMAL) : SV_Target {
    return float4(sbf_example(normalize(normal), normalize(view_alpha.xyz), view_alpha.w, coefficients, lut, lobe_table, lobe_volume, lobe_sampler), 1.0);
}
