//! The state both bake paths (CPU and GPU) share: per-item moments of the plain estimate,
//! the per-basis progressive encoders, ray guiding's sums and the filtered state.

use super::{BakeConfig, Targets};
use crate::layout::lightmap::Lightmap;
use sbf::glam::{DVec3, Vec3};
use sbf::solve::ProgressiveEncoder;

/// Per-item accumulation of the plain estimate (E/π, or L for probes) and its square,
/// over accepted samples; and the counts of accepted and back-face-rejected samples.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Moments {
    pub sum: [f64; 3],
    pub sum_sq: [f64; 3],
    pub accepted: u64,
    pub back_faces: u64,
    /// Samples whose value overflowed f32 (a light of extreme intensity very close to
    /// the point): dropped from the estimate and the encoders, counted and reported.
    pub non_finite: u64,
}

impl Moments {
    /// Samples this item has had (accepted, rejected at a back face, or not finite): the
    /// index of its next sample.
    pub fn count(&self) -> u64 {
        self.accepted + self.back_faces + self.non_finite
    }

    /// Fraction of this item's samples that met a back face first (0 without samples).
    pub fn back_face_fraction(&self) -> f64 {
        let n = self.accepted + self.back_faces;
        if n == 0 {
            0.0
        } else {
            self.back_faces as f64 / n as f64
        }
    }
}

/// An item with more than this fraction of back-face samples is inside geometry:
/// invalid (texels: alpha 0 and dilated over; probes: flagged).
pub const MAX_BACK_FACE_FRACTION: f64 = 0.5;

/// One pass's result at an item, in the item's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ItemSample {
    /// The point sample's direction (tangent space for texels, world for probes).
    pub local: DVec3,
    pub radiance: Vec3,
    /// Known projections: (direction in the item's frame, p·c_l) per light sample (p: the
    /// point sample's pdf), the delta lights first.
    pub lights: Vec<(DVec3, [f64; 3])>,
    /// How many of `lights` are delta lights.
    pub delta: usize,
    /// The plain estimate's sample (E/π for texels, sphere-mean L for probes).
    pub estimate: Vec3,
    /// Rejected: the first hit was a single-sided back face.
    pub back_face: bool,
    /// The encoders' sample weight: the uniform pdf over the point sample's (1 unguided).
    pub weight: f64,
}

impl ItemSample {
    /// Whether every value is finite (else the sample is dropped and counted).
    pub fn is_finite(&self) -> bool {
        self.radiance.is_finite() && self.estimate.is_finite() && self.lights.iter().all(|(_, c)| c.iter().all(|x| x.is_finite()))
    }
}

/// The progressive state of a bake: everything needed to continue it.
#[derive(Debug, Clone)]
pub struct BakeState {
    pub passes: u64,
    /// Per item.
    pub moments: Vec<Moments>,
    /// `encoders[b][item]` for `config.bases[b]`.
    pub encoders: Vec<Vec<ProgressiveEncoder<f32>>>,
    /// Ray guiding: the learned sums, 256 bins per cluster (empty without guiding).
    pub guide_sums: Vec<f32>,
    /// Ray guiding: the sums the current stage's distributions were built from
    /// ([`crate::sampling::guiding::stage`]; empty without guiding).
    pub guide_basis: Vec<f32>,
    /// Filtered accumulation ([`crate::accumulate::filter`]; None without a filter).
    pub filtered: Option<crate::accumulate::filter::FilteredState>,
}

impl BakeState {
    /// An empty state for `targets` under `config`.
    pub fn new(config: &BakeConfig, targets: &Targets) -> BakeState {
        let encoders_for = |n: usize| -> Vec<Vec<ProgressiveEncoder<f32>>> {
            config
                .bases
                .iter()
                .map(|b| {
                    let o = config.encoder_options(*b, targets.sphere);
                    let lobes = b.lobes();
                    vec![ProgressiveEncoder::new(lobes, o); n]
                })
                .collect()
        };
        let encoders = encoders_for(targets.items.len());
        let guide_sums = match config.guiding {
            Some(_) if !targets.sphere => vec![0.0; targets.cluster_count * crate::sampling::guiding::BIN_COUNT],
            _ => Vec::new(),
        };
        let guide_basis = guide_sums.clone();
        let filtered = config.filter.filter(|_| !targets.sphere).map(|_| {
            let n = crate::accumulate::filter::gather_targets(targets).len();
            crate::accumulate::filter::FilteredState {
                encoders: encoders_for(n),
                moments: vec![Default::default(); n],
                negative_weights: 0,
            }
        });
        BakeState { passes: 0, moments: vec![Moments::default(); targets.items.len()], encoders, guide_sums, guide_basis, filtered }
    }

    /// Mean estimate per item over its accepted samples (E/π for texels, mean L for
    /// probes; 0 for an item with none).
    pub fn mean(&self) -> Vec<[f64; 3]> {
        self.moments.iter().map(|m| m.sum.map(|s| s / m.accepted.max(1) as f64)).collect()
    }

    /// Whether each item is valid: some accepted samples and a back-face fraction of at
    /// most [`MAX_BACK_FACE_FRACTION`].
    pub fn valid(&self) -> Vec<bool> {
        self.moments.iter().map(|m| m.accepted > 0 && m.back_face_fraction() <= MAX_BACK_FACE_FRACTION).collect()
    }

    /// Standard error of the mean per item and channel (∞ below two accepted samples).
    pub fn standard_error(&self) -> Vec<[f64; 3]> {
        self.moments
            .iter()
            .map(|m| {
                let n = m.accepted as f64;
                std::array::from_fn(|c| {
                    if n < 2.0 {
                        return f64::INFINITY;
                    }
                    let mean = m.sum[c] / n;
                    ((m.sum_sq[c] / n - mean * mean).max(0.0) / (n - 1.0)).sqrt()
                })
            })
            .collect()
    }

    /// Mean E/π over each chart's texels (RGB averaged) and over the whole lightmap (the
    /// last entry), with the variance of that mean from the texels' standard errors
    /// (independent texels): (mean, variance) for every chart with texels, then the scene.
    /// `targets` must be [`Targets::lightmap`] of `lm`.
    pub fn chart_means(&self, lm: &Lightmap, targets: &Targets) -> Vec<(f64, f64)> {
        let (m, se) = (self.mean(), self.standard_error());
        let mut out = vec![(0.0, 0.0, 0usize); lm.chart_meshes.len() + 1];
        for (k, &[_, _, id]) in targets.items.iter().enumerate() {
            let ch = lm.texels[id as usize].chart as usize;
            for slot in [ch, lm.chart_meshes.len()] {
                for c in 0..3 {
                    out[slot].0 += m[k][c];
                    out[slot].1 += se[k][c] * se[k][c];
                }
                out[slot].2 += 3;
            }
        }
        out.into_iter().filter(|x| x.2 > 0).map(|(s, v, n)| (s / n as f64, v / (n * n) as f64)).collect()
    }
}
