//! The path-traced estimator of incoming radiance L_in(x, ω) ([Roughton19 ch. 6]).
//!
//! **At the baked point** (a texel's surface point or a probe) one pass draws the point
//! sample ω_s (uniform over the item's domain, pdf p_s = 1/2π for texels, 1/4π for
//! probes) and, by next-event estimation, one sample of every light kind (§6.1: delta
//! lights cannot be reached by a random direction): every directional, point and spot
//! light; one emissive triangle chosen by power (area lights: disks, spheres, meshes);
//! one environment direction by luminance × solid angle. Area-light and environment
//! samples are combined with the point sample by the power heuristic (Veach 1997, §9.2),
//! so the point sample's own hit on an emitter or the sky is weighted too. The light
//! samples reach the basis encoders as known projections (sbf `update_projected`) and
//! the plain irradiance as Σ c·cosθ/π.
//!
//! **Along the path**: the same light kinds by NEE at every vertex, BSDF sampling
//! (Lambert + GGX layers added, §6.3.1; the layer chosen with probability ½ each when
//! both are present, mixture pdf), MIS for emitters and the environment, Russian roulette
//! from the third bounce with survival min(max throughput, 0.95). Lights are evaluated
//! at the shaded point itself; shadow rays start at the offset point
//! ([`crate::scene::lights::offset_ray`]) and are aimed and measured from it.
//!
//! **Validity**: a point sample whose first hit is the back face of a single-sided
//! surface is rejected (the baked point is inside geometry, \[HWRTL\]'s valid-sample
//! count); the caller counts it.

use crate::sampling::environment::EnvSampler;
use crate::sampling::sequence::{PathSampler, DIRECTION, EMITTER, ENVIRONMENT};
use crate::scene::bvh::Bvh;
use crate::scene::lights::{delta_at, luminance, offset_ray, offset_towards, shadow_ray};
use crate::scene::{Material, Scene};
use sbf::glam::{DVec3, Vec3};

/// Scene data the estimator needs.
#[derive(Debug)]
pub struct Tracer<'a> {
    pub scene: &'a Scene,
    pub bvh: &'a Bvh,
    /// Emissive triangles (indices into `bvh.tris`) and the CDF of their power.
    emitters: Vec<u32>,
    cdf: Vec<f64>,
    /// Probability of choosing triangle k by NEE (0 for non-emitters), per `bvh.tris`.
    select_pdf: Vec<f64>,
    /// Σ over emitters of luminance × area (NEE's selection normaliser).
    pub total_power: f64,
    pub max_bounces: u32,
    /// The environment's importance sampler (None: black).
    pub env: Option<EnvSampler>,
    /// Indirect light only: what reaches the baked point (or the reference's visible
    /// point) straight from an emitter, a delta light or the sky is left out — its light
    /// samples and the first segment's emitter and sky hits — as the thesis' Fig. 8.6 bakes
    /// ([Roughton19 §8.4.3]: "indirect light from baked lightmaps").
    pub indirect_only: bool,
    /// Some material has an alpha mask: rays pass through its holes.
    masked: bool,
}

/// A light sample at the baked point: world direction towards the light and c = L·w/p·V
/// (radiance × MIS weight / solid-angle pdf × visibility; E·V for a delta light).
pub type LightSample = (Vec3, Vec3);

/// One pass at a baked point.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointSample {
    /// L_in along the point sample's direction (emitter and sky hits MIS-weighted).
    pub radiance: Vec3,
    /// The light samples (see [`LightSample`]): the delta lights first, then the area
    /// samples (emitter, environment).
    pub lights: Vec<LightSample>,
    /// How many of `lights` are delta lights.
    pub delta: usize,
    /// The first hit was the back face of a single-sided surface: reject the sample.
    pub back_face: bool,
}

/// A next-event sample of an area light (emitter point or environment direction).
#[derive(Debug, Clone, Copy)]
struct AreaSample {
    wi: Vec3,
    radiance: Vec3,
    /// Solid-angle pdf of drawing `wi`.
    pdf: f64,
    /// The emitter point a shadow ray must reach; None: the environment (unbounded).
    target: Option<Vec3>,
}

/// Points per side of the barycentric grid that averages a textured emitter's radiance.
const EMISSION_GRID: usize = 8;

/// A textured emitter's mean radiance over its triangle, from the centres of the
/// EMISSION_GRID² sub-triangles of a regular subdivision (equal areas). It only sets the
/// triangle's share of NEE (its selection probability); every sample evaluates the map at
/// its own point and MIS keeps the estimate unbiased for any share > 0.
pub(crate) fn mean_emission(scene: &Scene, t: &crate::scene::bvh::Tri) -> Vec3 {
    let n = EMISSION_GRID;
    let mut sum = Vec3::ZERO;
    for i in 0..n {
        for j in 0..n - i {
            // The upward sub-triangle (i, j) and, but on the diagonal, the downward one.
            let up = [(i as f32 + 1.0 / 3.0) / n as f32, (j as f32 + 1.0 / 3.0) / n as f32];
            sum += scene.material_at(t, up[0], up[1]).emissive;
            if i + j + 1 < n {
                let down = [(i as f32 + 2.0 / 3.0) / n as f32, (j as f32 + 2.0 / 3.0) / n as f32];
                sum += scene.material_at(t, down[0], down[1]).emissive;
            }
        }
    }
    sum / (n * n) as f32
}

/// The power heuristic (β = 2) weight of the strategy with pdf `a` against one with `b`.
fn power2(a: f64, b: f64) -> f64 {
    a * a / (a * a + b * b)
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene, bvh: &'a Bvh, max_bounces: u32) -> Self {
        let mut emitters = Vec::new();
        let mut power = Vec::new();
        for (k, t) in bvh.tris.iter().enumerate() {
            let m = &scene.materials[t.material as usize];
            if m.emissive.max_element() > 0.0 {
                emitters.push(k as u32);
                let le = match m.maps.emissive {
                    None => m.emissive,
                    Some(_) => mean_emission(scene, t),
                };
                power.push(luminance(le).max(1e-12) * t.area() as f64);
            }
        }
        let total: f64 = power.iter().sum();
        let mut select_pdf = vec![0.0; bvh.tris.len()];
        let mut cdf = Vec::with_capacity(power.len());
        let mut acc = 0.0;
        for (k, p) in emitters.iter().zip(&power) {
            acc += p / total;
            cdf.push(acc);
            select_pdf[*k as usize] = p / total;
        }
        let env = EnvSampler::new(&scene.environment);
        let masked = scene.materials.iter().any(|m| m.maps.mask.is_some());
        Tracer { scene, bvh, emitters, cdf, select_pdf, total_power: total, max_bounces, env, indirect_only: false, masked }
    }

    /// Closest hit along o + t·d, t in (tmin, tmax), through the holes of alpha masks.
    fn hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<crate::scene::bvh::Hit> {
        match self.masked {
            false => self.bvh.intersect(o, d, tmin, tmax),
            true => self.bvh.intersect_solid(o, d, tmin, tmax, &|k, u, v| !self.scene.is_hole(&self.bvh.tris[k as usize], u, v)),
        }
    }

    /// Whether a solid surface (not an alpha mask's hole) lies along o + t·d, t in (tmin, tmax).
    fn blocked(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> bool {
        match self.masked {
            false => self.bvh.occluded(o, d, tmin, tmax),
            true => self.bvh.occluded_solid(o, d, tmin, tmax, &|k, u, v| !self.scene.is_hole(&self.bvh.tris[k as usize], u, v)),
        }
    }

    /// Emissive triangles (indices into `bvh.tris`) with the CDF of their power.
    pub fn emitter_table(&self) -> impl Iterator<Item = (u32, f64)> + '_ {
        self.emitters.iter().copied().zip(self.cdf.iter().copied())
    }

    /// The tracer with indirect light only, or all light ([`Self::indirect_only`]).
    pub fn with_indirect_only(self, indirect_only: bool) -> Self {
        Tracer { indirect_only, ..self }
    }

    /// Solid-angle pdf of NEE choosing triangle `tri` and hitting it at distance t with
    /// cosine `cos_l` at the light.
    fn emitter_pdf(&self, tri: u32, t: f32, cos_l: f32) -> f64 {
        self.select_pdf[tri as usize] / self.bvh.tris[tri as usize].area() as f64 * (t as f64).powi(2) / cos_l as f64
    }

    /// One pass at a baked point `x`: texels pass their (shading, geometric) normals —
    /// the hemisphere about the shading normal is the domain, rays leave from the point
    /// offset along the geometric one, and directions below the geometric plane see the
    /// surface itself (radiance 0) — probes None (sphere). `dir` is the point sample's
    /// world direction, drawn uniformly over the domain.
    /// `smp` is at vertex 0 (the baked point); the path moves it along.
    pub fn sample_point(&self, x: Vec3, normal: Option<(Vec3, Vec3)>, dir: Vec3, smp: &mut PathSampler) -> PointSample {
        let p_s = if normal.is_some() { 1.0 / (2.0 * std::f64::consts::PI) } else { 1.0 / (4.0 * std::f64::consts::PI) };
        self.sample_point_with(x, normal, dir, &|_| p_s, smp)
    }

    /// [`Self::sample_point`] for a point sample drawn from any density: `pdf_of(ω)` is
    /// the solid-angle pdf of the point-sample strategy at a world direction in the
    /// domain (ray guiding, [`crate::sampling::guiding`]); it weights the light samples and the
    /// point sample's own emitter and sky hits by the power heuristic.
    pub fn sample_point_with(
        &self,
        x: Vec3,
        normal: Option<(Vec3, Vec3)>,
        dir: Vec3,
        pdf_of: &dyn Fn(Vec3) -> f64,
        smp: &mut PathSampler,
    ) -> PointSample {
        let origin = |d: Vec3| match normal {
            Some((_, ng)) => offset_towards(x, ng, d),
            None => x,
        };
        let in_domain = |d: Vec3| normal.is_none_or(|(ns, ng)| d.dot(ns) > 0.0 && d.dot(ng) > 0.0);
        let mut lights = Vec::new();
        // Delta lights: every one, evaluated at x; the shadow ray from the offset origin.
        let direct = if self.indirect_only { &[][..] } else { &self.scene.lights[..] };
        for l in direct {
            if let Some((wi, e, _)) = delta_at(l, x) {
                if in_domain(wi) && e.max_element() > 0.0 && self.visible_delta(l, origin(wi)) {
                    lights.push((wi, e));
                }
            }
        }
        let delta = lights.len();
        // One emitter point by power and one environment direction, MIS against the
        // point sample.
        for a in self.area_samples(x, smp).into_iter().flatten().filter(|_| !self.indirect_only) {
            if in_domain(a.wi) && self.visible(origin(a.wi), &a) {
                lights.push((a.wi, a.radiance * (power2(a.pdf, pdf_of(a.wi)) / a.pdf) as f32));
            }
        }
        if normal.is_some_and(|(_, ng)| dir.dot(ng) <= 0.0) {
            // Between the shading and the geometric horizon: the surface occludes.
            return PointSample { radiance: Vec3::ZERO, lights, delta, back_face: false };
        }
        let (radiance, back_face) = self.path(origin(dir), dir, pdf_of(dir), true, smp);
        PointSample { radiance, lights, delta, back_face }
    }

    /// Radiance arriving at an offset origin `o` from unit direction `dir` (the first
    /// segment counted fully): the estimator along a path, for callers without MIS at
    /// the start (the preview).
    pub fn incoming(&self, o: Vec3, dir: Vec3, smp: &mut PathSampler) -> Vec3 {
        self.path(o, dir, 0.0, false, smp).0
    }

    /// One next-event sample of the area lights seen from `x`: an emitter point chosen by
    /// power (area-uniform on its triangle) and an environment direction (luminance ×
    /// solid angle), each with its solid-angle pdf; None where a light kind is absent or
    /// the emitter faces away. The numbers come from the vertex's [`EMITTER`] and
    /// [`ENVIRONMENT`] groups.
    fn area_samples(&self, x: Vec3, smp: &PathSampler) -> [Option<AreaSample>; 2] {
        let ue = smp.get(EMITTER);
        let emitter = match self.pick_emitter([ue[0], ue[1], ue[2]]) {
            Some((tri, q, bary)) => {
                let to = q - x;
                let dist = to.length();
                let wi = to / dist;
                let t = &self.bvh.tris[tri as usize];
                let cos_l = -wi.dot(t.normal());
                (cos_l > 0.0).then(|| AreaSample {
                    wi,
                    radiance: self.scene.material_at(t, bary[0], bary[1]).emissive,
                    pdf: self.emitter_pdf(tri, dist, cos_l),
                    target: Some(q),
                })
            }
            None => None,
        };
        let uv = smp.get(ENVIRONMENT);
        let u = [uv[0], uv[1], uv[2]];
        let env = self.env.as_ref().and_then(|env| {
            let (wi, pdf) = env.sample(u);
            (pdf > 0.0).then(|| AreaSample { wi, radiance: self.scene.environment.radiance(wi), pdf, target: None })
        });
        [emitter, env]
    }

    /// Whether a shadow ray from offset origin `o` reaches an area sample.
    fn visible(&self, o: Vec3, a: &AreaSample) -> bool {
        match a.target {
            Some(q) => self.visible_point(o, q),
            None => !self.blocked(o, a.wi, 0.0, f32::INFINITY),
        }
    }

    /// Whether a shadow ray from offset origin `o` reaches the delta light.
    fn visible_delta(&self, l: &crate::scene::Light, o: Vec3) -> bool {
        let (d, len) = shadow_ray(l, o);
        !self.blocked(o, d, 0.0, len)
    }

    /// Whether a shadow ray from offset origin `o` reaches point `q` (aimed and measured
    /// from `o`, stopped 1e-4 relative short of q so the light's own surface is not hit).
    fn visible_point(&self, o: Vec3, q: Vec3) -> bool {
        let to = q - o;
        let d = to.length();
        d > 0.0 && !self.blocked(o, to / d, 0.0, d * (1.0 - 1e-4))
    }

    /// An emitter by power (u₀) and a point uniform on it (u₁, u₂), with its barycentric
    /// coordinates.
    fn pick_emitter(&self, u: [f64; 3]) -> Option<(u32, Vec3, [f32; 2])> {
        if self.emitters.is_empty() {
            return None;
        }
        let k = self.cdf.partition_point(|c| *c < u[0]).min(self.emitters.len() - 1);
        let ti = self.emitters[k];
        let tri = &self.bvh.tris[ti as usize];
        let [a, b] = [u[1], u[2]];
        let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
        Some((ti, tri.v0() + tri.e1() * a as f32 + tri.e2() * b as f32, [a as f32, b as f32]))
    }

    /// The path from origin `o` along `dir`. `first_pdf` > 0: the pdf of the strategy
    /// that chose `dir` (MIS for the first hit); 0: the first segment counts fully.
    /// `reject_back`: report a first hit on a single-sided back face (and stop).
    /// Hit k (bounce k − 1) draws from vertex k of `smp`.
    fn path(&self, o: Vec3, dir: Vec3, first_pdf: f64, reject_back: bool, smp: &mut PathSampler) -> (Vec3, bool) {
        let mut o = o;
        let mut d = dir;
        let mut throughput = Vec3::ONE;
        let mut radiance = Vec3::ZERO;
        // pdf of the sample that produced `d` (None: counted fully).
        let mut prev_pdf: Option<f64> = (first_pdf > 0.0).then_some(first_pdf);
        for bounce in 0..=self.max_bounces {
            let Some(hit) = self.hit(o, d, 0.0, f32::INFINITY) else {
                let w = match (prev_pdf, &self.env) {
                    (Some(pb), Some(env)) => power2(pb, env.pdf(d)),
                    _ => 1.0,
                };
                if bounce > 0 || !self.indirect_only {
                    radiance += throughput * self.scene.environment.radiance(d) * w as f32;
                }
                break;
            };
            let tri = &self.bvh.tris[hit.tri as usize];
            let mat = &self.scene.material_at(tri, hit.u, hit.v);
            let ng = tri.normal();
            let front = d.dot(ng) < 0.0;
            if bounce == 0 && reject_back && !front && !mat.double_sided {
                return (Vec3::ZERO, true);
            }
            if front && mat.emissive.max_element() > 0.0 && (bounce > 0 || !self.indirect_only) {
                let w = match prev_pdf {
                    None => 1.0,
                    Some(pb) => power2(pb, self.emitter_pdf(hit.tri, hit.t, -d.dot(ng))),
                };
                radiance += throughput * mat.emissive * w as f32;
            }
            if bounce == self.max_bounces {
                break;
            }
            let p = o + d * hit.t;
            let ns = if front { ng } else { -ng };
            let wo = -d;
            smp.at_vertex(bounce + 1);
            radiance += throughput * self.direct(p, ns, wo, mat, smp);
            // BSDF sampling: layer choice u₀, direction (u₁, u₂); Russian roulette u₃.
            let u = smp.get(DIRECTION);
            let Some((wi, f, pdf)) = sample_bsdf(mat, ns, wo, [u[0], u[1], u[2]]) else { break };
            throughput *= f * (wi.dot(ns) / pdf as f32);
            if !throughput.is_finite() || throughput.max_element() <= 0.0 {
                break;
            }
            if bounce >= 2 {
                let q = throughput.max_element().min(0.95);
                if u[3] as f32 >= q {
                    break;
                }
                throughput /= q;
            }
            prev_pdf = Some(pdf);
            o = offset_ray(p, ns);
            d = wi;
        }
        (radiance, false)
    }

    /// Next-event estimation at p (shading normal ns facing wo): one emitter by power and
    /// one environment direction, each MIS-weighted against the BSDF; every delta light.
    /// Shadow rays start at the offset point and aim from it.
    fn direct(&self, p: Vec3, ns: Vec3, wo: Vec3, mat: &Material, smp: &PathSampler) -> Vec3 {
        let mut l = Vec3::ZERO;
        let o = offset_ray(p, ns);
        for a in self.area_samples(p, smp).into_iter().flatten() {
            let cos_i = a.wi.dot(ns);
            if cos_i > 0.0 {
                let (f, pb) = eval_bsdf(mat, ns, wo, a.wi);
                if f.max_element() > 0.0 && self.visible(o, &a) {
                    l += f * a.radiance * (cos_i * (power2(a.pdf, pb) / a.pdf) as f32);
                }
            }
        }
        for light in &self.scene.lights {
            let Some((wi, e, _)) = delta_at(light, p) else { continue };
            let cos_i = wi.dot(ns);
            if cos_i <= 0.0 {
                continue;
            }
            let (f, _) = eval_bsdf(mat, ns, wo, wi);
            if f.max_element() > 0.0 && self.visible_delta(light, o) {
                l += f * e * cos_i;
            }
        }
        l
    }
}

/// Probability of sampling the GGX layer.
pub fn specular_probability(m: &Material) -> f64 {
    match (m.diffuse_albedo().max_element() > 0.0, m.is_glossy()) {
        (true, true) => 0.5,
        (false, true) => 1.0,
        _ => 0.0,
    }
}

/// (f, pdf of sampling wi) for the layered material; both zero below the surface.
pub fn eval_bsdf(m: &Material, ns: Vec3, wo: Vec3, wi: Vec3) -> (Vec3, f64) {
    let (ci, co) = (wi.dot(ns), wo.dot(ns));
    if ci <= 0.0 || co <= 0.0 {
        return (Vec3::ZERO, 0.0);
    }
    let ps = specular_probability(m);
    let mut f = m.diffuse_albedo() * std::f32::consts::FRAC_1_PI;
    let mut pdf = (1.0 - ps) * ci as f64 / std::f64::consts::PI;
    if m.is_glossy() {
        let (t, b) = sbf::basis::ambient_dice_bezier::tangent_frame(ns.as_dvec3());
        let n = ns.as_dvec3();
        let local = |w: Vec3| {
            let w = w.as_dvec3();
            DVec3::new(w.dot(t), w.dot(b), w.dot(n))
        };
        let (v, l) = (local(wo), local(wi));
        let alpha = m.alpha() as f64;
        let h = (v + l).normalize();
        let dg = sbf::ggx::d(h, alpha) * sbf::ggx::g2(v, l, alpha) / (4.0 * v.z * l.z);
        let fw = sbf::ggx::schlick_weight(v.dot(h)) as f32;
        let f0 = m.specular_f0();
        f += (f0 + (Vec3::ONE - f0) * fw) * dg as f32;
        pdf += ps * sbf::ggx::vndf_reflected_pdf(v, l, alpha);
    }
    (f, pdf)
}

/// Samples wi for the layered material from u = (layer choice, 2D direction): (wi, f,
/// pdf) or None.
pub fn sample_bsdf(m: &Material, ns: Vec3, wo: Vec3, u: [f64; 3]) -> Option<(Vec3, Vec3, f64)> {
    let ps = specular_probability(m);
    let choose = u[0];
    let u = [u[1], u[2]];
    let (t, b) = sbf::basis::ambient_dice_bezier::tangent_frame(ns.as_dvec3());
    let n = ns.as_dvec3();
    let world = |l: DVec3| (t * l.x + b * l.y + n * l.z).as_vec3();
    let wi = if choose < ps {
        let w = wo.as_dvec3();
        let v = DVec3::new(w.dot(t), w.dot(b), w.dot(n));
        let h = sbf::ggx::sample_vndf(v, m.alpha() as f64, u);
        world(sbf::ggx::reflect(v, h))
    } else if ps < 1.0 {
        world(sbf::sampling::cosine_hemisphere(u))
    } else {
        return None;
    };
    let wi = wi.normalize();
    let (f, pdf) = eval_bsdf(m, ns, wo, wi);
    (pdf > 0.0 && f.max_element() > 0.0).then_some((wi, f, pdf))
}
