//! The comparison modes. Ids follow the peer tool's suffixes (lower case).
//!
//! Every mode turns the input map into coefficients (timed) and produces an
//! irradiance image (E/π) on the output grid, plus a radiance image where the basis
//! stores radiance. Radiance fits use the map's texels weighted by their exact solid
//! angles (the integral least-squares problem). Fits to the irradiance image (`ac`,
//! `adrbf-irr`) weigh texels equally, as the peer does, so they minimise the unweighted
//! RMS reported. SH modes clamp the reconstructed irradiance at 0, as the peer does;
//! the fraction of texels that were negative is reported separately.

use crate::cost::CostJob;
use crate::reference;
use sbf::envmap::{LatLong, LatLongImage};
use sbf::glam::DVec3;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::nalgebra::DMatrix;
use sbf::recon::{ambient_dice as adr, sg as sgr, sh as shr};
use sbf::solve::{map_samples, moments, naive_projection, nnls_gram, solve_gram, LsOptions, NnlsOptions, RadianceSample};
use sbf::{AmbientCube, AmbientDiceSrbf, Basis, Domain, SgBasis, ShBasis};
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

/// Tangent space (normal +Z) to world (+Y up): (x, y, z) ↦ (x, z, y) — the frame in which
/// the peer (Probulator, and Roughton's fork of it) lays out its lobes, read in our world.
///
/// Both tools map a lat-long texel (u, v) to φ = π(2u − 1), θ = πv, but to different axes:
/// the peer's `latLongTexcoordToCartesian` gives (sin θ sin φ, −sin θ cos φ, cos θ) with z up;
/// ours ([`sbf::envmap::LatLong::uv_to_direction`]) gives (sin θ sin φ, cos θ, −sin θ cos φ)
/// with y up. The same texel is the same direction once the peer's (x, y, z) is read as our
/// (x, z, y): a swap of two axes, so the peer's z-up frame has the other handedness than our
/// y-up world. A proper rotation such as (x, z, −y) would put every lobe of a layout
/// without that mirror symmetry at the mirrored texel (AD 9 rotated 180° about the normal,
/// the Vogel spirals winding the other way). The map is its own inverse.
pub fn tangent_to_world(t: DVec3) -> DVec3 {
    DVec3::new(t.x, t.z, t.y)
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
    /// Encode runs timed: `--repeats`, or fewer once they took [`ENCODE_BUDGET_S`].
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
    /// channels, [`crate::engine_modes`]; compressed under BC6H); `None`: `storage`'s bytes
    /// per scalar.
    pub engine_bytes: Option<f64>,
    /// How the coefficients were stored ([`Context::storage`]).
    pub storage: crate::storage::Storage,
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

/// (id, description) of every mode, in report order.
pub const MODES: &[(&str, &str)] = &[
    ("mcis", "Monte Carlo importance sampling as the peer's reference: 5000 texels drawn by luminance × solid angle (fixed seed, shared by all output texels), vs our exact reference"),
    ("ac", "ambient cube fitted to the irradiance image, NNLS"),
    ("acproj", "ambient cube: irradiance sampled at the six axes"),
    ("shl1g", "SH L1, Geomerics reconstruction"),
    ("shl1zh3", "SH L1, ZH3 hallucination"),
    ("shl1", "SH L1 (4 coefficients), A_l convolution"),
    ("shl2", "SH L2 (9), A_l convolution"),
    ("shl3", "SH L3 (16)"),
    ("shl4", "SH L4 (25)"),
    ("shl5", "SH L5 (36)"),
    ("shl6", "SH L6 (49)"),
    ("shl7", "SH L7 (64)"),
    ("shl8", "SH L8 (81)"),
    ("shl9", "SH L9 (100)"),
    ("shl10", "SH L10 (121)"),
    ("shl11", "SH L11 (144)"),
    ("shl12", "SH L12 (169)"),
    ("shl13", "SH L13 (196)"),
    ("shl14", "SH L14 (225)"),
    ("shl15", "SH L15 (256)"),
    ("shl16", "SH L16 (289)"),
    ("adrbf", "Ambient Dice SRBF 12, radiance LS, irradiance by the exact lobe integral"),
    ("adrbf-irr", "Ambient Dice SRBF 12 fitted to the irradiance image (as the peer)"),
    ("sg", "SG 12 (λ 6, Vogel), naive projection with the peer's normalisation, irradiance by the peer's kernel (λ 8.5; `--sg-irradiance hill` for Hill)"),
    ("sgls", "SG 12, least squares; irradiance by the isotropic-prior estimate (`--sg-irradiance hill` for Hill)"),
    ("sglsa", "SG 12 + ambient lobe, least squares; irradiance by the isotropic-prior estimate"),
    ("sgnnls", "SG 12, non-negative least squares; irradiance by the peer's kernel (λ 3)"),
    ("shl2w", "SH L2 with sinc⁴ deringing where its irradiance would be negative"),
    ("ad", "Ambient Dice hybrid Bézier (36), fitted to the irradiance image (as the peer)"),
    ("adycocg", "Ambient Dice YCoCg (Bézier Y + linear Co/Cg, 60), fitted to the irradiance image"),
    ("sgra", "SG 12, running average over the map's texels in a fixed shuffled order (as the peer)"),
    ("sgnnra", "SG 12, non-negative running average"),
    ("sgpls", "SG 12, progressive least squares ([Roughton19 §7.3]), 4096 Halton samples, f32 state"),
    ("sgpnnls", "SG 12, progressive non-negative least squares"),
    ("adpls", "Ambient Dice SRBF 12, progressive least squares, 4096 Halton samples"),
    ("adpnnls", "Ambient Dice SRBF 12, progressive non-negative least squares"),
    ("sgnnlsc", "SG 12, NNLS keeping the map's SH L0 + L1 (equality-constrained; `conserving`); Hill irradiance"),
    ("adnnlsc", "Ambient Dice SRBF 12, NNLS keeping the map's SH L0 + L1 (equality-constrained)"),
    ("sgpnnlsc", "SG 12, progressive Monte Carlo projections (4096 Halton samples, f32 state), exact Gram, NNLS keeping SH L0 + L1"),
    ("adpnnlsc", "Ambient Dice SRBF 12, progressive Monte Carlo projections, exact Gram, NNLS keeping SH L0 + L1"),
    ("ad9", "Ambient Dice SRBF 9, Roughton's hemisphere set (§8.3.1), LS over the sphere, eq. 8.14 irradiance (Appendix C)"),
    ("sg9h", "SG 9, λ 6, Vogel spiral over the upper hemisphere, LS over the sphere, Hill irradiance (Appendix C)"),
    ("sg12h", "SG 12, λ 6, Vogel spiral over the upper hemisphere (Appendix C)"),
    ("adrbf-tangent", "Ambient Dice SRBF 12 on the icosahedron in tangent space, eq. 8.14 irradiance (Appendix C's AD12)"),
    ("h4", "H-basis 4 (tangent space, normal +Y in the map), fitted to the irradiance image over the upper hemisphere"),
    ("h6", "H-basis 6, fitted to the irradiance image over the upper hemisphere"),
    ("godot-l1", "Godot ≥ 4.4 LightmapGI SH: L0 + L1/L0 packed in three RGBA16F layers, Godot's decode"),
    ("godot-l1-legacy", "Godot 4.0–4.3 LightmapGI SH: L0 + signed L1 coefficients in three RGBA16F layers, its decode"),
    ("monosh", "Bakery MonoSH: RGB L0 + one luminance L1 direction (RGBA8), Bakery's default non-linear decode"),
    ("monosh-linear", "Bakery MonoSH with SH non-linear mode off: the linear decode"),
    ("enlighten", "Unity/Enlighten directional lightmap: one luminance direction + rescaling factor (RGBA8), Unity's half-Lambert decode"),
    ("enlighten-rgb", "one Enlighten direction + rescaling factor per channel (3 × RGBA8): a research layout no engine ships"),
];

/// Default modes for `--domain hemisphere` ([Roughton19 Appendix C]).
pub const HEMISPHERE_MODES: &[&str] = &["ad9", "adrbf-tangent", "sg9h", "sg12h", "h4", "h6"];

/// World (+Y up) to tangent space (normal +Z): the inverse of [`tangent_to_world`] (the
/// same swap).
pub fn world_to_tangent(w: DVec3) -> DVec3 {
    DVec3::new(w.x, w.z, w.y)
}

/// RGB coefficients, one per basis function.
type Rgb = Vec<[f64; 3]>;

/// Y (36), Co (12), Cg (12) coefficient vectors of the YCoCg mode.
type YCoCgCoeffs = (Vec<f64>, Vec<f64>, Vec<f64>);

/// Draws of the Monte Carlo mode (the peer's MCIS default).
pub const MCIS_SAMPLES: usize = 5000;

/// Samples taken by the progressive modes.
pub const PROGRESSIVE_SAMPLES: u64 = 4096;

/// The default set: every mode with a peer figure, plus adrbf and the progressive modes.
pub const DEFAULT_MODES: &[&str] = &[
    "ac",
    "acproj",
    "shl1g",
    "shl1zh3",
    "shl1",
    "shl2",
    "shl4",
    "shl2w",
    "ad",
    "adycocg",
    "adrbf-irr",
    "adrbf",
    "sg",
    "sgls",
    "sglsa",
    "sgnnls",
    "sgra",
    "sgnnra",
    "sgpls",
    "sgpnnls",
    "adpls",
    "adpnnls",
];

fn channels(m: &DMatrix<f64>) -> Vec<[f64; 3]> {
    (0..m.nrows()).map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]).collect()
}

fn channel(c: &[[f64; 3]], k: usize) -> Vec<f64> {
    c.iter().map(|v| v[k]).collect()
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

pub use crate::cost::{EncodeJob, Timing, ENCODE_BUDGET_S};

/// `f` run once (untimed) for its result, and `f` as the job that times it later
/// (`repeats` runs, [`crate::cost::time_encodes`]). `f` owns what it reads, so
/// the job outlives this mode's other work.
pub(crate) fn timed<'a, T: 'a>(repeats: usize, mut f: impl FnMut() -> T + Send + 'a) -> (T, EncodeJob<'a>) {
    let out = f();
    (out, EncodeJob::new(repeats, move || drop(std::hint::black_box(f()))))
}

/// The image of `f` over the output directions, and `f` as the job that measures its
/// steady-state cost later ([`crate::cost`]: a run measures every mode's job side by side).
pub(crate) fn eval_cost<'a>(ctx: &'a Context, mut f: impl FnMut(DVec3) -> [f64; 3] + Send + 'a) -> (Vec<[f64; 3]>, Option<CostJob<'a>>) {
    let out: Vec<[f64; 3]> = ctx.dirs.iter().map(|d| f(*d)).collect();
    let dirs = &ctx.dirs;
    (out, Some(CostJob::over(dirs.len(), ctx.eval_work, move |k| f(dirs[k]))))
}

/// Σ_i w_i·c_i over RGB coefficients: the runtime's form (each basis function's weight
/// computed once, then one multiply-add per channel).
pub(crate) fn dot_rgb(c: &[[f64; 3]], w: impl Iterator<Item = f64>) -> [f64; 3] {
    let mut e = [0.0; 3];
    for (ci, wi) in c.iter().zip(w) {
        for k in 0..3 {
            e[k] += wi * ci[k];
        }
    }
    e
}

/// E/π of an SG 12 mode from RGB coefficients (each lobe's kernel once), the same
/// function as `sbf::recon::sg::irradiance_basis` per channel (test
/// `runtime_evaluators_equal_the_per_channel_library`).
pub(crate) fn sg_irradiance_rgb(method: SgIrradiance, id: &str, basis: &SgBasis, lobes: &SgLobes, c: &[[f64; 3]], n: DVec3) -> [f64; 3] {
    let k = basis.lobe_count();
    let mut e = match method.for_mode(id) {
        // (The prior estimate has its own evaluator, `PriorRgb`; Hill stands in here.)
        SgIrradiance::Hill | SgIrradiance::Auto | SgIrradiance::Prior => dot_rgb(&c[..k], lobes.hill.iter().map(|h| h.eval(n))),
        SgIrradiance::Peer => dot_rgb(&c[..k], lobes.axes.iter().zip(&lobes.peer).map(|(a, p)| p.eval(a.dot(n).clamp(-1.0, 1.0)))),
    };
    // The ambient function (a constant) reflects its coefficient under any kernel of integral π.
    if basis.has_ambient() {
        for ch in 0..3 {
            e[ch] += c[k][ch];
        }
    }
    e
}

/// The isotropic-prior irradiance estimate of an SG basis from RGB coefficients c' =
/// Σ⁻¹G·c ([`sbf::recon::prior`]): each function's kernel once per direction.
#[derive(Clone)]
struct PriorRgb {
    est: sbf::recon::prior::PriorIrradiance,
    weights: Vec<f64>,
}

impl PriorRgb {
    fn new(basis: &SgBasis) -> Result<PriorRgb, sbf::SbfError> {
        let est = sbf::recon::prior::PriorIrradiance::for_sg_basis(basis, sbf::recon::prior::RadiancePrior::default())?;
        Ok(PriorRgb { weights: vec![0.0; est.len()], est })
    }

    /// c' per channel (what a probe stores for this reconstruction; c follows back by the
    /// inverse transform for radiance and specular).
    fn coefficients(&self, c: &[[f64; 3]]) -> Result<Vec<[f64; 3]>, sbf::SbfError> {
        let per: Vec<Vec<f64>> = (0..3).map(|k| self.est.coefficients(&channel(c, k))).collect::<Result<_, _>>()?;
        Ok((0..c.len()).map(|i| [per[0][i], per[1][i], per[2][i]]).collect())
    }

    fn eval(&mut self, cp: &[[f64; 3]], n: DVec3) -> [f64; 3] {
        self.est.weights(n, &mut self.weights);
        dot_rgb(cp, self.weights.iter().copied())
    }
}

/// The lobes of an SG basis with each reconstruction's per-lobe constants precomputed:
/// Hill's, and the peer's kernel (sharpness for mode `id`) as a zonal series
/// (`sbf::recon::prior::sg_kernel_series`, = `sg::irradiance_sg_kernel` to 1e-12).
pub(crate) struct SgLobes {
    axes: Vec<DVec3>,
    hill: Vec<sgr::HillLobe>,
    peer: Vec<sbf::recon::prior::Kernel>,
}

pub(crate) fn sg_lobes(basis: &SgBasis, id: &str) -> SgLobes {
    let kl = SgIrradiance::peer_kernel_sharpness(id);
    let lobes: Vec<sbf::Sg> = (0..basis.lobe_count()).map(|i| basis.lobe(i)).collect();
    SgLobes {
        axes: lobes.iter().map(|l| l.axis).collect(),
        hill: lobes.iter().map(sgr::HillLobe::new).collect(),
        peer: lobes.iter().map(|l| sbf::recon::prior::sg_kernel_series(l.sharpness, kl)).collect(),
    }
}

/// A basis's reconstruction from RGB coefficients as the irradiance evaluation (fits to
/// the irradiance image), with its cost.
fn eval_basis<'a, B: Basis + Send + 'a>(ctx: &'a Context, basis: B, c: Vec<[f64; 3]>) -> (Vec<[f64; 3]>, Option<CostJob<'a>>) {
    let mut s = vec![0.0; basis.len()];
    eval_cost(ctx, move |d| {
        basis.eval_into(d, &mut s);
        dot_rgb(&c, s.iter().copied())
    })
}

/// The radiance image of RGB coefficients (basis evaluated once per direction; parallel,
/// untimed).
pub(crate) fn reconstruct(basis: &(dyn Basis + Sync), c: &[[f64; 3]], dirs: &[DVec3]) -> Vec<[f64; 3]> {
    use rayon::prelude::*;
    dirs.par_iter()
        .map_init(
            || vec![0.0; basis.len()],
            |s, d| {
                basis.eval_into(*d, s);
                dot_rgb(c, s.iter().copied())
            },
        )
        .collect()
}

/// SH order of the SH modes: `shl1g`, `shl1zh3` and `shlN` for N = 1…16.
pub fn sh_order(id: &str) -> Option<usize> {
    match id {
        "shl1g" | "shl1zh3" => Some(1),
        _ => id.strip_prefix("shl").and_then(|n| n.parse::<usize>().ok()).filter(|n| (1..=16).contains(n) && id == format!("shl{n}")),
    }
}

/// Irradiance image as samples for fits to E/π. Like the peer, every output texel
/// weighs the same: these fits minimise exactly the unweighted RMS the reports quote.
fn irradiance_samples(ctx: &Context) -> Vec<RadianceSample> {
    ctx.dirs.iter().zip(&ctx.irradiance).map(|(d, e)| RadianceSample { direction: *d, value: *e, weight: 1.0 }).collect()
}

/// Clamps an irradiance image at 0 (as the peer displays and measures SH
/// reconstructions) and returns the fraction of texels that were negative.
fn clamp_negative(img: &mut [[f64; 3]]) -> f64 {
    let mut neg = 0usize;
    for t in img.iter_mut() {
        if t.iter().any(|v| *v < 0.0) {
            neg += 1;
        }
        for v in t.iter_mut() {
            *v = v.max(0.0);
        }
    }
    neg as f64 / img.len().max(1) as f64
}

/// A mode run except for its steady-state cost: the result (with `eval` not yet
/// measured) and the job that measures it (none for the Monte Carlo mode, whose cost is
/// its encode). A run measures every mode's job side by side
/// ([`crate::cost::measure_side_by_side`]) and stores each cost in `result.eval`.
#[derive(Debug)]
pub struct Prepared<'a> {
    pub result: ModeResult,
    pub eval: Option<CostJob<'a>>,
    /// The encode's timing job ([`Prepared::set_encode`] stores its result).
    pub encode: Option<EncodeJob<'a>>,
    /// The Monte Carlo mode: its per-texel cost is its encode time per output texel.
    pub eval_from_encode: bool,
}

impl Prepared<'_> {
    /// Stores the encode's timing (and, for the Monte Carlo mode, the cost it implies).
    pub fn set_encode(result: &mut ModeResult, t: Timing, eval_from_encode: bool, texels: usize) {
        result.encode_s = t.median_s;
        result.encode_runs = t.runs;
        result.encode_range_s = [t.min_s, t.max_s];
        if eval_from_encode {
            result.eval = crate::cost::CostStat::single(t.median_s * 1e9 / texels.max(1) as f64, texels);
        }
    }
}

/// Runs one mode alone, its cost measured on its own (a run of several modes uses
/// [`prepare`] and measures them side by side); `repeats` encode runs are timed and
/// their median reported.
pub fn run(id: &str, ctx: &Context, repeats: usize) -> Result<ModeResult, String> {
    let p = prepare(id, ctx, repeats)?;
    let mut r = p.result;
    if let Some(mut job) = p.encode {
        let t = crate::cost::time_encodes(std::slice::from_mut(&mut job)).remove(0);
        Prepared::set_encode(&mut r, t, p.eval_from_encode, ctx.dirs.len());
    }
    if let Some(job) = p.eval {
        r.eval = crate::cost::measure(job);
    }
    Ok(r)
}

/// Runs one mode up to its cost measurement (see [`Prepared`]); `repeats` encode runs are
/// timed and their median reported.
pub fn prepare<'a>(id: &str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let (name, description) =
        MODES.iter().find(|(m, _)| *m == id).copied().ok_or_else(|| format!("unknown mode '{id}' (see `probes list`)"))?;
    // From here on the mode's id is `name` (a 'static str the cost jobs may keep).
    let id = name;
    let vogel = sbf::layout::vogel_sphere(12).map_err(|e| e.to_string())?;
    let dirs = &ctx.dirs;
    let err = |e: sbf::SbfError| e.to_string();
    let mk = |basis: String,
              solver: &'static str,
              coefficients: Vec<[f64; 3]>,
              lobes: Vec<(DVec3, f64)>,
              radiance: Option<Vec<[f64; 3]>>,
              irradiance: Vec<[f64; 3]>,
              encode: EncodeJob<'a>,
              eval: Option<CostJob<'a>>| Prepared {
        eval,
        encode: Some(encode),
        eval_from_encode: false,
        result: ModeResult {
            id: name,
            name: description,
            basis,
            solver,
            lobes,
            radiance,
            irradiance,
            clamped_negative_fraction: None,
            stored_scalars: 3 * coefficients.len(),
            engine_bytes: None,
            storage: ctx.storage,
            wgsl_irradiance: true,
            irradiance_variant: "",
            encode_s: 0.0,
            encode_runs: 0,
            encode_range_s: [0.0; 2],
            needs_reference: false,
            eval: Default::default(),
            coefficients,
            convergence: Vec::new(),
        },
    };
    match id {
        "mcis" => {
            // As the peer's MCIS: texels drawn by luminance × solid angle (one discrete
            // distribution over the map), MCIS_SAMPLES draws from one fixed-seed sequence
            // shared by every output texel (the peer's non-jittered default), each draw
            // contributing L·Ω·max(0, n·ω)/p at the texel centre; E/π = mean/π.
            // One timed run on one thread, like every other mode's encode.
            let (irr, t) = timed(1, move || {
                let g = ctx.map.geometry;
                let weights: Vec<f64> = (0..g.texel_count())
                    .map(|k| {
                        let t = ctx.map.texel(k % g.width, k / g.width);
                        (0.2126 * t[0] as f64 + 0.7152 * t[1] as f64 + 0.0722 * t[2] as f64) * g.texel_solid_angle(k / g.width)
                    })
                    .collect();
                let total: f64 = weights.iter().sum();
                if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                    return vec![[0.0; 3]; dirs.len()];
                }
                let mut cdf = Vec::with_capacity(weights.len());
                let mut acc = 0.0;
                for w in &weights {
                    acc += w;
                    cdf.push(acc / total);
                }
                let mut rng = sbf::sampling::Pcg32::new(0, 0);
                // (direction, L·Ω/p) of each draw.
                let draws: Vec<(DVec3, [f64; 3])> = (0..MCIS_SAMPLES)
                    .map(|_| {
                        let u = rng.next_f64();
                        let k = cdf.partition_point(|c| *c <= u).min(weights.len() - 1);
                        let (i, j) = (k % g.width, k / g.width);
                        let p = weights[k] / total;
                        let l = ctx.map.texel(i, j);
                        let s = g.texel_solid_angle(j) / p;
                        (g.texel_direction(i, j), [l[0] as f64 * s, l[1] as f64 * s, l[2] as f64 * s])
                    })
                    .collect();
                // Four output texels per pass over the draws (independent accumulators, each
                // summed in draw order: the same result as one texel at a time, but the four
                // lanes vectorise).
                const LANES: usize = 4;
                let norm = MCIS_SAMPLES as f64 * std::f64::consts::PI;
                dirs.chunks(LANES)
                    .flat_map(|ns| {
                        let mut nx = [0.0; LANES];
                        let mut ny = [0.0; LANES];
                        let mut nz = [0.0; LANES];
                        for (k, n) in ns.iter().enumerate() {
                            (nx[k], ny[k], nz[k]) = (n.x, n.y, n.z);
                        }
                        let mut e = [[0.0f64; LANES]; 3];
                        for (d, v) in &draws {
                            for k in 0..LANES {
                                let c = (nx[k] * d.x + ny[k] * d.y + nz[k] * d.z).max(0.0);
                                e[0][k] += v[0] * c;
                                e[1][k] += v[1] * c;
                                e[2][k] += v[2] * c;
                            }
                        }
                        (0..ns.len()).map(move |k| [e[0][k] / norm, e[1][k] / norm, e[2][k] / norm])
                    })
                    .collect::<Vec<_>>()
            });
            let mut r = mk("none".into(), "Monte Carlo", Vec::new(), Vec::new(), None, irr, t, None);
            r.eval_from_encode = true;
            Ok(r)
        }
        "ac" | "acproj" => {
            let ac = AmbientCube;
            let (c, t) = if id == "ac" {
                let s = irradiance_samples(ctx);
                timed(repeats, move || -> Result<Vec<[f64; 3]>, String> {
                    let g = sbf::solve::sample_gram(&ac, &s);
                    let m = moments(&ac, &s);
                    let mut out = vec![[0.0; 3]; 6];
                    for k in 0..3 {
                        let col: Vec<f64> = m.column(k).iter().copied().collect();
                        let sol = nnls_gram(&g, &col, NnlsOptions::default()).map_err(err)?;
                        for i in 0..6 {
                            out[i][k] = sol.coeffs[i];
                        }
                    }
                    Ok(out)
                })
            } else {
                timed(repeats, move || -> Result<Vec<[f64; 3]>, String> {
                    // The exact quadrature over every texel at each axis (serial: a timed section).
                    let axes = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];
                    Ok(axes.iter().map(|a| reference::irradiance_at(&ctx.map, *a)).collect())
                })
            };
            let c = ctx.stored(c?);
            let cc = c.clone();
            let (irr, ns) = eval_cost(ctx, move |d| {
                let mut w = [0.0; 6];
                ac.eval_into(d, &mut w);
                [0, 1, 2].map(|k| (0..6).map(|i| w[i] * cc[i][k]).sum())
            });
            let mut r = mk(
                ac.name(),
                if id == "ac" { "NNLS on the irradiance image" } else { "projection (six axes)" },
                c,
                Vec::new(),
                None,
                irr,
                t,
                ns,
            );
            r.result.needs_reference = id == "ac";
            Ok(r)
        }
        _ if crate::conserving::is_mode(id) => {
            let run = crate::conserving::prepare(id, ctx, repeats)?;
            let mut r = mk(run.basis, run.solver, run.coefficients, run.lobes, Some(run.radiance), run.irradiance, run.encode, run.eval);
            r.result.convergence = run.convergence;
            Ok(r)
        }
        _ if crate::engine_modes::format(id).is_some() => {
            let format = crate::engine_modes::format(id).expect("guarded");
            let e = crate::engine_modes::prepare(format, ctx, repeats)?;
            let mut r = mk(
                e.basis,
                "SH L1 projection, encoded and stored as the engine does",
                e.stored,
                Vec::new(),
                None,
                e.irradiance,
                e.encode,
                e.eval,
            );
            r.result.stored_scalars = e.scalars;
            r.result.engine_bytes = Some(e.bytes);
            r.result.clamped_negative_fraction = e.clamped_negative_fraction;
            Ok(r)
        }
        _ if sh_order(id).is_some() => {
            let order = sh_order(id).expect("guarded");
            let sh = ShBasis::new(order).map_err(err)?;
            let sh_t = sh.clone();
            let (m, t) = timed(repeats, move || moments(&sh_t, &ctx.samples));
            let c = ctx.stored(channels(&m));
            let chans = [channel(&c, 0), channel(&c, 1), channel(&c, 2)];
            let (irr, ns) = match id {
                "shl1g" => {
                    let rgb: [[f64; 4]; 3] = [0, 1, 2].map(|k| chans[k].clone().try_into().expect("4 coefficients"));
                    eval_cost(ctx, move |d| [0, 1, 2].map(|k| shr::irradiance_l1_geomerics(&rgb[k], d)))
                }
                "shl1zh3" => {
                    let rgb: [[f64; 4]; 3] = [0, 1, 2].map(|k| chans[k].clone().try_into().unwrap());
                    eval_cost(ctx, move |d| shr::irradiance_l1_zh3(&rgb, d).unwrap_or([f64::NAN; 3]))
                }
                _ => {
                    let e = [0, 1, 2].map(|k| shr::irradiance_coefficients(&chans[k]).expect("(L+1)² coefficients"));
                    let mut y = vec![0.0; sh.len()];
                    let sh = sh.clone();
                    eval_cost(ctx, move |d| {
                        sh.eval_into(d, &mut y);
                        [0, 1, 2].map(|k| e[k].iter().zip(&y).map(|(a, b)| a * b).sum())
                    })
                }
            };
            let (mut irr, rad) = (irr, reconstruct(&sh, &c, dirs));
            let neg = clamp_negative(&mut irr);
            let mut r = mk(sh.name(), "projection (orthonormal LS); irradiance clamped at 0", c, Vec::new(), Some(rad), irr, t, ns);
            r.result.clamped_negative_fraction = Some(neg);
            Ok(r)
        }
        "adrbf" | "adrbf-irr" => {
            let ad = AmbientDiceSrbf::twelve();
            let g = gram_matrix(&ad, Domain::Sphere, GramOptions::default()).map_err(err)?;
            if id == "adrbf" {
                let ad_t = ad.clone();
                let (c, t) = timed(repeats, move || {
                    solve_gram(&g.matrix, &moments(&ad_t, &ctx.samples), LsOptions::default()).map(|s| channels(&s.coeffs))
                });
                let c = ctx.stored(c.map_err(err)?);
                let (cc, adc) = (c.clone(), ad.clone());
                let (irr, ns) = eval_cost(ctx, move |d| dot_rgb(&cc, adc.lobes().iter().map(|a| adr::lobe_irradiance_cos(a.dot(d)))));
                let rad = reconstruct(&ad, &c, dirs);
                Ok(mk(ad.name(), "least squares (radiance)", c, ad.lobes().iter().map(|l| (*l, 0.0)).collect(), Some(rad), irr, t, ns))
            } else {
                let s = irradiance_samples(ctx);
                let ad_t = ad.clone();
                let (c, t) = timed(repeats, move || {
                    solve_gram(&sbf::solve::sample_gram(&ad_t, &s), &moments(&ad_t, &s), LsOptions::default()).map(|s| channels(&s.coeffs))
                });
                let c = ctx.stored(c.map_err(err)?);
                let (irr, ns) = eval_basis(ctx, ad.clone(), c.clone());
                let mut r =
                    mk(ad.name(), "least squares (irradiance image)", c, ad.lobes().iter().map(|l| (*l, 0.0)).collect(), None, irr, t, ns);
                r.result.needs_reference = true;
                Ok(r)
            }
        }
        "sg" | "sgls" | "sglsa" | "sgnnls" => {
            let basis = SgBasis::new(&vogel, 6.0, id == "sglsa").map_err(err)?;
            let g = gram_matrix(&basis, Domain::Sphere, GramOptions::default()).map_err(err)?;
            let basis_t = basis.clone();
            let fit = move || -> Result<Vec<[f64; 3]>, String> {
                let basis = &basis_t;
                let m = moments(basis, &ctx.samples);
                match id {
                    // The peer's naive projection: moments scaled by 4λ²/((1 − e^(−2λ))·N)/(4π)
                    // (Probulator's sgBasisNormalizationFactor), which maps a constant to
                    // about that constant for N well-spread lobes. Equivalent to
                    // naive_projection with "diagonal" ∫B_i·N/(2λ).
                    "sg" => {
                        let lam = 6.0;
                        let n = basis.lobe_count() as f64;
                        let d: Vec<f64> = (0..basis.len()).map(|i| basis.lobe(i).integral() * n / (2.0 * lam)).collect();
                        Ok(channels(&naive_projection(&m, &d)))
                    }
                    "sgnnls" => {
                        let mut out = vec![[0.0; 3]; basis.len()];
                        for k in 0..3 {
                            let col: Vec<f64> = m.column(k).iter().copied().collect();
                            let sol = nnls_gram(&g.matrix, &col, NnlsOptions::default()).map_err(err)?;
                            for i in 0..basis.len() {
                                out[i][k] = sol.coeffs[i];
                            }
                        }
                        Ok(out)
                    }
                    _ => solve_gram(&g.matrix, &m, LsOptions::default()).map(|s| channels(&s.coeffs)).map_err(err),
                }
            };
            let method = ctx.sg_irradiance.for_mode(id);
            let prior = if method == SgIrradiance::Prior { Some(PriorRgb::new(&basis).map_err(err)?) } else { None };
            // The encode: the fit, and for the prior estimate the per-probe transform c' = Σ⁻¹G·c.
            let prior_t = prior.clone();
            let (c, t) = timed(repeats, move || -> Result<(Rgb, Rgb), String> {
                let c = fit()?;
                let cp = match &prior_t {
                    Some(p) => p.coefficients(&c).map_err(err)?,
                    None => Vec::new(),
                };
                Ok((c, cp))
            });
            let (c, cp) = c?;
            // The prior estimate stores c′ (what its runtime reads); the radiance image reads c.
            let (c, cp) = (ctx.stored(c), ctx.stored(cp));
            let lobes = sg_lobes(&basis, id);
            let (irr, ns) = match prior {
                Some(mut p) => eval_cost(ctx, move |d| p.eval(&cp, d)),
                None => {
                    let (b, cc) = (basis.clone(), c.clone());
                    eval_cost(ctx, move |d| sg_irradiance_rgb(ctx.sg_irradiance, id, &b, &lobes, &cc, d))
                }
            };
            let rad = reconstruct(&basis, &c, dirs);
            let solver = match id {
                "sg" if method == SgIrradiance::Peer => "naive projection; irradiance by the peer's SG kernel (λ 8.5)",
                "sg" => "naive projection",
                "sgnnls" if method == SgIrradiance::Peer => "NNLS; irradiance by the peer's SG kernel (λ 3)",
                "sgnnls" => "NNLS",
                _ if method == SgIrradiance::Prior => {
                    "least squares; irradiance by the isotropic-prior estimate (C_l ∝ l⁻², sbf::recon::prior)"
                }
                _ if method == SgIrradiance::Peer => "least squares; irradiance by the peer's SG kernel (λ 3)",
                _ => "least squares",
            };
            let mut r = mk(basis.name(), solver, c, vogel.iter().map(|a| (*a, 6.0)).collect(), Some(rad), irr, t, ns);
            r.result.wgsl_irradiance = method == SgIrradiance::Hill;
            r.result.irradiance_variant = method.name();
            Ok(r)
        }
        "shl2w" => {
            // SH L2 deringed with the sinc⁴ window (Sloan 2017) where the signal it
            // reconstructs rings: per channel, if the irradiance (E/π) is negative on any
            // of 4096 spherical-Fibonacci directions, the largest window width that makes
            // it non-negative is applied to the coefficients; otherwise nothing changes.
            // (The peer's Laplacian window sums each band from m = −1, a bug.)
            let sh = ShBasis::new(2).map_err(err)?;
            let fib: Vec<DVec3> = (0..4096).map(|i| sbf::sampling::spherical_fibonacci(i, 4096)).collect();
            let sh_t = sh.clone();
            let (c, t) = timed(repeats, move || -> Result<Vec<[f64; 3]>, String> {
                let c = channels(&moments(&sh_t, &ctx.samples));
                let mut out = c.clone();
                for k in 0..3 {
                    if let Some((_, windowed)) = shr::dering_irradiance(&channel(&c, k), &fib).map_err(err)? {
                        for i in 0..9 {
                            out[i][k] = windowed[i];
                        }
                    }
                }
                Ok(out)
            });
            let c = ctx.stored(c?);
            let chans = [channel(&c, 0), channel(&c, 1), channel(&c, 2)];
            let e = [0, 1, 2].map(|k| shr::irradiance_coefficients(&chans[k]).expect("9 coefficients"));
            let mut y = vec![0.0; sh.len()];
            let shc = sh.clone();
            let (mut irr, ns) = eval_cost(ctx, move |d| {
                let sh = &shc;
                sh.eval_into(d, &mut y);
                [0, 1, 2].map(|k| e[k].iter().zip(&y).map(|(a, b)| a * b).sum())
            });
            let neg = clamp_negative(&mut irr);
            let rad = reconstruct(&sh, &c, dirs);
            let mut r = mk(sh.name(), "projection + sinc⁴ deringing; irradiance clamped at 0", c, Vec::new(), Some(rad), irr, t, ns);
            r.result.clamped_negative_fraction = Some(neg);
            Ok(r)
        }
        "ad" | "adycocg" => {
            // Fitted to the irradiance image (as the peer), unweighted texels.
            let s = irradiance_samples(ctx);
            let bz = sbf::AmbientDiceBezier::new();
            if id == "ad" {
                let bz_t = bz.clone();
                let (c, t) = timed(repeats, move || {
                    solve_gram(&sbf::solve::sample_gram(&bz_t, &s), &moments(&bz_t, &s), LsOptions::default()).map(|x| channels(&x.coeffs))
                });
                let c = ctx.stored(c.map_err(err)?);
                let (irr, ns) = eval_basis(ctx, bz.clone(), c.clone());
                let mut r = mk(bz.name(), "least squares (irradiance image)", c, Vec::new(), None, irr, t, ns);
                r.result.needs_reference = true;
                Ok(r)
            } else {
                let lin = sbf::AmbientDiceLinear::new();
                let ys: Vec<RadianceSample> =
                    s.iter().map(|x| RadianceSample { value: sbf::basis::ambient_dice_bezier::rgb_to_ycocg(x.value), ..*x }).collect();
                let (c, t) = timed(repeats, move || -> Result<YCoCgCoeffs, String> {
                    let y = solve_gram(&sbf::solve::sample_gram(&bz, &ys), &moments(&bz, &ys), LsOptions::default()).map_err(err)?.coeffs;
                    let cc =
                        solve_gram(&sbf::solve::sample_gram(&lin, &ys), &moments(&lin, &ys), LsOptions::default()).map_err(err)?.coeffs;
                    Ok((
                        y.column(0).iter().copied().collect(),
                        cc.column(1).iter().copied().collect(),
                        cc.column(2).iter().copied().collect(),
                    ))
                });
                let (y, co, cg) = c?;
                let (y, co, cg) = (ctx.storage.store_scalars(&y), ctx.storage.store_scalars(&co), ctx.storage.store_scalars(&cg));
                let yc = sbf::AmbientDiceYCoCg::new();
                let (ya, coa, cga): ([f64; 36], [f64; 12], [f64; 12]) =
                    (y.clone().try_into().unwrap(), co.clone().try_into().unwrap(), cg.clone().try_into().unwrap());
                let (irr, ns) = eval_cost(ctx, move |d| yc.eval_rgb(&ya, &coa, &cga, d));
                // Coefficients as written: Y (36) then Co (12) then Cg (12), one value each.
                let coeffs: Vec<[f64; 3]> = y.iter().chain(&co).chain(&cg).map(|v| [*v, *v, *v]).collect();
                let mut r = mk(
                    "AD YCoCg (Bézier Y 36 + linear Co, Cg 12+12)".into(),
                    "least squares (irradiance image, per YCoCg channel)",
                    coeffs,
                    Vec::new(),
                    None,
                    irr,
                    t,
                    ns,
                );
                r.result.needs_reference = true;
                r.result.stored_scalars = 60;
                Ok(r)
            }
        }
        "sgra" | "sgnnra" | "sgpls" | "sgpnnls" | "adpls" | "adpnnls" => {
            let vogel12 = vogel.clone();
            let (basis, lobes): (std::sync::Arc<dyn Basis + Send + Sync>, Vec<(DVec3, f64)>) = if id.starts_with("sg") {
                (std::sync::Arc::new(SgBasis::new(&vogel12, 6.0, false).map_err(err)?), vogel12.iter().map(|a| (*a, 6.0)).collect())
            } else {
                let ad = AmbientDiceSrbf::twelve();
                let l = ad.lobes().iter().map(|a| (*a, 0.0)).collect();
                (std::sync::Arc::new(ad), l)
            };
            let opts = match id {
                "sgra" | "sgnnra" => {
                    let g = gram_matrix(basis.as_ref(), Domain::Sphere, GramOptions::default()).map_err(err)?;
                    let diag: Vec<f64> = (0..basis.len()).map(|i| g.matrix[(i, i)]).collect();
                    sbf::solve::ProgressiveOptions::running_average(&diag, 4.0 * std::f64::consts::PI, id == "sgnnra")
                }
                "sgpnnls" | "adpnnls" => sbf::solve::ProgressiveOptions::non_negative(),
                _ => sbf::solve::ProgressiveOptions::default(),
            };
            // Samples: the running averages take every texel once in a fixed shuffled
            // order (as the peer); the progressive modes take PROGRESSIVE_SAMPLES Halton
            // directions with bilinear radiance. Equal weights: only ratios matter.
            let samples: std::sync::Arc<Vec<RadianceSample>> = std::sync::Arc::new(if id.ends_with("ra") {
                let mut order: Vec<usize> = (0..ctx.samples.len()).collect();
                let mut rng = sbf::sampling::Pcg32::new(17, 3);
                for i in (1..order.len()).rev() {
                    order.swap(i, (rng.next_u32() as usize) % (i + 1));
                }
                order.iter().map(|&k| ctx.samples[k]).collect()
            } else {
                (0..PROGRESSIVE_SAMPLES)
                    .map(|i| {
                        let d = sbf::sampling::uniform_sphere(sbf::sampling::halton2(i));
                        RadianceSample { direction: d, value: ctx.map.bilinear(d), weight: 1.0 }
                    })
                    .collect()
            });
            let (b, smp, o) = (basis.clone(), samples.clone(), opts.clone());
            let (c, t) = timed(repeats, move || -> Result<Vec<[f64; 3]>, String> {
                let mut enc = sbf::solve::ProgressiveEncoder::<f32>::new(b.len(), o.clone());
                for s in smp.iter() {
                    enc.add(b.as_ref(), s).map_err(err)?;
                }
                Ok(channels(&enc.coefficients()))
            });
            let c = ctx.stored(c?);
            let sgb = SgBasis::new(&vogel12, 6.0, false).map_err(err)?;
            let ad = AmbientDiceSrbf::twelve();
            // Irradiance of one direction from RGB coefficients. The peer's running
            // averages use Hill's fit too (their figures match it).
            let sgb_lobes = sg_lobes(&sgb, id);
            let (irr, ns) = if id.starts_with("sg") {
                let (b, l, cc) = (sgb.clone(), sg_lobes(&sgb, id), c.clone());
                eval_cost(ctx, move |d| sg_irradiance_rgb(SgIrradiance::Hill, id, &b, &l, &cc, d))
            } else {
                let (a, cc) = (ad.clone(), c.clone());
                eval_cost(ctx, move |d| dot_rgb(&cc, a.lobes().iter().map(|x| adr::lobe_irradiance_cos(x.dot(d)))))
            };
            // Error against sample count: an untimed second pass with snapshots. The
            // irradiance is linear in the coefficients, so each snapshot is a product with
            // the per-lobe irradiance K[d][i] (same functions as above, one lobe at a time).
            let nb = basis.len();
            let kmat: Vec<f64> = dirs
                .iter()
                .flat_map(|d| {
                    (0..nb).map(|i| {
                        if id.starts_with("sg") {
                            sgb_lobes.hill[i].eval(*d)
                        } else {
                            adr::lobe_irradiance_cos(ad.lobes()[i].dot(*d))
                        }
                    })
                })
                .collect();
            let mut enc = sbf::solve::ProgressiveEncoder::<f32>::new(basis.len(), opts.clone());
            let mut convergence = Vec::new();
            let mut next = 16usize;
            for (i, s) in samples.iter().enumerate() {
                enc.add(basis.as_ref(), s).map_err(err)?;
                let n = i + 1;
                if n == next || n == samples.len() {
                    let cc = channels(&enc.coefficients());
                    let img: Vec<[f64; 3]> = {
                        use rayon::prelude::*;
                        kmat.par_chunks_exact(nb).map(|k| dot_rgb(&cc, k.iter().copied())).collect()
                    };
                    convergence.push((n as u64, crate::metrics::rms_rows(ctx.grid, &img, &ctx.irradiance, ctx.metric_rows())));
                    while next <= n {
                        next *= 2;
                    }
                }
            }
            let rad = reconstruct(basis.as_ref(), &c, dirs);
            let solver = match id {
                "sgra" => "running average (per-sample, Jacobi, α = 1, clamped denominators)",
                "sgnnra" => "non-negative running average",
                "sgpls" | "adpls" => "progressive LS, f32 state, 4096 Halton samples ([Roughton19 §7.3])",
                _ => "progressive NNLS, f32 state, 4096 Halton samples ([Roughton19 §7.3])",
            };
            let mut r = mk(basis.name(), solver, c, lobes, Some(rad), irr, t, ns);
            r.result.convergence = convergence;
            Ok(r)
        }
        "ad9" | "sg9h" | "sg12h" | "adrbf-tangent" => {
            // Appendix C: lobes laid out in tangent space (normal +Z), rotated to world
            // (+Y up); least squares over the whole sphere.
            let world = |v: Vec<DVec3>| v.into_iter().map(tangent_to_world).collect::<Vec<_>>();
            let (basis, is_ad): (std::sync::Arc<dyn Basis + Send + Sync>, bool) = match id {
                "ad9" => (
                    std::sync::Arc::new(
                        AmbientDiceSrbf::from_axes(&world(sbf::layout::icosahedron_hemisphere()), Domain::Sphere).map_err(err)?,
                    ),
                    true,
                ),
                "adrbf-tangent" => (
                    std::sync::Arc::new(AmbientDiceSrbf::from_axes(&world(sbf::layout::icosahedron()), Domain::Sphere).map_err(err)?),
                    true,
                ),
                "sg9h" => (
                    std::sync::Arc::new(SgBasis::new(&world(sbf::layout::vogel_hemisphere(9).map_err(err)?), 6.0, false).map_err(err)?),
                    false,
                ),
                _ => (
                    std::sync::Arc::new(SgBasis::new(&world(sbf::layout::vogel_hemisphere(12).map_err(err)?), 6.0, false).map_err(err)?),
                    false,
                ),
            };
            let b = basis.clone();
            let (c, t) = if !is_ad && ctx.convention == sbf::ggx::Convention::AppendixC {
                // Roughton's SG fits: its point samples, their own Gram (see appendix_c).
                let samples = crate::appendix_c::sg_samples(&ctx.map)?;
                timed(repeats, move || {
                    solve_gram(&sbf::solve::sample_gram(b.as_ref(), &samples), &moments(b.as_ref(), &samples), LsOptions::default())
                        .map(|s| channels(&s.coeffs))
                })
            } else {
                let g = gram_matrix(basis.as_ref(), Domain::Sphere, GramOptions::default()).map_err(err)?;
                timed(repeats, move || {
                    solve_gram(&g.matrix, &moments(b.as_ref(), &ctx.samples), LsOptions::default()).map(|s| channels(&s.coeffs))
                })
            };
            let c = ctx.stored(c.map_err(err)?);
            let chans = [channel(&c, 0), channel(&c, 1), channel(&c, 2)];
            let (axes, lobes): (Vec<DVec3>, Vec<(DVec3, f64)>) = if is_ad {
                let ad = AmbientDiceSrbf::from_axes(
                    &match id {
                        "ad9" => world(sbf::layout::icosahedron_hemisphere()),
                        _ => world(sbf::layout::icosahedron()),
                    },
                    Domain::Sphere,
                )
                .map_err(err)?;
                (ad.lobes().to_vec(), ad.lobes().iter().map(|a| (*a, 0.0)).collect())
            } else {
                let n = if id == "sg9h" { 9 } else { 12 };
                let a = world(sbf::layout::vogel_hemisphere(n).map_err(err)?);
                (a.clone(), a.iter().map(|x| (*x, 6.0)).collect())
            };
            let sharpness = vec![6.0; axes.len()];
            let (irr, ns) = if is_ad {
                eval_cost(ctx, move |d| [0, 1, 2].map(|k| adr::irradiance_fit(&axes, &chans[k], d, &adr::DIFFUSE_FIT_EQ_8_14)))
            } else {
                let cc = c.clone();
                eval_cost(ctx, move |d| {
                    dot_rgb(
                        &cc,
                        axes.iter()
                            .zip(&sharpness)
                            .map(|(a, l)| sgr::irradiance_hill(&sbf::Sg { axis: *a, sharpness: *l, amplitude: 1.0 }, d)),
                    )
                })
            };
            let rad = reconstruct(basis.as_ref(), &c, dirs);
            Ok(mk(basis.name(), "least squares over the sphere", c, lobes, Some(rad), irr, t, ns))
        }
        "h4" | "h6" => {
            // The H-basis lives on the upper hemisphere: fit the irradiance image there
            // (texels of the upper rows, equal weights as the peer's image fits), evaluate
            // in tangent space. The lower hemisphere is outside its domain (E/π = 0 there).
            let h = sbf::HBasis::new(if id == "h4" { 4 } else { 6 }).map_err(err)?;
            let upper = ctx.grid.width * (ctx.grid.height / 2);
            let s: Vec<RadianceSample> = ctx.dirs[..upper]
                .iter()
                .zip(&ctx.irradiance[..upper])
                .map(|(d, e)| RadianceSample { direction: world_to_tangent(*d), value: *e, weight: 1.0 })
                .collect();
            let (c, t) = timed(repeats, move || {
                solve_gram(&sbf::solve::sample_gram(&h, &s), &moments(&h, &s), LsOptions::default()).map(|x| channels(&x.coeffs))
            });
            let c = ctx.stored(c.map_err(err)?);
            let chans = [channel(&c, 0), channel(&c, 1), channel(&c, 2)];
            let mut sc = vec![0.0; h.len()];
            let (irr, ns) = eval_cost(ctx, move |d| {
                let tt = world_to_tangent(d);
                if tt.z < 0.0 {
                    [0.0; 3]
                } else {
                    [0, 1, 2].map(|k| h.reconstruct(&chans[k], tt, &mut sc))
                }
            });
            let mut r = mk(h.name(), "least squares (irradiance image, upper hemisphere)", c, Vec::new(), None, irr, t, ns);
            r.result.needs_reference = true;
            Ok(r)
        }
        _ => Err(format!("mode '{id}' is listed but not implemented")),
    }
}
