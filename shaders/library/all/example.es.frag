#version 300 es
precision highp float;
precision highp int;
// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
// OpenGL has no #include directive: the engine's include step, or a paste, puts
// sbf_all.es.glsl here.
#include "sbf_all.es.glsl"

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
// Not called here (they need state or data from the host): progressive_update (a pointer to state the caller keeps).
vec3 sbf_example(vec3 n, vec3 v, float alpha, vec4 coefficients[36], highp sampler2D lut, highp sampler2DArray lobe_table, highp sampler3D lobe_volume) {
    vec3 result = vec3(0.0);
    {
        float r[4] = sbf_sh_eval_l1(n);
        result += vec3(r[0]);
    }
    {
        float r[9] = sbf_sh_eval_l2(n);
        result += vec3(r[0]);
    }
    {
        float r[25] = sbf_sh_eval_l4(n);
        result += vec3(r[0]);
    }
    {
        vec3 sh_l1_irradiance_c[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sh_l1_irradiance(sh_l1_irradiance_c, n);
        result += r;
    }
    {
        vec3 sh_l2_irradiance_c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 9u; k++) {
            sh_l2_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sh_l2_irradiance(sh_l2_irradiance_c, n);
        result += r;
    }
    {
        vec3 sh_l4_irradiance_c[25] = vec3[25](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 25u; k++) {
            sh_l4_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sh_l4_irradiance(sh_l4_irradiance_c, n);
        result += r;
    }
    {
        vec3 sh_l1_geomerics_irradiance_c[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_geomerics_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sh_l1_geomerics_irradiance(sh_l1_geomerics_irradiance_c, n);
        result += r;
    }
    {
        vec3 sh_l1_zh3_irradiance_c[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_zh3_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sh_l1_zh3_irradiance(sh_l1_zh3_irradiance_c, n);
        result += r;
    }
    {
        vec3 sh_l1_specular_c[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 4u; k++) {
            sh_l1_specular_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sh_l1_specular(sh_l1_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        vec3 sh_l2_specular_c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 9u; k++) {
            sh_l2_specular_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_sh_l2_specular(sh_l2_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        vec3 sh_rotate_l1_c[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 4u; k++) {
            sh_rotate_l1_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r[4] = sbf_sh_rotate_l1(sh_rotate_l1_c, mat3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        vec3 sh_rotate_l2_c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 9u; k++) {
            sh_rotate_l2_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r[9] = sbf_sh_rotate_l2(sh_rotate_l2_c, mat3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        vec3 sh_rotate_l4_c[25] = vec3[25](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 25u; k++) {
            sh_rotate_l4_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r[25] = sbf_sh_rotate_l4(sh_rotate_l4_c, mat3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        float r = sbf_sg_eval(n, 0.5, v);
        result += vec3(r);
    }
    {
        float r = sbf_sg_integral(0.5);
        result += vec3(r);
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
    {
        SbfSgAsgWarp r = sbf_sg_asg_warp(n, v, alpha, 0.04, 1.0);
    }
    {
        SbfSgAsgWarp sg_asg_lobe_w = sbf_sg_asg_warp(n, v, alpha, 0.04, 1.0);
        float r = sbf_sg_asg_lobe(sg_asg_lobe_w, n, 0.5);
        result += vec3(r);
    }
    {
        float r = sbf_ad_srbf_eval(n, v);
        result += vec3(r);
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
    {
        vec3 ad9_specular_c[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 9u; k++) {
            ad9_specular_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_ad9_specular(ad9_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        vec3 ad12_specular_c[12] = vec3[12](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 12u; k++) {
            ad12_specular_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_ad12_specular(ad12_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        SbfLobeGgxPixel r = sbf_lobe_ggx_pixel(lobe_table, n, v, alpha);
    }
    {
        SbfLobeGgxPixel lobe_ggx_lobe_px = sbf_lobe_ggx_pixel(lobe_table, n, v, alpha);
        vec2 r = sbf_lobe_ggx_lobe(lobe_table, lobe_ggx_lobe_px, n);
        result += vec3(r, 0.0);
    }
    {
        SbfLobeGgxFilteredPixel r = sbf_lobe_ggx_filtered_pixel(lobe_volume, n, v, alpha);
    }
    {
        SbfLobeGgxFilteredPixel lobe_ggx_filtered_lobe_px = sbf_lobe_ggx_filtered_pixel(lobe_volume, n, v, alpha);
        vec2 r = sbf_lobe_ggx_filtered_lobe(lobe_volume, lobe_ggx_filtered_lobe_px, n);
        result += vec3(r, 0.0);
    }
    {
        float r = sbf_ggx_d(n, alpha);
        result += vec3(r);
    }
    {
        float r = sbf_ggx_g1(n, alpha);
        result += vec3(r);
    }
    {
        float r = sbf_ggx_g2(v, v, alpha);
        result += vec3(r);
    }
    {
        float r = sbf_ggx_lambda(n, alpha);
        result += vec3(r);
    }
    {
        float r = sbf_schlick_weight(0.5);
        result += vec3(r);
    }
    {
        float r = sbf_ggx_energy_compensation(vec2(0.5), 0.04);
        result += vec3(r);
    }
    {
        SbfAdBezierWeights r = sbf_ad_bezier_weights(n);
    }
    {
        vec3 ad_bezier_eval_c[36] = vec3[36](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 36u; k++) {
            ad_bezier_eval_c[k] = coefficients[k % 36u].xyz;
        }
        vec3 r = sbf_ad_bezier_eval(ad_bezier_eval_c, n);
        result += r;
    }
    {
        float ad_ycocg_eval_y[36] = float[36](0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for (uint k = 0u; k < 36u; k++) {
            ad_ycocg_eval_y[k] = coefficients[k % 36u].x;
        }
        float ad_ycocg_eval_co[12] = float[12](0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for (uint k = 0u; k < 12u; k++) {
            ad_ycocg_eval_co[k] = coefficients[k % 36u].x;
        }
        float ad_ycocg_eval_cg[12] = float[12](0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for (uint k = 0u; k < 12u; k++) {
            ad_ycocg_eval_cg[k] = coefficients[k % 36u].x;
        }
        vec3 r = sbf_ad_ycocg_eval(ad_ycocg_eval_y, ad_ycocg_eval_co, ad_ycocg_eval_cg, n);
        result += r;
    }
    {
        SbfLightmapTaps r = sbf_lightmap_bicubic_taps(vec2(0.5), vec2(0.5));
    }
    {
        vec4 r = sbf_lightmap_bspline_axis(0.5);
    }
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
    {
        float r = sbf_slc_acceptance(0.5, 0.5, 0.5);
        result += vec3(r);
    }
    {
        float r = sbf_slc_random_range(0.5, 0.5, 0.5);
        result += vec3(r);
    }
    {
        float r = sbf_slc_culled_estimate(0.5, 0.5, 0.5);
        result += vec3(r);
    }
    {
        float r = sbf_slc_schlick_max(0.04, 0.5);
        result += vec3(r);
    }
    {
        float r = sbf_slc_dielectric_max(0.5, 0.5);
        result += vec3(r);
    }
    {
        float r = sbf_slc_g1_dist(0.5, alpha);
        result += vec3(r);
    }
    {
        float r = sbf_slc_spheroid_scale(0.5, 0.5, 0.5, 0.5, 0.5, 0.5);
        result += vec3(r);
    }
    {
        float r = sbf_slc_bound_surface(0.5, 0.5, alpha);
        result += vec3(r);
    }
    {
        SbfSlcEllipsoid r = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
    }
    {
        SbfSlcSphere r = sbf_slc_diffuse_sphere(n, n, 0.5, 0.5, 0.5);
    }
    {
        float r = sbf_slc_diffuse_intensity_bound(0.5, 0.5);
        result += vec3(r);
    }
    {
        SbfSlcSphere r = sbf_slc_point_sphere(n, 0.5, 0.5, 0.5);
    }
    {
        SbfSlcSphere slc_ray_sphere_s = sbf_slc_diffuse_sphere(n, n, 0.5, 0.5, 0.5);
        vec3 r = sbf_slc_ray_sphere(n, n, slc_ray_sphere_s);
        result += r;
    }
    {
        vec2 r = sbf_slc_equiangular_sample(0.5, 0.5, 0.5, 0.5, 0.5);
        result += vec3(r, 0.0);
    }
    {
        float r = sbf_slc_equiangular_pdf(0.5, 0.5, 0.5, 0.5, 0.5);
        result += vec3(r);
    }
    {
        SbfSlcEllipsoid slc_cull_transform_e = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
        SbfSlcCullEllipsoid r = sbf_slc_cull_transform(slc_cull_transform_e, mat3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0)), n);
    }
    {
        vec3 r[8] = sbf_slc_tile_corners(0.5, 0.5, 0.5, 0.5, vec2(0.5), vec2(0.5), 0.5, 0.5);
        result += r[0];
    }
    {
        SbfSlcEllipsoid slc_cull_transform_e = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
        SbfSlcCullEllipsoid slc_ellipsoid_hits_corners_e = sbf_slc_cull_transform(slc_cull_transform_e, mat3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0)), n);
        vec3 slc_ellipsoid_hits_corners_corners[8] = vec3[8](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint k = 0u; k < 8u; k++) {
            slc_ellipsoid_hits_corners_corners[k] = coefficients[k % 36u].xyz;
        }
        bool r = sbf_slc_ellipsoid_hits_corners(slc_ellipsoid_hits_corners_e, slc_ellipsoid_hits_corners_corners);
        result += r ? vec3(1.0) : vec3(0.0);
    }
    return result;
}

layout(std140) uniform Inputs {
    vec4 coefficients[36];
    vec4 view_alpha;
};
uniform highp sampler2D lut;
uniform highp sampler2DArray lobe_table;
uniform highp sampler3D lobe_volume;
in vec3 normal;
layout(location = 0) out vec4 color;

void main() {
    color = vec4(sbf_example(normalize(normal), normalize(view_alpha.xyz), view_alpha.w, coefficients, lut, lobe_table, lobe_volume), 1.0);
}
