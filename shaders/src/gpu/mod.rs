//! A small wgpu compute harness: runs WGSL statements over many inputs and reads the
//! results back, so that every WGSL function can be compared with its `sbf` twin, and
//! times kernels for the throughput benchmark.
//!
//! Kernel layout: binding 0 `inp: array<f32>` (read), binding 1 `outp: array<f32>`
//! (write), optional binding 2 `lut: texture_2d<f32>` (an rg32float table), binding 3
//! `uni` (a uniform struct), binding 4 `io` (a read-write array of structs) and binding 5
//! `lobe_tab: texture_2d_array<f32>` (a lobe GGX table, see `wgsl/lobe_ggx.wgsl`), bindings 6
//! and 7 `lobe_tex3: texture_3d<f32>` and `lobe_smp: sampler` (the same table laid out for
//! the texture unit's filter, with a linear clamp-to-edge sampler). The body
//! sees the invocation index `i` (< `count`) and the helper `ld3(k)` (three floats of
//! `inp` from k). Dispatch is 2D so counts above 65535 × 64 work.
//!
//! [`lease`](mod@lease) shares one device between tests (with a watchdog); `textures` makes the tables
//! the kernels bind; `adapters` picks the adapters of several-GPU hosts ([`Gpu::hardware`],
//! [`Gpu::at`]); [`spirv`] builds the HLSL/GLSL kernels for Vulkan adapters.

mod adapters;
pub mod lease;
pub mod spirv;
mod textures;

pub use lease::{lease, shared, Lease, Watchdog};

use wgpu::util::DeviceExt;

/// A device and queue, plus what the adapter said about itself.
#[derive(Debug)]
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// "name (backend, driver)" of the adapter that ran.
    pub adapter: String,
    /// The adapter is a software rasteriser on the CPU (lavapipe, llvmpipe, WARP).
    pub software: bool,
    /// (smallest, largest) subgroup size where the adapter has subgroup operations (the
    /// device is created with `Features::SUBGROUP` then); None without them.
    pub subgroup_sizes: Option<(u32, u32)>,
    /// The device has `Features::TIMESTAMP_QUERY` (GPU times of compute passes).
    pub timestamps: bool,
    /// The API the adapter runs through (Vulkan, or GL where no Vulkan driver exists).
    pub backend: wgpu::Backend,
}

const WG: u32 = 64;

/// One kernel launch: `body` runs once per index `i` < `count`.
#[derive(Debug, Default, Clone, Copy)]
pub struct Launch<'a> {
    /// WGSL library the body calls (a composed module).
    pub library: &'a str,
    /// Statements of the kernel body.
    pub body: &'a str,
    /// Binding 0, `inp: array<f32>`.
    pub input: &'a [f32],
    /// Floats of binding 1 (`outp`) per invocation.
    pub out_per_item: usize,
    pub count: usize,
    /// Binding 2, `lut: texture_2d<f32>` (rg32float).
    pub lut: Option<&'a sbf::recon::lut::Lut2>,
    /// Binding 3, `uni: T` (WGSL type name, bytes): a shared `#[repr(C)]` struct.
    pub uniform: Option<(&'a str, &'a [u8])>,
    /// Binding 4, `io: array<T>` read-write (WGSL type name, initial bytes); read back.
    pub io: Option<(&'a str, &'a [u8])>,
    /// Binding 5, `lobe_tab: texture_2d_array<f32>` (rg32float; x = ψ, y = γ, layer =
    /// n·v node × N_√α + √α node).
    pub lobe: Option<&'a sbf::recon::lobe_ggx::Table>,
    /// Bindings 6 and 7, `lobe_tex3: texture_3d<f32>` (rg16float; x = √α node × N_ψ + ψ,
    /// y = γ, z = n·v) and `lobe_smp: sampler` (linear, clamp to edge).
    pub lobe_filtered: Option<&'a sbf::recon::lobe_ggx::Table>,
    /// Bindings 8 and 9, `env_cube: texture_cube<f32>` (rgba16float, the chain's mips) and
    /// `env_smp: sampler` (trilinear, clamp to edge): a prefiltered environment map as an
    /// engine binds it (WGSL kernels only).
    pub cube: Option<&'a sbf::recon::prefiltered::PrefilteredCube>,
    /// Timed dispatches after the checked one.
    pub repeats: usize,
    /// The language the kernel runs in: WGSL (wgpu's own front end), or HLSL/GLSL (the
    /// exported library included into a kernel in that language, compiled by glslang and
    /// run as SPIR-V; see [`spirv`]).
    pub lang: crate::export::Lang,
}

/// What a launch returns.
#[derive(Debug, Clone)]
pub struct Output {
    pub out: Vec<f32>,
    /// Binding 4's bytes after the checked dispatch (empty without `io`).
    pub io: Vec<u8>,
    /// Seconds per timed dispatch (0 without repeats).
    pub seconds_per_dispatch: f64,
}

/// Checks storage buffers (name, bytes) against the adapter's binding limit before anything
/// is uploaded: an over-limit binding otherwise panics inside wgpu. The error names the
/// first buffer over the limit and both sizes.
pub fn check_bindings(buffers: &[(&str, u64)], max_binding: u64) -> Result<(), String> {
    match buffers.iter().find(|(_, bytes)| *bytes > max_binding) {
        Some((what, bytes)) => {
            Err(format!("{what}: {bytes} bytes exceed the adapter's storage-buffer binding limit of {max_binding} bytes"))
        }
        None => Ok(()),
    }
}

/// Checks the workgroup memory `wgsl`'s entry points may use (the sum of its `var<workgroup>`
/// sizes, as naga lays them out) against the adapter's limit before a pipeline is made: over
/// the limit, wgpu's pipeline creation fails with a validation panic instead of an error.
pub fn check_workgroup_memory(what: &str, wgsl: &str, max_bytes: u32) -> Result<(), String> {
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| format!("{what}: {}", e.emit_to_string(wgsl)))?;
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).map_err(|e| format!("{what}: laying out its types: {e}"))?;
    let bytes: u32 =
        module.global_variables.iter().filter(|(_, v)| v.space == naga::AddressSpace::WorkGroup).map(|(_, v)| layouter[v.ty].size).sum();
    if bytes > max_bytes {
        return Err(format!("{what} needs {bytes} bytes of workgroup memory; the adapter allows {max_bytes}"));
    }
    Ok(())
}

/// `SBF_GPU_MAX_STORAGE_BINDING` (bytes): a lower storage-binding limit than the adapter's,
/// to run as a smaller adapter would (many report 128 MiB; lavapipe reports more).
fn storage_binding_cap() -> Result<Option<u64>, String> {
    match std::env::var("SBF_GPU_MAX_STORAGE_BINDING") {
        Err(_) => Ok(None),
        Ok(v) => v.trim().parse::<u64>().map(Some).map_err(|_| format!("SBF_GPU_MAX_STORAGE_BINDING={v}: expected a byte count")),
    }
}

impl Gpu {
    /// The best Vulkan or GL adapter (NVIDIA, or lavapipe / llvmpipe without a GPU).
    pub fn new() -> Result<Gpu, String> {
        let instance = Self::instance();
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(|e| format!("no GPU adapter (Vulkan or GL): {e}"))?;
        Self::on(&adapter)
    }

    /// Vulkan and GL, narrowed by wgpu's own `WGPU_BACKEND` variable where it is set
    /// (`WGPU_BACKEND=gl` runs as a machine without a Vulkan driver; CI sets `vulkan` so
    /// that a missing lavapipe fails instead of falling back to GL).
    fn backends() -> wgpu::Backends {
        (wgpu::Backends::VULKAN | wgpu::Backends::GL).with_env() & (wgpu::Backends::VULKAN | wgpu::Backends::GL)
    }

    fn instance() -> wgpu::Instance {
        wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: Self::backends(),
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        })
    }

    /// A device on `adapter` (with `Features::SUBGROUP` where it has them).
    fn on(adapter: &wgpu::Adapter) -> Result<Gpu, String> {
        let info = adapter.get_info();
        let subgroups = adapter.features().contains(wgpu::Features::SUBGROUP);
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut features = wgpu::Features::empty();
        if subgroups {
            features |= wgpu::Features::SUBGROUP;
        }
        if timestamps {
            features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        // Hardware-filtered rgba32float textures (the baker's renderer, when asked to filter
        // f32 lightmaps in the sampler).
        if adapter.features().contains(wgpu::Features::FLOAT32_FILTERABLE) {
            features |= wgpu::Features::FLOAT32_FILTERABLE;
        }
        // glslang's SPIR-V as is, for the HLSL/GLSL parity runs.
        if adapter.features().contains(wgpu::Features::PASSTHROUGH_SHADERS) {
            features |= wgpu::Features::PASSTHROUGH_SHADERS;
        }
        let mut limits = adapter.limits();
        if let Some(cap) = storage_binding_cap()? {
            limits.max_storage_buffer_binding_size = limits.max_storage_buffer_binding_size.min(cap);
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("sbf shaders harness"),
            required_features: features,
            required_limits: limits,
            ..Default::default()
        }))
        .map_err(|e| format!("requesting a device from {}: {e}", info.name))?;
        let software = info.device_type == wgpu::DeviceType::Cpu;
        let subgroup_sizes = subgroups.then_some((info.subgroup_min_size, info.subgroup_max_size));
        Ok(Gpu {
            device,
            queue,
            adapter: format!("{} ({:?}, {} {})", info.name, info.backend, info.driver, info.driver_info),
            software,
            subgroup_sizes,
            timestamps,
            backend: info.backend,
        })
    }

    /// `n` logical devices on the best adapter (each its own device and queue): the
    /// multi-device code paths on a machine with one adapter (CI's lavapipe).
    pub fn logical(n: usize) -> Result<Vec<Gpu>, String> {
        let instance = Self::instance();
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| format!("no GPU adapter (Vulkan or GL): {e}"))?;
        (0..n).map(|_| Self::on(&adapter)).collect()
    }

    /// Nanoseconds per timestamp tick of this device's queue.
    pub fn timestamp_period(&self) -> f32 {
        self.queue.get_timestamp_period()
    }

    /// The wgpu device (for callers that build their own pipelines, e.g. the baker).
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue of [`Gpu::device`].
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Workgroups along x and y for `count` invocations (2D past 65535 groups).
    fn groups(count: usize) -> (u32, u32) {
        let groups = (count as u32).div_ceil(WG).max(1);
        if groups <= 65535 {
            (groups, 1)
        } else {
            (65535, groups.div_ceil(65535))
        }
    }

    /// The full kernel source for a launch (library, harness bindings, the body as
    /// `fn sbf_body(i: u32)`, and the entry point that calls it).
    pub fn kernel_source(l: &Launch) -> String {
        let (library, body, count) = (l.library, l.body, l.count);
        let row = Self::groups(count).0 * WG;
        let mut bindings = String::new();
        if l.lut.is_some() {
            bindings += "@group(0) @binding(2) var lut: texture_2d<f32>;\n";
        }
        if let Some((ty, _)) = l.uniform {
            bindings += &format!("@group(0) @binding(3) var<uniform> uni: {ty};\n");
        }
        if let Some((ty, _)) = l.io {
            bindings += &format!("@group(0) @binding(4) var<storage, read_write> io: array<{ty}>;\n");
        }
        if l.lobe.is_some() {
            bindings += "@group(0) @binding(5) var lobe_tab: texture_2d_array<f32>;\n";
        }
        if l.lobe_filtered.is_some() {
            bindings += "@group(0) @binding(6) var lobe_tex3: texture_3d<f32>;\n@group(0) @binding(7) var lobe_smp: sampler;\n";
        }
        if l.cube.is_some() {
            bindings += "@group(0) @binding(8) var env_cube: texture_cube<f32>;\n@group(0) @binding(9) var env_smp: sampler;\n";
        }
        format!(
            "{library}\n\n// ---- harness ----\n@group(0) @binding(0) var<storage, read> inp: array<f32>;\n@group(0) @binding(1) var<storage, read_write> outp: array<f32>;\n{bindings}\nfn ld3(k: u32) -> vec3<f32> {{\n    return vec3<f32>(inp[k], inp[k + 1u], inp[k + 2u]);\n}}\n\nfn sbf_body(i: u32) {{\n{body}\n}}\n\n@compute @workgroup_size({WG})\nfn sbf_kernel(@builtin(global_invocation_id) gid: vec3<u32>) {{\n    let i = gid.x + gid.y * {row}u;\n    if (i >= {count}u) {{\n        return;\n    }}\n    sbf_body(i);\n}}\n"
        )
    }

    /// Why this device cannot run glslang's SPIR-V (the HLSL/GLSL parity kernels), or None
    /// when it can: SPIR-V passthrough exists on Vulkan alone — wgpu's GL backend reports
    /// `PASSTHROUGH_SHADERS` too, but what it passes through is GLSL source, not SPIR-V.
    pub fn spirv_unavailable(&self) -> Option<String> {
        if self.backend != wgpu::Backend::Vulkan {
            Some(format!("SPIR-V kernels need a Vulkan adapter; {} runs {:?}", self.adapter, self.backend))
        } else if !self.device.features().contains(wgpu::Features::PASSTHROUGH_SHADERS) {
            Some(format!("{} cannot take SPIR-V as is (no PASSTHROUGH_SHADERS)", self.adapter))
        } else {
            None
        }
    }

    /// The launch's pipeline: WGSL, or HLSL/GLSL compiled by glslang and given to wgpu as
    /// SPIR-V (passthrough, with the harness's bind group layout spelled out).
    fn pipeline(&self, l: &Launch, src: &str) -> Result<wgpu::ComputePipeline, String> {
        let d = &self.device;
        if l.lang == crate::export::Lang::Wgsl {
            let module = d.create_shader_module(wgpu::ShaderModuleDescriptor { label: None, source: wgpu::ShaderSource::Wgsl(src.into()) });
            return Ok(d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: None,
                layout: None,
                module: &module,
                entry_point: Some("sbf_kernel"),
                compilation_options: Default::default(),
                cache: None,
            }));
        }
        if let Some(why) = self.spirv_unavailable() {
            return Err(why);
        }
        let words = spirv::build(l, src, Self::groups(l.count).0 * WG, WG)?;
        let module = Self::passthrough(d, words);
        let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let texture = |binding, view_dimension| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float {
                    filterable: matches!(view_dimension, wgpu::TextureViewDimension::D3 | wgpu::TextureViewDimension::Cube),
                },
                view_dimension,
                multisampled: false,
            },
            count: None,
        };
        let mut entries = vec![storage(0, true), storage(1, false)];
        if l.lut.is_some() {
            entries.push(texture(2, wgpu::TextureViewDimension::D2));
        }
        if l.uniform.is_some() {
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: 3,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
                count: None,
            });
        }
        if l.io.is_some() {
            entries.push(storage(4, false));
        }
        if l.lobe.is_some() {
            entries.push(texture(5, wgpu::TextureViewDimension::D2Array));
        }
        let sampler = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        };
        if l.lobe_filtered.is_some() {
            entries.push(texture(6, wgpu::TextureViewDimension::D3));
            entries.push(sampler(7));
        }
        if l.cube.is_some() {
            entries.push(texture(8, wgpu::TextureViewDimension::Cube));
            entries.push(sampler(9));
        }
        let bgl = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: None, entries: &entries });
        let layout =
            d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: None, bind_group_layouts: &[Some(&bgl)], immediate_size: 0 });
        Ok(d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: None,
            layout: Some(&layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        }))
    }

    /// glslang's SPIR-V given to the driver as is (as an engine's would be): naga's SPIR-V
    /// front end is not in the way (it cannot take an arrayed image's size query as
    /// OpImageQuerySizeLod returns it, 3 components).
    #[allow(unsafe_code)]
    fn passthrough(d: &wgpu::Device, words: Vec<u32>) -> wgpu::ShaderModule {
        let entry = [wgpu::PassthroughShaderEntryPoint { name: "main".into(), workgroup_size: (WG, 1, 1) }];
        // SAFETY: glslang compiled and validated the module for Vulkan 1.1 (it refuses
        // invalid input); its bindings are exactly the layout the caller spells out (set 0,
        // the WGSL kernel's binding numbers and kinds), and its one entry point is `main`.
        unsafe {
            d.create_shader_module_passthrough(wgpu::ShaderModuleDescriptorPassthrough {
                label: Some("sbf parity (SPIR-V from glslang)"),
                entry_points: entry[..].into(),
                spirv: Some(words.into()),
                ..Default::default()
            })
        }
    }

    /// Runs `body` for `count` invocations; returns `outp` (`count × out_per_item` floats)
    /// and the GPU wall time of `repeats` dispatches (seconds per dispatch; 0 if repeats = 0).
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &self,
        library: &str,
        body: &str,
        input: &[f32],
        out_per_item: usize,
        count: usize,
        lut: Option<&sbf::recon::lut::Lut2>,
        repeats: usize,
    ) -> Result<(Vec<f32>, f64), String> {
        let o = self.launch(&Launch { library, body, input, out_per_item, count, lut, repeats, ..Default::default() })?;
        Ok((o.out, o.seconds_per_dispatch))
    }

    /// A buffer of `size` bytes the GPU copies into and the CPU maps.
    fn read_back_buffer(&self, size: u64) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// The bytes of a [`Self::read_back_buffer`] once the queue is done (`what` names it in errors).
    fn map_read(&self, b: &wgpu::Buffer, what: &str) -> Result<Vec<u8>, String> {
        let slice = b.slice(..);
        let w = what.to_string();
        slice.map_async(wgpu::MapMode::Read, move |r| r.unwrap_or_else(|e| panic!("mapping the {w} buffer: {e}")));
        self.wait()?;
        let bytes = slice.get_mapped_range().map_err(|e| format!("{what}: {e}"))?.to_vec();
        b.unmap();
        Ok(bytes)
    }

    /// Runs a launch (see [`Launch`]).
    pub fn launch(&self, l: &Launch) -> Result<Output, String> {
        let (input, out_per_item, count, lut, repeats) = (l.input, l.out_per_item, l.count, l.lut, l.repeats);
        // Storage buffers beyond the device's binding limit: an error here, not a wgpu
        // validation panic at bind-group creation.
        let limit = self.device.limits().max_storage_buffer_binding_size as usize;
        for (what, bytes) in [("input", input.len() * 4), ("output", count * out_per_item * 4), ("state", l.io.map_or(0, |(_, b)| b.len()))]
        {
            if bytes > limit {
                return Err(format!("the {what} buffer ({bytes} bytes) exceeds the device's storage-binding limit ({limit} bytes)"));
            }
        }
        let src = Self::kernel_source(l);
        crate::export::validate(&src).map_err(|e| format!("harness kernel: {e}"))?;
        let d = &self.device;
        let pipeline = self.pipeline(l, &src)?;
        let input = if input.is_empty() { &[0.0f32][..] } else { input };
        let inb = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::cast_slice(input),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let out_bytes = (count * out_per_item).max(1) as u64 * 4;
        let outb = d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: out_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readb = self.read_back_buffer(out_bytes);
        let tex_view = lut.map(|l| self.lut_texture(l).create_view(&Default::default()));
        let lobe_view = l.lobe.map(|t| {
            self.lobe_texture(t)
                .create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() })
        });
        let filtered =
            l.lobe_filtered.map(|t| (self.lobe_texture_filtered(t).create_view(&Default::default()), self.linear_clamp_sampler()));
        let cube = l.cube.map(|c| {
            let view = self
                .cube_texture(c)
                .create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::Cube), ..Default::default() });
            (view, self.trilinear_sampler())
        });
        let unib = l.uniform.map(|(_, bytes)| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("uni"),
                contents: bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            })
        });
        let io_bytes = l.io.map(|(_, b)| b.len() as u64).unwrap_or(0);
        let iob = l.io.map(|(_, bytes)| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("io"),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
        });
        let io_read = iob.as_ref().map(|_| self.read_back_buffer(io_bytes));
        let mut entries = vec![
            wgpu::BindGroupEntry { binding: 0, resource: inb.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: outb.as_entire_binding() },
        ];
        if let Some(v) = &tex_view {
            entries.push(wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(v) });
        }
        if let Some(b) = &unib {
            entries.push(wgpu::BindGroupEntry { binding: 3, resource: b.as_entire_binding() });
        }
        if let Some(b) = &iob {
            entries.push(wgpu::BindGroupEntry { binding: 4, resource: b.as_entire_binding() });
        }
        if let Some(v) = &lobe_view {
            entries.push(wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::TextureView(v) });
        }
        if let Some((v, s)) = &filtered {
            entries.push(wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::TextureView(v) });
            entries.push(wgpu::BindGroupEntry { binding: 7, resource: wgpu::BindingResource::Sampler(s) });
        }
        if let Some((v, s)) = &cube {
            entries.push(wgpu::BindGroupEntry { binding: 8, resource: wgpu::BindingResource::TextureView(v) });
            entries.push(wgpu::BindGroupEntry { binding: 9, resource: wgpu::BindingResource::Sampler(s) });
        }
        let bg =
            d.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &pipeline.get_bind_group_layout(0), entries: &entries });
        let (gx, gy) = Self::groups(count);
        let dispatch = |n: usize| {
            let mut enc = d.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bg, &[]);
                for _ in 0..n {
                    pass.dispatch_workgroups(gx, gy, 1);
                }
            }
            enc
        };
        // Warm-up and the checked run.
        let mut enc = dispatch(1);
        enc.copy_buffer_to_buffer(&outb, 0, &readb, 0, out_bytes);
        if let (Some(src), Some(dst)) = (&iob, &io_read) {
            enc.copy_buffer_to_buffer(src, 0, dst, 0, io_bytes);
        }
        self.queue.submit([enc.finish()]);
        self.wait()?;
        let mut per_dispatch = 0.0;
        if repeats > 0 {
            let t = std::time::Instant::now();
            self.queue.submit([dispatch(repeats).finish()]);
            self.wait()?;
            per_dispatch = t.elapsed().as_secs_f64() / repeats as f64;
        }
        let out: Vec<f32> = bytemuck::cast_slice(&self.map_read(&readb, "read-back")?).to_vec();
        let io = match &io_read {
            Some(b) => self.map_read(b, "io read-back")?,
            None => Vec::new(),
        };
        Ok(Output { out: out[..count * out_per_item].to_vec(), io, seconds_per_dispatch: per_dispatch })
    }

    /// Copies a buffer (with `COPY_SRC` usage) back to the host.
    pub fn read_back(&self, src: &wgpu::Buffer) -> Result<Vec<u8>, String> {
        let size = src.size();
        let dst = self.read_back_buffer(size);
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(src, 0, &dst, 0, size);
        self.queue.submit([enc.finish()]);
        self.map_read(&dst, "read-back")
    }

    /// Blocks until the queue's submitted work is done.
    pub fn wait(&self) -> Result<(), String> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map(|_| ()).map_err(|e| format!("device poll: {e}"))
    }
}

/// The filtered layout's f16 texels (one layout for the GPU harness and the KTX2 files).
pub use crate::tables::lobe_filtered_texels;
