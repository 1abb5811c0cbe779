//! The wgpu path of [`crate::slc`]: `slc/cull.wgsl` composed with the `shaders` slc
//! module (bounds per light on the GPU, one workgroup per 16 × 16 tile with shared-memory
//! light lists), run on a G-buffer and a VPL set; results read back in the CPU twin's form.

use crate::slc::{Bound, Culling, Filter, GBuffer, Layers, Mode, Render, Vpl, TILE};
use sbf::glam::{Vec3, Vec4};
use shaders::gpu::Gpu;
use wgpu::util::DeviceExt;

/// Uniform parameters (WGSL `SlcParams`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SlcParams {
    pub width: u32,
    pub height: u32,
    pub light_count: u32,
    pub mode: u32,
    pub tan_x: f32,
    pub tan_y: f32,
    pub delta: f32,
    pub interleave: u32,
    /// 0: every light's ξ as uploaded (the CPU twin's, [`Vpl::xi`]); otherwise the GPU
    /// draws its own ξ per light from this seed (`slc_gpu_xi` in cull.wgsl).
    pub xi_seed: u32,
    /// The filter joining the subregions: 0 the box of one period, R the cross-bilateral
    /// filter of radius R ([`crate::slc::Filter`]).
    pub filter_radius: u32,
    /// 0: Modified HalfZ tiles; n > 2: n depth slices per tile ([`crate::slc::Culling`]).
    pub clusters: u32,
    pub pad2: u32,
}
shaders::gpu_struct!(
    SlcParams,
    "SlcParams",
    [width, height, light_count, mode, tan_x, tan_y, delta, interleave, xi_seed, filter_radius, clusters, pad2]
);

/// The culling kernel and, appended (it reads the kernel's bindings), the filters.
const KERNEL: &str = concat!(include_str!("cull.wgsl"), "\n", include_str!("filter.wgsl"));

/// The composed kernel source (validated by naga).
pub fn kernel() -> Result<String, String> {
    let roots = [
        "slc_diffuse_sphere",
        "slc_spheroid_scale",
        "slc_schlick_max",
        "slc_g1_dist",
        "slc_ggx_spheroid",
        "slc_cull_transform",
        "slc_tile_corners",
        "slc_ellipsoid_hits_corners",
        "slc_acceptance",
        "slc_culled_estimate",
        "slc_random_range",
        "ggx_d",
        "ggx_lambda",
        "schlick_weight",
        "tangent_frame",
        "PI",
        "INV_PI",
    ];
    compose_kernel("slc-cull", &roots, KERNEL)
}

/// The `shaders` library functions reachable from `roots`, the shared hash (hash.wgsl) and
/// `kernel`, validated by naga — how every light-culling kernel is put together.
pub fn compose_kernel(name: &str, roots: &[&str], kernel: &str) -> Result<String, String> {
    let cfg = shaders::compose::Config { name: name.into(), features: Default::default() };
    let lib = shaders::compose::compose_roots(cfg, roots)?;
    let source = format!("{}\n{}\n{kernel}", lib.source, include_str!("hash.wgsl"));
    shaders::export::validate(&source).map_err(|e| format!("{name} kernel: {e}"))?;
    Ok(source)
}

/// A G-buffer and VPL set uploaded with the two pipelines built: run frames, time them.
#[derive(Debug)]
pub struct SlcGpu<'g> {
    gpu: &'g Gpu,
    prepare: wgpu::ComputePipeline,
    shade: wgpu::ComputePipeline,
    /// The box filter, and the bilateral filter's two passes (rows, then columns).
    filter: wgpu::ComputePipeline,
    filter_rows: wgpu::ComputePipeline,
    filter_cols: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    params: SlcParams,
    params_buf: wgpu::Buffer,
    // What `params_buf` holds: frames write the parameters only when they changed.
    params_written: SlcParams,
    image_buf: wgpu::Buffer,
    stats_buf: wgpu::Buffer,
    filtered_buf: wgpu::Buffer,
    pixels: (u32, u32),
    lights: u32,
    tiles: (u32, u32, u32),
    bound: Bound,
    filter_on: bool,
    /// Some receiver has a GGX layer (SlcParams.mode bit 4: the specular layer runs).
    specular: bool,
    /// The receivers, to compose the unfiltered image from the layers read back.
    surfaces: Vec<Option<crate::slc::Surface>>,
}

impl<'g> SlcGpu<'g> {
    /// Uploads `g` and `vpls` and compiles the kernel; `interleave` I (1: off) splits the
    /// screen into I × I subregions that each shade 1/I² of the VPLs (weighted by I²).
    pub fn new(gpu: &'g Gpu, g: &GBuffer, vpls: &[Vpl], delta: f32, interleave: usize) -> Result<Self, String> {
        if interleave == 0 || interleave > 16 {
            return Err(format!("interleave must be 1..=16, not {interleave}"));
        }
        let d = gpu.device();
        let source = kernel()?;
        shaders::gpu::check_workgroup_memory("slc_cull.wgsl", &source, d.limits().max_compute_workgroup_storage_size)?;
        let module =
            d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("slc"), source: wgpu::ShaderSource::Wgsl(source.into()) });
        let entry = |binding: u32, ty: wgpu::BufferBindingType| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
            count: None,
        };
        let storage = |read_only| wgpu::BufferBindingType::Storage { read_only };
        let layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("slc"),
            entries: &[
                entry(0, wgpu::BufferBindingType::Uniform),
                entry(1, storage(true)),
                entry(2, storage(true)),
                entry(3, storage(false)),
                entry(4, storage(false)),
                entry(5, storage(false)),
                entry(6, storage(false)),
                entry(7, storage(false)),
            ],
        });
        let pl = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("slc"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |name: &str| {
            d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&pl),
                module: &module,
                entry_point: Some(name),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let params = SlcParams {
            width: g.width as u32,
            height: g.height as u32,
            light_count: vpls.len() as u32,
            mode: 0,
            tan_x: g.tan_xy.0,
            tan_y: g.tan_xy.1,
            delta,
            interleave: interleave as u32,
            xi_seed: 0,
            filter_radius: Filter::SEED.gpu_radius(),
            clusters: 0,
            pad2: 0,
        };
        let (gb, lv) = (pack_gbuffer(g), pack_vpls(vpls));
        shaders::gpu::check_bindings(
            &[("G-buffer", (gb.len() * 16) as u64), ("VPLs", (lv.len() * 16) as u64), ("image", (g.width * g.height * 32) as u64)],
            d.limits().max_storage_buffer_binding_size,
        )?;
        let rw = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let init = |label: &str, bytes: &[u8], usage| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytes, usage })
        };
        let params_buf = init("params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
        let gbb = init("gbuffer", bytemuck::cast_slice(&gb), wgpu::BufferUsages::STORAGE);
        let lb = init("lights", bytemuck::cast_slice(if lv.is_empty() { &[[0.0f32; 4]][..] } else { &lv }), wgpu::BufferUsages::STORAGE);
        let bb = init("bounds", &vec![0u8; vpls.len().max(1) * 64], rw);
        let image_buf = init("image", &vec![0u8; g.width * g.height * 32], rw);
        let stats_buf = init("stats", &[0u8; 8], rw);
        let filtered_buf = init("filtered", &vec![0u8; g.width * g.height * 16], rw);
        let rows_buf = init("filter rows", &vec![0u8; g.width * g.height * 32], wgpu::BufferUsages::STORAGE);
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("slc"),
            layout: &layout,
            entries: &[
                params_buf.as_entire_binding(),
                gbb.as_entire_binding(),
                lb.as_entire_binding(),
                bb.as_entire_binding(),
                image_buf.as_entire_binding(),
                stats_buf.as_entire_binding(),
                filtered_buf.as_entire_binding(),
                rows_buf.as_entire_binding(),
            ]
            .into_iter()
            .enumerate()
            .map(|(k, resource)| wgpu::BindGroupEntry { binding: k as u32, resource })
            .collect::<Vec<_>>(),
        });
        Ok(SlcGpu {
            gpu,
            prepare: pipeline("slc_prepare"),
            shade: pipeline("slc_cull_shade"),
            filter: pipeline("slc_filter"),
            filter_rows: pipeline("slc_filter_rows"),
            filter_cols: pipeline("slc_filter_cols"),
            group,
            params,
            params_buf,
            params_written: params,
            image_buf,
            stats_buf,
            filtered_buf,
            pixels: (g.width as u32, g.height as u32),
            lights: vpls.len() as u32,
            tiles: (
                g.width.div_ceil(interleave).div_ceil(TILE) as u32,
                g.height.div_ceil(interleave).div_ceil(TILE) as u32,
                (interleave * interleave) as u32,
            ),
            bound: Bound::Tight,
            filter_on: true,
            specular: g.has_glossy(),
            surfaces: g.texels.clone(),
        })
    }

    /// Whether frames run the filter (default on; off to time without it).
    pub fn set_filter(&mut self, on: bool) {
        self.filter_on = on;
    }

    /// Which filter joins the subregions in the following frames (default
    /// [`Filter::SEED`], as the CPU's [`crate::slc::render_with`]).
    pub fn set_filter_kind(&mut self, f: Filter) {
        self.params.filter_radius = f.gpu_radius();
    }

    /// Where the following frames take each light's ξ from: None, the uploaded VPLs' (the
    /// CPU twin's, so images agree pixel for pixel); Some(seed), the GPU's own stream — a
    /// hash of (seed, light) independent of the CPU's generator (seed 0 is taken as 1).
    pub fn set_xi_seed(&mut self, seed: Option<u32>) {
        self.params.xi_seed = seed.map_or(0, |s| s.max(1));
    }

    /// How tiles cull lights against their depths in the following frames (default
    /// [`Culling::HalfZ`]).
    pub fn set_culling(&mut self, c: Culling) -> Result<(), String> {
        c.check()?;
        self.params.clusters = c.gpu_clusters();
        Ok(())
    }

    /// Which bound culls glossy VPLs in the following frames.
    pub fn set_bound(&mut self, bound: Bound) {
        self.bound = bound;
    }

    fn dispatch(&mut self, mode: Mode) {
        self.record(mode, None);
    }

    /// Submits one frame; with `timestamps` (query set, first index) each stage runs in its
    /// own compute pass and writes its begin and end times at first + 2·stage (+1): stage 0
    /// the bounds (range determination), 1 culling + shading, 2 the filter.
    fn record(&mut self, mode: Mode, timestamps: Option<(&wgpu::QuerySet, u32)>) {
        self.params.mode = match mode {
            Mode::Culled => 0,
            Mode::BruteForce => 1,
            Mode::RangeCut => 2,
        } | match self.bound {
            Bound::Tight => 0,
            Bound::Sphere => 4,
            Bound::Th16 => 8,
        } | if self.specular { 16 } else { 0 };
        let q = self.gpu.queue();
        if self.params != self.params_written {
            q.write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&self.params));
            self.params_written = self.params;
        }
        let mut enc = self.gpu.device().create_command_encoder(&Default::default());
        enc.clear_buffer(&self.stats_buf, 0, None);
        let groups = (self.pixels.0.div_ceil(8), self.pixels.1.div_ceil(8));
        let mut stages: Vec<Stage> = vec![vec![(&self.prepare, (self.lights.div_ceil(64).max(1), 1, 1))], vec![(&self.shade, self.tiles)]];
        if self.filter_on {
            stages.push(if self.params.filter_radius == 0 {
                vec![(&self.filter, (groups.0, groups.1, 1))]
            } else {
                // The passes' workgroups: 32 × 8 and 8 × 32 (cull.wgsl).
                vec![
                    (&self.filter_rows, (self.pixels.0.div_ceil(32), self.pixels.1.div_ceil(8), 1)),
                    (&self.filter_cols, (self.pixels.0.div_ceil(8), self.pixels.1.div_ceil(32), 1)),
                ]
            });
        }
        if timestamps.is_none() {
            // One pass for the whole frame.
            stages = vec![stages.concat()];
        } else if !self.filter_on {
            // An empty pass still writes the filter's two timestamps (resolved with the rest).
            stages.push(Vec::new());
        }
        for (k, stage) in stages.iter().enumerate() {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("slc"),
                timestamp_writes: timestamps.map(|(qs, first)| wgpu::ComputePassTimestampWrites {
                    query_set: qs,
                    beginning_of_pass_write_index: Some(first + 2 * k as u32),
                    end_of_pass_write_index: Some(first + 2 * k as u32 + 1),
                }),
            });
            pass.set_bind_group(0, &self.group, &[]);
            for (pipeline, (x, y, z)) in stage {
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups(*x, *y, *z);
            }
        }
        q.submit([enc.finish()]);
    }

    /// Per-stage GPU times (medians of `frames` frames after [`WARM_UP`] of warm-up frames and two
    /// untimed frames, by timestamp queries). None where the adapter has no timestamp queries.
    pub fn time_stages(&mut self, mode: Mode, frames: usize) -> Result<Option<StageTimes>, String> {
        if !self.gpu.timestamps {
            return Ok(None);
        }
        let d = self.gpu.device();
        let total = (frames.max(1) + 2) as u32;
        let queries =
            d.create_query_set(&wgpu::QuerySetDescriptor { label: Some("slc stages"), ty: wgpu::QueryType::Timestamp, count: 6 * total });
        let resolve = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("slc stages"),
            size: 8 * 6 * total as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        self.warm_up(mode)?;
        for k in 0..total {
            self.record(mode, Some((&queries, 6 * k)));
            self.gpu.wait()?;
        }
        let stages = if self.filter_on { 3 } else { 2 };
        let mut enc = d.create_command_encoder(&Default::default());
        enc.resolve_query_set(&queries, 0..6 * total, &resolve, 0);
        self.gpu.queue().submit([enc.finish()]);
        let ticks: Vec<u64> = bytemuck::cast_slice(&self.gpu.read_back(&resolve)?).to_vec();
        let period = self.gpu.timestamp_period() as f64 * 1e-9;
        // Median over the timed frames of the span between two of a frame's timestamps.
        let median = |from: usize, to: usize| {
            let mut t: Vec<f64> =
                (2..total as usize).map(|k| ticks[6 * k + to].saturating_sub(ticks[6 * k + from]) as f64 * period).collect();
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        };
        let mut out = [0.0; 3];
        for (s, o) in out.iter_mut().enumerate().take(stages as usize) {
            *o = median(2 * s, 2 * s + 1);
        }
        Ok(Some(StageTimes { bounds: out[0], culling_shading: out[1], filter: out[2], frame: median(0, 5) }))
    }

    /// Seconds per frame for comparing settings: the frame's span on the GPU
    /// ([`StageTimes::frame`]) where the adapter has timestamp queries, else [`Self::time`]'s
    /// wall time. The span leaves out the host's submission and wait, which are the same
    /// for every setting and made isolated frames' times vary by up to 2× between runs.
    pub fn time_frame(&mut self, mode: Mode, frames: usize) -> Result<f64, String> {
        match self.time_stages(mode, frames)? {
            Some(t) => Ok(t.frame),
            None => self.time(mode, frames),
        }
    }

    /// Seconds per frame of frames dispatched back to back as a renderer runs them (the host
    /// waits once, after the last), after [`WARM_UP`]: the frame rate's inverse, where
    /// [`Self::time`] adds to each frame its submission and the host's wait. As many frames
    /// as take about [`WARM_UP`] at the warm-up's pace, at least `frames` and at most
    /// `max_frames`.
    pub fn time_back_to_back(&mut self, mode: Mode, frames: usize, max_frames: usize) -> Result<f64, String> {
        let pace = self.warm_up(mode)?;
        let n = ((WARM_UP.as_secs_f64() / pace) as usize).clamp(frames.max(1), max_frames.max(frames).max(1));
        let s = std::time::Instant::now();
        for _ in 0..n {
            self.dispatch(mode);
        }
        self.gpu.wait()?;
        Ok(s.elapsed().as_secs_f64() / n as f64)
    }

    /// One frame: bounds, culling, shading and the filter; the images and statistics read
    /// back.
    pub fn run(&mut self, mode: Mode) -> Result<Render, String> {
        self.dispatch(mode);
        let img: Vec<[[f32; 4]; 2]> = bytemuck::pod_collect_to_vec(&self.gpu.read_back(&self.image_buf)?);
        let st: Vec<u32> = bytemuck::pod_collect_to_vec(&self.gpu.read_back(&self.stats_buf)?);
        let filtered: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&self.gpu.read_back(&self.filtered_buf)?);
        let rgb = |v: [f32; 4]| Vec3::new(v[0], v[1], v[2]);
        let layers = Layers { irradiance: img.iter().map(|p| rgb(p[0])).collect(), specular: img.iter().map(|p| rgb(p[1])).collect() };
        let image = self
            .surfaces
            .iter()
            .zip(&layers.irradiance)
            .zip(&layers.specular)
            .map(|((t, e), s)| t.map_or(Vec3::ZERO, |t| t.radiance(*e, *s)))
            .collect();
        Ok(Render {
            image,
            filtered: filtered.into_iter().map(rgb).collect(),
            lights_per_pixel: img.iter().map(|p| p[0][3] as u32).collect(),
            false_per_pixel: img.iter().map(|p| p[1][3] as u32).collect(),
            layers,
            kept: st[0] as u64,
            false_positives: st[1] as u64,
        })
    }

    /// Frames dispatched (each waited for) for at least [`WARM_UP`] and two frames, so the
    /// GPU is at its working clock when timing starts; returns their mean seconds per frame.
    fn warm_up(&mut self, mode: Mode) -> Result<f64, String> {
        let start = std::time::Instant::now();
        let mut n = 0;
        while n < 2 || start.elapsed() < WARM_UP {
            self.dispatch(mode);
            self.gpu.wait()?;
            n += 1;
        }
        Ok(start.elapsed().as_secs_f64() / n as f64)
    }

    /// Seconds per frame (bounds + culling + shading + filter), median of `frames` timed frames
    /// after [`WARM_UP`] of warm-up frames, each waited for (wall time around submit + wait).
    pub fn time(&mut self, mode: Mode, frames: usize) -> Result<f64, String> {
        self.warm_up(mode)?;
        let mut t = Vec::with_capacity(frames);
        for _ in 0..frames.max(1) {
            let s = std::time::Instant::now();
            self.dispatch(mode);
            self.gpu.wait()?;
            t.push(s.elapsed().as_secs_f64());
        }
        t.sort_by(f64::total_cmp);
        Ok(t[t.len() / 2])
    }
}

/// How long frames run untimed before a measurement: an idle GPU drops its clock (the H100
/// idles at 345 MHz of 1 980) and two frames of a few milliseconds do not bring it back, so
/// timings taken after CPU work (a readback, a new δ) came out up to 10× slow and unordered.
pub const WARM_UP: std::time::Duration = std::time::Duration::from_millis(300);

/// One frame's GPU times in seconds by timestamp queries (medians over frames): \[TH17\]
/// Table 1's rows that run here, and the frame's span on the GPU.
#[derive(Clone, Copy, Debug)]
pub struct StageTimes {
    /// The bounds (range determination).
    pub bounds: f64,
    /// Culling and shading.
    pub culling_shading: f64,
    /// The filter (0 with the filter off).
    pub filter: f64,
    /// From the bounds' start to the filter's end: the stages and the gaps between them.
    pub frame: f64,
}

/// One stage's dispatches: (pipeline, workgroups).
type Stage<'a> = Vec<(&'a wgpu::ComputePipeline, (u32, u32, u32))>;

/// Renders one frame on the GPU (same result as [`crate::slc::render`] up to f32 rounding).
pub fn render(gpu: &Gpu, g: &GBuffer, vpls: &[Vpl], delta: f32, mode: Mode, interleave: usize) -> Result<Render, String> {
    SlcGpu::new(gpu, g, vpls, delta, interleave)?.run(mode)
}

/// The G-buffer as the kernel reads it, in two planes: per pixel (position, 1), (normal, α),
/// then per pixel (albedo, 0), (F0, 0) — the culling and the filter's taps read only the
/// first.
fn pack_gbuffer(g: &GBuffer) -> Vec<[f32; 4]> {
    let geometry = g.texels.iter().flat_map(|t| match t {
        Some(s) => [s.position.extend(1.0), s.normal.extend(s.alpha)].map(|v: Vec4| v.to_array()),
        None => [[0.0; 4], [0.0, 0.0, 1.0, 1.0]],
    });
    let material = g.texels.iter().flat_map(|t| match t {
        Some(s) => [s.albedo.extend(0.0), s.f0.extend(0.0)].map(|v: Vec4| v.to_array()),
        None => [[0.0; 4]; 2],
    });
    geometry.chain(material).collect()
}

/// The VPLs as the kernel reads them: (position, ξ), (normal, α), (incoming, 1 diffuse / 0
/// GGX), (flux, 0), (diffuse k or F0, 0).
fn pack_vpls(vpls: &[Vpl]) -> Vec<[f32; 4]> {
    vpls.iter()
        .flat_map(|v| {
            [
                v.position.extend(v.xi),
                v.normal.extend(v.alpha),
                v.incoming.extend(v.is_diffuse() as u8 as f32),
                v.flux.extend(0.0),
                if v.is_diffuse() { v.diffuse } else { v.f0 }.extend(0.0),
            ]
            .map(|v: Vec4| v.to_array())
        })
        .collect()
}
