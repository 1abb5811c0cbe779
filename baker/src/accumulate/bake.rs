//! Progressive baking on the CPU (the reference path; rayon over items), and the state
//! both paths share.
//!
//! An item is a lightmap texel (hemisphere about its normal) or a light probe (whole
//! sphere). Sample p of item k uses its point p mod (its points) — every `count`
//! consecutive samples visit each point once — and draws every number from
//! [`crate::sampling::sequence`]: by default a shuffled, Owen-scrambled Sobol' point per (item, path
//! vertex, use) indexed by p — the baked point's direction with the guided mixture
//! choice, and each bounce's BSDF sample and next-event samples ([Roughton19 §6.2];
//! power-of-two prefixes of passes are nets, the order §7.3.1 asks for). Every random
//! number depends only on (seed, id, pass), so results are identical for any thread
//! count and a resumed bake equals an uninterrupted one.
//!
//! Each pass at an item yields a point sample L_in(ω_s) and light samples (ω_l, c_l)
//! (`trace::Tracer::sample_point`). They are (a) accumulated as plain irradiance
//! E/π = 2·L·cosθ_s + Σ c_l·cosθ_l/π (uniform hemisphere pdf 1/2π; probes accumulate the
//! sphere mean of L: L + Σ c_l/4π), with its second moment for a standard error, and
//! (b) added to every configured basis's progressive encoder (sbf's
//! `ProgressiveEncoder<f32>`, the twin of the WGSL update) with the light samples as
//! known projections p_s·c_l at ω_l, in tangent space (normal +Z) for texels, world
//! space for probes. A sample whose first hit is a single-sided back face is rejected
//! and counted; the means divide by the accepted count.
//!
//! With ray guiding ([`crate::sampling::guiding`]) a texel's point sample comes from a mixture of
//! density p instead: the estimate uses L·cosθ/(π·p), the encoders take the sample with
//! weight (1/2π)/p and the light samples' projections scaled by p.

use super::{BakeConfig, BakeState, ItemSample, Moments, Targets};
use crate::estimator::trace::Tracer;
use crate::sampling::sequence::{PathSampler, DIRECTION};
use crate::scene::geometry::frame;
use rayon::prelude::*;
use sbf::glam::{DVec3, Vec3};
use sbf::Basis;

/// A bake in progress on the CPU.
pub struct Bake<'a> {
    pub config: BakeConfig,
    pub targets: &'a Targets,
    pub tracer: Tracer<'a>,
    bases: Vec<Box<dyn Basis + Send + Sync>>,
    pub state: BakeState,
    /// Ray guiding's distributions once learning ended ([`crate::sampling::guiding::build`]).
    guide: Option<Vec<f32>>,
    /// Adaptive sampling's tiles (None: uniform passes).
    tiles: Option<crate::accumulate::adaptive::Tiles>,
    /// Filtered accumulation's layout (None without a filter).
    gather: Option<crate::accumulate::filter::GatherLayout>,
    /// The items this bake traces when it is a part of a bake
    /// ([`crate::accumulate::partition`]; the others keep their empty state); None: all.
    partition: Option<super::Partition>,
}

impl std::fmt::Debug for Bake<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bake").field("config", &self.config).field("passes", &self.state.passes).finish_non_exhaustive()
    }
}

impl<'a> Bake<'a> {
    /// Panics on a configuration [`BakeConfig::check`] refuses (the `baker` command
    /// checks first and reports).
    pub fn new(config: BakeConfig, targets: &'a Targets, tracer: Tracer<'a>) -> Self {
        let tracer = tracer.with_indirect_only(config.indirect_only);
        if let Err(e) = config.check(targets) {
            panic!("{e}");
        }
        let bases: Vec<_> = config.bases.iter().map(|k| config.basis(*k)).collect();
        let state = BakeState::new(&config, targets);
        let tiles = config.adaptive.map(|_| crate::accumulate::adaptive::Tiles::new(targets, targets.width).expect("checked"));
        let gather = config.filter.map(|f| crate::accumulate::filter::GatherLayout::new(targets, &f).expect("checked"));
        Bake { config, targets, tracer, bases, state, guide: None, tiles, gather, partition: None }
    }

    /// Continues from a saved state (see [`crate::checkpoint`]); its shape must match.
    pub fn resume(config: BakeConfig, targets: &'a Targets, tracer: Tracer<'a>, state: BakeState) -> Result<Self, String> {
        let tracer = tracer.with_indirect_only(config.indirect_only);
        let fresh = BakeState::new(&config, targets);
        let shape = |s: &BakeState| {
            (
                s.moments.len(),
                s.encoders.iter().map(|e| (e.len(), e.first().map(|x| x.coefficients().nrows()))).collect::<Vec<_>>(),
                s.guide_sums.len(),
                s.guide_basis.len(),
            )
        };
        if shape(&fresh) != shape(&state) {
            return Err("the saved state does not match this bake's targets and bases".into());
        }
        let mut b = Bake::new(config, targets, tracer);
        b.state = state;
        if let Some(g) = b.config.guiding {
            if !b.state.guide_basis.is_empty() && b.state.passes >= g.learn_passes {
                b.guide = Some(crate::sampling::guiding::build(&b.state.guide_basis));
            }
        }
        Ok(b)
    }

    /// Bakes only the items of `p` (a shard of a bake spread over machines); the others
    /// keep their empty state. Refused for the strategies that read every item each pass.
    pub fn set_partition(&mut self, p: super::Partition) -> Result<(), String> {
        if p.count > 1 {
            self.config.check_partitionable()?;
        }
        self.partition = (p.count > 1).then_some(p);
        Ok(())
    }

    /// The configured bases' sbf objects.
    pub fn bases(&self) -> &[Box<dyn Basis + Send + Sync>] {
        &self.bases
    }

    /// Runs one pass (one path per item) — or, in an adaptive bake after its pilot
    /// passes, one batch ([`crate::accumulate::adaptive`]).
    pub fn pass(&mut self) {
        match (self.config.adaptive, &self.tiles) {
            (Some(a), Some(tiles)) if self.state.passes >= a.pilot_passes => {
                let rate = crate::accumulate::adaptive::rates(tiles, &self.state.moments, &a);
                let (seq, seed, batch) = (self.config.sampler, self.config.seed, self.state.passes);
                // Each texel's samples of this batch, in order: (item, sample index).
                let list: Vec<(u32, u64)> = (0..self.targets.items.len())
                    .flat_map(|k| {
                        let n = crate::accumulate::adaptive::samples_in_batch(seq, seed, self.targets.items[k][2], batch, rate[k]);
                        let first = self.state.moments[k].count();
                        (0..n as u64).map(move |j| (k as u32, first + j))
                    })
                    .collect();
                let samples = self.trace_items(&list);
                self.absorb(&list, &samples);
            }
            _ => match self.config.camera {
                Some(c) if self.state.passes >= c.pilot_passes => {
                    let batch = self.state.passes;
                    let counts = crate::accumulate::camera::pixel_counts(
                        &c.camera,
                        crate::accumulate::camera::jitter(batch),
                        self.tracer.bvh,
                        self.targets,
                    );
                    let list: Vec<(u32, u64)> = (0..self.targets.items.len())
                        .flat_map(|k| {
                            let first = self.state.moments[k].count();
                            (0..counts[k].min(c.max_per_batch) as u64).map(move |j| (k as u32, first + j))
                        })
                        .collect();
                    let samples = self.trace_items(&list);
                    self.absorb(&list, &samples);
                }
                _ => {
                    self.pass_samples();
                }
            },
        }
    }

    /// Paths traced so far: the sum of every item's sample count.
    pub fn paths(&self) -> u64 {
        self.state.moments.iter().map(Moments::count).sum()
    }

    /// Ray guiding: at the start of each stage ([`crate::sampling::guiding::stage`]) the
    /// distributions are rebuilt from the sums of every pass so far, which are kept as
    /// the stage's basis (a resumed bake rebuilds exactly what it had).
    fn build_guide(&mut self) {
        if let Some(g) = self.config.guiding {
            let p = self.state.passes;
            if !self.state.guide_sums.is_empty() && p >= g.learn_passes && crate::sampling::guiding::stage(p, g.learn_passes).1 == p {
                self.state.guide_basis.clone_from(&self.state.guide_sums);
                self.guide = Some(crate::sampling::guiding::build(&self.state.guide_basis));
            }
        }
    }

    /// Runs one pass and returns its samples per item — e.g. to fit the same samples in
    /// batch.
    pub fn pass_samples(&mut self) -> Vec<ItemSample> {
        let p = self.state.passes;
        let n = self.targets.items.len();
        let all: Vec<(u32, u64)> = match &self.partition {
            Some(part) => part.ranges(n).flatten().map(|k| (k as u32, p)).collect(),
            None => (0..n as u32).map(|k| (k, p)).collect(),
        };
        let samples = self.trace_items(&all);
        self.absorb(&all, &samples);
        samples
    }

    /// Traces sample p_k of each listed item (k, p_k), in parallel.
    fn trace_items(&self, list: &[(u32, u64)]) -> Vec<ItemSample> {
        let p = self.state.passes;
        let seed = self.config.seed;
        let sampler = self.config.sampler;
        let tracer = &self.tracer;
        let tg = self.targets;
        let guide = self.config.guiding.filter(|_| !self.state.guide_sums.is_empty());
        let dists = self.guide.as_deref();
        list.par_iter()
            .map(|&(k, pk)| {
                let ([first, count, id], cluster) = (tg.items[k as usize], tg.clusters[k as usize]);
                let mut smp = PathSampler::new(sampler, seed, id, pk);
                if let Some(g) = guide {
                    // A guided bake's numbers: the stage's own (PathSampler::staged).
                    let (k, start) = crate::sampling::guiding::stage(p, g.learn_passes);
                    smp = smp.staged(k, start);
                }
                let u = smp.get(DIRECTION);
                let pt = &tg.points[(first as u64 + pk % count as u64) as usize];
                let normal = (!tg.sphere).then_some((pt.normal, pt.geometric));
                match guide {
                    Some(g) => {
                        use crate::sampling::guiding::CDF_LEN;
                        let dist = dists.map(|d| &d[cluster as usize * CDF_LEN..(cluster as usize + 1) * CDF_LEN]);
                        let (local, dir, pdf) = tg.guided_direction(u, pt.normal, dist, g.guided_fraction);
                        let (tn, bn) = frame(pt.normal);
                        let pdf_of = |w: Vec3| match dist {
                            Some(d) => {
                                let l = DVec3::new(w.dot(tn) as f64, w.dot(bn) as f64, w.dot(pt.normal) as f64);
                                crate::sampling::guiding::mixture_pdf(d, l, g.guided_fraction)
                            }
                            None => 0.5 / std::f64::consts::PI,
                        };
                        let s = tracer.sample_point_with(pt.position, normal, dir, &pdf_of, &mut smp);
                        let w = (local.z / (std::f64::consts::PI * pdf)) as f32;
                        tg.item_sample(pt.normal, local, w, pdf, s)
                    }
                    None => {
                        let (local, dir, w) = tg.direction(u, pt.normal);
                        let s = tracer.sample_point(pt.position, normal, dir, &mut smp);
                        let p_s = if tg.sphere { 0.25 / std::f64::consts::PI } else { 0.5 / std::f64::consts::PI };
                        tg.item_sample(pt.normal, local, w, p_s, s)
                    }
                }
            })
            .collect()
    }

    /// Feeds the listed items' samples to the guiding sums (uniform passes), the moments
    /// and the encoders, in item order; one more pass or batch.
    fn absorb(&mut self, list: &[(u32, u64)], samples: &[ItemSample]) {
        let tg = self.targets;
        // Per item, its samples of this pass or batch, in order (the list is sorted by
        // item, then sample index).
        let mut of_item: Vec<&[ItemSample]> = vec![&[]; tg.items.len()];
        let mut start = 0;
        while start < list.len() {
            let k = list[start].0;
            let end = start + list[start..].iter().take_while(|(j, _)| *j == k).count();
            of_item[k as usize] = &samples[start..end];
            start = end;
        }
        if !self.state.guide_sums.is_empty() {
            // Every pass learns from the point sample and the area-light samples, in item
            // order: deterministic sums (the GPU gathers the same). Each value estimates
            // (1/2π)·∫_bin L cosθ: the point sample's lum(L)·(1/2π)/p (L MIS-weighted), a
            // light sample's lum(c)/2π (c = L·w/p_l, stored here as p·c).
            let lum = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
            for (ss, &c) in of_item.iter().zip(&tg.clusters) {
                for s in ss.iter().filter(|s| !s.back_face && s.is_finite()) {
                    let v = crate::scene::lights::luminance(s.radiance) * s.weight;
                    crate::sampling::guiding::record(&mut self.state.guide_sums, c, s.local, v as f32);
                    for (ld, cl) in &s.lights[s.delta..] {
                        crate::sampling::guiding::record(&mut self.state.guide_sums, c, *ld, (lum(*cl) * s.weight) as f32);
                    }
                }
            }
        }
        self.state.moments.par_iter_mut().zip(of_item.par_iter()).for_each(|(m, ss)| {
            for s in ss.iter() {
                if s.back_face {
                    m.back_faces += 1;
                } else if !s.is_finite() {
                    m.non_finite += 1;
                } else {
                    m.accepted += 1;
                    for c in 0..3 {
                        m.sum[c] += s.estimate[c] as f64;
                        m.sum_sq[c] += (s.estimate[c] as f64).powi(2);
                    }
                }
            }
        });
        for (b, encs) in self.state.encoders.iter_mut().enumerate() {
            let basis = &self.bases[b];
            encs.par_iter_mut().zip(of_item.par_iter()).for_each(|(enc, ss)| {
                for s in ss.iter().filter(|s| !s.back_face && s.is_finite()) {
                    let l = [s.radiance.x as f64, s.radiance.y as f64, s.radiance.z as f64];
                    // Finite (checked above) and of the encoder's size: cannot fail.
                    if let Err(e) = enc.add_sample_projected(basis.as_ref(), s.local, l, s.weight, &s.lights) {
                        panic!("encoder refused a finite sample: {e}");
                    }
                }
            });
        }
        if let (Some(layout), Some(f), Some(fs)) = (&self.gather, &self.config.filter, &mut self.state.filtered) {
            // Each sample's point (its continuous position), per item in order.
            let mut per_item: crate::accumulate::filter::ItemSamples = vec![Vec::new(); tg.items.len()];
            for (&(k, pk), s) in list.iter().zip(samples) {
                let [first, count, _] = tg.items[k as usize];
                per_item[k as usize].push(((first as u64 + pk % count as u64) as u32, s));
            }
            crate::accumulate::filter::gather_batch(layout, f, tg, &self.bases, &per_item, fs);
        }
        self.state.passes += 1;
        self.build_guide();
    }
}
