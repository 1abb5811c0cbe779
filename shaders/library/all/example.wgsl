// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
// WGSL has no #include: this file follows sbf_all.wgsl (naga validates the two together).

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
// Not called here (they need state or data from the host): progressive_update (a pointer to state the caller keeps).
fn sbf_example(n: vec3<f32>, v: vec3<f32>, alpha: f32, coefficients: array<vec4<f32>, 36>, lut: texture_2d<f32>, lobe_table: texture_2d_array<f32>, lobe_volume: texture_3d<f32>, lobe_sampler: sampler) -> vec3<f32> {
    var result = vec3<f32>(0.0);
    {
        // sh_eval_l1
        let r = sbf_sh_eval_l1(n);
        result += vec3<f32>(r[0]);
    }
    {
        // sh_eval_l2
        let r = sbf_sh_eval_l2(n);
        result += vec3<f32>(r[0]);
    }
    {
        // sh_eval_l4
        let r = sbf_sh_eval_l4(n);
        result += vec3<f32>(r[0]);
    }
    {
        // sh_l1_irradiance
        var sh_l1_irradiance_c: array<vec3<f32>, 4>;
        for (var k = 0u; k < 4u; k++) {
            sh_l1_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_l1_irradiance(sh_l1_irradiance_c, n);
        result += r;
    }
    {
        // sh_l2_irradiance
        var sh_l2_irradiance_c: array<vec3<f32>, 9>;
        for (var k = 0u; k < 9u; k++) {
            sh_l2_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_l2_irradiance(sh_l2_irradiance_c, n);
        result += r;
    }
    {
        // sh_l4_irradiance
        var sh_l4_irradiance_c: array<vec3<f32>, 25>;
        for (var k = 0u; k < 25u; k++) {
            sh_l4_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_l4_irradiance(sh_l4_irradiance_c, n);
        result += r;
    }
    {
        // sh_l1_geomerics_irradiance
        var sh_l1_geomerics_irradiance_c: array<vec3<f32>, 4>;
        for (var k = 0u; k < 4u; k++) {
            sh_l1_geomerics_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_l1_geomerics_irradiance(sh_l1_geomerics_irradiance_c, n);
        result += r;
    }
    {
        // sh_l1_zh3_irradiance
        var sh_l1_zh3_irradiance_c: array<vec3<f32>, 4>;
        for (var k = 0u; k < 4u; k++) {
            sh_l1_zh3_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_l1_zh3_irradiance(sh_l1_zh3_irradiance_c, n);
        result += r;
    }
    {
        // sh_l1_specular
        var sh_l1_specular_c: array<vec3<f32>, 4>;
        for (var k = 0u; k < 4u; k++) {
            sh_l1_specular_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_l1_specular(sh_l1_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        // sh_l2_specular
        var sh_l2_specular_c: array<vec3<f32>, 9>;
        for (var k = 0u; k < 9u; k++) {
            sh_l2_specular_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_l2_specular(sh_l2_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        // sh_rotate_l1
        var sh_rotate_l1_c: array<vec3<f32>, 4>;
        for (var k = 0u; k < 4u; k++) {
            sh_rotate_l1_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_rotate_l1(sh_rotate_l1_c, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        // sh_rotate_l2
        var sh_rotate_l2_c: array<vec3<f32>, 9>;
        for (var k = 0u; k < 9u; k++) {
            sh_rotate_l2_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_rotate_l2(sh_rotate_l2_c, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        // sh_rotate_l4
        var sh_rotate_l4_c: array<vec3<f32>, 25>;
        for (var k = 0u; k < 25u; k++) {
            sh_rotate_l4_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sh_rotate_l4(sh_rotate_l4_c, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)));
        result += r[0];
    }
    {
        // sg_eval
        let r = sbf_sg_eval(n, 0.5, v);
        result += vec3<f32>(r);
    }
    {
        // sg_integral
        let r = sbf_sg_integral(0.5);
        result += vec3<f32>(r);
    }
    {
        // sg_hill_irradiance
        let r = sbf_sg_hill_irradiance(n, 0.5, n);
        result += vec3<f32>(r);
    }
    {
        // sg9_irradiance
        var sg9_irradiance_c: array<vec3<f32>, 9>;
        for (var k = 0u; k < 9u; k++) {
            sg9_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sg9_irradiance(sg9_irradiance_c, 0.5, n);
        result += r;
    }
    {
        // sg12_irradiance
        var sg12_irradiance_c: array<vec3<f32>, 12>;
        for (var k = 0u; k < 12u; k++) {
            sg12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sg12_irradiance(sg12_irradiance_c, 0.5, n);
        result += r;
    }
    {
        // sg_split_sum_setup
        let r = sbf_sg_split_sum_setup(lut, n, v, alpha, 0.04, 1.0);
    }
    {
        // sg_split_sum_lobe
        let sg_split_sum_lobe_w = sbf_sg_split_sum_setup(lut, n, v, alpha, 0.04, 1.0);
        let r = sbf_sg_split_sum_lobe(sg_split_sum_lobe_w, n, 0.5);
        result += vec3<f32>(r);
    }
    {
        // sg9_specular
        var sg9_specular_c: array<vec3<f32>, 9>;
        for (var k = 0u; k < 9u; k++) {
            sg9_specular_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sg9_specular(sg9_specular_c, 0.5, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        // sg12_specular
        var sg12_specular_c: array<vec3<f32>, 12>;
        for (var k = 0u; k < 12u; k++) {
            sg12_specular_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_sg12_specular(sg12_specular_c, 0.5, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        // sg_asg_warp
        let r = sbf_sg_asg_warp(n, v, alpha, 0.04, 1.0);
    }
    {
        // sg_asg_lobe
        let sg_asg_lobe_w = sbf_sg_asg_warp(n, v, alpha, 0.04, 1.0);
        let r = sbf_sg_asg_lobe(sg_asg_lobe_w, n, 0.5);
        result += vec3<f32>(r);
    }
    {
        // ad_srbf_eval
        let r = sbf_ad_srbf_eval(n, v);
        result += vec3<f32>(r);
    }
    {
        // ad9_irradiance
        var ad9_irradiance_c: array<vec3<f32>, 9>;
        for (var k = 0u; k < 9u; k++) {
            ad9_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_ad9_irradiance(ad9_irradiance_c, n);
        result += r;
    }
    {
        // ad12_irradiance
        var ad12_irradiance_c: array<vec3<f32>, 12>;
        for (var k = 0u; k < 12u; k++) {
            ad12_irradiance_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_ad12_irradiance(ad12_irradiance_c, n);
        result += r;
    }
    {
        // ad9_specular
        var ad9_specular_c: array<vec3<f32>, 9>;
        for (var k = 0u; k < 9u; k++) {
            ad9_specular_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_ad9_specular(ad9_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        // ad12_specular
        var ad12_specular_c: array<vec3<f32>, 12>;
        for (var k = 0u; k < 12u; k++) {
            ad12_specular_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_ad12_specular(ad12_specular_c, lut, n, v, alpha, 0.04, 1.0);
        result += r;
    }
    {
        // lobe_ggx_pixel
        let r = sbf_lobe_ggx_pixel(lobe_table, n, v, alpha);
    }
    {
        // lobe_ggx_lobe
        let lobe_ggx_lobe_px = sbf_lobe_ggx_pixel(lobe_table, n, v, alpha);
        let r = sbf_lobe_ggx_lobe(lobe_table, lobe_ggx_lobe_px, n);
        result += vec3<f32>(r, 0.0);
    }
    {
        // lobe_ggx_filtered_pixel
        let r = sbf_lobe_ggx_filtered_pixel(lobe_volume, n, v, alpha);
    }
    {
        // lobe_ggx_filtered_lobe
        let lobe_ggx_filtered_lobe_px = sbf_lobe_ggx_filtered_pixel(lobe_volume, n, v, alpha);
        let r = sbf_lobe_ggx_filtered_lobe(lobe_volume, lobe_sampler, lobe_ggx_filtered_lobe_px, n);
        result += vec3<f32>(r, 0.0);
    }
    {
        // ggx_d
        let r = sbf_ggx_d(n, alpha);
        result += vec3<f32>(r);
    }
    {
        // ggx_g1
        let r = sbf_ggx_g1(n, alpha);
        result += vec3<f32>(r);
    }
    {
        // ggx_g2
        let r = sbf_ggx_g2(v, v, alpha);
        result += vec3<f32>(r);
    }
    {
        // ggx_lambda
        let r = sbf_ggx_lambda(n, alpha);
        result += vec3<f32>(r);
    }
    {
        // schlick_weight
        let r = sbf_schlick_weight(0.5);
        result += vec3<f32>(r);
    }
    {
        // ggx_energy_compensation
        let r = sbf_ggx_energy_compensation(vec2<f32>(0.5), 0.04);
        result += vec3<f32>(r);
    }
    {
        // ad_bezier_weights
        let r = sbf_ad_bezier_weights(n);
    }
    {
        // ad_bezier_eval
        var ad_bezier_eval_c: array<vec3<f32>, 36>;
        for (var k = 0u; k < 36u; k++) {
            ad_bezier_eval_c[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_ad_bezier_eval(ad_bezier_eval_c, n);
        result += r;
    }
    {
        // ad_ycocg_eval
        var ad_ycocg_eval_y: array<f32, 36>;
        for (var k = 0u; k < 36u; k++) {
            ad_ycocg_eval_y[k] = coefficients[k % 36u].x;
        }
        var ad_ycocg_eval_co: array<f32, 12>;
        for (var k = 0u; k < 12u; k++) {
            ad_ycocg_eval_co[k] = coefficients[k % 36u].x;
        }
        var ad_ycocg_eval_cg: array<f32, 12>;
        for (var k = 0u; k < 12u; k++) {
            ad_ycocg_eval_cg[k] = coefficients[k % 36u].x;
        }
        let r = sbf_ad_ycocg_eval(ad_ycocg_eval_y, ad_ycocg_eval_co, ad_ycocg_eval_cg, n);
        result += r;
    }
    {
        // lightmap_bicubic_taps
        let r = sbf_lightmap_bicubic_taps(vec2<f32>(0.5), vec2<f32>(0.5));
    }
    {
        // lightmap_bspline_axis
        let r = sbf_lightmap_bspline_axis(0.5);
    }
    {
        // godot_l1_irradiance
        let r = sbf_godot_l1_irradiance(n, n, n, n, n);
        result += r;
    }
    {
        // godot_l1_legacy_irradiance
        let r = sbf_godot_l1_legacy_irradiance(n, n, n, n, n);
        result += r;
    }
    {
        // monosh_irradiance
        let r = sbf_monosh_irradiance(n, n, n);
        result += r;
    }
    {
        // monosh_linear_irradiance
        let r = sbf_monosh_linear_irradiance(n, n, n);
        result += r;
    }
    {
        // enlighten_irradiance
        let r = sbf_enlighten_irradiance(n, vec4<f32>(0.5), n);
        result += r;
    }
    {
        // enlighten_rgb_irradiance
        let r = sbf_enlighten_rgb_irradiance(n, vec4<f32>(0.5), vec4<f32>(0.5), vec4<f32>(0.5), n);
        result += r;
    }
    {
        // slc_acceptance
        let r = sbf_slc_acceptance(0.5, 0.5, 0.5);
        result += vec3<f32>(r);
    }
    {
        // slc_random_range
        let r = sbf_slc_random_range(0.5, 0.5, 0.5);
        result += vec3<f32>(r);
    }
    {
        // slc_culled_estimate
        let r = sbf_slc_culled_estimate(0.5, 0.5, 0.5);
        result += vec3<f32>(r);
    }
    {
        // slc_schlick_max
        let r = sbf_slc_schlick_max(0.04, 0.5);
        result += vec3<f32>(r);
    }
    {
        // slc_dielectric_max
        let r = sbf_slc_dielectric_max(0.5, 0.5);
        result += vec3<f32>(r);
    }
    {
        // slc_g1_dist
        let r = sbf_slc_g1_dist(0.5, alpha);
        result += vec3<f32>(r);
    }
    {
        // slc_spheroid_scale
        let r = sbf_slc_spheroid_scale(0.5, 0.5, 0.5, 0.5, 0.5, 0.5);
        result += vec3<f32>(r);
    }
    {
        // slc_bound_surface
        let r = sbf_slc_bound_surface(0.5, 0.5, alpha);
        result += vec3<f32>(r);
    }
    {
        // slc_ggx_spheroid
        let r = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
    }
    {
        // slc_diffuse_sphere
        let r = sbf_slc_diffuse_sphere(n, n, 0.5, 0.5, 0.5);
    }
    {
        // slc_diffuse_intensity_bound
        let r = sbf_slc_diffuse_intensity_bound(0.5, 0.5);
        result += vec3<f32>(r);
    }
    {
        // slc_point_sphere
        let r = sbf_slc_point_sphere(n, 0.5, 0.5, 0.5);
    }
    {
        // slc_ray_sphere
        let slc_ray_sphere_s = sbf_slc_diffuse_sphere(n, n, 0.5, 0.5, 0.5);
        let r = sbf_slc_ray_sphere(n, n, slc_ray_sphere_s);
        result += r;
    }
    {
        // slc_equiangular_sample
        let r = sbf_slc_equiangular_sample(0.5, 0.5, 0.5, 0.5, 0.5);
        result += vec3<f32>(r, 0.0);
    }
    {
        // slc_equiangular_pdf
        let r = sbf_slc_equiangular_pdf(0.5, 0.5, 0.5, 0.5, 0.5);
        result += vec3<f32>(r);
    }
    {
        // slc_cull_transform
        let slc_cull_transform_e = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
        let r = sbf_slc_cull_transform(slc_cull_transform_e, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)), n);
    }
    {
        // slc_tile_corners
        let r = sbf_slc_tile_corners(0.5, 0.5, 0.5, 0.5, vec2<f32>(0.5), vec2<f32>(0.5), 0.5, 0.5);
        result += r[0];
    }
    {
        // slc_ellipsoid_hits_corners
        let slc_cull_transform_e = sbf_slc_ggx_spheroid(n, v, n, alpha, 0.5);
        let slc_ellipsoid_hits_corners_e = sbf_slc_cull_transform(slc_cull_transform_e, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)), n);
        var slc_ellipsoid_hits_corners_corners: array<vec3<f32>, 8>;
        for (var k = 0u; k < 8u; k++) {
            slc_ellipsoid_hits_corners_corners[k] = coefficients[k % 36u].xyz;
        }
        let r = sbf_slc_ellipsoid_hits_corners(slc_ellipsoid_hits_corners_e, slc_ellipsoid_hits_corners_corners);
        result += select(vec3<f32>(0.0), vec3<f32>(1.0), r);
    }
    return result;
}

struct Inputs {
    coefficients: array<vec4<f32>, 36>,
    view_alpha: vec4<f32>,
}

@group(0) @binding(0) var<uniform> inputs: Inputs;
@group(0) @binding(1) var lut: texture_2d<f32>;
@group(0) @binding(2) var lobe_table: texture_2d_array<f32>;
@group(0) @binding(3) var lobe_volume: texture_3d<f32>;
@group(0) @binding(4) var lobe_sampler: sampler;

@fragment
fn fs_main(@location(0) normal: vec3<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(sbf_example(normalize(normal), normalize(inputs.view_alpha.xyz), inputs.view_alpha.w, inputs.coefficients, lut, lobe_table, lobe_volume, lobe_sampler), 1.0);
}
