//! The pass loop of one set of targets (texels or probes) on the CPU or the GPUs: progress
//! with ETA, a checkpoint every N passes, resume from a checkpoint.

use super::Options;
use crate::accumulate::{Bake, BakeConfig, BakeState, Progressive, Targets};
use crate::checkpoint;
use crate::estimator::trace::Tracer;
use crate::gpu::multi::MultiGpuBake;
use crate::scene::Scene;

/// Runs passes on `targets` with progress, checkpoints and resume; returns the state.
///
/// On GPUs, where the encoder states of all bases exceed one storage binding, the bases are
/// baked in groups that fit, one after another over the same paths (every random number
/// depends on seed, item and pass only, so each group traces the very paths of the others
/// and their moments agree), each with its own checkpoint; the states are joined.
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
    let groups = match gpus.first() {
        Some(g) => {
            let adapter = g.device().limits().max_storage_buffer_binding_size;
            basis_groups(&config.bases, targets.items.len(), o.run.max_binding.map_or(adapter, |m| m.min(adapter)))
        }
        None => vec![config.bases.clone()],
    };
    if groups.len() <= 1 {
        return run_group(o, config, gpus, tracer_of, scene, targets, what, log);
    }
    let names = |g: &[crate::accumulate::BasisId]| g.iter().map(|b| b.name()).collect::<Vec<_>>().join("+");
    log(format!(
        "{what}: the encoder states of {} bases × {} items exceed one storage binding: baked in {} groups over the same paths ({})",
        config.bases.len(),
        targets.items.len(),
        groups.len(),
        groups.iter().map(|g| names(g)).collect::<Vec<_>>().join(", ")
    ));
    let mut joined: Option<(BakeState, u64)> = None;
    for g in &groups {
        let c = BakeConfig { bases: g.clone(), ..config.clone() };
        let (st, run) = run_group(o, &c, gpus, tracer_of, scene, targets, &format!("{what}.{}", names(g)), log)?;
        joined = Some(match joined {
            None => (st, run),
            Some((mut all, r)) => {
                let drift = moments_drift(&all.moments, &st.moments);
                if all.passes != st.passes || drift.is_nan() || drift > MOMENTS_AGREE {
                    let how =
                        if drift.is_finite() { format!("sums differ by {drift:.2e} relative") } else { "sample counts differ".into() };
                    return Err(format!("{what}: the group {} traced other paths than the first ({how})", names(g)));
                }
                log(format!("{what}: group {}: moments agree with the first group's to {drift:.1e} (Σ|Δ|/Σ)", names(g)));
                all.encoders.extend(st.encoders);
                if let (Some(a), Some(b)) = (all.filtered.as_mut(), st.filtered) {
                    a.encoders.extend(b.encoders);
                }
                (all, r.max(run))
            }
        });
    }
    Ok(joined.expect("at least two groups"))
}

/// How far two groups' moments may differ, as Σ|Δ sum| / Σ|sum| over items and channels:
/// the same paths through kernels compiled with different encoders, where f32 rounding of
/// the shared terms may differ with inlining and, rarely, a path then takes another turn
/// (measured on the H200: the largest per-texel difference 0.75 % among 2.75 M texels).
/// Sample counts must
/// be equal.
const MOMENTS_AGREE: f64 = 1e-4;

/// Σ|Δ sum| / Σ|sum| of `a` and `b` over items and channels, or ∞ where the sample counts
/// differ.
fn moments_drift(a: &[crate::accumulate::state::Moments], b: &[crate::accumulate::state::Moments]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let (mut diff, mut total) = (0.0f64, 0.0f64);
    for (x, y) in a.iter().zip(b) {
        if (x.accepted, x.back_faces, x.non_finite) != (y.accepted, y.back_faces, y.non_finite) {
            return f64::INFINITY;
        }
        for c in 0..3 {
            diff += (x.sum[c] - y.sum[c]).abs();
            total += x.sum[c].abs();
        }
    }
    if diff == 0.0 {
        0.0
    } else {
        diff / total.max(1e-300)
    }
}

/// `bases` in order, split into groups whose encoder states (`items` per basis) fit one
/// storage binding of `max_binding` bytes (a basis alone that does not fit is a group of
/// its own: the bake's size check then names it).
pub fn basis_groups(bases: &[crate::accumulate::BasisId], items: usize, max_binding: u64) -> Vec<Vec<crate::accumulate::BasisId>> {
    let per_basis = (items.max(1) * std::mem::size_of::<shaders::progressive::EncoderState>()) as u64;
    let fit = ((max_binding / per_basis) as usize).max(1);
    bases.chunks(fit).map(<[_]>::to_vec).collect()
}

/// [`run_targets`] for one group of bases.
#[allow(clippy::too_many_arguments)]
fn run_group<'s>(
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
    // A shard's targets are its part ([`Targets::part`]): it bakes, holds and checkpoints
    // only its items, under its own name and identity.
    let (ckpt, fp) = match &targets.part {
        Some((p, _)) => {
            config.check_partitionable()?;
            let name = format!("{what}.shard-{}-of-{}", p.index, p.count);
            (o.run.out.join(format!("{name}.checkpoint")), checkpoint::content_fingerprint(scene, targets, config, &name))
        }
        None => (o.run.out.join(format!("{what}.checkpoint")), checkpoint::content_fingerprint(scene, targets, config, what)),
    };
    if let Some((p, n)) = targets.part.filter(|_| targets.items.is_empty()) {
        // A part that holds none of this set's items (the probes, one block, all in shard 0):
        // nothing to trace; its empty state records the bake's passes.
        log(format!("{what}: shard {} of {}: none of the {n} items", p.index, p.count));
        let mut st = BakeState::new(config, targets);
        st.passes = o.spec.passes;
        return Ok((st, 0));
    }
    let saved = if o.run.resume && ckpt.exists() {
        let bytes = std::fs::read(&ckpt).map_err(|e| format!("{}: {e}", ckpt.display()))?;
        let st = checkpoint::from_bytes(&bytes, fp, config, targets).map_err(|e| format!("{}: {e}", ckpt.display()))?;
        log(format!("{what}: resuming from {} at pass {}", ckpt.display(), st.passes));
        Some(st)
    } else {
        if o.run.resume {
            log(format!("{what}: --resume given but no checkpoint at {}; starting from pass 0", ckpt.display()));
        }
        None
    };
    let mut engine = match gpus {
        [] => {
            let b = match saved {
                Some(st) => Bake::resume(config.clone(), targets, tracer_of(), st)?,
                None => Bake::new(config.clone(), targets, tracer_of()),
            };
            Box::new(b) as Box<dyn Progressive>
        }
        gpus => {
            let mut b = MultiGpuBake::new(gpus, tracer_of, targets, config)?;
            match o.run.batch_seconds {
                Some(s) => b.set_batch_target(Some(s)),
                None => b.set_chunk(usize::MAX),
            }
            let left_out = &b.devices()[0].kernel.left_out;
            if o.run.verbose {
                for l in left_out {
                    log(format!("{what}: left out of the GPU kernel: {l}"));
                }
                if let Some(g) = b.devices()[0].pass_graph() {
                    log(format!("{what}: wavefront pass graph of a wave:\n{g}"));
                }
            } else if !left_out.is_empty() {
                log(format!("{what}: {} features left out of the GPU kernel (this bake does not use them; -v lists them)", left_out.len()));
            }
            if gpus.len() > 1 {
                let shares: Vec<String> = b.devices().iter().map(|d| d.share().to_string()).collect();
                log(format!("{what}: items dealt to {} GPUs in blocks of {}: {} items each", gpus.len(), b.block(), shares.join(", ")));
            }
            if let Some(st) = &saved {
                b.upload(st)?;
            }
            Box::new(b)
        }
    };
    if let Some((p, n)) = &targets.part {
        log(format!("{what}: shard {} of {}: {} of {n} items, dealt in blocks of {}", p.index, p.count, targets.items.len(), p.block));
    }
    // Adaptive bakes count pilot passes and batches (about the paths of o.spec.passes passes).
    let total = config.adaptive.map_or(o.spec.passes, |a| a.batches_for(o.spec.passes));
    let unit = if config.adaptive.is_some() { "passes + batches" } else { "passes" };
    let start = engine.passes();
    if start > total {
        // A reused folder's checkpoint from a longer bake: continuing would write its state
        // under this bake's settings.
        return Err(format!(
            "{}: the checkpoint is at {unit} {start}, past this bake's {total} (--passes {}): resume with --passes ≥ {start}, or delete the checkpoint to bake {} from the start",
            ckpt.display(),
            o.spec.passes,
            o.spec.passes
        ));
    }
    let todo = total.saturating_sub(start);
    let bar = if o.run.quiet { indicatif::ProgressBar::hidden() } else { indicatif::ProgressBar::new(total) };
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!("{{msg}} [{{bar:30}}] {{pos}}/{{len}} {unit}, {{per_sec}}, ETA {{eta}}"))
            .expect("template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar.set_position(start);
    let chunk = if o.run.checkpoint_every > 0 { o.run.checkpoint_every } else { todo.max(1) };
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
        if o.run.checkpoint_every > 0 {
            let st = engine.state()?;
            checkpoint::write_atomic(&ckpt, &checkpoint::to_bytes_for(&st, fp, config, targets))?;
        }
    }
    bar.finish_and_clear();
    Ok((engine.state()?, run))
}

#[cfg(test)]
mod tests {
    use super::{moments_drift, MOMENTS_AGREE};
    use crate::accumulate::state::Moments;

    fn moments(sums: &[[f64; 3]]) -> Vec<Moments> {
        sums.iter().map(|s| Moments { sum: *s, sum_sq: [0.0; 3], accepted: 16, back_faces: 1, non_finite: 0 }).collect()
    }

    /// The groups' agreement: Σ|Δ|/Σ by hand on three items; different sample counts or
    /// item counts are never "in agreement"; a drift of 1e-3 is refused, 1e-6 accepted.
    #[test]
    fn moments_drift_is_the_relative_sum_difference() {
        let a = moments(&[[1.0, 2.0, 3.0], [0.5, 0.5, 0.5], [4.0, 0.0, 0.0]]);
        assert_eq!(moments_drift(&a, &a), 0.0);
        let mut b = moments(&[[1.0, 2.0, 3.0], [0.5, 0.5, 0.5], [4.0, 0.0, 0.0]]);
        b[1].sum[2] += 0.0115; // Σ|sum| = 11.5 → 1e-3
        assert!((moments_drift(&a, &b) - 1e-3).abs() < 1e-15);
        assert!(moments_drift(&a, &b) > MOMENTS_AGREE);
        b[1].sum[2] = 0.5 + 1.15e-5;
        assert!(moments_drift(&a, &b) <= MOMENTS_AGREE);
        let mut c = moments(&[[1.0, 2.0, 3.0], [0.5, 0.5, 0.5], [4.0, 0.0, 0.0]]);
        c[2].accepted += 1;
        assert_eq!(moments_drift(&a, &c), f64::INFINITY);
        let mut d = moments(&[[1.0, 2.0, 3.0], [0.5, 0.5, 0.5], [4.0, 0.0, 0.0]]);
        d[0].back_faces = 0;
        assert_eq!(moments_drift(&a, &d), f64::INFINITY);
        assert_eq!(moments_drift(&a, &a[..2]), f64::INFINITY);
    }
}
