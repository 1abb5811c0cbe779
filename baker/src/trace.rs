//! The path-traced estimator of incoming radiance L_in(x, ω) (seed 004 ch. 6): next-event
//! estimation on emissive triangles (chosen by power, area-uniform points) combined with
//! BSDF sampling by the power heuristic (Veach 1997, §9.2); directional and point lights
//! by NEE only (delta lights); the environment by BSDF sampling only (it is reached
//! through openings). Russian roulette from the third bounce with survival probability
//! min(max throughput, 0.95). Material: Lambert + GGX layers added (§6.3.1); the layer
//! is chosen with probability ½ each when both are present, and the mixture pdf is used.

use crate::bvh::Bvh;
use crate::scene::{Light, Material, Scene};
use sbf::glam::{DVec3, Vec3};
use sbf::sampling::Pcg32;

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
    /// Ray offset from surfaces (scene-scale relative).
    pub epsilon: f32,
}

fn luminance(c: Vec3) -> f64 {
    (0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) as f64
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene, bvh: &'a Bvh, max_bounces: u32) -> Self {
        let mut emitters = Vec::new();
        let mut power = Vec::new();
        for (k, t) in bvh.tris.iter().enumerate() {
            let le = scene.materials[t.material as usize].emissive;
            if le.max_element() > 0.0 {
                emitters.push(k as u32);
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
        let (lo, hi) = bvh.nodes.first().map(|n| (Vec3::from(n.min), Vec3::from(n.max))).unwrap_or((Vec3::ZERO, Vec3::ONE));
        let epsilon = 1e-4 * (hi - lo).max_element().max(1e-3);
        Tracer { scene, bvh, emitters, cdf, select_pdf, total_power: total, max_bounces, epsilon }
    }

    /// Emissive triangles (indices into `bvh.tris`) with the CDF of their power.
    pub fn emitter_table(&self) -> impl Iterator<Item = (u32, f64)> + '_ {
        self.emitters.iter().copied().zip(self.cdf.iter().copied())
    }

    /// Radiance arriving at `x` (geometric normal `n`) from unit direction `dir`.
    pub fn incoming(&self, x: Vec3, n: Vec3, dir: Vec3, rng: &mut Pcg32) -> Vec3 {
        let mut o = offset(x, n, dir, self.epsilon);
        let mut d = dir;
        let mut throughput = Vec3::ONE;
        let mut radiance = Vec3::ZERO;
        // pdf of the BSDF sample that produced `d` (None: the first segment, counted fully).
        let mut prev_pdf: Option<f64> = None;
        for bounce in 0..=self.max_bounces {
            let Some(hit) = self.bvh.intersect(o, d, 0.0, f32::INFINITY) else {
                radiance += throughput * self.scene.environment.radiance(d);
                break;
            };
            let tri = &self.bvh.tris[hit.tri as usize];
            let mat = &self.scene.materials[tri.material as usize];
            let ng = tri.normal();
            let front = d.dot(ng) < 0.0;
            if front && mat.emissive.max_element() > 0.0 {
                let w = match prev_pdf {
                    None => 1.0,
                    Some(pb) => {
                        let pl = self.select_pdf[hit.tri as usize] / tri.area() as f64 * (hit.t as f64).powi(2) / (-d.dot(ng)) as f64;
                        pb * pb / (pb * pb + pl * pl)
                    }
                };
                radiance += throughput * mat.emissive * w as f32;
            }
            if bounce == self.max_bounces {
                break;
            }
            let p = o + d * hit.t;
            let ns = if front { ng } else { -ng };
            let wo = -d;
            radiance += throughput * self.direct(p, ns, wo, mat, rng);
            // BSDF sampling.
            let Some((wi, f, pdf)) = sample_bsdf(mat, ns, wo, rng) else { break };
            throughput *= f * (wi.dot(ns) / pdf as f32);
            if !throughput.is_finite() || throughput.max_element() <= 0.0 {
                break;
            }
            if bounce >= 2 {
                let q = throughput.max_element().min(0.95);
                if rng.next_f64() as f32 >= q {
                    break;
                }
                throughput /= q;
            }
            prev_pdf = Some(pdf);
            o = offset(p, ns, wi, self.epsilon);
            d = wi;
        }
        radiance
    }

    /// Next-event estimation at p (shading normal ns facing wo).
    fn direct(&self, p: Vec3, ns: Vec3, wo: Vec3, mat: &Material, rng: &mut Pcg32) -> Vec3 {
        let mut l = Vec3::ZERO;
        if !self.emitters.is_empty() {
            let u = rng.next_f64();
            let k = self.cdf.partition_point(|c| *c < u).min(self.emitters.len() - 1);
            let ti = self.emitters[k];
            let tri = &self.bvh.tris[ti as usize];
            let [a, b] = rng.next_2d();
            let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
            let q = tri.v0() + tri.e1() * a as f32 + tri.e2() * b as f32;
            let to = q - p;
            let dist2 = to.length_squared();
            let wi = to / dist2.sqrt();
            let nl = tri.normal();
            let cos_l = -wi.dot(nl);
            let cos_i = wi.dot(ns);
            if cos_l > 0.0 && cos_i > 0.0 {
                let pl = self.select_pdf[ti as usize] / tri.area() as f64 * dist2 as f64 / cos_l as f64;
                let (f, pb) = eval_bsdf(mat, ns, wo, wi);
                if f.max_element() > 0.0 {
                    let o = offset(p, ns, wi, self.epsilon);
                    let tmax = (q - o).length() * (1.0 - 1e-4);
                    if !self.bvh.occluded(o, wi, 0.0, tmax) {
                        let w = pl * pl / (pl * pl + pb * pb);
                        let le = self.scene.materials[tri.material as usize].emissive;
                        l += f * le * (cos_i * (w / pl) as f32);
                    }
                }
            }
        }
        for light in &self.scene.lights {
            let (wi, e, tmax) = match *light {
                Light::Directional { direction, irradiance } => (direction, irradiance, f32::INFINITY),
                Light::Point { position, intensity } => {
                    let to = position - p;
                    let d2 = to.length_squared();
                    (to / d2.sqrt(), intensity / d2, d2.sqrt() * (1.0 - 1e-4))
                }
            };
            let cos_i = wi.dot(ns);
            if cos_i <= 0.0 {
                continue;
            }
            let (f, _) = eval_bsdf(mat, ns, wo, wi);
            if f.max_element() > 0.0 && !self.bvh.occluded(offset(p, ns, wi, self.epsilon), wi, 0.0, tmax) {
                l += f * e * cos_i;
            }
        }
        l
    }
}

/// Origin moved off the surface to the side `dir` leaves from.
fn offset(p: Vec3, n: Vec3, dir: Vec3, eps: f32) -> Vec3 {
    if dir.dot(n) >= 0.0 {
        p + n * eps
    } else {
        p - n * eps
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

/// Samples wi for the layered material: (wi, f, pdf) or None.
pub fn sample_bsdf(m: &Material, ns: Vec3, wo: Vec3, rng: &mut Pcg32) -> Option<(Vec3, Vec3, f64)> {
    let ps = specular_probability(m);
    let choose = rng.next_f64();
    let u = rng.next_2d();
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
