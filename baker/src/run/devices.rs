//! Which engine traces — the CPU, a GPU, or several — and the ray-throughput measurement
//! that replaces a bake with `--measure-rays`.

use super::{Device, Options};
use crate::accumulate::{BakeConfig, BakeState, Pipeline, Targets};
use crate::estimator::trace::Tracer;
use crate::gpu::GpuBake;
use shaders::gpu::Gpu;

/// The GPUs to bake on (none: the CPU path) for `o.run.device` and `o.run.gpus`, and the device
/// line bake.json records.
pub(crate) fn select(o: &Options, log: &mut dyn FnMut(String)) -> Result<(Vec<Gpu>, String), String> {
    if o.run.gpus == 0 || (o.run.gpus > 1 && o.run.device == Device::Cpu) {
        return Err(format!(
            "--gpus {} with --device {:?}: give ≥ 1 GPU, and more than one only on a GPU device",
            o.run.gpus, o.run.device
        ));
    }
    if let Some(i) = o.run.gpu_index {
        if o.run.device == Device::Cpu || o.run.gpus > 1 {
            return Err(format!("--gpu-index {i} picks one GPU: not with --device cpu or --gpus > 1"));
        }
    }
    let gpus: Vec<Gpu> = match o.run.device {
        _ if o.run.gpus > 1 => Gpu::hardware(o.run.gpus)?,
        _ if o.run.gpu_index.is_some() => vec![Gpu::at(o.run.gpu_index.unwrap_or_default())?],
        Device::Cpu => Vec::new(),
        Device::Gpu => vec![Gpu::new()?],
        Device::Auto => match Gpu::new() {
            Ok(g) if g.software => {
                log(format!("the only adapter is a software rasteriser ({}); baking on the CPU path (--device gpu forces it)", g.adapter));
                Vec::new()
            }
            Ok(g) => vec![g],
            Err(e) => {
                log(format!("no GPU adapter ({e}); baking on the CPU"));
                Vec::new()
            }
        },
    };
    let device = match gpus.as_slice() {
        [] => format!("CPU: {} threads (rayon)", rayon::current_num_threads()),
        [g] => format!("GPU: {}", g.adapter),
        gs => format!("{} GPUs: {}", gs.len(), gs.iter().map(|g| g.adapter.as_str()).collect::<Vec<_>>().join("; ")),
    };
    log(format!("device: {device}"));
    Ok((gpus, device))
}

/// Measures rays per second over `passes` passes on `g` and logs them (with the wavefront
/// pipeline also the GPU time of every pass, where the adapter has timestamp queries);
/// returns the throw-away bake's state.
pub(crate) fn measure_rays<'s>(
    g: &Gpu,
    tracer_of: &dyn Fn() -> Tracer<'s>,
    targets: &Targets,
    config: &BakeConfig,
    passes: u64,
    log: &mut dyn FnMut(String),
) -> Result<BakeState, String> {
    let mut b = GpuBake::new(g, &tracer_of(), targets, config)?;
    let r = b.time_rays(passes)?;
    log(format!(
        "rays over {passes} passes × {} texels: primary {} in {:.4} s = {:.3} G rays/s; secondary {} extension + {} shadow in {:.4} s (full − primary) = {:.3} G rays/s; all rays {:.3} G rays/s",
        targets.items.len(),
        r.primary,
        r.primary_seconds,
        r.primary_rate() * 1e-9,
        r.extension,
        r.shadow,
        r.full_seconds - r.primary_seconds,
        r.secondary_rate() * 1e-9,
        (r.primary + r.extension + r.shadow) as f64 / r.full_seconds * 1e-9
    ));
    if config.pipeline == Pipeline::Wavefront {
        if g.timestamps {
            // Per-pass GPU times of a fresh bake over the same passes.
            let mut p = GpuBake::new(g, &tracer_of(), targets, config)?;
            let times = p.profile_passes(passes)?;
            let total: f64 = times.iter().map(|t| t.1).sum();
            let parts: Vec<String> =
                times.iter().map(|(pass, s, n)| format!("{pass} {:.2} ms ({:.1}%, {n}×)", 1e3 * s, 100.0 * s / total.max(1e-30))).collect();
            log(format!("wavefront GPU time over {passes} passes: {:.2} ms — {}", 1e3 * total, parts.join(", ")));
        } else {
            log("wavefront per-pass GPU times: the adapter has no timestamp queries".into());
        }
    }
    b.state()
}
