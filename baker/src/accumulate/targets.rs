//! What a bake samples — lightmap texels (in 8 × 8 tile order) or probe positions — and
//! how a traced point sample becomes an item's sample in its frame.

use super::{ItemSample, Partition};
use crate::layout::digest::Fnv;
use crate::layout::lightmap::{points_digest, Lightmap, SurfacePoint};
use crate::scene::geometry::frame;
use sbf::glam::{DVec3, Vec3};

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
    /// Per item: its ray-guiding cluster ([`crate::sampling::guiding::clusters`]; 0 for probes).
    pub clusters: Vec<u32>,
    pub cluster_count: usize,
    /// The atlas size in texels (ids are y·width + x); 0 × 0 for probes.
    pub width: usize,
    pub height: usize,
    /// Atlas UV (in texels) of every vertex of every triangle, `[mesh][triangle]` (see
    /// [`Lightmap::triangle_uv`]; empty for probes): camera-based sampling finds texels by it.
    pub triangle_uv: Vec<Vec<[sbf::glam::Vec2; 3]>>,
    /// Per point, its continuous atlas position in texels (the sub-texel position it was
    /// rasterised at; [`crate::accumulate::filter`]); empty for probes.
    pub point_uv: Vec<[f32; 2]>,
    /// Per atlas texel, the chart a filtered gather treats it as part of
    /// ([`Lightmap::texel_charts`]); empty for probes.
    pub texel_charts: Vec<u32>,
    /// The identity of the whole set's sample points: FNV-1a of the kind (texels or
    /// probes) and, per item of the whole set in order, its point count, id and point
    /// digest ([`crate::layout::digest`]). A part keeps the whole set's; the bake's
    /// fingerprint hashes it ([`crate::checkpoint::content_fingerprint`]).
    pub identity: u64,
    /// For the targets of one part of a bake spread over machines: the part and the whole
    /// set's item count (the items here are the part's, in order); None: the whole set.
    pub part: Option<(Partition, usize)>,
}

/// The side of the texel tiles whose order lightmap items follow ([`Targets::lightmap`]).
pub const TILE: u32 = crate::layout::tiles::ITEM_TILE;

/// [`Targets::identity`] of items given as (point count, id, point digest), in order.
fn identity(sphere: bool, items: impl Iterator<Item = (u32, u32, u64)>) -> u64 {
    let mut h = Fnv::default();
    h.u64(sphere as u64);
    for (count, id, digest) in items {
        h.u64(((count as u64) << 32) | id as u64);
        h.u64(digest);
    }
    h.finish()
}

impl Targets {
    /// Every valid texel of a lightmap (built whole: [`Lightmap::build`]), in 8 × 8 tile
    /// order ([`crate::layout::tiles::item_order`], [Roughton19 §5.2, eq. 5.2]).
    pub fn lightmap(lm: &Lightmap) -> Targets {
        assert!(!lm.partial, "Targets::lightmap of a partial layout: use Targets::lightmap_part");
        let order = lm.item_order();
        // Guiding's clusters come per valid texel in row-major order.
        let (row_major, cluster_count) = crate::sampling::guiding::clusters(lm);
        let mut cluster_of = vec![u32::MAX; lm.texels.len()];
        let valid = (0..lm.texels.len()).filter(|k| lm.texels[*k].is_valid());
        for (k, c) in valid.zip(row_major) {
            cluster_of[k] = c;
        }
        let mut t = Targets::of_texels(lm, &order, order.iter().copied(), None);
        t.clusters = order.iter().map(|k| cluster_of[*k]).collect();
        t.cluster_count = cluster_count;
        t
    }

    /// Part `part` of a lightmap's texels, from a layout built for it
    /// ([`Lightmap::build_part`] keeping `part`'s items): only its items, with their ids
    /// (which seed their random numbers) and the whole set's identity — what a shard of a
    /// bake holds. No guiding clusters: a guided bake is never split.
    pub fn lightmap_part(lm: &Lightmap, part: Partition) -> Result<Targets, String> {
        let order = lm.item_order();
        let owned: Vec<usize> = part.ranges(order.len()).flatten().map(|i| order[i]).collect();
        if let Some(k) = owned.iter().find(|k| lm.texels[**k].points.is_empty()) {
            return Err(format!("the layout lacks the points of texel {k}, an item of part {} of {}", part.index, part.count));
        }
        let mut t = Targets::of_texels(lm, &order, owned.into_iter(), Some(part));
        t.clusters = vec![0; t.items.len()];
        Ok(t)
    }

    /// The targets of the texels `held` (in item order) of a layout whose items are
    /// `order`, the whole set's identity from `order`.
    fn of_texels(lm: &Lightmap, order: &[usize], held: impl Iterator<Item = usize>, part: Option<Partition>) -> Targets {
        let part = part.filter(|p| p.count > 1);
        let ident = identity(false, order.iter().map(|k| (lm.texels[*k].coverage.count_ones(), *k as u32, lm.digests[*k])));
        let (mut points, mut items, mut point_uv) = (Vec::new(), Vec::new(), Vec::new());
        for k in held {
            let t = &lm.texels[k];
            items.push([points.len() as u32, t.points.len() as u32, k as u32]);
            points.extend_from_slice(&t.points);
            // The points are in coverage-bit order; bit s is sub-position (s % 4, s / 4).
            let (x, y) = ((k % lm.width) as f32, (k / lm.width) as f32);
            let sub = |s: usize| [x + ((s % 4) as f32 + 0.5) / 4.0, y + ((s / 4) as f32 + 0.5) / 4.0];
            point_uv.extend((0..crate::layout::lightmap::SUBSAMPLES).filter(|s| t.coverage & (1 << s) != 0).map(sub));
        }
        Targets {
            points,
            items,
            sphere: false,
            slots: lm.texels.len(),
            clusters: Vec::new(),
            cluster_count: 0,
            width: lm.width,
            height: lm.height,
            // A part needs neither (camera-based sampling and filtered gathers are never split).
            triangle_uv: if part.is_none() { lm.triangle_uv.clone() } else { Vec::new() },
            point_uv,
            texel_charts: if part.is_none() { lm.texel_charts.clone() } else { Vec::new() },
            identity: ident,
            part: part.map(|p| (p, order.len())),
        }
    }

    /// Light probes at the given positions.
    pub fn probes(positions: &[Vec3]) -> Targets {
        let points: Vec<SurfacePoint> = positions.iter().map(|p| SurfacePoint::flat(*p, Vec3::Y)).collect();
        let items = (0..positions.len() as u32).map(|k| [k, 1, k]).collect();
        let clusters = vec![0; positions.len()];
        let ident = identity(true, points.iter().enumerate().map(|(k, p)| (1, k as u32, points_digest(std::slice::from_ref(p)))));
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
            identity: ident,
            part: None,
        }
    }

    /// Part `part` of these (whole) targets: its items in order, their points re-based,
    /// ids and the whole set's identity kept.
    pub fn part(&self, part: Partition) -> Result<Targets, String> {
        if self.part.is_some() {
            return Err("the targets are already a part".into());
        }
        if part.count == 1 {
            return Ok(self.clone());
        }
        let n = self.items.len();
        let (mut points, mut items, mut clusters, mut point_uv) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for k in part.ranges(n).flatten() {
            let [first, count, id] = self.items[k];
            let pts = first as usize..(first + count) as usize;
            items.push([points.len() as u32, count, id]);
            points.extend_from_slice(&self.points[pts.clone()]);
            if !self.point_uv.is_empty() {
                point_uv.extend_from_slice(&self.point_uv[pts]);
            }
            clusters.push(self.clusters[k]);
        }
        Ok(Targets {
            points,
            items,
            clusters,
            point_uv,
            part: Some((part, n)),
            // Camera-based sampling and filtered gathers, which need these, are never split.
            triangle_uv: Vec::new(),
            texel_charts: Vec::new(),
            ..*self
        })
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
    /// ([`crate::sampling::sequence::PathSampler::staged`]: stratified over the stage's passes): the
    /// direction (u₀, u₁) and the mixture choice u₃. With the cluster's distribution
    /// `dist` (after learning) and u₃ < m the point is warped through it, else it is the
    /// uniform direction. Returns (tangent-space direction, world direction, its pdf:
    /// 1/2π while learning, the mixture's after).
    pub fn guided_direction(&self, u: [f64; 4], normal: Vec3, dist: Option<&[f32]>, m: f64) -> (DVec3, Vec3, f64) {
        let local = match dist {
            Some(d) if u[3] < m => crate::sampling::guiding::sample_guided(d, [u[0] as f32, u[1] as f32]),
            _ => sbf::sampling::uniform_hemisphere([u[0], u[1]]),
        };
        let pdf = dist.map_or(0.5 / std::f64::consts::PI, |d| crate::sampling::guiding::mixture_pdf(d, local, m));
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
    /// p_s/pdf (1 unguided; [`crate::sampling::guiding`]).
    pub fn item_sample(&self, normal: Vec3, local: DVec3, w: f32, pdf: f64, s: crate::estimator::trace::PointSample) -> ItemSample {
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
