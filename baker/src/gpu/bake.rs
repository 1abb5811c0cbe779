//! The wgpu path: the same estimator as [`crate::estimator::trace`] in WGSL (`wgsl/path.wgsl`
//! and the modules it imports), traversing the CPU-built BVH nodes, one path per item and
//! pass, each sample fed to the `shaders` crate's `progressive_update` for every
//! configured basis.
//!
//! The shaders are composed per bake from modules ([`mod@super::kernel`]): only the entry
//! shaders the bake runs, with only what its configuration needs (the configured bases,
//! the GGX layer when a material is glossy, guiding, batches, filtering). What was left
//! out is reported.
//!
//! Random numbers: the same sequences as the CPU's ([`crate::sampling::sequence`], `wgsl/sequence.wgsl`,
//! bit for bit); the estimator runs in f32 (the CPU's partly in f64), so CPU and GPU bakes
//! agree statistically, not bit for bit (the CPU↔GPU test checks means within 4σ).

use super::buffers::{check_sizes, upload, BakeBuffers};
use super::guide::{grid, GuideGpu};
use super::kernel::{GuideBuild, Kernel};
use super::params::{aux_data, trace_params, TraceParams};
use crate::accumulate::{BakeConfig, Targets};
use crate::estimator::trace::Tracer;
use shaders::gpu::Gpu;
use shaders::progressive::EncoderState;

const WG: u32 = 64;

/// A bake on the GPU.
#[derive(Debug)]
pub struct GpuBake<'g> {
    pub(crate) gpu: &'g Gpu,
    /// The megakernel and its bind group (None: the wavefront pipeline runs the passes).
    pub(crate) mega: Option<(wgpu::ComputePipeline, wgpu::BindGroup)>,
    /// The wavefront passes ([`crate::gpu::wavefront`]; None: the megakernel runs them).
    pub(crate) wavefront: Option<crate::gpu::wavefront::Wavefront>,
    pub(crate) params_buf: wgpu::Buffer,
    pub(crate) moments_buf: wgpu::Buffer,
    pub(crate) states_buf: wgpu::Buffer,
    pub(crate) counters_buf: wgpu::Buffer,
    pub params: TraceParams,
    pub(crate) config: BakeConfig,
    pub(crate) sphere: bool,
    pub(crate) items: usize,
    pub passes: u64,
    pub kernel: Kernel,
    pub(crate) guide: Option<GuideGpu>,
    pub(crate) batching: Batching,
    /// Items this device dispatches (all by default; its blocks when the bake is one
    /// device of a [`crate::gpu::multi::MultiGpuBake`]: see [`TraceParams::part_block`]).
    pub(crate) share: usize,
    /// Adaptive sampling's selection (None: uniform passes).
    pub(crate) adapt: Option<crate::gpu::adaptive::AdaptGpu>,
    /// GPU seconds and count per wavefront pass while a profile is taken.
    pub(crate) profile: Option<Vec<(&'static str, f64, u64)>>,
    /// Filtered accumulation's records, targets and gather ([`crate::gpu::filter`]).
    pub(crate) filter: Option<crate::gpu::filter::FilterGpu>,
}

/// Items per dispatch ([Roughton19 §3.4.1], frame-time load balancing): a pass is split into
/// dispatches of `chunk` items, and `chunk` follows N ← N·T_target/T (eq. 3.1–3.2) from
/// the measured time per dispatch, so every dispatch stays near the target whatever the
/// atlas size — far below driver watchdogs. Measured (one wait) at passes 0, 1, 2, 4, …,
/// then every 64 passes; between them the passes are queued back to back.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Batching {
    /// Target seconds per dispatch; None: `chunk` fixed.
    target: Option<f64>,
    chunk: usize,
    /// Passes per dispatch once a whole pass is one dispatch and takes less than the
    /// target (1 with ray guiding, whose learning runs between passes): every dispatch
    /// ends in a tail where the last, longest paths leave the GPU idle — ~0.5 ms per
    /// dispatch on an H200 — which several passes per dispatch share.
    passes: u64,
    /// Dispatches so far (the measurement schedule).
    dispatches: u64,
    /// Submissions of bake work so far (one per chunk of items and dispatch).
    submissions: u64,
    /// The most jobs × passes of one dispatch (the wavefront's path pool; unbounded for
    /// the megakernel).
    max_slots: usize,
}

/// The most adaptive batches recorded into one submission.
const MAX_BATCHES_PER_SUBMISSION: u64 = 16;

/// The most passes one dispatch runs (also the progress granularity of `baker::run`).
pub const MAX_PASSES_PER_DISPATCH: u64 = 8;

/// Items of the first dispatches, before any measurement (2¹⁸: a few ms on a large GPU,
/// well under a second on a software rasteriser's worst scenes).
const INITIAL_CHUNK: usize = 1 << 18;
/// The default target time per dispatch (a 60 Hz frame).
pub const BATCH_TARGET_SECONDS: f64 = 0.016;

/// Adds the wavefront passes timed in the last submission to `totals` (when a profile is
/// being taken).
fn collect_profile(
    gpu: &Gpu,
    wavefront: &Option<crate::gpu::wavefront::Wavefront>,
    totals: &mut Option<Vec<(&'static str, f64, u64)>>,
) -> Result<(), String> {
    if let (Some(w), Some(totals)) = (wavefront, totals) {
        for t in w.take_profile(gpu)? {
            match totals.iter_mut().find(|(p, _, _)| *p == t.pass) {
                Some(e) => {
                    e.1 += t.seconds;
                    e.2 += 1;
                }
                None => totals.push((t.pass, t.seconds, 1)),
            }
        }
    }
    Ok(())
}

/// Slots of the wavefront's path pool for a bake of `items` items on a device whose
/// storage bindings hold `max_binding` bytes: a uniform wave of up to
/// [`MAX_PASSES_PER_DISPATCH`] passes of every item (at most
/// [`crate::gpu::wavefront::MAX_UNIFORM_SLOTS`] slots, and what one binding of 64-byte path
/// states holds), or the most samples one batch can take — adaptive: λ_k ≤ L per texel and
/// Σλ_k ≤ f·N, rounded up per texel, so at most N·min(⌈L⌉, ⌈f⌉ + 1); camera: at most L per
/// texel and one per pixel.
pub fn wave_capacity(config: &BakeConfig, items: usize, max_binding: u64) -> usize {
    // Several passes per wave: the per-bounce passes (compaction, indirect arguments,
    // barriers) cost about the same for few paths as for many.
    let most = crate::gpu::wavefront::MAX_UNIFORM_SLOTS.min((max_binding / 64) as usize);
    let uniform = (items * MAX_PASSES_PER_DISPATCH as usize).min(most).max(items.min(most));
    let batch = match (&config.adaptive, &config.camera) {
        (Some(a), _) => items * (a.max_per_batch as usize).min(a.batch_fraction.ceil() as usize + 1),
        (None, Some(c)) => (items * c.max_per_batch as usize).min((c.camera.width as usize * c.camera.height as usize).max(items)),
        (None, None) => 0,
    };
    uniform.max(batch).max(64)
}

impl<'g> GpuBake<'g> {
    /// Uploads the scene, BVH and targets and compiles the kernel.
    pub fn new(gpu: &'g Gpu, tracer: &Tracer, targets: &Targets, config: &BakeConfig) -> Result<Self, String> {
        if targets.items.is_empty() {
            return Err("nothing to bake: no valid texels or probes".into());
        }
        if targets.sphere && config.bases.iter().any(|b| !b.is_sphere()) {
            return Err("probes need sphere bases (sh1, sh2, ad12)".into());
        }
        config.check(targets)?;
        let textured = tracer.scene.has_textures();
        let kernel = crate::gpu::kernel::kernel_with(config, targets.sphere, tracer.scene.has_glossy(), textured)?;
        let maps = textured.then(|| crate::gpu::maps::maps_data(tracer));
        let d = gpu.device();
        let wavefront = config.pipeline == crate::accumulate::Pipeline::Wavefront;
        let (aux, at) = aux_data(tracer);
        let items = targets.items.len();
        let states_len = (config.bases.len() * items).max(1) * std::mem::size_of::<EncoderState>();
        let guiding = config.guiding.filter(|_| !targets.sphere && targets.cluster_count > 0);
        let clusters = if guiding.is_some() { targets.cluster_count } else { 0 };
        let limit = d.limits().max_storage_buffer_binding_size;
        let pool = if wavefront { wave_capacity(config, items, limit) } else { 0 };
        check_sizes(tracer, targets, aux.len(), states_len, clusters, pool, limit)?;
        crate::gpu::check_bindings(&[("material maps", maps.as_ref().map_or(0, |m| 4 * m.len() as u64))], limit)?;
        let mut params = trace_params(tracer, targets, config, &at);
        params.point_split = crate::gpu::buffers::point_split(targets.points.len(), limit);
        let buffers = upload(d, tracer, targets, &params, &aux, states_len, maps.as_deref());
        let guide = guiding.map(|g| GuideGpu::for_bake(d, targets, g, gpu.subgroup_sizes)).transpose()?;
        let adapt = batch_selector(d, tracer, targets, config, &buffers.moments)?;
        let filter = filtered_accumulation(d, &kernel, targets, config, &buffers.moments, adapt.as_ref())?;
        let entries = bind_entries(&buffers, !config.bases.is_empty(), guide.as_ref(), adapt.as_ref(), filter.as_ref());
        let (mega, wavefront) = if wavefront {
            let bound: Vec<(u32, &wgpu::Buffer)> = entries
                .iter()
                .map(|e| match &e.resource {
                    wgpu::BindingResource::Buffer(b) => (e.binding, b.buffer),
                    _ => unreachable!("the bake binds whole buffers"),
                })
                .collect();
            (None, Some(crate::gpu::wavefront::Wavefront::new(d, &kernel, &bound, pool, items)?))
        } else {
            let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("megakernel.wgsl"),
                source: wgpu::ShaderSource::Wgsl(kernel.shader("megakernel.wgsl")?.into()),
            });
            (Some(megakernel(d, &module, &entries)), None)
        };
        let max_slots = wavefront.as_ref().map_or(usize::MAX, |w| w.capacity);
        let BakeBuffers { params: params_buf, moments: moments_buf, states: states_buf, counters: counters_buf, .. } = buffers;
        Ok(GpuBake {
            gpu,
            mega,
            wavefront,
            params_buf,
            moments_buf,
            states_buf,
            counters_buf,
            params,
            config: config.clone(),
            sphere: targets.sphere,
            items,
            passes: 0,
            kernel,
            guide,
            batching: Batching {
                target: Some(BATCH_TARGET_SECONDS),
                chunk: items.min(INITIAL_CHUNK).min(max_slots),
                passes: 1,
                dispatches: 0,
                submissions: 0,
                max_slots,
            },
            share: items,
            adapt,
            profile: None,
            filter,
        })
    }

    /// The wave's pass graph (the wavefront pipeline; None on the megakernel).
    pub fn pass_graph(&self) -> Option<&crate::gpu::wavefront::graph::PassGraph> {
        self.wavefront.as_ref().map(|w| &w.graph)
    }

    /// Sets the target time per dispatch (None: keep the items per dispatch fixed).
    pub fn set_batch_target(&mut self, seconds: Option<f64>) {
        self.batching.target = seconds.filter(|s| s.is_finite() && *s > 0.0);
    }

    /// Fixes the items per dispatch (at least 1; adaptation off).
    pub fn set_chunk(&mut self, items: usize) {
        let b = self.batching;
        self.batching =
            Batching { target: None, chunk: items.clamp(1, self.range_len()).min(b.max_slots), passes: 1, dispatches: b.dispatches, ..b };
    }

    /// Makes this bake device `index` of `count`: it dispatches only the items of blocks
    /// b ≡ index (mod count), blocks of `block` items (the others keep their state). Ray
    /// guiding learns from every texel of a cluster in each pass, so a guided bake cannot
    /// be partitioned.
    pub fn set_partition(&mut self, index: usize, count: usize, block: usize) -> Result<(), String> {
        if count == 0 || index >= count || block == 0 || block > u32::MAX as usize {
            return Err(format!("partition {index} of {count} with blocks of {block} items is invalid"));
        }
        if self.guide.is_some() && count > 1 {
            return Err("a guided bake cannot be split across devices (guiding learns from whole clusters every pass)".into());
        }
        if self.filter.is_some() && count > 1 {
            return Err("a filtered bake cannot be split across devices (each texel gathers its neighbours' samples every pass)".into());
        }
        if self.adapt.is_some() && count > 1 {
            return Err("an adaptive or camera-based bake cannot be split across devices (each batch draws from the whole atlas)".into());
        }
        (self.params.part_block, self.params.part_count, self.params.part_index) = (block as u32, count as u32, index as u32);
        self.share = (0..self.items.div_ceil(block)).filter(|b| b % count == index).map(|b| block.min(self.items - b * block)).sum();
        self.batching.chunk = self.batching.chunk.clamp(1, self.share.max(1));
        Ok(())
    }

    /// Whether this bake dispatches `item` (see [`GpuBake::set_partition`]).
    pub fn owns(&self, item: usize) -> bool {
        let p = &self.params;
        (item / p.part_block as usize) % p.part_count as usize == p.part_index as usize
    }

    /// Items this bake dispatches per pass.
    pub fn share(&self) -> usize {
        self.share
    }

    /// Items in the bake (all targets, whatever its partition).
    pub fn item_count(&self) -> usize {
        self.items
    }

    fn range_len(&self) -> usize {
        self.share.max(1)
    }

    /// The current items per dispatch.
    pub fn chunk(&self) -> usize {
        self.batching.chunk
    }

    /// The current passes per dispatch.
    pub fn passes_per_dispatch(&self) -> u64 {
        self.batching.passes
    }

    /// Submissions of bake work so far: one per chunk of items and dispatch, so more than
    /// the dispatches when a pass is split ([`GpuBake::set_chunk`]).
    pub fn submissions(&self) -> u64 {
        self.batching.submissions
    }

    /// One pass, as dispatches of at most `chunk` items (one submission each); with ray
    /// guiding, the gather of its learning records and, once learning ends, the build of
    /// the distributions follow the last one. Per-item results do not depend on the split.
    fn dispatch(&mut self) -> Result<(), String> {
        let d = self.gpu.device();
        self.params.guide_phase = match &self.guide {
            Some(g) if self.passes < g.learn_passes => 1,
            Some(_) => 2,
            None => 0,
        };
        if let Some(g) = &self.guide {
            let (k, start) = crate::sampling::guiding::stage(self.passes, g.learn_passes);
            (self.params.guide_stage, self.params.guide_start) = (k, start as u32);
        }
        let chunk = self.batching.chunk.max(1);
        let (mut start, last) = (0, self.share);
        let mut enc = loop {
            let end = (start + chunk).min(last);
            (self.params.item_offset, self.params.item_end) = (start as u32, end as u32);
            self.gpu.queue().write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&self.params));
            let mut enc = d.create_command_encoder(&Default::default());
            let groups = grid((end - start) as u32, WG);
            self.record_jobs(&mut enc, crate::gpu::wavefront::JobGrid::Direct(groups), (end - start) * self.params.pass_count as usize);
            if end == last {
                break enc;
            }
            self.gpu.queue().submit([enc.finish()]);
            self.batching.submissions += 1;
            self.collect_profile()?;
            start = end;
        };
        if let Some(f) = self.filter.as_mut().filter(|_| self.params.primary_only == 0) {
            // (Primary-only timing passes write no records.)
            f.record(self.gpu.queue(), &mut enc, self.params.pass_count, false);
        }
        if let Some(g) = &mut self.guide {
            // Every pass learns; at the start of each stage the distributions are rebuilt
            // from all sums (baker::guiding::stage).
            g.record(&mut enc, false);
            let next = self.passes + 1;
            if next >= g.learn_passes && crate::sampling::guiding::stage(next, g.learn_passes).1 == next {
                g.record_build(&mut enc);
                g.built = true;
            }
        }
        self.gpu.queue().submit([enc.finish()]);
        self.batching.submissions += 1;
        self.collect_profile()
    }

    /// Adds the wavefront passes timed in the last submission to the profile (when one is
    /// being taken: [`GpuBake::profile_passes`]).
    fn collect_profile(&mut self) -> Result<(), String> {
        collect_profile(self.gpu, &self.wavefront, &mut self.profile)
    }

    /// Records the bake's passes over `jobs`: the megakernel, or a wavefront wave.
    /// `slots`: the most samples the jobs take (the wavefront's wave size).
    fn record_jobs(&self, enc: &mut wgpu::CommandEncoder, jobs: crate::gpu::wavefront::JobGrid, slots: usize) {
        if let Some(w) = &self.wavefront {
            w.record(enc, jobs, slots, self.params.max_bounces, self.params.primary_only == 1);
        } else if let Some((pipeline, group)) = &self.mega {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            match jobs {
                crate::gpu::wavefront::JobGrid::Direct((x, y)) => pass.dispatch_workgroups(x, y, 1),
                crate::gpu::wavefront::JobGrid::Indirect(args) => pass.dispatch_workgroups_indirect(args, 0),
            }
        }
    }

    /// `k` adaptive batches in one submission: each the selection, then the bake kernel
    /// over the listed items by an indirect dispatch.
    fn batches(&mut self, k: u64) -> Result<(), String> {
        let Some(a) = self.adapt.as_ref() else { return Ok(()) };
        let (d, q) = (self.gpu.device(), self.gpu.queue());
        self.params.batch_mode = 1;
        self.params.pass_count = 1;
        q.write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&self.params));
        a.set_batch(q, self.passes);
        // Camera batches write their jitter from here: one batch per submission.
        let per = a.per_submission();
        let mut b = 0;
        while b < k {
            let mut enc = d.create_command_encoder(&Default::default());
            for j in b..(b + per).min(k) {
                a.record_select(q, &mut enc, self.passes + j);
                self.record_jobs(&mut enc, crate::gpu::wavefront::JobGrid::Indirect(&a.args), usize::MAX);
                if let Some(f) = self.filter.as_mut().filter(|_| self.params.primary_only == 0) {
                    f.record(q, &mut enc, 1, true);
                }
            }
            q.submit([enc.finish()]);
            b += per;
            collect_profile(self.gpu, &self.wavefront, &mut self.profile)?;
        }
        self.params.batch_mode = 0;
        Ok(())
    }

    /// Runs `n` passes — in an adaptive bake after its pilot, batches — (waits for them).
    pub fn run(&mut self, n: u64) -> Result<(), String> {
        if self.share == 0 {
            // A device of a partition that received no block.
            self.passes += n;
            return Ok(());
        }
        let mut done = 0;
        while done < n {
            if self.adapt.as_ref().is_some_and(|a| self.passes >= a.pilot_passes) {
                let k = (n - done).min(MAX_BATCHES_PER_SUBMISSION);
                self.batches(k)?;
                self.passes += k;
                done += k;
                continue;
            }
            let mut k = self.batching.passes.clamp(1, n - done);
            if let Some(a) = &self.adapt {
                // Uniform passes stop at the end of the pilot.
                k = k.min(a.pilot_passes - self.passes);
            }
            // The wavefront's pool holds chunk × passes paths.
            k = k.min((self.batching.max_slots / self.batching.chunk.max(1)).max(1) as u64);
            if let Some(f) = &self.filter {
                // The records hold that many passes of every item.
                k = k.min(f.max_passes);
            }
            self.params.pass_index = self.passes as u32;
            self.params.pass_count = k as u32;
            let d = self.batching.dispatches;
            let measure = self.batching.target.is_some() && (d.is_power_of_two() || d == 0 || d % 64 == 0);
            if measure {
                // Time this dispatch alone: wait for the queue first.
                self.gpu.wait()?;
            }
            let t = std::time::Instant::now();
            self.dispatch()?;
            self.passes += k;
            done += k;
            self.batching.dispatches += 1;
            if let (true, Some(target)) = (measure, self.batching.target) {
                self.gpu.wait()?;
                let chunks = self.range_len().div_ceil(self.batching.chunk.max(1));
                // Seconds per dispatch of one pass over `chunk` items.
                let per = t.elapsed().as_secs_f64() / (chunks as u64 * k) as f64;
                // Eq. 3.1–3.2: N ← N·T_target/T, at most doubling or halving per step: first
                // the passes per dispatch (whole passes only, no guiding), then the items.
                let scale = (target / (per * self.batching.passes as f64).max(1e-9)).clamp(0.5, 2.0);
                let whole = self.batching.chunk >= self.range_len();
                if whole && self.guide.is_none() && (scale > 1.0 || self.batching.passes > 1) {
                    self.batching.passes = ((self.batching.passes as f64 * scale) as u64).clamp(1, MAX_PASSES_PER_DISPATCH);
                } else {
                    let scale = (target / per.max(1e-9)).clamp(0.5, 2.0);
                    let next = ((self.batching.chunk as f64 * scale) as usize).div_ceil(WG as usize) * WG as usize;
                    self.batching.chunk = next.max(WG as usize).min(self.range_len()).min(self.batching.max_slots).max(1);
                }
            }
        }
        self.gpu.wait()?;
        if let Some(w) = &self.wavefront {
            let c: [u32; 4] = bytemuck::pod_read_unaligned(&self.gpu.read_back(w.overflow_counter())?);
            if c[2] > 0 {
                return Err(format!(
                    "wavefront: {} samples found the path pool of {} slots full (a bug: the pool is sized for every batch)",
                    c[2], w.capacity
                ));
            }
        }
        Ok(())
    }

    /// How this bake builds ray guiding's distributions (None: no guiding).
    pub fn guide_build_path(&self) -> Option<GuideBuild> {
        self.guide.as_ref().map(|g| g.path)
    }

    /// Ray guiding's distributions as the GPU built them (None: no guiding, or not built
    /// yet) — for comparison with [`crate::sampling::guiding::build`].
    pub fn guide_distributions(&self) -> Result<Option<Vec<f32>>, String> {
        match &self.guide {
            Some(g) if g.built => Ok(Some(bytemuck::pod_collect_to_vec(&self.gpu.read_back(&g.dist_buf)?))),
            _ => Ok(None),
        }
    }
}

/// The GPU selector of adaptive or camera-based batches, if the bake has one.
fn batch_selector(
    d: &wgpu::Device,
    tracer: &Tracer,
    targets: &Targets,
    config: &BakeConfig,
    moments: &wgpu::Buffer,
) -> Result<Option<crate::gpu::adaptive::AdaptGpu>, String> {
    Ok(match config.adaptive {
        Some(a) => Some(crate::gpu::adaptive::AdaptGpu::new(d, targets, crate::gpu::adaptive::BatchSource::Variance(a), config, moments)?),
        None => match &config.camera {
            Some(c) => Some(crate::gpu::adaptive::AdaptGpu::new(
                d,
                targets,
                crate::gpu::adaptive::BatchSource::Camera(c, tracer.bvh),
                config,
                moments,
            )?),
            None => None,
        },
    })
}

/// The filtered accumulation's gather on the GPU, if the bake filters (lightmaps only).
fn filtered_accumulation(
    d: &wgpu::Device,
    kernel: &Kernel,
    targets: &Targets,
    config: &BakeConfig,
    moments: &wgpu::Buffer,
    adapt: Option<&crate::gpu::adaptive::AdaptGpu>,
) -> Result<Option<crate::gpu::filter::FilterGpu>, String> {
    Ok(match config.filter.filter(|_| !targets.sphere) {
        Some(_) => {
            let limit = d.limits().max_storage_buffer_binding_size;
            let mut bake: Vec<(u32, &wgpu::Buffer)> = vec![(6, moments)];
            if let Some(a) = adapt {
                bake.push((13, &a.samples));
            }
            let source = kernel.shader("filter_gather.wgsl")?;
            Some(crate::gpu::filter::FilterGpu::new(d, source, targets, config, MAX_PASSES_PER_DISPATCH, limit, &bake)?)
        }
        None => None,
    })
}

/// The bake kernel's bindings: the buffers every bake has (the encoder states where it
/// encodes into any basis) and those of the strategies it runs.
fn bind_entries<'a>(
    b: &'a BakeBuffers,
    states: bool,
    guide: Option<&'a GuideGpu>,
    adapt: Option<&'a crate::gpu::adaptive::AdaptGpu>,
    filter: Option<&'a crate::gpu::filter::FilterGpu>,
) -> Vec<wgpu::BindGroupEntry<'a>> {
    let entry = |binding: u32, buffer: &'a wgpu::Buffer| wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() };
    let mut entries = vec![
        entry(0, &b.params),
        entry(1, &b.nodes),
        entry(2, &b.tris),
        entry(3, &b.aux),
        entry(4, &b.items),
        entry(5, &b.points),
        entry(19, &b.points_hi),
        entry(6, &b.moments),
        entry(8, &b.counters),
    ];
    if states {
        entries.push(entry(7, &b.states));
    }
    if let Some(m) = &b.maps {
        entries.push(entry(20, m));
    }
    if let Some(g) = guide {
        entries.extend([entry(9, &g.rec_buf), entry(10, &g.dist_buf)]);
    }
    if let Some(f) = filter {
        entries.extend([entry(14, &f.records), entry(18, &f.params_buf)]);
    }
    if let Some(a) = adapt {
        entries.extend([entry(11, &a.selected), entry(12, &a.count), entry(13, &a.samples)]);
    }
    entries
}

/// The megakernel pipeline (`bake_pass`, a thread per job through whole paths) and its
/// bind group.
fn megakernel(d: &wgpu::Device, module: &wgpu::ShaderModule, entries: &[wgpu::BindGroupEntry]) -> (wgpu::ComputePipeline, wgpu::BindGroup) {
    let p = super::compute_pipeline(d, module, "bake_pass");
    let group = d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("bake"), layout: &p.get_bind_group_layout(0), entries });
    (p, group)
}

impl crate::accumulate::Progressive for GpuBake<'_> {
    fn run(&mut self, n: u64) -> Result<(), String> {
        GpuBake::run(self, n)
    }
    fn state(&self) -> Result<crate::accumulate::BakeState, String> {
        GpuBake::state(self)
    }
    fn passes(&self) -> u64 {
        self.passes
    }
}
