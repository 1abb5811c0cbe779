//! What the adapter's texture filter does to a lookup, measured: the precision of its
//! filter weights and of the value it returns.
//!
//! Hardware samplers interpolate with fixed-point weights — Vulkan reports the number of
//! fractional bits as `subTexelPrecisionBits` (at least 4, commonly 8 on NVIDIA, AMD and
//! Intel; Vulkan spec §16 "Texel Filtering"), and leaves open whether the fraction is rounded
//! or truncated — and may return the filtered value of a 16-bit float texture rounded to
//! that format. wgpu reports neither, so the adapter is asked by a probe: a texture of the size
//! of the one it stands for whose red, green and blue channels hold the parity of each
//! texel's x, y and z index (so the filtered value is the weight the sampler used on that
//! axis, or one minus it) and whose alpha holds 1 + δ·(p_x + 2 p_y + 4 p_z), sampled at
//! 4 096 positions in pseudo-random cells, on a 2⁻¹² grid of fractions per axis. An exact
//! lerp (lavapipe) returns the positions themselves; NVIDIA's hardware (H100) returns
//! weights in steps of 2⁻⁸, and on a 3D texture up to 1.5 steps from the exact fraction.
//!
//! From the weights: the smallest b with every weight a multiple of 2⁻ᵇ, and whether each
//! weight is ≤ the exact fraction (truncation: an error below 2⁻ᵇ) or within 2⁻ᵇ⁻¹ of it
//! (rounding). From alpha, against the trilinear blend of the texels with the sampler's own
//! weights in f64: the relative error of the returned value, rounded up to a power of two
//! (2⁻¹¹ is an f16 result rounded to nearest; 2⁻²⁴ or less an f32 one).

use wgpu::util::DeviceExt;

use crate::gpu::Gpu;

/// Probe positions per axis: fractions k / 4096.
const N: u32 = 4096;

/// The sampler's precision on one texture format, as measured by [`measure`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SamplerPrecision {
    /// Fractional bits of the filter weights as far as the probe resolves them: its
    /// fractions lie on a 2⁻¹² grid, so 12 means 12 or more (lavapipe); 24: weights off
    /// that grid at f32 precision (an f32 lerp of the rounded coordinate).
    pub weight_bits: u32,
    /// The weights are truncated (always ≤ the exact fraction), not rounded.
    pub truncates: bool,
    /// The largest |weight − exact fraction| seen on any axis.
    pub weight_error_seen: f64,
    /// The largest relative error of the returned value seen, against the exact blend of
    /// the texels with the sampler's own weights.
    pub result_error_seen: f64,
}

impl SamplerPrecision {
    /// A bound on the error of one axis' weight: 2⁻ᵇ when truncating, 2⁻ᵇ⁻¹ when
    /// rounding (never below what was seen).
    pub fn weight_error(&self) -> f64 {
        let model = 2f64.powi(-(self.weight_bits as i32) - i32::from(!self.truncates));
        model.max(self.weight_error_seen)
    }

    /// A bound on the relative error of the returned value: the seen error rounded up to a
    /// power of two, at least f32's 2⁻²⁴.
    pub fn result_error(&self) -> f64 {
        let seen = self.result_error_seen.max(2f64.powi(-24));
        2f64.powi(seen.log2().ceil() as i32)
    }
}

/// Texture formats the probe measures: the 16-bit float formats of the lobe GGX tables and
/// f16 lightmaps, and the 32-bit float format of f32 lightmaps (filtered where the adapter
/// has `FLOAT32_FILTERABLE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProbeFormat {
    F16,
    F32,
}

/// Measures the sampler on a texture of `size` texels (x, y, z; `three_d`: a 3D texture as
/// the lobe tables, else 2D as lightmaps, z = 1) and `format`, with the linear clamp-to-edge
/// sampler the library uses. The probe has the size of the texture it stands for: hardware
/// converts the normalised coordinate to texels in fixed point, so the weights' error can
/// grow with the size (a 2-texel probe would not show it).
pub fn measure(gpu: &Gpu, format: ProbeFormat, size: [u32; 3], three_d: bool) -> Result<SamplerPrecision, String> {
    let (device, queue) = (gpu.device(), gpu.queue());
    if format == ProbeFormat::F32 && !device.features().contains(wgpu::Features::FLOAT32_FILTERABLE) {
        return Err(format!("{} cannot filter 32-bit float textures (no FLOAT32_FILTERABLE)", gpu.adapter));
    }
    let axes = if three_d { 3 } else { 2 };
    if size[..axes].iter().any(|s| *s < 2) || (!three_d && size[2] != 1) {
        return Err(format!("sampler probe: a {axes}D texture of {size:?} texels has no cell to filter in"));
    }
    // δ: the alpha ramp's step, one f16 ulp at 1 (2⁻¹⁰) or 2⁻¹⁴ in f32 (so the exact blend
    // needs more bits than f32 holds only by rounding in the last place).
    let delta = match format {
        ProbeFormat::F16 => 2f64.powi(-10),
        ProbeFormat::F32 => 2f64.powi(-14),
    };
    // Each texel holds its indices' parities (x & 1, y & 1, z & 1) and the alpha ramp: the
    // filtered value between texels c and c + 1 is the weight w for even c, 1 − w for odd.
    let [w, h, d] = size.map(|s| s as usize);
    let texels: Vec<[f32; 4]> = (0..w * h * d)
        .map(|t| {
            let (x, y, z) = ((t % w) & 1, ((t / w) % h) & 1, (t / (w * h)) & 1);
            [x as f32, y as f32, z as f32, (1.0 + delta * (x + 2 * y + 4 * z) as f64) as f32]
        })
        .collect();
    // Probe k: in cell (c_x, c_y, c_z) (pseudo-random), at fractions k/N, (1237 k mod N)/N,
    // (2897 k mod N)/N — odd multipliers, so each axis visits every point of the 2⁻¹² grid
    // once. The normalised coordinates are rounded to f32 here and passed as they are.
    let mut rng = sbf::sampling::Pcg32::new(17, 5);
    let (mut coords, mut cells) = (Vec::with_capacity(N as usize), Vec::with_capacity(N as usize));
    for k in 0..N as u64 {
        let f = [k, (k * 1237) % N as u64, (k * 2897) % N as u64].map(|m| m as f64 / N as f64);
        let c: [u32; 3] = std::array::from_fn(|a| if a < axes { rng.next_u32() % (size[a] - 1) } else { 0 });
        let u: [f32; 3] = std::array::from_fn(|a| if a < axes { ((c[a] as f64 + 0.5 + f[a]) / size[a] as f64) as f32 } else { 0.5 });
        coords.push([u[0], u[1], u[2], 0.0]);
        cells.push(c);
    }
    let (wgpu_format, bytes): (wgpu::TextureFormat, Vec<u8>) = match format {
        ProbeFormat::F16 => (
            wgpu::TextureFormat::Rgba16Float,
            bytemuck::cast_slice(&texels.iter().flatten().map(|v| half::f16::from_f32(*v).to_bits()).collect::<Vec<u16>>()).to_vec(),
        ),
        ProbeFormat::F32 => (wgpu::TextureFormat::Rgba32Float, bytemuck::cast_slice(&texels).to_vec()),
    };
    let texture = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("sampler probe"),
            size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: size[2] },
            mip_level_count: 1,
            sample_count: 1,
            dimension: if three_d { wgpu::TextureDimension::D3 } else { wgpu::TextureDimension::D2 },
            format: wgpu_format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &bytes,
    );
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("sampler probe coordinates"),
        contents: bytemuck::cast_slice(&coords),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sampler probe out"),
        size: 16 * N as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let (tex_type, coord) = if three_d { ("texture_3d<f32>", "u.xyz") } else { ("texture_2d<f32>", "u.xy") };
    let src = format!(
        "@group(0) @binding(0) var tex: {tex_type};\n\
         @group(0) @binding(1) var smp: sampler;\n\
         @group(0) @binding(2) var<storage, read_write> outp: array<vec4<f32>>;\n\
         @group(0) @binding(3) var<storage, read> coords: array<vec4<f32>>;\n\
         @compute @workgroup_size(64)\n\
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
             let k = id.x;\n\
             if (k >= {N}u) {{ return; }}\n\
             let u = coords[k];\n\
             outp[k] = textureSampleLevel(tex, smp, {coord}, 0.0);\n\
         }}\n"
    );
    let module = device
        .create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("sampler probe"), source: wgpu::ShaderSource::Wgsl(src.into()) });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("sampler probe"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let view = texture.create_view(&Default::default());
    let sampler = gpu.linear_clamp_sampler();
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sampler probe"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&sampler) },
            wgpu::BindGroupEntry { binding: 2, resource: out.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: input.as_entire_binding() },
        ],
    });
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(N / 64, 1, 1);
    }
    queue.submit([enc.finish()]);
    let got: Vec<[f32; 4]> = bytemuck::cast_slice(&gpu.read_back(&out)?).to_vec();
    // The exact fraction of each probe's f32 coordinate in its cell, and the cell's parity.
    let exact: Vec<([f64; 3], [bool; 3])> = coords
        .iter()
        .zip(&cells)
        .map(|(u, c)| (std::array::from_fn(|a| u[a] as f64 * size[a] as f64 - 0.5 - c[a] as f64), c.map(|x| x & 1 == 1)))
        .collect();
    summarise(&got, &exact, delta, axes)
}

/// The precision the probe's returned texels show (see the module docs): per probe the
/// returned value and (exact fraction, cell index odd) per axis.
fn summarise(got: &[[f32; 4]], exact: &[([f64; 3], [bool; 3])], delta: f64, axes: usize) -> Result<SamplerPrecision, String> {
    let (mut bits, mut truncates, mut weight_error_seen, mut result_error_seen) = (0u32, true, 0.0f64, 0.0f64);
    for (k, (s, (f, odd))) in got.iter().zip(exact).enumerate() {
        if s.iter().any(|v| !v.is_finite()) {
            return Err(format!("the sampler returned {s:?} at probe {k}"));
        }
        for a in 0..axes {
            let v = s[a] as f64;
            let w = if odd[a] { 1.0 - v } else { v };
            let e = w - f[a];
            weight_error_seen = weight_error_seen.max(e.abs());
            truncates &= e <= 0.0;
            // The fewest fractional bits that hold this weight.
            let b = (0..=24u32).find(|b| (w * 2f64.powi(*b as i32)).fract() == 0.0).unwrap_or(24);
            bits = bits.max(b);
        }
        let blend = 1.0 + delta * (0..axes).map(|a| (1 << a) as f64 * s[a] as f64).sum::<f64>();
        result_error_seen = result_error_seen.max((s[3] as f64 - blend).abs() / blend);
    }
    if weight_error_seen > 0.25 {
        return Err(format!("the sampler's weights are off by {weight_error_seen} of a texel: not a linear filter"));
    }
    // An exact lerp's weights are the fractions themselves (up to the f32 coordinate's
    // rounding): no quantisation to report; weights equal to the fractions are not
    // truncated ones.
    if bits > 16 {
        bits = 24;
    }
    if bits > 16 || weight_error_seen == 0.0 {
        truncates = false;
    }
    Ok(SamplerPrecision { weight_bits: bits, truncates, weight_error_seen, result_error_seen })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Weights truncated to 8 bits, f16 results rounded to nearest: 8 bits, truncating,
    /// bound 2⁻⁸; result bound 2⁻¹¹.
    #[test]
    fn summarise_reads_the_precision_off_the_samples() {
        let delta = 2f64.powi(-10);
        let cases: Vec<([f64; 3], [bool; 3])> = (0..N as u64)
            .map(|k| ([k, (k * 1237) % N as u64, (k * 2897) % N as u64].map(|m| m as f64 / N as f64), [k & 1 == 1, k & 2 == 2, false]))
            .collect();
        let sample = |q: Option<f64>, half: bool| -> Vec<[f32; 4]> {
            cases
                .iter()
                .map(|(f, odd)| {
                    let w = f.map(|x| q.map_or(x, |q| (x / q).floor() * q));
                    let v: [f64; 3] = std::array::from_fn(|a| if odd[a] { 1.0 - w[a] } else { w[a] });
                    let a = 1.0 + delta * (v[0] + 2.0 * v[1] + 4.0 * v[2]);
                    let a = if half { half::f16::from_f64(a).to_f64() } else { a };
                    [v[0] as f32, v[1] as f32, v[2] as f32, a as f32]
                })
                .collect()
        };
        let hw = summarise(&sample(Some(1.0 / 256.0), true), &cases, delta, 3).unwrap();
        assert_eq!((hw.weight_bits, hw.truncates), (8, true));
        assert_eq!(hw.weight_error(), 1.0 / 256.0);
        assert_eq!(hw.result_error(), 2f64.powi(-11));
        // Exact weights on the probe's 2⁻¹² grid: 12 bits or more, bound 2⁻¹³.
        let exact = summarise(&sample(None, false), &cases, delta, 3).unwrap();
        assert_eq!((exact.weight_bits, exact.truncates, exact.weight_error()), (12, false, 2f64.powi(-13)));
        assert!(exact.result_error() <= 2f64.powi(-24));
    }
}
