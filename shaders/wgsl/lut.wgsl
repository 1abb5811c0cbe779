// lut.wgsl — sampling of fitgen's 2D tables (luts/*.sbflut) uploaded as rgba32float
// (or rg32float) textures, width along u, height along v, texel (i, j) at
// ((i + ½)/w, (j + ½)/h). Bilinear between texel centres, clamped to the outermost
// centres, computed by hand from textureLoad: hardware filtering interpolates with
// 8-bit fixed-point weights on many GPUs (≈ 4e-3 relative), far above the 1e-4 the
// parity tests hold. CPU twin: sbf::recon::lut::Lut2::sample2.
// The split-sum table `dfg` (luts/dfg.sbflut, read by the SH and SG specular and by
// ggx_energy_compensation's caller): u = n·v, v = GGX α (roughness², not the perceptual
// roughness Filament's DFG is indexed by); x = f0 scale, y = f90 scale of
// ∫ f·cos = f0·x + f90·y (Karis 2013).

fn lut2_sample(t: texture_2d<f32>, u: f32, v: f32) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(t));
    // NaN coordinates read as 0, as on the CPU (select is NaN-safe: u == u is false).
    let uu = select(0.0, u, u == u);
    let vv = select(0.0, v, v == v);
    let x = clamp(uu * f32(size.x) - 0.5, 0.0, f32(size.x - 1));
    let y = clamp(vv * f32(size.y) - 0.5, 0.0, f32(size.y - 1));
    let i0 = min(i32(floor(x)), size.x - 1);
    let j0 = min(i32(floor(y)), size.y - 1);
    let i1 = min(i0 + 1, size.x - 1);
    let j1 = min(j0 + 1, size.y - 1);
    let fx = x - f32(i0);
    let fy = y - f32(j0);
    let a = textureLoad(t, vec2<i32>(i0, j0), 0).xy * (1.0 - fx) + textureLoad(t, vec2<i32>(i1, j0), 0).xy * fx;
    let b = textureLoad(t, vec2<i32>(i0, j1), 0).xy * (1.0 - fx) + textureLoad(t, vec2<i32>(i1, j1), 0).xy * fx;
    return a * (1.0 - fy) + b * fy;
}
