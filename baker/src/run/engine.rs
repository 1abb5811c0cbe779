//! The pass loop of one set of targets (texels or probes) on the CPU or the GPUs: progress
//! with ETA, a checkpoint every N passes, resume from a checkpoint.

use super::Options;
use crate::accumulate::{Bake, BakeConfig, BakeState, Partition, Progressive, Targets};
use crate::checkpoint;
use crate::estimator::trace::Tracer;
use crate::gpu::multi::MultiGpuBake;
use crate::scene::Scene;

/// Runs passes on `targets` with progress, checkpoints and resume; returns the state.
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_targets<'s>(
    o: &Options,
    config: &BakeConfig,
    gpus: &'s [shaders::gpu::Gpu],
    tracer_of: &dyn Fn() -> Tracer<'s>,
    scene: &Scene,
    targets: &Targets,
    what: &str,
    log: &mut dyn FnMut(String),
) -> Result<(BakeState, u64), String> {
    config.check(targets)?;
    // A shard bakes its own part and checkpoints it under its own name and identity.
    let (part, ckpt, fp) = match &o.shard {
        Some(s) => {
            let part = Partition::of(s.index, s.count, targets.items.len())?;
            let name = format!("{what}.shard-{}-of-{}", s.index, s.count);
            (part, o.out.join(format!("{name}.checkpoint")), checkpoint::content_fingerprint(scene, targets, config, &name))
        }
        None => (
            Partition::with_block(0, 1, crate::accumulate::partition::partition_block(targets.items.len(), gpus.len()))?,
            o.out.join(format!("{what}.checkpoint")),
            checkpoint::content_fingerprint(scene, targets, config, what),
        ),
    };
    let saved = if o.resume && ckpt.exists() {
        let bytes = std::fs::read(&ckpt).map_err(|e| format!("{}: {e}", ckpt.display()))?;
        let st = checkpoint::from_bytes(&bytes, fp, config, targets).map_err(|e| format!("{}: {e}", ckpt.display()))?;
        log(format!("{what}: resuming from {} at pass {}", ckpt.display(), st.passes));
        Some(st)
    } else {
        if o.resume {
            log(format!("{what}: --resume given but no checkpoint at {}; starting from pass 0", ckpt.display()));
        }
        None
    };
    let mut engine = match gpus {
        [] => {
            let mut b = match saved {
                Some(st) => Bake::resume(config.clone(), targets, tracer_of(), st)?,
                None => Bake::new(config.clone(), targets, tracer_of()),
            };
            b.set_partition(part)?;
            Box::new(b) as Box<dyn Progressive>
        }
        gpus => {
            let mut b = MultiGpuBake::for_part(gpus, tracer_of, targets, config, part)?;
            match o.batch_seconds {
                Some(s) => b.set_batch_target(Some(s)),
                None => b.set_chunk(usize::MAX),
            }
            let left_out = &b.devices()[0].kernel.left_out;
            if o.verbose {
                for l in left_out {
                    log(format!("{what}: left out of the GPU kernel: {l}"));
                }
                if let Some(g) = b.devices()[0].pass_graph() {
                    log(format!("{what}: wavefront pass graph of a wave:\n{g}"));
                }
            } else if !left_out.is_empty() {
                log(format!("{what}: {} features left out of the GPU kernel (this bake does not use them; -v lists them)", left_out.len()));
            }
            if gpus.len() > 1 && o.shard.is_none() {
                let shares: Vec<String> = b.devices().iter().map(|d| d.share().to_string()).collect();
                log(format!("{what}: items dealt to {} GPUs in blocks of {}: {} items each", gpus.len(), b.block(), shares.join(", ")));
            }
            if let Some(st) = &saved {
                b.upload(st)?;
            }
            Box::new(b)
        }
    };
    if let Some(s) = &o.shard {
        let n = targets.items.len();
        log(format!("{what}: shard {} of {}: {} of {n} items, dealt in blocks of {}", s.index, s.count, part.share(n), part.block));
    }
    // Adaptive bakes count pilot passes and batches (about the paths of o.passes passes).
    let total = config.adaptive.map_or(o.passes, |a| a.batches_for(o.passes));
    let unit = if config.adaptive.is_some() { "passes + batches" } else { "passes" };
    let start = engine.passes();
    let todo = total.saturating_sub(start);
    let bar = if o.quiet { indicatif::ProgressBar::hidden() } else { indicatif::ProgressBar::new(total) };
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!("{{msg}} [{{bar:30}}] {{pos}}/{{len}} {unit}, {{per_sec}}, ETA {{eta}}"))
            .expect("template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar.set_position(start);
    let chunk = if o.checkpoint_every > 0 { o.checkpoint_every } else { todo.max(1) };
    let mut run = 0;
    while engine.passes() < total {
        let n = chunk.min(total - engine.passes());
        // Progress granularity: at most 8 passes per call between bar updates.
        let mut left = n;
        while left > 0 {
            let k = left.min(8);
            engine.run(k)?;
            bar.inc(k);
            left -= k;
        }
        run += n;
        if o.checkpoint_every > 0 {
            let st = engine.state()?;
            checkpoint::write_atomic(&ckpt, &checkpoint::to_bytes(&st, fp))?;
        }
    }
    bar.finish_and_clear();
    Ok((engine.state()?, run))
}
