//! Progressive baking on the CPU (the reference path; rayon over items), and the state
//! both paths share.
//!
//! An item is a lightmap texel (hemisphere about its normal) or a light probe (whole
//! sphere). Sample p of item k uses its point p mod (its points) — every `count`
//! consecutive samples visit each point once — and draws every number from
//! [`crate::sampler`]: by default a shuffled, Owen-scrambled Sobol' point per (item, path
//! vertex, use) indexed by p — the baked point's direction with the guided mixture
//! choice, and each bounce's BSDF sample and next-event samples (seed 004 §6.2;
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
//! With ray guiding ([`crate::guiding`]) a texel's point sample comes from a mixture of
//! density p instead: the estimate uses L·cosθ/(π·p), the encoders take the sample with
//! weight (1/2π)/p and the light samples' projections scaled by p.

use crate::lightmap::{frame, Lightmap, SurfacePoint};
use crate::sampler::{PathSampler, Sequence, DIRECTION};
use crate::trace::Tracer;
use rayon::prelude::*;
use sbf::glam::{DVec3, Vec3};
use sbf::solve::{ProgressiveEncoder, ProgressiveOptions};
use sbf::Basis;

/// Sharpness of the hemisphere SG sets (9 and 12 lobes), "experimentally selected" as
/// in seed 004 §7.2 after Pettineo and Neubelt; the same λ = 6 as the `probes` tool's
/// `sg9h`/`sg12h` and the Appendix C tests. (Probulator's spacing heuristic,
/// `sbf::layout::sharpness_from_spacing`, is meant for sphere sets: on the 9-lobe
/// hemisphere spiral it gives λ ≈ 56, lobes too narrow to represent a constant.)
pub const SG_HEMISPHERE_SHARPNESS: f64 = 6.0;

/// Acceleration α of the progressive update for path-traced samples. The seed's α = 3
/// (sbf's default, tuned on noise-free map samples) amplifies Monte Carlo noise: on the
/// built-in scene at 256 samples per texel, AD9 progressive NNLS with α = 3 has 1.69×
/// the irradiance RMSE of a batch NNLS fit of the same samples, α = 2 1.35×, α = 1
/// 0.96× (tests/convergence.rs prints the comparison).
pub const BAKE_ACCELERATION: f64 = 1.0;

/// A basis the baker encodes into.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BasisKind {
    ShL1,
    ShL2,
    Sg9,
    Sg12,
    Ad9,
    Ad12,
}

impl BasisKind {
    pub const ALL: [(BasisKind, &'static str); 6] = [
        (BasisKind::ShL1, "sh1"),
        (BasisKind::ShL2, "sh2"),
        (BasisKind::Sg9, "sg9"),
        (BasisKind::Sg12, "sg12"),
        (BasisKind::Ad9, "ad9"),
        (BasisKind::Ad12, "ad12"),
    ];
    pub fn parse(s: &str) -> Option<BasisKind> {
        Self::ALL.iter().find(|(_, n)| *n == s).map(|(k, _)| *k)
    }
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(k, _)| *k == self).map(|(_, n)| *n).unwrap_or("?")
    }
    /// The sbf basis in tangent space (hemisphere lobes for SG; the seed's 9-lobe set for AD9).
    pub fn basis(self) -> Box<dyn Basis + Send + Sync> {
        match self {
            BasisKind::ShL1 => Box::new(sbf::ShBasis::new(1).expect("order 1")),
            BasisKind::ShL2 => Box::new(sbf::ShBasis::new(2).expect("order 2")),
            BasisKind::Sg9 | BasisKind::Sg12 => {
                let (axes, lambda) = self.sg_lobes();
                Box::new(sbf::SgBasis::new(&axes, lambda, false).expect("SG basis"))
            }
            BasisKind::Ad9 => Box::new(sbf::AmbientDiceSrbf::nine_hemisphere()),
            BasisKind::Ad12 => Box::new(sbf::AmbientDiceSrbf::twelve()),
        }
    }
    /// SG lobe axes (Vogel hemisphere about +Z) and their shared sharpness
    /// [`SG_HEMISPHERE_SHARPNESS`].
    pub fn sg_lobes(self) -> (Vec<DVec3>, f64) {
        let n = if self == BasisKind::Sg9 { 9 } else { 12 };
        (sbf::layout::vogel_hemisphere(n).expect("vogel layout"), SG_HEMISPHERE_SHARPNESS)
    }
    /// Whether every basis function is ≥ 0 (so a non-negativity constraint on the
    /// coefficients means something): SG and Ambient Dice SRBF lobes, not SH.
    pub fn non_negative(self) -> bool {
        !matches!(self, BasisKind::ShL1 | BasisKind::ShL2)
    }
    /// Whether the basis covers the whole sphere (else the upper hemisphere).
    pub fn is_sphere(self) -> bool {
        matches!(self, BasisKind::ShL1 | BasisKind::ShL2 | BasisKind::Ad12)
    }
}

/// Least squares or non-negative least squares (progressive, seed §7.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver {
    Ls,
    Nnls,
}

/// Bake settings.
#[derive(Debug, Clone, PartialEq)]
pub struct BakeConfig {
    pub seed: u64,
    pub max_bounces: u32,
    pub bases: Vec<BasisKind>,
    pub solver: Solver,
    /// First-bounce ray guiding of lightmap texels ([`crate::guiding`]); probes are never
    /// guided.
    pub guiding: Option<crate::guiding::GuidingOptions>,
    /// The sample sequences ([`crate::sampler`]).
    pub sampler: Sequence,
    /// Adaptive sampling of lightmap texels ([`crate::adapt`]); None: every texel every
    /// pass. Not with ray guiding, probes or several GPUs.
    pub adaptive: Option<crate::adapt::AdaptiveOptions>,
    /// Camera-based sampling of lightmap texels ([`crate::camera`]); not with
    /// `adaptive`, guiding, probes or several GPUs.
    pub camera: Option<crate::camera::CameraSampling>,
    /// How a GPU bake runs its passes ([`Pipeline`]); the CPU bake ignores it.
    pub pipeline: Pipeline,
    /// Filtered gather-based accumulation ([`crate::filter`]); None: each sample feeds
    /// its own texel only (a one-texel box). Lightmaps only.
    pub filter: Option<crate::filter::Filter>,
}

/// How the GPU runs a pass: one thread per texel through whole paths, or breadth first
/// (seed 004 §3.1, §5.1; [`crate::wavefront`]). Both run the same estimator on the same
/// sample numbers, so the choice changes the time, not the bake.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pipeline {
    /// One kernel, one thread per job through whole paths (`trace.wgsl`'s `bake_pass`).
    #[default]
    Megakernel,
    /// Generate, then per bounce intersect, shade and compact the active paths, then
    /// accumulate ([`crate::wavefront`]).
    Wavefront,
}

impl Pipeline {
    pub fn parse(s: &str) -> Option<Pipeline> {
        match s {
            "megakernel" => Some(Pipeline::Megakernel),
            "wavefront" => Some(Pipeline::Wavefront),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Pipeline::Megakernel => "megakernel",
            Pipeline::Wavefront => "wavefront",
        }
    }
}

impl Default for BakeConfig {
    /// The `baker` command's defaults: seed 1, 4 bounces, SH L2 and Ambient Dice 9 with
    /// NNLS (where it applies), Sobol' sequences, uniform passes on the megakernel, no
    /// guiding and no filter.
    fn default() -> Self {
        BakeConfig {
            seed: 1,
            max_bounces: 4,
            bases: vec![BasisKind::ShL2, BasisKind::Ad9],
            solver: Solver::Nnls,
            guiding: None,
            sampler: Default::default(),
            adaptive: None,
            camera: None,
            pipeline: Default::default(),
            filter: None,
        }
    }
}

impl BakeConfig {
    /// Refuses combinations the bake cannot run, with the reason.
    pub fn check(&self, targets: &Targets) -> Result<(), String> {
        if let Some(f) = &self.filter {
            f.validate()?;
            if targets.sphere {
                return Err("filtered accumulation applies to lightmap texels, not probes".into());
            }
        }
        if let Some(c) = &self.camera {
            c.validate()?;
            if targets.sphere {
                return Err("camera-based sampling applies to lightmap texels, not probes".into());
            }
            if self.guiding.is_some() || self.adaptive.is_some() {
                return Err("camera-based sampling cannot be combined with ray guiding or adaptive sampling".into());
            }
        }
        if let Some(a) = &self.adaptive {
            a.validate()?;
            if targets.sphere {
                return Err("adaptive sampling applies to lightmap texels, not probes".into());
            }
            if self.guiding.is_some() {
                return Err("adaptive sampling and ray guiding cannot be combined (guiding learns from whole passes)".into());
            }
        }
        Ok(())
    }

    /// The progressive options for `basis` on these targets: Gauss–Seidel with the
    /// eq. 7.15 denominator at acceleration [`BAKE_ACCELERATION`]; sphere bases on
    /// texels see only the upper hemisphere, so mirrored zero samples pin the lower half
    /// (seed §7.3's hemisphere handling); probes sample the whole sphere.
    /// NNLS applies only to bases whose functions are non-negative (SG, Ambient Dice):
    /// SH coefficients of a non-negative signal are legitimately negative, so SH is
    /// always least squares ([`BasisKind::non_negative`]).
    pub fn encoder_options(&self, basis: BasisKind, sphere_targets: bool) -> ProgressiveOptions {
        let opts = match self.solver {
            Solver::Nnls if basis.non_negative() => ProgressiveOptions::non_negative(),
            _ => ProgressiveOptions::default(),
        };
        ProgressiveOptions { acceleration: BAKE_ACCELERATION, mirror_hemisphere: basis.is_sphere() && !sphere_targets, ..opts }
    }
}

/// What a bake samples: lightmap texels or probe positions.
#[derive(Debug, Clone)]
pub struct Targets {
    pub points: Vec<SurfacePoint>,
    /// Per item: (first point, point count, id): the id is the texel index in the
    /// lightmap or the probe index; it seeds the item's random numbers.
    pub items: Vec<[u32; 3]>,
    /// Probes: directions over the whole sphere in world space.
    pub sphere: bool,
    /// Number of ids (texels in the atlas, or probes).
    pub slots: usize,
    /// Per item: its ray-guiding cluster ([`crate::guiding::clusters`]; 0 for probes).
    pub clusters: Vec<u32>,
    pub cluster_count: usize,
    /// The atlas size in texels (ids are y·width + x); 0 × 0 for probes.
    pub width: usize,
    pub height: usize,
    /// Atlas UV (in texels) of every vertex of every triangle, `[mesh][triangle]` (see
    /// [`Lightmap::triangle_uv`]; empty for probes): camera-based sampling finds texels by it.
    pub triangle_uv: Vec<Vec<[sbf::glam::Vec2; 3]>>,
    /// Per point, its continuous atlas position in texels (the sub-texel position it was
    /// rasterised at; [`crate::filter`]); empty for probes.
    pub point_uv: Vec<[f32; 2]>,
    /// Per atlas texel, the chart a filtered gather treats it as part of
    /// ([`Lightmap::texel_charts`]); empty for probes.
    pub texel_charts: Vec<u32>,
}

/// The side of the texel tiles whose order lightmap items follow ([`Targets::lightmap`]).
pub const TILE: u32 = 8;

impl Targets {
    /// Every valid texel of a lightmap.
    pub fn lightmap(lm: &Lightmap) -> Targets {
        // Items in tile order (seed 004 §5.2, eq. 5.2): 8 × 8 texel tiles, row by row
        // within a tile, so that consecutive GPU threads bake a compact block of texels
        // (nearby origins, similar normals) rather than a strip of one row.
        let tiles_per_row = lm.width.div_ceil(TILE as usize) as u32;
        let mut order: Vec<usize> = (0..lm.texels.len()).filter(|k| lm.texels[*k].is_valid()).collect();
        order.sort_by_key(|k| {
            crate::gpu_prims::tile_index((k % lm.width) as u32, (k / lm.width) as u32, TILE.trailing_zeros(), tiles_per_row)
        });
        // Guiding's clusters come per valid texel in row-major order.
        let (row_major, cluster_count) = crate::guiding::clusters(lm);
        let mut cluster_of = vec![u32::MAX; lm.texels.len()];
        let valid = (0..lm.texels.len()).filter(|k| lm.texels[*k].is_valid());
        for (k, c) in valid.zip(row_major) {
            cluster_of[k] = c;
        }
        let (mut points, mut items, mut clusters, mut point_uv) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for k in order {
            let t = &lm.texels[k];
            items.push([points.len() as u32, t.points.len() as u32, k as u32]);
            points.extend_from_slice(&t.points);
            clusters.push(cluster_of[k]);
            // The points are in coverage-bit order; bit s is sub-position (s % 4, s / 4).
            let (x, y) = ((k % lm.width) as f32, (k / lm.width) as f32);
            let sub = |s: usize| [x + ((s % 4) as f32 + 0.5) / 4.0, y + ((s / 4) as f32 + 0.5) / 4.0];
            point_uv.extend((0..crate::lightmap::SUBSAMPLES).filter(|s| t.coverage & (1 << s) != 0).map(sub));
        }
        Targets {
            points,
            items,
            sphere: false,
            slots: lm.texels.len(),
            clusters,
            cluster_count,
            width: lm.width,
            height: lm.height,
            triangle_uv: lm.triangle_uv.clone(),
            point_uv,
            texel_charts: lm.texel_charts.clone(),
        }
    }

    /// Light probes at the given positions.
    pub fn probes(positions: &[Vec3]) -> Targets {
        let points = positions.iter().map(|p| SurfacePoint::flat(*p, Vec3::Y)).collect();
        let items = (0..positions.len() as u32).map(|k| [k, 1, k]).collect();
        let clusters = vec![0; positions.len()];
        Targets {
            points,
            items,
            sphere: true,
            slots: positions.len(),
            clusters,
            cluster_count: 0,
            width: 0,
            height: 0,
            triangle_uv: Vec::new(),
            point_uv: Vec::new(),
            texel_charts: Vec::new(),
        }
    }

    /// The sample direction of a pass from (u₀, u₁) of its direction group: (direction in
    /// the item's frame, world direction, the E/π weight of the sample: 2cosθ for texels,
    /// 1 for probes).
    pub fn direction(&self, u: [f64; 4], normal: Vec3) -> (DVec3, Vec3, f32) {
        let u = [u[0], u[1]];
        if self.sphere {
            let d = sbf::sampling::uniform_sphere(u);
            return (d, d.as_vec3(), 1.0);
        }
        let local = sbf::sampling::uniform_hemisphere(u);
        (local, world_of(normal, local), 2.0 * local.z as f32)
    }

    /// The sample direction of a texel in a guided bake from its stage's direction point
    /// ([`PathSampler::staged`]: stratified over the stage's passes): the
    /// direction (u₀, u₁) and the mixture choice u₃. With the cluster's distribution
    /// `dist` (after learning) and u₃ < m the point is warped through it, else it is the
    /// uniform direction. Returns (tangent-space direction, world direction, its pdf:
    /// 1/2π while learning, the mixture's after).
    pub fn guided_direction(&self, u: [f64; 4], normal: Vec3, dist: Option<&[f32]>, m: f64) -> (DVec3, Vec3, f64) {
        let local = match dist {
            Some(d) if u[3] < m => crate::guiding::sample_guided(d, [u[0] as f32, u[1] as f32]),
            _ => sbf::sampling::uniform_hemisphere([u[0], u[1]]),
        };
        let pdf = dist.map_or(0.5 / std::f64::consts::PI, |d| crate::guiding::mixture_pdf(d, local, m));
        (local, world_of(normal, local), pdf)
    }
}

/// A tangent-space direction about `normal` in world space.
fn world_of(normal: Vec3, local: DVec3) -> Vec3 {
    let (tn, bn) = frame(normal);
    (tn.as_dvec3() * local.x + bn.as_dvec3() * local.y + normal.as_dvec3() * local.z).normalize().as_vec3()
}

impl Targets {
    /// Turns a traced point sample into the item's frame: the light samples' directions
    /// (tangent frame about `normal` for texels) with c scaled by the point sample's pdf
    /// `pdf` (1/2π, 1/4π, or the guided mixture's), the plain estimate's sample (`w`:
    /// cosθ/(π·pdf) = 2cosθ uniform, or 1 for probes) and the encoders' weight
    /// p_s/pdf (1 unguided; [`crate::guiding`]).
    pub fn item_sample(&self, normal: Vec3, local: DVec3, w: f32, pdf: f64, s: crate::trace::PointSample) -> ItemSample {
        let (tn, bn) = frame(normal);
        let to_local = |d: Vec3| -> DVec3 {
            if self.sphere {
                d.as_dvec3()
            } else {
                DVec3::new(d.dot(tn) as f64, d.dot(bn) as f64, d.dot(normal) as f64)
            }
        };
        let p_s = if self.sphere { 0.25 / std::f64::consts::PI } else { 0.5 / std::f64::consts::PI };
        let mut estimate = s.radiance * w;
        let mut lights = Vec::with_capacity(s.lights.len());
        for (d, c) in &s.lights {
            let ld = to_local(*d);
            // E/π gains c·cosθ/π (texels) or the sphere mean gains c/4π (probes).
            let k = if self.sphere { p_s } else { ld.z.max(0.0) / std::f64::consts::PI };
            estimate += *c * k as f32;
            lights.push((ld, [c.x as f64 * pdf, c.y as f64 * pdf, c.z as f64 * pdf]));
        }
        let weight = if pdf == p_s { 1.0 } else { p_s / pdf };
        ItemSample { local, radiance: s.radiance, lights, delta: s.delta, estimate, back_face: s.back_face, weight }
    }
}

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
    /// ([`crate::guiding::stage`]; empty without guiding).
    pub guide_basis: Vec<f32>,
    /// Filtered accumulation ([`crate::filter`]; None without a filter).
    pub filtered: Option<crate::filter::FilteredState>,
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
                    let lobes = b.basis().len();
                    vec![ProgressiveEncoder::new(lobes, o); n]
                })
                .collect()
        };
        let encoders = encoders_for(targets.items.len());
        let guide_sums = match config.guiding {
            Some(_) if !targets.sphere => vec![0.0; targets.cluster_count * crate::guiding::BIN_COUNT],
            _ => Vec::new(),
        };
        let guide_basis = guide_sums.clone();
        let filtered = config.filter.filter(|_| !targets.sphere).map(|_| {
            let n = crate::filter::gather_targets(targets).len();
            crate::filter::FilteredState { encoders: encoders_for(n), moments: vec![Default::default(); n], negative_weights: 0 }
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

/// A bake in progress on the CPU.
pub struct Bake<'a> {
    pub config: BakeConfig,
    pub targets: &'a Targets,
    pub tracer: Tracer<'a>,
    bases: Vec<Box<dyn Basis + Send + Sync>>,
    pub state: BakeState,
    /// Ray guiding's distributions once learning ended ([`crate::guiding::build`]).
    guide: Option<Vec<f32>>,
    /// Adaptive sampling's tiles (None: uniform passes).
    tiles: Option<crate::adapt::Tiles>,
    /// Filtered accumulation's layout (None without a filter).
    gather: Option<crate::filter::GatherLayout>,
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
        if let Err(e) = config.check(targets) {
            panic!("{e}");
        }
        let bases: Vec<_> = config.bases.iter().map(|k| k.basis()).collect();
        let state = BakeState::new(&config, targets);
        let tiles = config.adaptive.map(|_| crate::adapt::Tiles::new(targets, targets.width).expect("checked"));
        let gather = config.filter.map(|f| crate::filter::GatherLayout::new(targets, &f).expect("checked"));
        Bake { config, targets, tracer, bases, state, guide: None, tiles, gather }
    }

    /// Continues from a saved state (see [`crate::checkpoint`]); its shape must match.
    pub fn resume(config: BakeConfig, targets: &'a Targets, tracer: Tracer<'a>, state: BakeState) -> Result<Self, String> {
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
                b.guide = Some(crate::guiding::build(&b.state.guide_basis));
            }
        }
        Ok(b)
    }

    /// The configured bases' sbf objects.
    pub fn bases(&self) -> &[Box<dyn Basis + Send + Sync>] {
        &self.bases
    }

    /// Runs one pass (one path per item) — or, in an adaptive bake after its pilot
    /// passes, one batch ([`crate::adapt`]).
    pub fn pass(&mut self) {
        match (self.config.adaptive, &self.tiles) {
            (Some(a), Some(tiles)) if self.state.passes >= a.pilot_passes => {
                let rate = crate::adapt::rates(tiles, &self.state.moments, &a);
                let (seq, seed, batch) = (self.config.sampler, self.config.seed, self.state.passes);
                // Each texel's samples of this batch, in order: (item, sample index).
                let list: Vec<(u32, u64)> = (0..self.targets.items.len())
                    .flat_map(|k| {
                        let n = crate::adapt::samples_in_batch(seq, seed, self.targets.items[k][2], batch, rate[k]);
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
                    let counts = crate::camera::pixel_counts(&c.camera, crate::camera::jitter(batch), self.tracer.bvh, self.targets);
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

    /// Ray guiding: at the start of each stage ([`crate::guiding::stage`]) the
    /// distributions are rebuilt from the sums of every pass so far, which are kept as
    /// the stage's basis (a resumed bake rebuilds exactly what it had).
    fn build_guide(&mut self) {
        if let Some(g) = self.config.guiding {
            let p = self.state.passes;
            if !self.state.guide_sums.is_empty() && p >= g.learn_passes && crate::guiding::stage(p, g.learn_passes).1 == p {
                self.state.guide_basis.clone_from(&self.state.guide_sums);
                self.guide = Some(crate::guiding::build(&self.state.guide_basis));
            }
        }
    }

    /// Runs one pass and returns its samples per item — e.g. to fit the same samples in
    /// batch.
    pub fn pass_samples(&mut self) -> Vec<ItemSample> {
        let p = self.state.passes;
        let all: Vec<(u32, u64)> = (0..self.targets.items.len() as u32).map(|k| (k, p)).collect();
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
                    let (k, start) = crate::guiding::stage(p, g.learn_passes);
                    smp = smp.staged(k, start);
                }
                let u = smp.get(DIRECTION);
                let pt = &tg.points[(first as u64 + pk % count as u64) as usize];
                let normal = (!tg.sphere).then_some((pt.normal, pt.geometric));
                match guide {
                    Some(g) => {
                        use crate::guiding::CDF_LEN;
                        let dist = dists.map(|d| &d[cluster as usize * CDF_LEN..(cluster as usize + 1) * CDF_LEN]);
                        let (local, dir, pdf) = tg.guided_direction(u, pt.normal, dist, g.guided_fraction);
                        let (tn, bn) = frame(pt.normal);
                        let pdf_of = |w: Vec3| match dist {
                            Some(d) => {
                                let l = DVec3::new(w.dot(tn) as f64, w.dot(bn) as f64, w.dot(pt.normal) as f64);
                                crate::guiding::mixture_pdf(d, l, g.guided_fraction)
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
                    let v = crate::lights::luminance(s.radiance) * s.weight;
                    crate::guiding::record(&mut self.state.guide_sums, c, s.local, v as f32);
                    for (ld, cl) in &s.lights[s.delta..] {
                        crate::guiding::record(&mut self.state.guide_sums, c, *ld, (lum(*cl) * s.weight) as f32);
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
            let mut per_item: crate::filter::ItemSamples = vec![Vec::new(); tg.items.len()];
            for (&(k, pk), s) in list.iter().zip(samples) {
                let [first, count, _] = tg.items[k as usize];
                per_item[k as usize].push(((first as u64 + pk % count as u64) as u32, s));
            }
            crate::filter::gather_batch(layout, f, tg, &self.bases, &per_item, fs);
        }
        self.state.passes += 1;
        self.build_guide();
    }
}
