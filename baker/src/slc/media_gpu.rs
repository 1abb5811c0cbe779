//! The wgpu path of [`crate::slc::media`]: `slc/media.wgsl` composed with the `shaders` slc
//! module — one workgroup per 16 × 16 tile culling the lights' spheres into a shared bit mask,
//! one distance sample per pixel and kept light — with its own distance samples (a PCG hash
//! of (seed, pixel, light)) and the lights' ξ as uploaded.

use crate::slc::media::{MediaLight, MediaMode, MediaRender, Medium};
use crate::slc::{GBuffer, TILE};
use sbf::glam::Vec3;
use shaders::gpu::Gpu;
use wgpu::util::DeviceExt;

/// Uniform parameters (WGSL `MediaParams`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MediaParams {
    pub width: u32,
    pub height: u32,
    pub light_count: u32,
    /// 0 culled, 1 brute force.
    pub mode: u32,
    pub tan_x: f32,
    pub tan_y: f32,
    pub delta: f32,
    /// Seed of the GPU's random numbers (0 is taken as 1).
    pub seed: u32,
    pub sigma_s: f32,
    pub sigma_t: f32,
    pub near: f32,
    pub far: f32,
}
shaders::gpu_struct!(
    MediaParams,
    "MediaParams",
    [width, height, light_count, mode, tan_x, tan_y, delta, seed, sigma_s, sigma_t, near, far]
);

const KERNEL: &str = include_str!("media.wgsl");

/// The composed kernel source (validated by naga).
pub fn kernel() -> Result<String, String> {
    let roots = [
        "slc_diffuse_sphere",
        "slc_point_sphere",
        "slc_ray_sphere",
        "slc_equiangular_sample",
        "slc_diffuse_intensity_bound",
        "slc_acceptance",
        "slc_cull_transform",
        "slc_tile_corners",
        "slc_ellipsoid_hits_corners",
        "PI",
    ];
    super::gpu::compose_kernel("slc-media", &roots, KERNEL)
}

/// The lights as the kernel reads them: per light (position, peak), (normal, ξ), (tint, 0).
fn light_vectors(lights: &[MediaLight]) -> Vec<[f32; 4]> {
    lights
        .iter()
        .flat_map(|l| [l.position.extend(l.peak()).to_array(), l.normal.extend(l.xi).to_array(), l.tint().extend(0.0).to_array()])
        .collect()
}

/// A G-buffer, medium and light set uploaded with the pipeline built.
#[derive(Debug)]
pub struct MediaGpu<'g> {
    gpu: &'g Gpu,
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    params: MediaParams,
    params_buf: wgpu::Buffer,
    out_buf: wgpu::Buffer,
    light_buf: wgpu::Buffer,
    tiles: (u32, u32),
}

impl<'g> MediaGpu<'g> {
    /// Uploads the surfaces' distances along the camera rays of `g`, the medium and the
    /// lights, and compiles the kernel.
    pub fn new(gpu: &'g Gpu, g: &GBuffer, m: &Medium, lights: &[MediaLight], delta: f32) -> Result<Self, String> {
        m.validate()?;
        let d = gpu.device();
        let source = kernel()?;
        shaders::gpu::check_workgroup_memory("slc media.wgsl", &source, d.limits().max_compute_workgroup_storage_size)?;
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("slc media"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let params = MediaParams {
            width: g.width as u32,
            height: g.height as u32,
            light_count: lights.len() as u32,
            mode: 0,
            tan_x: g.tan_xy.0,
            tan_y: g.tan_xy.1,
            delta,
            seed: 1,
            sigma_s: m.sigma_s,
            sigma_t: m.sigma_t,
            near: m.near,
            far: if m.far.is_finite() { m.far } else { f32::MAX },
        };
        let dist: Vec<f32> = g.texels.iter().map(|t| t.map_or(3.4e38, |s| s.position.length())).collect();
        let lv = light_vectors(lights);
        shaders::gpu::check_bindings(
            &[("lights", (lv.len() * 16) as u64), ("image", (dist.len() * 32) as u64)],
            d.limits().max_storage_buffer_binding_size,
        )?;
        let init = |label: &str, bytes: &[u8], usage| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytes, usage })
        };
        let params_buf = init("media params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
        let dist_buf = init("surface distance", bytemuck::cast_slice(&dist), wgpu::BufferUsages::STORAGE);
        let light_buf = init(
            "media lights",
            bytemuck::cast_slice(if lv.is_empty() { &[[0.0f32; 4]][..] } else { &lv }),
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        );
        let out_buf = init("media image", &vec![0u8; dist.len() * 32], wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("media_cull_shade"),
            layout: None,
            module: &module,
            entry_point: Some("media_cull_shade"),
            compilation_options: Default::default(),
            cache: None,
        });
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("slc media"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[&params_buf, &dist_buf, &light_buf, &out_buf]
                .iter()
                .enumerate()
                .map(|(k, b)| wgpu::BindGroupEntry { binding: k as u32, resource: b.as_entire_binding() })
                .collect::<Vec<_>>(),
        });
        Ok(MediaGpu {
            gpu,
            pipeline,
            group,
            params,
            params_buf,
            out_buf,
            light_buf,
            tiles: (g.width.div_ceil(TILE) as u32, g.height.div_ceil(TILE) as u32),
        })
    }

    /// Replaces the lights (as many as uploaded: new ξ or powers for the next frames).
    pub fn set_lights(&mut self, lights: &[MediaLight]) -> Result<(), String> {
        if lights.len() as u32 != self.params.light_count {
            return Err(format!("{} lights given, {} uploaded", lights.len(), self.params.light_count));
        }
        let lv = light_vectors(lights);
        self.gpu.queue().write_buffer(&self.light_buf, 0, bytemuck::cast_slice(&lv));
        Ok(())
    }

    fn dispatch(&mut self, mode: MediaMode, seed: u32) {
        self.params.mode = (mode == MediaMode::BruteForce) as u32;
        self.params.seed = seed.max(1);
        let q = self.gpu.queue();
        q.write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&self.params));
        let mut enc = self.gpu.device().create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.dispatch_workgroups(self.tiles.0, self.tiles.1, 1);
        }
        q.submit([enc.finish()]);
    }

    /// One frame with random numbers from `seed`, read back.
    pub fn run(&mut self, mode: MediaMode, seed: u32) -> Result<MediaRender, String> {
        self.dispatch(mode, seed);
        let px: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&self.gpu.read_back(&self.out_buf)?);
        Ok(MediaRender {
            image: px.chunks_exact(2).map(|p| Vec3::new(p[0][0], p[0][1], p[0][2])).collect(),
            lights_per_pixel: px.chunks_exact(2).map(|p| p[0][3] as u32).collect(),
            false_per_pixel: px.chunks_exact(2).map(|p| p[1][0] as u32).collect(),
        })
    }

    /// Seconds per frame: median of `frames` frames after two warm-up frames, each waited for.
    pub fn time(&mut self, mode: MediaMode, frames: usize) -> Result<f64, String> {
        let mut t = Vec::new();
        for k in 0..frames.max(1) + 2 {
            let s = std::time::Instant::now();
            self.dispatch(mode, k as u32 + 1);
            self.gpu.wait()?;
            if k >= 2 {
                t.push(s.elapsed().as_secs_f64());
            }
        }
        t.sort_by(f64::total_cmp);
        Ok(t[t.len() / 2])
    }
}
