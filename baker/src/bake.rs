//! Progressive lightmap baking on the CPU (the reference path; rayon over texels).
//!
//! Pass p of texel k: the sub-texel point (p mod covered points), a direction on the
//! hemisphere about the texel's normal from an R2 sequence with a per-texel
//! Cranley–Patterson shift (successive samples decorrelated, seed §7.3.1), the path's
//! remaining dimensions from a PCG stream seeded by (seed, pass, texel). Every random
//! number depends only on (seed, texel, pass), so results are identical for any thread
//! count and a resumed bake equals an uninterrupted one.
//!
//! Each radiance sample L_in(ω) is (a) accumulated as plain irradiance E/π = 2·L·cosθ
//! (uniform hemisphere pdf 1/2π), with its second moment for a standard error, and
//! (b) added to every configured basis's progressive encoder (sbf's
//! `ProgressiveEncoder<f32>`, the twin of the WGSL update), in tangent space (normal +Z).

use crate::lightmap::{frame, Lightmap};
use crate::trace::Tracer;
use rayon::prelude::*;
use sbf::glam::{DVec3, Vec3};
use sbf::sampling::{Pcg32, R2};
use sbf::solve::{ProgressiveEncoder, ProgressiveOptions};
use sbf::Basis;

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
                let n = if self == BasisKind::Sg9 { 9 } else { 12 };
                let axes = sbf::layout::vogel_hemisphere(n).expect("vogel layout");
                let lambda = sbf::layout::sharpness_from_spacing(&axes).expect("sharpness");
                Box::new(sbf::SgBasis::new(&axes, lambda, false).expect("SG basis"))
            }
            BasisKind::Ad9 => Box::new(sbf::AmbientDiceSrbf::nine_hemisphere()),
            BasisKind::Ad12 => Box::new(sbf::AmbientDiceSrbf::twelve()),
        }
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
}

/// Per-texel accumulation of plain irradiance (E/π) and its second moment.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Moments {
    pub sum: [f64; 3],
    pub sum_sq: [f64; 3],
}

/// The progressive state of a bake: everything needed to continue it.
#[derive(Debug, Clone)]
pub struct BakeState {
    pub passes: u64,
    pub moments: Vec<Moments>,
    /// `encoders[b][texel]` for `config.bases[b]` (None for invalid texels).
    pub encoders: Vec<Vec<Option<ProgressiveEncoder<f32>>>>,
}

/// A bake in progress.
pub struct Bake<'a> {
    pub config: BakeConfig,
    pub lightmap: &'a Lightmap,
    pub tracer: Tracer<'a>,
    bases: Vec<Box<dyn Basis + Send + Sync>>,
    pub state: BakeState,
}

impl std::fmt::Debug for Bake<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bake").field("config", &self.config).field("passes", &self.state.passes).finish_non_exhaustive()
    }
}

impl<'a> Bake<'a> {
    pub fn new(config: BakeConfig, lightmap: &'a Lightmap, tracer: Tracer<'a>) -> Self {
        let bases: Vec<_> = config.bases.iter().map(|k| k.basis()).collect();
        let opts = match config.solver {
            Solver::Ls => ProgressiveOptions::default(),
            Solver::Nnls => ProgressiveOptions::non_negative(),
        };
        let encoders = bases
            .iter()
            .map(|b| {
                // Sphere bases see only the upper hemisphere: mirrored zero samples pin the
                // lower half (seed §7.3's hemisphere handling).
                let o = ProgressiveOptions { mirror_hemisphere: b.domain() == sbf::Domain::Sphere, ..opts.clone() };
                lightmap.texels.iter().map(|t| t.is_valid().then(|| ProgressiveEncoder::new(b.len(), o.clone()))).collect()
            })
            .collect();
        let state = BakeState { passes: 0, moments: vec![Moments::default(); lightmap.texels.len()], encoders };
        Bake { config, lightmap, tracer, bases, state }
    }

    /// The configured bases' sbf objects.
    pub fn bases(&self) -> &[Box<dyn Basis + Send + Sync>] {
        &self.bases
    }

    /// Runs one pass (one path per valid texel).
    pub fn pass(&mut self) {
        let p = self.state.passes;
        let seed = self.config.seed;
        let tracer = &self.tracer;
        let lm = self.lightmap;
        // Trace in parallel, then feed the encoders per texel (the samples are kept so
        // that each texel's update order is the pass order on any thread count).
        let samples: Vec<Option<(DVec3, Vec3)>> = (0..lm.texels.len())
            .into_par_iter()
            .map(|k| {
                let t = &lm.texels[k];
                if !t.is_valid() {
                    return None;
                }
                let pt = &t.points[(p % t.points.len() as u64) as usize];
                let u = R2::with_seed(seed ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)).point(p);
                let local = sbf::sampling::uniform_hemisphere(u);
                let (tn, bn) = frame(pt.normal);
                let dir = (tn.as_dvec3() * local.x + bn.as_dvec3() * local.y + pt.normal.as_dvec3() * local.z).normalize().as_vec3();
                let mut rng = Pcg32::new(seed.wrapping_add(p.wrapping_mul(0x2545_F491_4F6C_DD1D)), k as u64);
                let l = tracer.incoming(pt.position, pt.normal, dir, &mut rng);
                Some((local, l))
            })
            .collect();
        let bases = &self.bases;
        self.state.moments.par_iter_mut().zip(samples.par_iter()).for_each(|(m, s)| {
            if let Some((local, l)) = s {
                let e = *l * (2.0 * local.z as f32);
                for c in 0..3 {
                    m.sum[c] += e[c] as f64;
                    m.sum_sq[c] += (e[c] as f64).powi(2);
                }
            }
        });
        for (b, encs) in self.state.encoders.iter_mut().enumerate() {
            let basis = &bases[b];
            encs.par_iter_mut().zip(samples.par_iter()).for_each(|(enc, s)| {
                if let (Some(enc), Some((local, l))) = (enc, s) {
                    // Finite by construction (the estimator never returns NaN/Inf from
                    // finite scene data); an error here would be a bug worth a panic.
                    enc.add_sample(basis.as_ref(), *local, [l.x as f64, l.y as f64, l.z as f64], 1.0).expect("finite radiance sample");
                }
            });
        }
        self.state.passes += 1;
    }

    /// Mean E/π per texel (zero for invalid texels).
    pub fn irradiance(&self) -> Vec<[f64; 3]> {
        let n = self.state.passes.max(1) as f64;
        self.state.moments.iter().map(|m| m.sum.map(|s| s / n)).collect()
    }

    /// Standard error of the mean E/π per texel and channel.
    pub fn standard_error(&self) -> Vec<[f64; 3]> {
        let n = self.state.passes as f64;
        self.state
            .moments
            .iter()
            .map(|m| {
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
}
