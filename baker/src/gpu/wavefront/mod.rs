//! # The wavefront pipeline ([Roughton19 §3.1, §5.1])
//!
//! A pass split breadth first: instead of one thread taking its texel through a whole
//! path (the megakernel, `megakernel.wgsl`'s `bake_pass`), every stage of every path of a
//! **wave** — the jobs of one dispatch range, each job an item and its samples — runs as
//! its own kernel over the paths still alive, so that short and long paths no longer share
//! a thread's lifetime. The pass graph of one wave, recorded by [`Wavefront::record`]:
//!
//! ```text
//!  generate ─► wave_start ─► ┌ intersect ─► shade ─► compact ─► wave_args ┐ ─► accumulate
//!                            └──────────── per bounce, 0 ..= max_bounces ──┘
//! ```
//!
//! | pass | WGSL | what it does | CPU twin |
//! |---|---|---|---|
//! | generate | `generate.wgsl` | per job: its samples take consecutive slots of the path pool (workgroup scan, one atomic per workgroup), each slot the first segment of its point sample's path | `Tracer::sample_point` |
//! | wave_start, wave_args | `wave.wgsl` | the queue's length and the indirect dispatch arguments (2D) | — |
//! | intersect | `intersect.wgsl` | per active path: closest hit of its segment (the BVH traversal of `traverse.wgsl`) | `Bvh::intersect` |
//! | shade | `shade.wgsl` | per active path: `path_step` — environment or emission (MIS), next-event estimation with its shadow rays, the BSDF sample, Russian roulette; a flag per queue position says whether the path goes on | `Tracer::path` |
//! | compact | [`crate::gpu::prims`] | the queue's surviving paths, order kept: flags → exclusive prefix sum (multi-level, subgroup or workgroup block scan) → scatter into the other queue of the ping-pong pair | [`crate::gpu::prims::compact_cpu`] |
//! | accumulate | `accumulate.wgsl` | per job, its samples in order (the progressive encoder's ordering, §7.3.1): `finish_item` — the light samples at the baked point, moments, encoders, guiding records | `Targets::item_sample` |
//!
//! Generate, shade and accumulate call the very functions the megakernel calls
//! (`first_vertex`, `path_step`, `finish_item`), and every random number comes from
//! (seed, item, sample, vertex, use) ([`crate::sampling::sequence`]), so both pipelines run the same
//! estimator on the same numbers; only the arithmetic's schedule differs. The passes after
//! generate are dispatched indirectly from the queue's length, so the host never waits
//! inside a wave; a wave's jobs are those the megakernel would have dispatched (a pass
//! range of [`crate::gpu::GpuBake`]'s frame-time batching, or an adaptive or camera batch).
//!
//! Bindings: group 0 is the megakernel's; group 1 holds the path pool (`wave.wgsl`). Each
//! pass's pipeline has the layout naga finds for its entry point ([`bindings_used`]).

pub mod graph;

use crate::gpu::prims::{CompactPlan, Prims};
use graph::{buffer_name, GraphPass, PassGraph};
use std::cell::RefCell;
use wgpu::util::DeviceExt;

/// Bytes per slot of the path pool: the path state (64), its hit (8), its sampler key (8),
/// two queue entries, a flag and a scan offset (16).
pub const BYTES_PER_SLOT: usize = 96;

/// The most slots of a uniform wave (2²²: 384 MiB of pool); a wave of more jobs × samples
/// is split by the frame-time batching.
pub const MAX_UNIFORM_SLOTS: usize = 1 << 22;

/// The (group, binding) pairs entry point `entry` of a validated module uses.
pub fn bindings_used(module: &naga::Module, info: &naga::valid::ModuleInfo, entry: &str) -> Result<Vec<(u32, u32)>, String> {
    let index = module.entry_points.iter().position(|e| e.name == entry).ok_or_else(|| format!("no entry point {entry}"))?;
    let fi = info.get_entry_point(index);
    let mut used: Vec<(u32, u32)> = module
        .global_variables
        .iter()
        .filter(|(h, _)| !fi[*h].is_empty())
        .filter_map(|(_, v)| v.binding.as_ref().map(|b| (b.group, b.binding)))
        .collect();
    used.sort_unstable();
    Ok(used)
}

/// The smallest wave size with plans of its own.
const MIN_PLAN: usize = 1024;

/// The compaction (queue 0 → 1 and 1 → 0) over the first `n` queue positions.
#[derive(Debug)]
struct SizePlans {
    n: usize,
    compact: [CompactPlan; 2],
}

/// A pass's pipeline and its bind groups: per group, one per queue of the ping-pong pair.
#[derive(Debug)]
struct Pass {
    pipeline: wgpu::ComputePipeline,
    groups: Vec<[wgpu::BindGroup; 2]>,
}

/// How a wave's jobs are dispatched: a 2D grid of 64-thread workgroups, or the indirect
/// arguments of an adaptive or camera batch.
#[derive(Debug, Clone, Copy)]
pub enum JobGrid<'a> {
    Direct((u32, u32)),
    Indirect(&'a wgpu::Buffer),
}

/// The wavefront passes of one bake, their path pool and compaction plans.
#[derive(Debug)]
pub struct Wavefront {
    generate: Pass,
    start: Pass,
    intersect: Pass,
    shade: Pass,
    args: Pass,
    accumulate: Pass,
    prims: Prims,
    /// Per wave size (powers of two from [`MIN_PLAN`] up to the pool), the compaction
    /// plans over that many queue positions: their scans cost in proportion to the wave,
    /// not to the pool.
    plans: Vec<SizePlans>,
    wave: wgpu::Buffer,
    wave_args: wgpu::Buffer,
    flags: wgpu::Buffer,
    /// Per-pass GPU times ([`Wavefront::enable_profiling`]).
    profiler: Option<Profiler>,
    /// The passes of a wave with the buffers each binds.
    pub graph: PassGraph,
    /// Slots in the path pool.
    pub capacity: usize,
}

/// Timestamps at the start and end of every pass of a wave (`Features::TIMESTAMP_QUERY`).
#[derive(Debug)]
struct Profiler {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    /// The label of each recorded pass, in order (pass k wrote timestamps 2k and 2k + 1).
    labels: RefCell<Vec<&'static str>>,
}

/// Passes one submission may time (a wave has 2 + 3·(bounces + 1) + 1 passes).
const PROFILED_PASSES: usize = 128;

/// The GPU time of one recorded pass ([`Wavefront::take_profile`]); "compact" is the time
/// between a shade pass's end and the next wave_args pass's start (the compaction's copy,
/// scan and scatter, recorded by `gpu_prims`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PassTime {
    pub pass: &'static str,
    pub seconds: f64,
}

impl Wavefront {
    /// The passes of the bake's composed `kernel` (one entry shader per pass),
    /// `group0` the megakernel's bindings, a pool of `capacity` slots and `jobs` job
    /// positions (the most jobs a wave has).
    pub fn new(
        d: &wgpu::Device,
        kernel: &crate::gpu::kernel::Kernel,
        group0: &[(u32, &wgpu::Buffer)],
        capacity: usize,
        jobs: usize,
    ) -> Result<Wavefront, String> {
        let capacity = capacity.max(64);
        let storage = |label: &str, bytes: usize, extra: wgpu::BufferUsages| {
            d.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(16) as u64,
                usage: wgpu::BufferUsages::STORAGE | extra,
                mapped_at_creation: false,
            })
        };
        let copy = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let paths = storage("wavefront paths", 64 * capacity, wgpu::BufferUsages::empty());
        let hits = storage("wavefront hits", 8 * capacity, wgpu::BufferUsages::empty());
        let keys = storage("wavefront sampler keys", 8 * capacity, wgpu::BufferUsages::empty());
        let queues = [storage("wavefront queue 0", 4 * capacity, copy), storage("wavefront queue 1", 4 * capacity, copy)];
        let flags = storage("wavefront flags", 4 * capacity, copy);
        let offsets = storage("wavefront offsets", 4 * capacity, copy);
        let wave = storage("wavefront counters", 16, copy);
        let job_buf = storage("wavefront jobs", 16 * jobs.max(1), wgpu::BufferUsages::empty());
        let wave_args = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("wavefront args"),
            contents: bytemuck::cast_slice(&[0u32, 1, 1]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
        });
        let group1 = |q: usize| -> Vec<(u32, &wgpu::Buffer)> {
            vec![(0, &paths), (1, &hits), (2, &keys), (3, &queues[q]), (4, &flags), (5, &wave), (6, &job_buf), (7, &wave_args)]
        };
        let groups = [group0.to_vec(), group1(0)];
        let alt = [group0.to_vec(), group1(1)];
        // Each pass's entry shader, composed on its own (the modules it imports).
        let mut shaders = Vec::new();
        for (file, _) in crate::gpu::kernel::WAVEFRONT {
            let source = kernel.shader(file)?;
            let naga = shaders::export::validate(source).map_err(|e| format!("{file}: {e}"))?;
            let module =
                d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(file), source: wgpu::ShaderSource::Wgsl(source.into()) });
            shaders.push((file, module, naga));
        }
        let file_of = |entry: &str| match entry {
            "wf_generate" => "generate.wgsl",
            "wave_start" | "wave_args_from_length" => "queue.wgsl",
            "wf_intersect" => "intersect.wgsl",
            "wf_shade" => "shade.wgsl",
            _ => "accumulate.wgsl",
        };
        let shader = |entry: &str| shaders.iter().find(|s| s.0 == file_of(entry)).expect("every pass's shader");
        let used_by = |entry: &str| {
            let s = shader(entry);
            bindings_used(&s.2 .0, &s.2 .1, entry)
        };
        let pass = |entry: &str| -> Result<Pass, String> {
            let pipeline = super::compute_pipeline(d, &shader(entry).1, entry);
            let used = used_by(entry)?;
            let top = used.iter().map(|u| u.0).max().unwrap_or(0);
            let mut out = Vec::new();
            for g in 0..=top {
                let layout = pipeline.get_bind_group_layout(g);
                let make = |list: &[(u32, &wgpu::Buffer)]| {
                    let entries: Vec<wgpu::BindGroupEntry> = list
                        .iter()
                        .filter(|(b, _)| used.contains(&(g, *b)))
                        .map(|(b, buf)| wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() })
                        .collect();
                    d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(entry), layout: &layout, entries: &entries })
                };
                out.push([make(&groups[g as usize]), make(&alt[g as usize])]);
            }
            Ok(Pass { pipeline, groups: out })
        };
        let prims = Prims::new(d);
        let mut sizes = Vec::new();
        let mut n = MIN_PLAN.min(capacity);
        while n < capacity {
            sizes.push(n);
            n *= 2;
        }
        sizes.push(capacity);
        let plans = sizes
            .into_iter()
            .map(|n| SizePlans {
                n,
                compact: [
                    prims.compact_plan(d, &queues[0], &flags, &offsets, &queues[1], n),
                    prims.compact_plan(d, &queues[1], &flags, &offsets, &queues[0], n),
                ],
            })
            .collect();
        let graph = pass_graph(&used_by)?;
        Ok(Wavefront {
            graph,
            generate: pass("wf_generate")?,
            start: pass("wave_start")?,
            intersect: pass("wf_intersect")?,
            shade: pass("wf_shade")?,
            args: pass("wave_args_from_length")?,
            accumulate: pass("wf_accumulate")?,
            prims,
            plans,
            profiler: None,
            wave,
            wave_args,
            flags,
            capacity,
        })
    }

    /// Times every pass of the following waves on the GPU (the device must have
    /// `Features::TIMESTAMP_QUERY`); read with [`Wavefront::take_profile`] after each
    /// submission.
    pub fn enable_profiling(&mut self, d: &wgpu::Device) -> Result<(), String> {
        if !d.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return Err("per-pass GPU times need timestamp queries, which this adapter does not offer".into());
        }
        self.profiler = Some(Profiler {
            set: d.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("wavefront passes"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * PROFILED_PASSES as u32,
            }),
            resolve: d.create_buffer(&wgpu::BufferDescriptor {
                label: Some("wavefront timestamps"),
                size: (16 * PROFILED_PASSES) as u64,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            labels: RefCell::new(Vec::new()),
        });
        Ok(())
    }

    /// Stops timing the passes.
    pub fn disable_profiling(&mut self) {
        self.profiler = None;
    }

    /// The passes timed since the last call (their submission must have been made), in
    /// order; empty without profiling.
    pub fn take_profile(&self, gpu: &shaders::gpu::Gpu) -> Result<Vec<PassTime>, String> {
        let Some(p) = &self.profiler else { return Ok(Vec::new()) };
        let labels = std::mem::take(&mut *p.labels.borrow_mut());
        if labels.is_empty() {
            return Ok(Vec::new());
        }
        let raw: Vec<u64> = bytemuck::pod_collect_to_vec(&gpu.read_back(&p.resolve)?);
        let tick = gpu.timestamp_period() as f64 * 1e-9;
        let mut out = Vec::new();
        for (k, label) in labels.iter().enumerate() {
            if k > 0 && *label == "wave_args" && labels[k - 1] == "shade" {
                out.push(PassTime { pass: "compact", seconds: raw[2 * k].saturating_sub(raw[2 * k - 1]) as f64 * tick });
            }
            out.push(PassTime { pass: label, seconds: raw[2 * k + 1].saturating_sub(raw[2 * k]) as f64 * tick });
        }
        Ok(out)
    }

    fn run_pass(&self, enc: &mut wgpu::CommandEncoder, p: &Pass, label: &'static str, queue: usize, grid: JobGrid) {
        let mut desc = wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: None };
        if let Some(prof) = &self.profiler {
            let mut labels = prof.labels.borrow_mut();
            if labels.len() < PROFILED_PASSES {
                let k = labels.len() as u32;
                labels.push(label);
                desc.timestamp_writes = Some(wgpu::ComputePassTimestampWrites {
                    query_set: &prof.set,
                    beginning_of_pass_write_index: Some(2 * k),
                    end_of_pass_write_index: Some(2 * k + 1),
                });
            }
        }
        let mut cp = enc.begin_compute_pass(&desc);
        cp.set_pipeline(&p.pipeline);
        for (g, pair) in p.groups.iter().enumerate() {
            cp.set_bind_group(g as u32, &pair[queue], &[]);
        }
        match grid {
            JobGrid::Direct((x, y)) => cp.dispatch_workgroups(x, y, 1),
            JobGrid::Indirect(args) => cp.dispatch_workgroups_indirect(args, 0),
        }
    }

    /// Records one wave over `jobs` whose samples take at most `slots` slots: generate,
    /// then per bounce intersect, shade and compaction of the queue, then accumulate
    /// (`primary_only`: generate and the first intersect only — the primary-ray timing of
    /// [`crate::gpu::GpuBake::time_rays`]).
    pub fn record(&self, enc: &mut wgpu::CommandEncoder, jobs: JobGrid, slots: usize, max_bounces: u32, primary_only: bool) {
        let size = self.plans.iter().find(|p| p.n >= slots).unwrap_or_else(|| self.plans.last().expect("a plan"));
        // Queue length and slots taken back to 0 (the overflow count stays).
        enc.clear_buffer(&self.wave, 0, Some(8));
        self.run_pass(enc, &self.generate, "generate", 0, jobs);
        self.run_pass(enc, &self.start, "wave_start", 0, JobGrid::Direct((1, 1)));
        let indirect = JobGrid::Indirect(&self.wave_args);
        let bounces = if primary_only { 0 } else { max_bounces };
        for b in 0..=bounces {
            let q = (b % 2) as usize;
            self.run_pass(enc, &self.intersect, if b == 0 { "intersect (primary)" } else { "intersect (extension)" }, q, indirect);
            if primary_only {
                self.resolve_profile(enc);
                return;
            }
            enc.clear_buffer(&self.flags, 0, Some(4 * size.n as u64));
            self.run_pass(enc, &self.shade, "shade", q, indirect);
            if b == bounces {
                // Every path ends at its hit of index max_bounces.
                break;
            }
            let plan = &size.compact[q];
            self.prims.record_compact(enc, plan);
            enc.copy_buffer_to_buffer(plan.total(), 0, &self.wave, 0, 4);
            self.run_pass(enc, &self.args, "wave_args", q, JobGrid::Direct((1, 1)));
        }
        self.run_pass(enc, &self.accumulate, "accumulate", 0, jobs);
        self.resolve_profile(enc);
    }

    /// Resolves the timestamps recorded so far into the read-back buffer.
    fn resolve_profile(&self, enc: &mut wgpu::CommandEncoder) {
        if let Some(p) = &self.profiler {
            let n = p.labels.borrow().len() as u32;
            if n > 0 {
                enc.resolve_query_set(&p.set, 0..2 * n, &p.resolve, 0);
            }
        }
    }

    /// The counter of samples that found the pool full (must stay 0; see `generate.wgsl`).
    pub fn overflow_counter(&self) -> &wgpu::Buffer {
        &self.wave
    }
}

/// The (group, binding) pairs an entry point uses.
type BindingsOf<'a> = dyn Fn(&str) -> Result<Vec<(u32, u32)>, String> + 'a;

/// The wave's pass graph, each pass's buffers from `used_by` (naga's bindings of an entry point).
fn pass_graph(used_by: &BindingsOf) -> Result<PassGraph, String> {
    let node = |name, wgsl: &'static str, entry: &'static str, dispatch, repeat| -> Result<GraphPass, String> {
        let buffers = used_by(entry)?.into_iter().map(|(g, b)| buffer_name(g, b)).collect();
        Ok(GraphPass { name, wgsl, entry: Some(entry), buffers, dispatch, repeat })
    };
    let compact = GraphPass {
        name: "compact",
        wgsl: "gpu/prims",
        entry: None,
        buffers: vec!["queue", "path flags", "scan offsets", "other queue"],
        dispatch: "host",
        repeat: "per bounce",
    };
    let graph = PassGraph {
        passes: vec![
            node("generate", "generate.wgsl", "wf_generate", "jobs", "once")?,
            node("wave_start", "wave.wgsl", "wave_start", "one", "once")?,
            node("intersect", "intersect.wgsl", "wf_intersect", "queue", "per bounce")?,
            node("shade", "shade.wgsl", "wf_shade", "queue", "per bounce")?,
            compact,
            node("wave_args", "wave.wgsl", "wave_args_from_length", "one", "per bounce")?,
            node("accumulate", "accumulate.wgsl", "wf_accumulate", "jobs", "once")?,
        ],
    };
    Ok(graph)
}
