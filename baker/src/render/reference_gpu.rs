//! The path-traced reference on the GPU (`wgsl/reference.wgsl`): the same per-sample
//! estimator as [`super::reference`] — the bake's incident-radiance estimator at the
//! visible surface, weighted by its BSDF — run by the bake's WGSL path tracer over the
//! bake's buffers (BVH, materials, lights, environment). The visible surfaces come from
//! the CPU ray cast ([`super::visible`]), so both references shade the same points. Each
//! dispatch takes a range of samples per pixel, one thread per sample, and sums them per
//! pixel in f32 by a tree in workgroup memory (at most [`SAMPLES_PER_DISPATCH`] samples:
//! the sums keep ~1e-6 relative accuracy); the host adds the dispatches in f64, so the
//! noise estimate and the progressive stop are the CPU reference's.

use super::reference::{finish, progressive, PixelAcc, Reference};
use super::visible::Visible;
use crate::estimator::trace::Tracer;
use crate::gpu::buffers::storage;
use crate::gpu::params::{aux_data, scene_params};
use crate::sampling::sequence::{gpu_seed, Sequence};
use sbf::glam::{DVec3, Vec3};
use shaders::gpu::Gpu;
use wgpu::util::DeviceExt;

const REFERENCE_WGSL: (&str, &str) = ("reference.wgsl", include_str!("wgsl/reference.wgsl"));

/// The most samples per pixel one dispatch sums.
pub const SAMPLES_PER_DISPATCH: u32 = 64;
/// Samples per dispatch aimed at (pixels × samples), so that no dispatch runs for long.
const SAMPLE_BUDGET: u64 = 1 << 22;
/// vec4s per surface in the sums.
const SUM_VEC4: usize = 7;

/// WGSL `RefParams`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct RefParams {
    eye: [f32; 3],
    count: u32,
    first: u32,
    samples: u32,
    slot: u32,
    pad_b: u32,
}
shaders::gpu_struct!(RefParams, "RefParams", [eye, count, first, samples, slot, pad_b]);

/// The reference kernel with the scene uploaded and the visible surfaces bound.
#[derive(Debug)]
pub struct GpuReference<'g> {
    gpu: &'g Gpu,
    pipeline: wgpu::ComputePipeline,
    scene_group: wgpu::BindGroup,
    surface_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    sums: wgpu::Buffer,
    counters: wgpu::Buffer,
    /// Pixel index of each surface.
    pixels: Vec<u32>,
    /// Pixels of the image.
    image: usize,
    eye: Vec3,
}

impl<'g> GpuReference<'g> {
    /// Uploads the scene of `tracer` (its bounce count) and the surfaces of `visible` that
    /// the reference shades (lightmapped or dynamic), seen from `eye`, with random numbers
    /// from `seed`.
    pub fn new(gpu: &'g Gpu, tracer: &Tracer, visible: &[Option<Visible>], eye: Vec3, seed: u64) -> Result<Self, String> {
        if tracer.scene.has_textures() {
            // The reference kernel reads the materials' factors (the renderer drops maps).
            return Err("the scene's materials have texture maps: the GPU reference reads their factors only (Scene::without_maps)".into());
        }
        let d = gpu.device();
        let glossy = tracer.scene.has_glossy();
        let source = crate::gpu::kernel::estimator_kernel(REFERENCE_WGSL, glossy)?;
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("reference.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = crate::gpu::compute_pipeline(d, &module, "reference_pass");
        let (aux, at) = aux_data(tracer);
        let params = scene_params(tracer, &at, tracer.max_bounces, gpu_seed(seed), Sequence::Independent.code());
        let mut pixels = Vec::new();
        let mut surf: Vec<[f32; 4]> = Vec::new();
        for (k, v) in visible.iter().enumerate() {
            if let Some(v) = v.as_ref().filter(|v| v.lightmapped || v.probed) {
                pixels.push(k as u32);
                let (p, n, g) = (v.position, v.normal, v.geometric);
                surf.push([p.x, p.y, p.z, f32::from_bits(k as u32)]);
                surf.push([n.x, n.y, n.z, f32::from_bits(v.material)]);
                surf.push([g.x, g.y, g.z, 0.0]);
            }
        }
        if pixels.is_empty() {
            surf.push([0.0; 4]);
        }
        let sums_len = (pixels.len().max(1) * SUM_VEC4 * 16) as u64;
        let limit = d.limits().max_storage_buffer_binding_size;
        crate::gpu::check_bindings(
            &[
                ("BVH nodes", std::mem::size_of_val(&tracer.bvh.nodes[..]) as u64),
                ("triangles", std::mem::size_of_val(&tracer.bvh.tris[..]) as u64),
                ("materials, lights and environment", (aux.len() * 16) as u64),
                ("reference surfaces", (surf.len() * 16) as u64),
                ("reference sums", sums_len),
            ],
            limit,
        )?;
        let none = wgpu::BufferUsages::empty();
        let uniform = |label: &str, bytes: &[u8]| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            })
        };
        let trace = uniform("trace params", bytemuck::bytes_of(&params));
        let nodes = storage(d, "nodes", bytemuck::cast_slice(&tracer.bvh.nodes), none);
        let tris = storage(d, "tris", bytemuck::cast_slice(&tracer.bvh.tris), none);
        let auxb = storage(d, "aux", bytemuck::cast_slice(&aux), none);
        let counters = storage(d, "counters", &[0u8; 16], wgpu::BufferUsages::COPY_SRC);
        let ref_params = uniform("reference params", bytemuck::bytes_of(&<RefParams as bytemuck::Zeroable>::zeroed()));
        let surfaces = storage(d, "reference surfaces", bytemuck::cast_slice(&surf), none);
        let sums = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("reference sums"),
            size: sums_len,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
        }
        // The bindings the kernel uses (the layout comes from the shader).
        let used = |layout: &wgpu::BindGroupLayout, entries: &[wgpu::BindGroupEntry], label| {
            d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(label), layout, entries })
        };
        let scene_group = used(
            &pipeline.get_bind_group_layout(0),
            &[entry(0, &trace), entry(1, &nodes), entry(2, &tris), entry(3, &auxb), entry(8, &counters)],
            "reference scene",
        );
        let surface_group =
            used(&pipeline.get_bind_group_layout(1), &[entry(0, &ref_params), entry(1, &surfaces), entry(2, &sums)], "reference surfaces");
        Ok(GpuReference {
            gpu,
            pipeline,
            scene_group,
            surface_group,
            params: ref_params,
            sums,
            counters,
            pixels,
            image: visible.len(),
            eye,
        })
    }

    /// Adds samples `range` of every shaded pixel to `acc` (image-sized).
    fn add(&self, range: std::ops::Range<u32>, acc: &mut [PixelAcc]) -> Result<(), String> {
        let n = self.pixels.len();
        if n == 0 {
            return Ok(());
        }
        // A power of two, so that whole slots fill the 64-thread workgroups.
        let per = prev_power_of_two(((SAMPLE_BUDGET / n as u64) as u32).clamp(1, SAMPLES_PER_DISPATCH));
        let mut first = range.start;
        while first < range.end {
            let samples = per.min(range.end - first);
            let slot = samples.next_power_of_two();
            let p = RefParams { eye: self.eye.to_array(), count: n as u32, first, samples, slot, pad_b: 0 };
            self.gpu.queue().write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
            let mut enc = self.gpu.device().create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&Default::default());
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.scene_group, &[]);
                pass.set_bind_group(1, &self.surface_group, &[]);
                let groups = (n * slot as usize).div_ceil(64) as u32;
                let (x, y) = if groups <= 65_535 { (groups, 1) } else { (65_535, groups.div_ceil(65_535)) };
                pass.dispatch_workgroups(x, y, 1);
            }
            self.gpu.queue().submit([enc.finish()]);
            crate::gpu::buffers::check_cut_traversals(self.gpu, &self.counters)?;
            let bytes = self.gpu.read_back(&self.sums)?;
            let v: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
            for (j, &px) in self.pixels.iter().enumerate() {
                let s = &v[SUM_VEC4 * j..SUM_VEC4 * (j + 1)];
                let a = &mut acc[px as usize];
                let d = |x: [f32; 4]| DVec3::new(x[0] as f64, x[1] as f64, x[2] as f64);
                for i in 0..3 {
                    a.sum[i] += d(s[i]);
                    a.sq[i] += d(s[3 + i]);
                }
                a.n += s[6][0] as u32;
            }
            first += samples;
        }
        Ok(())
    }

    /// The reference with `samples` samples per pixel.
    pub fn render(&self, samples: u32) -> Result<Reference, String> {
        let mut acc = vec![PixelAcc::default(); self.image];
        self.add(0..samples, &mut acc)?;
        Ok(finish(&acc, samples))
    }

    /// The reference rendered progressively to a stated noise level, as
    /// [`super::reference::render_to_noise`].
    pub fn render_to_noise(&self, noise: f64, first: u32, max_samples: u32, report: &mut dyn FnMut(u32, f64)) -> Result<Reference, String> {
        progressive(self.image, noise, first, max_samples, report, &mut |r, acc| self.add(r, acc))
    }
}

/// The largest power of two ≤ `x` (x ≥ 1).
fn prev_power_of_two(x: u32) -> u32 {
    1 << (31 - x.leading_zeros())
}
