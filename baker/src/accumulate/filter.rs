//! Filtered gather-based accumulation ([Roughton19 §3.2], Listings 3.1–3.2).
//!
//! Every sample has a continuous position in the atlas: the sub-texel position its baked
//! point was rasterised at ([`crate::layout::lightmap::SUBSAMPLES`], a 4 × 4 grid per texel). With a
//! filter, each *gather target* — every texel a chart's triangles overlap, covered or not
//! ([`crate::layout::lightmap::Lightmap::texel_charts`]) — gathers, after each pass or batch, the
//! samples of every texel of its own chart within the filter's reach, each weighted by the
//! separable filter of its position's offset from the target's centre, neighbours in
//! row-major order and each neighbour's samples in order. The filter weight multiplies
//! the encoders' sample weight (the progressive encoders take per-sample weights; the
//! light samples' known projections ride with the same weight) and feeds a weighted
//! Welford running mean and variance of the plain estimate (West 1979).
//!
//! Texels whose sub-positions all miss the geometry but that a triangle overlaps thus get
//! a value from the samples around them instead of being left empty for dilation.
//!
//! Mitchell–Netravali's negative lobes: the progressive encoders and the weighted Welford
//! update need positive weights (a running total weight that can shrink towards zero
//! divides by it), so samples whose weight is ≤ 0 are not gathered; bake.json says so and
//! counts them. Box and Gaussian weights are never negative.
//!
//! CPU here ([`gather_batch`]); the GPU twin is `gpu/wgsl/filter_gather.wgsl`.

use crate::accumulate::{ItemSample, Targets};
use crate::layout::lightmap::NO_CHART;
use rayon::prelude::*;
use sbf::basis::Basis;
use sbf::solve::ProgressiveEncoder;

/// The reconstruction filter of the gather: separable, w(d) = f(d.x)·f(d.y) for the offset
/// d of a path's continuous atlas position from the texel centre, zero from `radius` on.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GatherFilter {
    /// 1 inside the radius.
    Box,
    /// exp(−d²/2σ²) − exp(−r²/2σ²), σ = r/2, clamped at 0 (zero at the radius).
    Gaussian,
    /// Mitchell–Netravali with B = C = 1/3 over [−r, r] (negative lobes included).
    Mitchell,
}

impl GatherFilter {
    /// The kernel code of `filter_kernel.wgsl`.
    pub fn code(self) -> u32 {
        match self {
            GatherFilter::Box => 0,
            GatherFilter::Gaussian => 1,
            GatherFilter::Mitchell => 2,
        }
    }
    /// The 1D weight at offset `d` for radius `r` (the WGSL `filter_1d`, same f32 steps).
    pub fn weight_1d(self, r: f32, d: f32) -> f32 {
        let a = d.abs();
        match self {
            GatherFilter::Box => (a < r) as u32 as f32,
            GatherFilter::Gaussian => {
                let s2 = 2.0 * (0.5 * r) * (0.5 * r);
                ((-d * d / s2).exp() - (-r * r / s2).exp()).max(0.0)
            }
            GatherFilter::Mitchell => {
                let x = 2.0 * a / r;
                let (b, c) = (1.0f32 / 3.0, 1.0f32 / 3.0);
                if x < 1.0 {
                    ((12.0 - 9.0 * b - 6.0 * c) * x * x * x + (-18.0 + 12.0 * b + 6.0 * c) * x * x + (6.0 - 2.0 * b)) / 6.0
                } else if x < 2.0 {
                    ((-b - 6.0 * c) * x * x * x + (6.0 * b + 30.0 * c) * x * x + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)) / 6.0
                } else {
                    0.0
                }
            }
        }
    }
}

/// Texels on each side a gather of radius `r` must visit: a path of texel x + k lies at
/// least k − ½ from the centre of x, so k < r + ½.
pub fn gather_reach(r: f32) -> u32 {
    ((r + 0.5).ceil() as u32).saturating_sub(1)
}

/// A reconstruction filter and its radius in texels.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Filter {
    pub kernel: GatherFilter,
    pub radius: f32,
}

/// Roughton's radius (LlamaEngine's 1.5-texel support, footnote 4 of §3.2).
pub const DEFAULT_RADIUS: f32 = 1.5;

impl Filter {
    /// `box`, `gaussian` or `mitchell`, optionally `:radius` (texels; default 1.5).
    pub fn parse(s: &str) -> Result<Filter, String> {
        let (name, radius) = match s.split_once(':') {
            Some((n, r)) => (n, r.parse::<f32>().map_err(|_| format!("filter radius '{r}' is not a number"))?),
            None => (s, DEFAULT_RADIUS),
        };
        let kernel = match name {
            "box" => GatherFilter::Box,
            "gaussian" => GatherFilter::Gaussian,
            "mitchell" => GatherFilter::Mitchell,
            _ => return Err(format!("unknown filter '{name}' (box, gaussian or mitchell, optionally :radius)")),
        };
        let f = Filter { kernel, radius };
        f.validate()?;
        Ok(f)
    }

    pub fn validate(&self) -> Result<(), String> {
        // Below half a texel a box would miss the texel's own outer sub-positions; the
        // upper bound keeps a gather's neighbourhood (2·reach + 1)² small.
        if !(self.radius.is_finite() && (0.5..=4.0).contains(&self.radius)) {
            return Err(format!("filter radius must be in [0.5, 4] texels, not {}", self.radius));
        }
        Ok(())
    }

    pub fn name(&self) -> &'static str {
        match self.kernel {
            GatherFilter::Box => "box",
            GatherFilter::Gaussian => "gaussian",
            GatherFilter::Mitchell => "mitchell",
        }
    }

    /// The 2D weight of a sample at atlas position `p` for the texel (x, y).
    pub fn weight(&self, x: usize, y: usize, p: [f32; 2]) -> f32 {
        let d = [p[0] - (x as f32 + 0.5), p[1] - (y as f32 + 0.5)];
        self.kernel.weight_1d(self.radius, d[0]) * self.kernel.weight_1d(self.radius, d[1])
    }
}

/// Where the gather runs: the targets (atlas ids with a chart), and the maps it reads.
#[derive(Debug, Clone)]
pub struct GatherLayout {
    pub width: usize,
    pub height: usize,
    /// Atlas ids of the gather targets, in item order first (the texels with samples, so
    /// target k < items is item k), then the covered-by-none texels in row-major order.
    pub targets: Vec<u32>,
    /// Per atlas texel: its chart ([`NO_CHART`]: neither gathers nor is gathered from).
    pub charts: Vec<u32>,
    /// Per atlas texel: its item, or `u32::MAX`.
    pub item_of: Vec<u32>,
    /// Texels on each side of a target that the filter reaches.
    pub reach: usize,
}

impl GatherLayout {
    /// The layout of a lightmap's targets under `filter`.
    pub fn new(targets: &Targets, filter: &Filter) -> Result<GatherLayout, String> {
        if targets.sphere {
            return Err("filtered accumulation applies to lightmap texels, not probes".into());
        }
        let (w, h) = (targets.width, targets.height);
        let charts = targets.texel_charts.clone();
        if charts.len() != w * h {
            return Err(format!("filtered accumulation: {} texel charts for a {w}×{h} atlas", charts.len()));
        }
        let mut item_of = vec![u32::MAX; w * h];
        for (k, it) in targets.items.iter().enumerate() {
            item_of[it[2] as usize] = k as u32;
        }
        let list = gather_targets(targets);
        Ok(GatherLayout { width: w, height: h, targets: list, charts, item_of, reach: gather_reach(filter.radius) as usize })
    }

    /// The gather targets that are not items (covered by no sub-position).
    pub fn uncovered(&self, items: usize) -> usize {
        self.targets.len() - items
    }
}

/// The atlas ids of the gather targets of lightmap `targets`: the items' texels in item
/// order, then every other texel with a chart in row-major order.
pub fn gather_targets(targets: &Targets) -> Vec<u32> {
    let mut is_item = vec![false; targets.texel_charts.len()];
    let mut list: Vec<u32> = targets.items.iter().map(|it| it[2]).collect();
    for t in &list {
        is_item[*t as usize] = true;
    }
    list.extend((0..targets.texel_charts.len() as u32).filter(|t| targets.texel_charts[*t as usize] != NO_CHART && !is_item[*t as usize]));
    list
}

/// Weighted running mean and variance (West 1979's weighted Welford update).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WeightedMoments {
    /// Σw, Σw².
    pub weight: f64,
    pub weight_sq: f64,
    pub mean: [f64; 3],
    /// Σ w·(x − mean)² (updated in place).
    pub m2: [f64; 3],
    pub samples: u64,
}

impl WeightedMoments {
    /// Adds x with weight w > 0.
    pub fn add(&mut self, x: [f64; 3], w: f64) {
        self.samples += 1;
        self.weight += w;
        self.weight_sq += w * w;
        let r = w / self.weight;
        for c in 0..3 {
            let d = x[c] - self.mean[c];
            self.mean[c] += r * d;
            self.m2[c] += w * d * (x[c] - self.mean[c]);
        }
    }

    /// Standard error of the weighted mean: the weighted variance with the effective
    /// sample count n_e = (Σw)²/Σw² (σ² ≈ M2/Σw · n_e/(n_e − 1)), times √(Σw²)/Σw.
    /// ∞ below two effective samples.
    pub fn standard_error(&self) -> [f64; 3] {
        let ne = if self.weight_sq > 0.0 { self.weight * self.weight / self.weight_sq } else { 0.0 };
        std::array::from_fn(|c| {
            if ne < 2.0 - 1e-9 || self.samples < 2 {
                return f64::INFINITY;
            }
            let var = (self.m2[c] / self.weight).max(0.0) * ne / (ne - 1.0);
            (var / ne).sqrt()
        })
    }
}

/// The filtered accumulation of a bake: per gather target, its encoders and moments.
#[derive(Debug, Clone)]
pub struct FilteredState {
    /// `encoders[b][target]`.
    pub encoders: Vec<Vec<ProgressiveEncoder<f32>>>,
    pub moments: Vec<WeightedMoments>,
    /// Samples not gathered because their filter weight was negative (Mitchell's lobes).
    pub negative_weights: u64,
}

/// One pass's or batch's samples, per item: `(point index, sample)` in order.
pub type ItemSamples<'a> = Vec<Vec<(u32, &'a ItemSample)>>;

/// Gathers one pass's or batch's samples into every target (in parallel over targets; the
/// order within a target is fixed, so the result does not depend on the thread count).
pub fn gather_batch(
    layout: &GatherLayout,
    filter: &Filter,
    targets: &Targets,
    bases: &[Box<dyn Basis + Send + Sync>],
    of_item: &ItemSamples,
    state: &mut FilteredState,
) {
    let (w, h, reach) = (layout.width, layout.height, layout.reach);
    let gathered = |t: usize| -> Vec<(&ItemSample, f64)> {
        let (x, y) = (t % w, t / w);
        let chart = layout.charts[t];
        let mut out = Vec::new();
        for ny in y.saturating_sub(reach)..=(y + reach).min(h - 1) {
            for nx in x.saturating_sub(reach)..=(x + reach).min(w - 1) {
                let n = ny * w + nx;
                let item = layout.item_of[n];
                if layout.charts[n] != chart || item == u32::MAX {
                    continue;
                }
                for (point, s) in &of_item[item as usize] {
                    if s.back_face || !s.is_finite() {
                        continue;
                    }
                    let wf = filter.weight(x, y, targets.point_uv[*point as usize]);
                    if wf != 0.0 {
                        out.push((*s, wf as f64));
                    }
                }
            }
        }
        out
    };
    // Each target's gathered samples, once (negative weights counted, not gathered).
    let lists: Vec<Vec<(&ItemSample, f64)>> = layout.targets.par_iter().map(|&t| gathered(t as usize)).collect();
    let FilteredState { encoders, moments, negative_weights } = state;
    *negative_weights += lists.iter().map(|l| l.iter().filter(|(_, wf)| *wf < 0.0).count() as u64).sum::<u64>();
    moments.par_iter_mut().zip(lists.par_iter()).for_each(|(m, list)| {
        for (s, wf) in list.iter().filter(|(_, wf)| *wf > 0.0) {
            m.add(s.estimate.to_array().map(|v| v as f64), *wf);
        }
    });
    for (b, encs) in encoders.iter_mut().enumerate() {
        let basis = bases[b].as_ref();
        encs.par_iter_mut().zip(lists.par_iter()).for_each(|(enc, list)| {
            for (s, wf) in list.iter().filter(|(_, wf)| *wf > 0.0) {
                let l = s.radiance.to_array().map(|v| v as f64);
                // Finite (checked above) and of the encoder's size: cannot fail.
                if let Err(e) = enc.add_sample_projected(basis, s.local, l, s.weight * wf, &s.lights) {
                    panic!("encoder refused a finite sample: {e}");
                }
            }
        });
    }
}
