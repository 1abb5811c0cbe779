//! What every mode reads (`Context`: the map, its samples, the output grid, the exact
//! reference and the run's settings) and what it produces (`ModeResult`).

use crate::reference;
use sbf::envmap::{LatLong, LatLongImage};
use sbf::glam::DVec3;
use sbf::solve::{map_samples, RadianceSample};
use sbf::Domain;
use std::time::Instant;

/// Everything a mode needs: the source, its samples, the output grid and the
/// reference irradiance on it.
#[derive(Debug)]
pub struct Context {
    pub map: LatLongImage,
    pub samples: Vec<RadianceSample>,
    pub grid: LatLong,
    pub dirs: Vec<DVec3>,
    pub irradiance: Vec<[f64; 3]>,
    /// How the reference was computed.
    pub reference_method: String,
    /// Where errors are measured: the whole sphere, or the upper hemisphere (world +Y,
    /// tangent +Z) as in [Roughton19 Appendix C].
    pub domain: Domain,
    /// How the 12-lobe SG modes turn lobes into irradiance.
    pub sg_irradiance: SgIrradiance,
    /// The specular runtime path of the SG and AD modes.
    pub specular_runtime: SpecularRuntime,
    /// Which GGX integral the specular reference computes, and with it the runtimes'
    /// Fresnel and the SG fits' samples (`--reference`; see [`crate::appendix_c`]).
    pub convention: sbf::ggx::Convention,
    /// Seconds it took to make `irradiance` (charged to the modes that fit it).
    pub reference_s: f64,
    /// Evaluations per direction in the cost measurement (1; the cost-axis test sets 2 as
    /// its "twice as expensive" mutation, see [`crate::cost::CostJob::over`]).
    pub eval_work: usize,
    /// Work several modes share (per-lobe specular responses of one lobe layout and α).
    pub shared: crate::memo::Memo<Vec<f32>>,
    /// How coefficients are stored (`--storage`): every mode's images are reconstructed
    /// from its stored values.
    pub storage: crate::storage::Storage,
    /// Appendix C's reference by \[RoughtonFork\]'s Monte Carlo estimator (see
    /// [`crate::compare::Settings::seed_estimator`]).
    pub seed_estimator: Option<u32>,
}

/// Irradiance reconstruction of the SG 12 batch modes (`sg`, `sgls`, `sglsa`, `sgnnls`).
/// The running averages (`sgra`, `sgnnra`) always use Hill's fit, as the peer's do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SgIrradiance {
    /// Hill's fit per lobe (the runtime path; within 2% of the exact convolution).
    Hill,
    /// The peer's: the cosine replaced by an SG kernel normalised to π, sharpness 8.5
    /// after the naive projection and 3.0 after the other solvers (Probulator's
    /// "BRDF lambda"); reproduces its published figures (see the accuracy test).
    Peer,
    /// The best linear estimate of the irradiance from the coefficients under an isotropic
    /// radiance prior with power spectrum C_l ∝ l⁻² ([`sbf::recon::prior`]): it also
    /// estimates what the 12 lobes leave out, instead of assuming the radiance is their sum.
    Prior,
    /// The default, per mode the reconstruction whose worst ratio to the peer's figure over
    /// the five probes is lowest (`peer_figures` test; ratios ours/peer, ennis grace pisa
    /// uffizi wells):
    /// - `sg` → the peer's kernel: its naive projection carries the peer's normalisation,
    ///   tuned with that kernel (Hill: 1.4–2.2× the peer's error on pisa, uffizi, wells);
    /// - `sgls`, `sglsa` → the prior estimate (sgls 0.70 0.33 0.94 0.59 0.84; Hill 0.55
    ///   0.32 0.69 0.68 1.09, the peer's kernel 0.97–1.01);
    /// - `sgnnls` → the peer's kernel (0.97 0.60 0.99 1.02 0.98; Hill 1.12 on wells, the
    ///   prior 1.09 there: non-negative lobes leave a residual neither models well).
    Auto,
}

impl SgIrradiance {
    /// The reconstruction a mode gets (resolves [`SgIrradiance::Auto`]).
    pub fn for_mode(self, id: &str) -> SgIrradiance {
        match self {
            SgIrradiance::Auto if matches!(id, "sg" | "sgnnls") => SgIrradiance::Peer,
            SgIrradiance::Auto if matches!(id, "sgls" | "sglsa") => SgIrradiance::Prior,
            SgIrradiance::Auto => SgIrradiance::Hill,
            m => m,
        }
    }

    /// The reconstruction's name (`hill`, `peer`, `prior`; `auto` unresolved).
    pub fn name(self) -> &'static str {
        match self {
            SgIrradiance::Hill => "hill",
            SgIrradiance::Peer => "peer",
            SgIrradiance::Prior => "prior",
            SgIrradiance::Auto => "auto",
        }
    }

    /// Kernel sharpness the peer used for a mode.
    pub fn peer_kernel_sharpness(id: &str) -> f64 {
        if id == "sg" {
            8.5
        } else {
            3.0
        }
    }
}

/// The runtime path of the lobe modes (SG and Ambient Dice); SH always uses its zonal
/// convolution with the DFG.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SpecularRuntime {
    /// Per-lobe GGX response tables (`sbf::recon::lobe_ggx`, 4D over (n·v, √α, γ, ψ)):
    /// interpolation is the only approximation.
    #[default]
    Table,
    /// The closed-form fits: SG through the split sum over the warped NDF (Karis 2013; the
    /// ASG warp of Xu et al. 2013 under the Appendix C convention), AD through
    /// [Roughton19 Listing 8.1] × the 2D LUT of Listing 8.2.
    Fit,
}

impl SpecularRuntime {
    /// Parses `table` or `fit`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "table" => Ok(SpecularRuntime::Table),
            "fit" => Ok(SpecularRuntime::Fit),
            other => Err(format!("--specular-runtime {other}: expected `table` or `fit`")),
        }
    }

    /// `table` or `fit`.
    pub fn name(self) -> &'static str {
        match self {
            SpecularRuntime::Table => "table",
            SpecularRuntime::Fit => "fit",
        }
    }

    /// One line for the report.
    pub fn describe(&self) -> &'static str {
        match self {
            SpecularRuntime::Table => "SG and AD lobes through per-lobe GGX response tables (luts/lobe_ggx_*.sbflut: 4D over n·v, √α and the lobe axis about the mirror direction, multilinear; table error in luts/MANIFEST); SH by its zonal GGX convolution × DFG",
            SpecularRuntime::Fit => "SG lobes through the split sum over the warped NDF (Karis 2013; Appendix C convention: the ASG warp, Xu et al. 2013), AD lobes through [Roughton19 Listing 8.1] × the Listing 8.2 LUT; SH by its zonal GGX convolution × DFG",
        }
    }
}

impl Context {
    /// Whole-sphere context (see [`Context::with_domain`]).
    pub fn new(map: LatLongImage) -> Self {
        Self::with_domain(map, Domain::Sphere)
    }

    /// Output grid rows where errors are measured.
    pub fn metric_rows(&self) -> std::ops::Range<usize> {
        match self.domain {
            Domain::Sphere => 0..self.grid.height,
            Domain::UpperHemisphere => 0..self.grid.height / 2,
        }
    }

    /// Samples the map, builds the output grid and the exact reference irradiance;
    /// fits always use the whole sphere (as Appendix C), errors use `domain`.
    pub fn with_domain(map: LatLongImage, domain: Domain) -> Self {
        let grid = reference::output_grid(&map);
        let dirs: Vec<DVec3> =
            (0..grid.height).flat_map(|j| (0..grid.width).map(move |i| (i, j))).map(|(i, j)| grid.texel_direction(i, j)).collect();
        let t = Instant::now();
        let (irradiance, reference_method) = reference::reference_irradiance_grid(&map, grid);
        let reference_s = t.elapsed().as_secs_f64();
        Context {
            samples: map_samples(&map),
            map,
            grid,
            dirs,
            irradiance,
            reference_method,
            domain,
            sg_irradiance: SgIrradiance::Auto,
            specular_runtime: Default::default(),
            convention: Default::default(),
            reference_s,
            eval_work: 1,
            shared: crate::memo::Memo::new(),
            storage: crate::storage::Storage::F32,
            seed_estimator: None,
        }
    }

    /// RGB coefficients as [`Context::storage`] stores them.
    pub fn stored(&self, c: Vec<[f64; 3]>) -> Vec<[f64; 3]> {
        self.storage.store(&c)
    }

    /// The map's radiance at the output grid's texel centres (bilinear).
    pub fn radiance(&self) -> Vec<[f64; 3]> {
        self.dirs.iter().map(|d| self.map.bilinear(*d)).collect()
    }
}

/// What a mode produced.
#[derive(Debug, Clone)]
pub struct ModeResult {
    pub id: &'static str,
    pub name: &'static str,
    pub basis: String,
    pub solver: &'static str,
    /// RGB coefficients, one per basis function.
    pub coefficients: Vec<[f64; 3]>,
    /// (axis, sharpness) for lobe bases.
    pub lobes: Vec<(DVec3, f64)>,
    pub radiance: Option<Vec<[f64; 3]>>,
    pub irradiance: Vec<[f64; 3]>,
    /// Fraction of texels whose irradiance was negative before a clamp (SH modes clamp
    /// at 0 like the peer; `None` when the mode does not clamp).
    pub clamped_negative_fraction: Option<f64>,
    /// Encode time (median of `encode_runs` runs), seconds, from the mode's input.
    pub encode_s: f64,
    /// Encode runs timed: `--repeats`, or fewer once they took [`ENCODE_BUDGET_S`](crate::cost::ENCODE_BUDGET_S).
    pub encode_runs: usize,
    /// The fastest and slowest of those runs, seconds.
    pub encode_range_s: [f64; 2],
    /// The mode fits the exact irradiance image, not the radiance map: its encode is
    /// charged [`Context::reference_s`] on top (see [`ModeResult::encode_total_s`]).
    pub needs_reference: bool,
    /// Steady-state CPU cost of the irradiance runtime evaluation ([`crate::cost`]).
    pub eval: crate::cost::CostStat,
    /// Scalars stored per probe/texel (RGB coefficients × 3, or per YCoCg channel).
    pub stored_scalars: usize,
    /// Bytes per probe/texel where a mode is an engine's storage format (f16 and 8-bit
    /// channels, [`super::engine`]; compressed under BC6H); `None`: `storage`'s bytes
    /// per scalar.
    pub engine_bytes: Option<f64>,
    /// How the coefficients were stored ([`Context::storage`]).
    pub storage: crate::storage::Storage,
    /// What [`ModeResult::storage_precision`] says where the mode stores part of its data
    /// otherwise (a prefiltered map in RGB9E5); `None`: from `storage` and `engine_bytes`.
    pub precision: Option<String>,
    /// Whether the irradiance path is the WGSL runtime's (`shaders`): false for the SG
    /// modes reconstructed with the peer's kernel or the prior estimate, which have none —
    /// their GPU cost is then not reported.
    pub wgsl_irradiance: bool,
    /// The irradiance reconstruction where a mode has several (`hill`, `peer`, `prior` for
    /// the SG batch modes); empty otherwise. Part of the key of its calibrated CPU cost.
    pub irradiance_variant: &'static str,
    /// Per-sample encoders: (samples taken, irradiance RMS over the metric rows) at
    /// 16, 32, 64, … samples and at the end (an untimed second pass); empty otherwise.
    pub convergence: Vec<(u64, f64)>,
}

impl ModeResult {
    /// Encode time from the radiance map: the encode plus, for modes that fit the
    /// irradiance image, the time it took to make it.
    pub fn encode_total_s(&self, reference_s: f64) -> f64 {
        self.encode_s + if self.needs_reference { reference_s } else { 0.0 }
    }

    /// How the values are stored: `f32`, `f16` or `bc6h`; an engine format's own
    /// precision (`engine`) or, under BC6H, its compressed textures (`bc6h+bc1/bc7`).
    pub fn storage_precision(&self) -> String {
        if let Some(p) = &self.precision {
            return p.clone();
        }
        match (self.engine_bytes.is_some(), self.storage) {
            (true, crate::storage::Storage::Bc6h) => "bc6h+bc1/bc7".into(),
            (true, _) => "engine".into(),
            (false, s) => s.name().into(),
        }
    }

    /// Bytes per probe/texel: the storage's bytes per scalar, or an engine format's own.
    pub fn storage_bytes(&self) -> f64 {
        self.engine_bytes.unwrap_or_else(|| self.storage.bytes(self.stored_scalars))
    }
}
