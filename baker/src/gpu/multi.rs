//! A bake split across several GPUs of one host (the thesis' pipeline is
//! designed per device, [Roughton19 §3.4]).
//!
//! The targets (texels or probes) are dealt out in blocks of consecutive items, block b to
//! device b mod N (interleaved, so every device gets a like share of bright and dark, simple
//! and deep regions: contiguous halves of an atlas differ in cost — 1.74× on two H200s for
//! the fair scene, against 1.8× wanted); every device runs every pass over its blocks on
//! its own thread and queue. A pass's per-item results do not depend on which dispatch
//! computes an item — each item's sample sequence is indexed by (item, pass) only, which the
//! frame-time chunking already relies on (test `chunked_dispatches_give_the_identical_bake`)
//! — so the merged state, every item taken from the device that baked it, **is** the
//! single-device state: bit for bit on devices of one model, within f32 rounding of the
//! device's arithmetic otherwise. No reduction across devices is needed (the encoder state
//! is per item).
//!
//! The dealing is [`crate::accumulate::partition`]'s; [`MultiGpuBake::for_part`] bakes one
//! part of whole targets, its blocks dealt to its devices again (a `baker --shard` run
//! instead bakes its part's own targets, [`crate::accumulate::Targets::part`]).
//!
//! Left out: ray guiding (its clusters learn from all their texels every pass, which would
//! need a cross-device reduction per pass) — refused with a clear error.

use crate::accumulate::{BakeConfig, BakeState, Partition, Targets};
use crate::estimator::trace::Tracer;
use crate::gpu::GpuBake;
use shaders::gpu::Gpu;

pub use crate::accumulate::partition::{owner, partition_block};

/// One bake on several devices.
pub struct MultiGpuBake<'g> {
    bakes: Vec<GpuBake<'g>>,
    /// Each device's part of the items.
    parts: Vec<Partition>,
    /// Wall seconds each device's thread took in the last [`MultiGpuBake::run`].
    seconds: Vec<f64>,
}

impl std::fmt::Debug for MultiGpuBake<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MultiGpuBake")
            .field("parts", &self.parts)
            .field("shares", &self.bakes.iter().map(|b| b.share()).collect::<Vec<_>>())
            .field("passes", &self.passes())
            .finish()
    }
}

impl<'g> MultiGpuBake<'g> {
    /// One [`GpuBake`] per device, the targets dealt out in blocks ([`partition_block`]).
    pub fn new<'s>(gpus: &'g [Gpu], tracer_of: &dyn Fn() -> Tracer<'s>, targets: &Targets, config: &BakeConfig) -> Result<Self, String> {
        let whole = Partition::with_block(0, 1, partition_block(targets.items.len(), gpus.len()))?;
        MultiGpuBake::for_part(gpus, tracer_of, targets, config, whole)
    }

    /// One [`GpuBake`] per device baking `part` of the targets (a shard), its blocks dealt
    /// out to the devices ([`Partition::split`]).
    pub fn for_part<'s>(
        gpus: &'g [Gpu],
        tracer_of: &dyn Fn() -> Tracer<'s>,
        targets: &Targets,
        config: &BakeConfig,
        part: Partition,
    ) -> Result<Self, String> {
        if gpus.is_empty() {
            return Err("no device to bake on".into());
        }
        if gpus.len() > 1 && config.guiding.is_some() {
            return Err(
                "ray guiding runs on one device only (its clusters learn from all their texels every pass); drop --guiding or use one GPU"
                    .into(),
            );
        }
        if part.count > 1 {
            config.check_partitionable()?;
        }
        let parts: Vec<Partition> = (0..gpus.len()).map(|g| part.split(g, gpus.len())).collect();
        let mut bakes = Vec::with_capacity(gpus.len());
        for (g, p) in gpus.iter().zip(&parts) {
            let mut bake = GpuBake::new(g, &tracer_of(), targets, config)?;
            bake.set_partition(p.index, p.count, p.block)?;
            bakes.push(bake);
        }
        let seconds = vec![0.0; bakes.len()];
        Ok(MultiGpuBake { bakes, parts, seconds })
    }

    /// Items per partition block.
    pub fn block(&self) -> usize {
        self.parts[0].block
    }

    /// The per-device bakes (their item ranges, kernels, batching).
    pub fn devices(&self) -> &[GpuBake<'g>] {
        &self.bakes
    }

    /// Sets every device's target time per dispatch (see [`GpuBake::set_batch_target`]).
    pub fn set_batch_target(&mut self, seconds: Option<f64>) {
        self.bakes.iter_mut().for_each(|b| b.set_batch_target(seconds));
    }

    /// Fixes every device's items per dispatch.
    pub fn set_chunk(&mut self, items: usize) {
        self.bakes.iter_mut().for_each(|b| b.set_chunk(items));
    }

    /// Passes run so far (every device runs the same passes).
    pub fn passes(&self) -> u64 {
        self.bakes[0].passes
    }

    /// Runs `n` passes on every device at once (one thread per device); returns when all
    /// are done. Errors name the device.
    pub fn run(&mut self, n: u64) -> Result<(), String> {
        let timed = |b: &mut GpuBake| {
            let t = std::time::Instant::now();
            b.run(n).map(|_| t.elapsed().as_secs_f64())
        };
        let results: Vec<Result<f64, String>> = if self.bakes.len() == 1 {
            vec![timed(&mut self.bakes[0])]
        } else {
            std::thread::scope(|s| {
                let handles: Vec<_> = self.bakes.iter_mut().map(|b| s.spawn(move || timed(b))).collect();
                handles.into_iter().map(|h| h.join().unwrap_or_else(|_| Err("bake thread panicked".into()))).collect()
            })
        };
        for (k, r) in results.into_iter().enumerate() {
            self.seconds[k] = r.map_err(|e| format!("device {k}: {e}"))?;
        }
        Ok(())
    }

    /// Wall seconds each device took in the last [`MultiGpuBake::run`] (its share of the
    /// imbalance shows here).
    pub fn device_seconds(&self) -> &[f64] {
        &self.seconds
    }

    /// The merged state: each item from the device that baked it.
    pub fn state(&self) -> Result<BakeState, String> {
        let mut merged = self.bakes[0].state()?;
        for (b, p) in self.bakes.iter().zip(&self.parts).skip(1) {
            let part = b.state()?;
            if part.passes != merged.passes {
                return Err(format!("devices disagree on the passes run ({} vs {})", part.passes, merged.passes));
            }
            for r in p.ranges(merged.moments.len()) {
                merged.moments[r.clone()].clone_from_slice(&part.moments[r.clone()]);
                for (m, q) in merged.encoders.iter_mut().zip(&part.encoders) {
                    m[r.clone()].clone_from_slice(&q[r.clone()]);
                }
            }
        }
        Ok(merged)
    }

    /// Replaces every device's state with `state` (resuming a checkpoint).
    pub fn upload(&mut self, state: &BakeState) -> Result<(), String> {
        self.bakes.iter_mut().try_for_each(|b| b.upload(state))
    }
}

impl crate::accumulate::Progressive for MultiGpuBake<'_> {
    fn run(&mut self, n: u64) -> Result<(), String> {
        MultiGpuBake::run(self, n)
    }
    fn state(&self) -> Result<BakeState, String> {
        MultiGpuBake::state(self)
    }
    fn passes(&self) -> u64 {
        MultiGpuBake::passes(self)
    }
}
