// lightmap.wgsl — reading a lightmap before the runtime: the cubic B-spline filter by four
// bilinear taps of the hardware sampler (Sigg and Hadwiger 2005, "Fast Third-Order Texture
// Filtering", GPU Gems 2 ch. 20). Smoother than bilinear across texels, it blurs shadow
// edges and reaches one texel further — past a chart's padding it can leak (docs/render.md).
// CPU twin: sbf::recon::lut::bspline_taps.

// One axis at texel coordinate c (texel centres at i + 1/2): the two taps' positions in
// texels (xy) and their weights (zw). A bilinear lookup at tap 0 weights texels i − 1 and i
// as w0 : w1, at tap 1 texels i + 1 and i + 2 as w2 : w3.
fn lightmap_bspline_axis(c: f32) -> vec4<f32> {
    let x = c - 0.5;
    let i = floor(x);
    let f = x - i;
    let f2 = f * f;
    let f3 = f2 * f;
    let w0 = (1.0 - f) * (1.0 - f) * (1.0 - f) / 6.0;
    let w1 = (3.0 * f3 - 6.0 * f2 + 4.0) / 6.0;
    let w2 = (-3.0 * f3 + 3.0 * f2 + 3.0 * f + 1.0) / 6.0;
    let w3 = f3 / 6.0;
    let g0 = w0 + w1;
    let g1 = w2 + w3;
    return vec4<f32>(i - 0.5 + w1 / g0, i + 1.5 + w3 / g1, g0, g1);
}

// The four taps of a lookup: positions in normalised coordinates (x0, x1, y0, y1) and
// weights (gx0, gx1, gy0, gy1); tap (a, b) at (pos[a], pos[2 + b]) weighs w[a]·w[2 + b].
struct LightmapTaps {
    pos: vec4<f32>,
    w: vec4<f32>,
}

// The B-spline's taps at normalised uv on a lightmap of `size` texels. With a linear,
// clamped sampler S: value = w.z·(w.x·S(pos.xz) + w.y·S(pos.yz)) + w.w·(w.x·S(pos.xw) + w.y·S(pos.yw)).
fn lightmap_bicubic_taps(uv: vec2<f32>, size: vec2<f32>) -> LightmapTaps {
    let c = uv * size;
    let ax = lightmap_bspline_axis(c.x);
    let ay = lightmap_bspline_axis(c.y);
    return LightmapTaps(vec4<f32>(ax.xy / size.x, ay.xy / size.y), vec4<f32>(ax.zw, ay.zw));
}
