// Example: a fragment shader that includes the library and shades with it. The inputs are
// placeholders an engine replaces with its own (lightmap or probe coefficients, view, α).
// WGSL has no #include: this file follows sbf_engine_lightmaps.wgsl (naga validates the two together).

// Shades with every public function of the library: n and v unit vectors in the frame of the
// coefficients (world space for SH and AD 12 probes and the engine formats; the texel's tangent
// frame, +Z its normal, for SG and AD 9 lightmap lobes), alpha GGX α, coefficients the RGB
// coefficients (xyz) an engine reads from its lightmap or probes.
fn sbf_example(n: vec3<f32>, v: vec3<f32>, alpha: f32, coefficients: array<vec4<f32>, 36>) -> vec3<f32> {
    var result = vec3<f32>(0.0);
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
    return result;
}

struct Inputs {
    coefficients: array<vec4<f32>, 36>,
    view_alpha: vec4<f32>,
}

@group(0) @binding(0) var<uniform> inputs: Inputs;

@fragment
fn fs_main(@location(0) normal: vec3<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(sbf_example(normalize(normal), normalize(inputs.view_alpha.xyz), inputs.view_alpha.w, inputs.coefficients), 1.0);
}
