// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
// WGSL has no #include: this file follows sbf_sg.wgsl (naga validates the two together).

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
fn sbf_example(n: vec3<f32>, v: vec3<f32>, alpha: f32, coefficients: array<vec4<f32>, 36>, lut: texture_2d<f32>) -> vec3<f32> {
    var result = vec3<f32>(0.0);
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
    return result;
}

struct Inputs {
    coefficients: array<vec4<f32>, 36>,
    view_alpha: vec4<f32>,
}

@group(0) @binding(0) var<uniform> inputs: Inputs;
@group(0) @binding(1) var lut: texture_2d<f32>;

@fragment
fn fs_main(@location(0) normal: vec3<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(sbf_example(normalize(normal), normalize(inputs.view_alpha.xyz), inputs.view_alpha.w, inputs.coefficients, lut), 1.0);
}
