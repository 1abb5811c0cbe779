//! What a bake is asked to do: the bases it encodes into, the solver, the sample
//! sequences and the optional accumulation strategies (guiding, adaptive, camera-based,
//! filtered), with the checks that refuse combinations a bake cannot run.

use super::Targets;
use crate::sampling::sequence::Sequence;
use sbf::glam::DVec3;
use sbf::solve::ProgressiveOptions;
use sbf::Basis;

/// Default sharpness of the hemisphere SG sets (9 and 12 lobes; a bake may choose
/// another, [`BakeConfig::sg_sharpness`]), "experimentally selected" as in [Roughton19 §7.2]
/// after Pettineo and Neubelt; the same λ = 6 as the `probes` tool's
/// `sg9h`/`sg12h` and the Appendix C tests. (Probulator's spacing heuristic,
/// `sbf::layout::sharpness_from_spacing`, is meant for sphere sets: on the 9-lobe
/// hemisphere spiral it gives λ ≈ 56, lobes too narrow to represent a constant.)
pub const SG_HEMISPHERE_SHARPNESS: f64 = sbf::registry::SG_SHARPNESS;

/// The SG sharpness a bake accepts: the range the SG runtime's fits are stated over
/// (Hill's irradiance fit, `sbf::recon::sg`: λ ∈ [2, 64]).
pub const SG_SHARPNESS_RANGE: (f64, f64) = (2.0, 64.0);

/// Acceleration α of the progressive update for path-traced samples. Roughton's α = 3
/// (sbf's default, tuned on noise-free map samples) amplifies Monte Carlo noise: on the
/// built-in scene at 256 samples per texel, AD9 progressive NNLS with α = 3 has 1.69×
/// the irradiance RMSE of a batch NNLS fit of the same samples, α = 2 1.35×, α = 1
/// 0.96× (tests/convergence.rs prints the comparison).
pub const BAKE_ACCELERATION: f64 = 1.0;

/// The bases the baker encodes into: the registry's lightmap bases ([`sbf::registry`]).
pub use sbf::BasisId;

/// A lightmap basis by name (`--bases` of `baker` and `render`), or an error naming them.
pub fn lightmap_basis(name: &str) -> Result<BasisId, String> {
    BasisId::from_name(name).filter(|b| b.info().lightmap).ok_or_else(|| {
        let names: Vec<&str> = BasisId::lightmap().map(BasisId::name).collect();
        format!("unknown basis '{name}' (expected one of {})", names.join(", "))
    })
}

/// Each basis family's Lambert runtime on baked coefficients (the CPU twin of the runtime
/// the bake ships); the irradiance bases (ambient cube, H-basis) reconstruct E/π itself.
pub trait BakedBasis {
    /// E/π at the tangent-frame normal +Z from the lobes' RGB values `c` — each family's
    /// Lambert runtime: SH's band factors (Ramamoorthi & Hanrahan 2001), SG by Hill's fit
    /// at sharpness `sg_sharpness`, AD by the minimax quadratic per lobe ([Roughton19 §8.3]).
    fn irradiance_at_normal(self, c: &[DVec3], sg_sharpness: f64) -> DVec3;
    /// E/π at unit tangent-frame direction `n` (a normal-mapped normal; +Z is the texel's
    /// own), by the same runtimes as [`BakedBasis::irradiance_at_normal`].
    fn irradiance_at(self, c: &[DVec3], n: DVec3, sg_sharpness: f64) -> DVec3;
}

impl BakedBasis for BasisId {
    fn irradiance_at_normal(self, c: &[DVec3], sg_sharpness: f64) -> DVec3 {
        self.irradiance_at(c, DVec3::Z, sg_sharpness)
    }

    fn irradiance_at(self, c: &[DVec3], n: DVec3, sg_sharpness: f64) -> DVec3 {
        use sbf::recon::{ambient_dice, sg, sh};
        use sbf::registry::Family;
        match self.family() {
            Family::Sh if self == BasisId::Zh3 => {
                let ch = |k: usize| std::array::from_fn(|i| c[i][k]);
                DVec3::from(sh::irradiance_l1_zh3(&[ch(0), ch(1), ch(2)], n).expect("finite SH L1 coefficients"))
            }
            Family::Sh => {
                let ch = |k: usize| sh::irradiance(&c.iter().map(|x| x[k]).collect::<Vec<_>>(), n).expect("SH coefficients");
                DVec3::new(ch(0), ch(1), ch(2))
            }
            Family::Sg => self.axes().iter().zip(c).fold(DVec3::ZERO, |acc, (a, ci)| {
                let lobe = sg::HillLobe::new(&sbf::Sg { axis: *a, sharpness: sg_sharpness, amplitude: 1.0 });
                acc + *ci * lobe.eval(n)
            }),
            Family::AmbientDice => self.axes().iter().zip(c).fold(DVec3::ZERO, |acc, (a, ci)| {
                acc + *ci * ambient_dice::lobe_irradiance_fit(&ambient_dice::DIFFUSE_FIT_MINIMAX, a.dot(n))
            }),
            // The irradiance bases: their coefficients reconstruct E/π itself.
            Family::AmbientCube | Family::HBasis => {
                let b = self.basis();
                let mut scratch = vec![0.0; b.len()];
                let mut ch = |k: usize| b.reconstruct(&c.iter().map(|x| x[k]).collect::<Vec<_>>(), n, &mut scratch);
                DVec3::new(ch(0), ch(1), ch(2))
            }
        }
    }
}

/// Least squares or non-negative least squares (progressive, [Roughton19 §7.3]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Solver {
    Ls,
    Nnls,
    /// Texels: progressive LS while baking, then per texel the NNLS fit of the same normal
    /// equations with E/π at the normal pinned to the texel's estimate
    /// ([`crate::post::refit`]); probes (sphere targets): NNLS.
    NnlsIrradiance,
    /// Progressive NNLS, then per texel and channel the lobes scaled so that their E/π at
    /// the normal equals the texel's estimate ([`crate::post::refit::rescale_irradiance`]);
    /// probes: NNLS.
    NnlsRescaled,
}

/// Bake settings.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakeConfig {
    pub seed: u64,
    pub max_bounces: u32,
    pub bases: Vec<BasisId>,
    pub solver: Solver,
    /// First-bounce ray guiding of lightmap texels ([`crate::sampling::guiding`]); probes are never
    /// guided.
    pub guiding: Option<crate::sampling::guiding::GuidingOptions>,
    /// The sample sequences ([`crate::sampling::sequence`]).
    pub sampler: Sequence,
    /// Adaptive sampling of lightmap texels ([`crate::accumulate::adaptive`]); None: every texel every
    /// pass. Not with ray guiding, probes or several GPUs.
    pub adaptive: Option<crate::accumulate::adaptive::AdaptiveOptions>,
    /// Camera-based sampling of lightmap texels ([`crate::accumulate::camera`]); not with
    /// `adaptive`, guiding, probes or several GPUs.
    pub camera: Option<crate::accumulate::camera::CameraSampling>,
    /// How a GPU bake runs its passes ([`Pipeline`]); the CPU bake ignores it. How, not
    /// what: both pipelines give the same bake bit for bit, so it is not serialised (a bake
    /// spec's canonical form, its checkpoint fingerprint and shard header leave it out;
    /// the run options set it).
    #[serde(skip)]
    pub pipeline: Pipeline,
    /// Filtered gather-based accumulation ([`crate::accumulate::filter`]); None: each sample feeds
    /// its own texel only (a one-texel box). Lightmaps only.
    pub filter: Option<crate::accumulate::filter::Filter>,
    /// Sharpness λ of every SG lobe (SG 9 and SG 12), within [`SG_SHARPNESS_RANGE`].
    pub sg_sharpness: f64,
    /// Bake indirect light only (`Tracer::indirect_only`): the light arriving straight
    /// from emitters, delta lights and the sky is left to the runtime.
    pub indirect_only: bool,
}

/// How the GPU runs a pass: one thread per texel through whole paths, or breadth first
/// ([Roughton19 §3.1, §5.1]; [`crate::gpu::wavefront`]). Both run the same estimator on the same
/// sample numbers, so the choice changes the time, not the bake.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pipeline {
    /// One kernel, one thread per job through whole paths (`megakernel.wgsl`'s `bake_pass`).
    #[default]
    Megakernel,
    /// Generate, then per bounce intersect, shade and compact the active paths, then
    /// accumulate ([`crate::gpu::wavefront`]).
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
    /// NNLS rescaled to the texels' E/π (where it applies), Sobol' sequences, uniform
    /// passes on the megakernel, no guiding and no filter.
    fn default() -> Self {
        BakeConfig {
            seed: 1,
            max_bounces: 4,
            bases: vec![BasisId::Sh2, BasisId::Ad9],
            solver: Solver::NnlsRescaled,
            guiding: None,
            sampler: Default::default(),
            adaptive: None,
            camera: None,
            pipeline: Default::default(),
            filter: None,
            sg_sharpness: SG_HEMISPHERE_SHARPNESS,
            indirect_only: false,
        }
    }
}

impl BakeConfig {
    /// Refuses combinations the bake cannot run, with the reason.
    pub fn check(&self, targets: &Targets) -> Result<(), String> {
        // A bake encodes radiance into the bases the GPU has slots for (the registry's
        // lightmap and probe bases); the irradiance bases (ambient cube, H-basis) are fitted
        // to an irradiance, which a bake does not estimate.
        if let Some(b) = self.bases.iter().find(|b| b.gpu_kind().is_none()) {
            let baked: Vec<&str> = BasisId::ALL.iter().filter(|b| b.gpu_kind().is_some()).map(|b| b.name()).collect();
            return Err(format!("{b} is not a basis a bake encodes into (one of {})", baked.join(", ")));
        }
        if targets.sphere {
            if let Some(b) = self.bases.iter().find(|b| !b.info().probe) {
                return Err(format!("{b} covers a hemisphere: probes need a sphere basis"));
            }
        }
        let (lo, hi) = SG_SHARPNESS_RANGE;
        if !(lo..=hi).contains(&self.sg_sharpness) {
            return Err(format!(
                "SG sharpness {} is outside [{lo}, {hi}] (the range the SG runtime's fits are stated over)",
                self.sg_sharpness
            ));
        }
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

    /// Whether the items can be baked in parts (devices, shards) that never see each
    /// other's samples: not with the strategies that read every item each pass — ray
    /// guiding (its clusters learn from all their texels), filtered accumulation (a texel
    /// gathers its neighbours' samples), adaptive and camera-based sampling (each batch
    /// draws from the whole atlas). The error names the option.
    pub fn check_partitionable(&self) -> Result<(), String> {
        let why = [
            (self.guiding.is_some(), "--guiding", "ray guiding's clusters learn from all their texels every pass"),
            (self.filter.is_some(), "--filter", "each texel gathers its neighbours' samples every pass"),
            (self.adaptive.is_some(), "--adaptive", "each batch draws its texels from the whole atlas"),
            (self.camera.is_some(), "--camera", "each batch draws its texels from the whole view"),
        ];
        match why.iter().find(|w| w.0) {
            Some((_, option, reason)) => Err(format!("{option} cannot be split into parts baked apart ({reason}); bake it whole")),
            None => Ok(()),
        }
    }

    /// The sbf basis `kind` as this bake encodes it (its SG sharpness).
    pub fn basis(&self, kind: BasisId) -> Box<dyn Basis + Send + Sync> {
        kind.basis_with(self.sg_sharpness)
    }

    /// The progressive options for `basis` on these targets: SG and Ambient Dice by
    /// Gauss–Seidel with the eq. 7.15 denominator at acceleration [`BAKE_ACCELERATION`]
    /// (NNLS or LS by the solver); SH by the running Monte Carlo projection
    /// (`sbf::solve::Denominator::Projection`: its least-squares fit, unbiased at every
    /// pass). Sphere bases on texels see only the upper hemisphere, so mirrored zero samples
    /// pin the lower half ([Roughton19 §7.3]'s hemisphere handling); probes sample the whole sphere.
    /// NNLS applies only to bases whose functions are non-negative (SG, Ambient Dice): SH
    /// coefficients of a non-negative signal are legitimately negative
    /// ([`BasisId::non_negative`]).
    pub fn encoder_options(&self, basis: BasisId, sphere_targets: bool) -> ProgressiveOptions {
        let opts = match self.solver {
            Solver::Nnls | Solver::NnlsRescaled if basis.non_negative() => ProgressiveOptions::non_negative(),
            Solver::NnlsIrradiance if basis.non_negative() && sphere_targets => ProgressiveOptions::non_negative(),
            // SH is orthonormal over the sphere, which probes sample uniformly and texels
            // with a mirrored zero below every upper-hemisphere sample: its Gram is the
            // identity, so the projection ∫Y_i f — a running mean — is the least-squares
            // fit, unbiased at every pass.
            _ if !basis.non_negative() => ProgressiveOptions::projection(vec![0.25 / std::f64::consts::PI; basis.lobes()], false),
            _ => ProgressiveOptions::default(),
        };
        ProgressiveOptions { acceleration: BAKE_ACCELERATION, mirror_hemisphere: basis.is_sphere() && !sphere_targets, ..opts }
    }
}
