//! The GGX specular signal (f0 = f90 = 1, single scattering, height-correlated Smith).
//!
//! Geometry per output texel with direction d: over the sphere, normal = view = d
//! (normal incidence: the prefiltered environment); over the upper hemisphere, the
//! normal is the map's up (+Y) and the view is d ([Roughton19 Appendix C]), zero below.
//!
//! Reference: visible-normal samples plus map samples (by texel luminance) combined by
//! multiple importance sampling ([`sbf::recon::reference::ggx_specular_mis`]), a
//! reported number of each per texel, radiance by bilinear lookup; its error is
//! estimated against 16× the samples on a texel subset ([`reference_error`]).
//! Reconstructions, from the coefficients a mode stored: SH by zonal convolution about
//! the dominant direction with the committed DFG table; SG lobes by the split sum over the warped NDF
//! ([`sbf::recon::sg::SplitSumWarp`]; the ASG warp under the Appendix C convention); Ambient
//! Dice SRBF lobes by Roughton's fit (Listing 8.1) times the committed 2D LUT
//! (Listing 8.2); prefiltered cube maps by the split sum (the map at the reflected direction,
//! trilinear, times the DFG terms). Other modes store irradiance, not radiance, and have no
//! specular.

pub use crate::modes::SpecularRuntime;
use crate::modes::{Context, ModeResult};
use crate::prefilter::coarsened;
pub use crate::prefilter::{coarsening, subdivision};
use rayon::prelude::*;
use sbf::envmap::{LatLong, LatLongImage};
use sbf::ggx::Convention;
use sbf::glam::DVec3;
use sbf::recon::reference::MapSampler;
use sbf::recon::{ambient_dice as adr, sg as sgr, sh as shr};
use sbf::Domain;

/// (normal, view) of output texel `k`, or `None` where the signal is zero.
pub(crate) fn geometry(ctx: &Context, k: usize) -> Option<(DVec3, DVec3)> {
    let d = ctx.dirs[k];
    match ctx.domain {
        Domain::Sphere => Some((d, d)),
        Domain::UpperHemisphere => (d.y > 0.0).then_some((DVec3::Y, d)),
    }
}

/// One reference texel: `samples` visible-normal plus `samples` map samples, MIS.
fn reference_texel(ctx: &Context, sampler: Option<&MapSampler>, k: usize, alpha: f64, samples: u32) -> [f64; 3] {
    match geometry(ctx, k) {
        Some((n, v)) => sbf::recon::reference::ggx_specular_mis(&ctx.map, sampler, n, v, alpha, 1.0, 1.0, samples),
        None => [0.0; 3],
    }
}

/// Reference specular image for roughness `alpha`.
pub fn reference(ctx: &Context, alpha: f64, samples: u32) -> Vec<[f64; 3]> {
    let sampler = MapSampler::new(&ctx.map);
    (0..ctx.dirs.len()).into_par_iter().map(|k| reference_texel(ctx, sampler.as_ref(), k, alpha, samples)).collect()
}

/// GGX f·cos with F ≡ 1 for unit world vectors: D(h)·G2(v, l)/(4 n·v) — the same function
/// as the Monte Carlo reference's, from cosines and cross-product sines (no cancellation
/// near the normal); 0 when v or l is below the surface.
pub fn ggx_kernel(n: DVec3, v: DVec3, l: DVec3, alpha: f64) -> f64 {
    let (nv, nl) = (n.dot(v), n.dot(l));
    if nv <= 0.0 || nl <= 0.0 {
        return 0.0;
    }
    let h = (v + l).normalize();
    let nh = n.dot(h);
    if nh.is_nan() || nh <= 0.0 {
        return 0.0;
    }
    let t = |c: f64, w: DVec3| DVec3::new(n.cross(w).length(), 0.0, c);
    let alpha = alpha.clamp(1e-4, 1.0);
    sbf::ggx::d(t(nh, h), alpha) * sbf::ggx::g2(t(nv, v), t(nl, l), alpha) / (4.0 * nv)
}

/// Output row stride of the deterministic reference's quadrature check.
pub const FFT_CHECK_STRIDE: usize = 8;

/// The deterministic specular reference: the GGX integral of the map's
/// bilinear radiance at every output texel by the azimuthal FFT quadrature
/// ([`crate::azimuthal`]) with [`subdivision`] sub-cells per texel side — exact in φ up
/// to that midpoint rule, since the BRDF is invariant under rotation about the pole
/// (Appendix C: normal +Y) or about the view itself (whole sphere: normal = view).
/// On maps wider than the output grid, texels far below α/16 are first merged
/// ([`coarsening`]: D × D blocks, one sub-cell each) — the bilinear radiance of the
/// box-filtered map differs from the map's by O(h²) for smooth radiance, like the
/// quadrature itself, and the check below measures it.
/// Error estimate: the same quadrature with the cells halved — twice the subdivision, or
/// the map coarsened by D/2 — on every [`FFT_CHECK_STRIDE`]-th output row where the
/// signal is defined; for an h² rule R_h − R_{h/2} is ¾ of R_h's own error, so the RMS
/// difference × 4/3 is reported. Errors with why the grid does not allow it.
pub fn reference_fft(ctx: &Context, alpha: f64) -> Result<FftReference, String> {
    let d = coarsening(alpha, ctx.map.geometry, ctx.grid);
    let source = coarsened(&ctx.map, d);
    let q = crate::azimuthal::Quadrature::new(&source, ctx.grid)?;
    let sub = if d > 1 { 1 } else { subdivision(alpha, ctx.map.geometry.height) };
    let (rows, kernel) = fft_setup(ctx.grid, ctx.domain, alpha, ctx.convention);
    let image = fft_image(&q, ctx.grid, rows.clone(), sub, &kernel);
    // The check's quadrature: the map at D/2 (one sub-cell), or 2S sub-cells at D = 1.
    let (check_q, check_sub) =
        if d > 1 { (crate::azimuthal::Quadrature::new(&coarsened(&ctx.map, d / 2), ctx.grid)?, 1) } else { (q, 2 * sub) };
    let w_out = ctx.grid.width;
    let check: Vec<usize> = rows.clone().step_by(FFT_CHECK_STRIDE).collect();
    let (mut e2, mut s2, mut n) = (0.0, 0.0, 0usize);
    let fine = check_q.integrate_rows_at(&check, check_sub, &kernel);
    for (&j, fine) in check.iter().zip(fine.chunks(w_out)) {
        for (i, f) in fine.iter().enumerate() {
            for c in 0..3 {
                e2 += (image[j * w_out + i][c] - f[c]).powi(2);
                s2 += f[c].powi(2);
            }
            n += 1;
        }
    }
    let m = (3 * n).max(1) as f64;
    Ok(FftReference {
        image,
        error_rms: (e2 / m).sqrt() * 4.0 / 3.0,
        signal_rms: (s2 / m).sqrt(),
        texels_checked: n,
        subdivision: sub,
        coarsening: d,
    })
}

/// The output rows where the signal is defined and the GGX kernel for `domain`.
fn fft_setup(grid: LatLong, domain: Domain, alpha: f64, convention: Convention) -> (std::ops::Range<usize>, GgxRows) {
    let h_out = grid.height;
    let rows = match domain {
        Domain::Sphere => 0..h_out,
        // Rows whose centre is above the horizon (d.y > 0).
        Domain::UpperHemisphere => 0..h_out / 2,
    };
    (rows, GgxRows { domain, alpha: alpha.clamp(1e-4, 1.0), h_out, convention })
}

/// [`ggx_kernel`] along a fine azimuth row of the quadrature ([`crate::azimuthal`]): view
/// v at output row j's polar angle θ_v and azimuth Δφ, light l at (θ_l, 0). What does not
/// depend on Δφ is computed once per row, the rest from cos Δφ and sin Δφ, with the
/// half-vector's cosines as ratios of exact squared lengths (no normalisation, no
/// cancellation):
/// - hemisphere (n = +Y): m = |v + l|² = p + q with p = (n·(v + l))² and
///   q = |n × (v + l)|²; D = α²m²/(π(α²p + q)²) (Walter et al. 2007, eq. 33, times m²/m²),
///   G2 constant along the row (its Λ depend on θ_v and θ_l only);
/// - sphere (n = v): n·l = cos γ, cos²θ_h = (1 + cos γ)/2, sin²θ_h = (1 − cos γ)/2 with
///   1 − cos γ = |v − l|²/2; D = α²/(π(α²c² + s²)²), G2 = 1/(1 + Λ(l)) (Λ(v) = 0).
///
/// Equals [`ggx_kernel`] to rounding (test `row_kernel_equals_the_pointwise_kernel`).
///
/// Under [`Convention::AppendixC`] (hemisphere only) the kernel is Roughton's reference's:
/// f·cos = F·D·G2·G1(v)²/(4 n·v) — its per-sample weight G2·G1(v) times the visible-normal
/// density G1(v)·D/(4 n·v) — wherever n·h > 0 (n·(v + l) > 0), light below the surface
/// included with Λ(l) from |cos θ_l|; F = f0 + (1 − f0)(1 − v·h)⁵ with f0 0.9 and
/// v·h = |v + l|/2 = √m/2.
#[derive(Debug, Clone, Copy)]
pub struct GgxRows {
    pub domain: Domain,
    pub alpha: f64,
    /// Output grid rows (θ_v of row j is π(j + ½)/h_out).
    pub h_out: usize,
    pub convention: Convention,
}

impl crate::azimuthal::RowKernel for GgxRows {
    fn row(&self, j: usize, theta_l: f64, az: &crate::azimuthal::Azimuths, out: &mut [f64]) -> bool {
        let (sv, cv) = (std::f64::consts::PI * (j as f64 + 0.5) / self.h_out as f64).sin_cos();
        let (sl, cl) = theta_l.sin_cos();
        let a2 = self.alpha * self.alpha;
        let inv_pi = std::f64::consts::FRAC_1_PI;
        // Smith Λ from cos and sin of the angle to the normal: a = α² tan², Λ = a/(2(1 + √(1 + a))).
        let lambda = |s: f64, c: f64| {
            let a = a2 * s * s / (c * c);
            a / (2.0 * (1.0 + (1.0 + a).sqrt()))
        };
        let mut any = false;
        match self.domain {
            Domain::UpperHemisphere => {
                let seed = self.convention == Convention::AppendixC;
                // Physical: light from above the surface only. Appendix C: any light with
                // n·h > 0, i.e. c_v + c_l > 0 (Λ is even in cos θ_l).
                if cv <= 0.0 || cl == 0.0 || (!seed && cl < 0.0) || cv + cl <= 0.0 {
                    out.fill(0.0);
                    return false;
                }
                let g2 = 1.0 / (1.0 + lambda(sv, cv) + lambda(sl, cl));
                let mut scale = a2 * inv_pi * g2 / (4.0 * cv);
                let f0 = match self.convention.fresnel() {
                    Some((f0, _)) => {
                        let g1 = 1.0 / (1.0 + lambda(sv, cv));
                        scale *= g1 * g1;
                        f0
                    }
                    None => 1.0,
                };
                let p = (cv + cl) * (cv + cl);
                for (o, (c, s)) in out.iter_mut().zip(az.cos.iter().zip(az.sin)) {
                    // v + l = (s_v sin Δφ, c_v + c_l, −s_v cos Δφ − s_l).
                    let (x, z) = (sv * s, sv * c + sl);
                    let q = x * x + z * z;
                    let m = p + q;
                    let t = a2 * p + q;
                    let f = if f0 == 1.0 { 1.0 } else { f0 + (1.0 - f0) * sbf::ggx::schlick_weight(0.5 * m.sqrt()) };
                    *o = f * scale * m * m / (t * t);
                    any = true;
                }
            }
            Domain::Sphere => {
                for (o, (c, s)) in out.iter_mut().zip(az.cos.iter().zip(az.sin)) {
                    let nl = cv * cl + sv * sl * c;
                    if nl <= 0.0 {
                        *o = 0.0;
                        continue;
                    }
                    // v − l = (s_v sin Δφ, c_v − c_l, −s_v cos Δφ + s_l).
                    let (x, y, z) = (sv * s, cv - cl, sl - sv * c);
                    let one_minus = 0.5 * (x * x + y * y + z * z);
                    let (c2, s2) = (0.5 * (1.0 + nl), 0.5 * one_minus);
                    let t = a2 * c2 + s2;
                    let sin_l2 = one_minus * (1.0 + nl);
                    let a = a2 * sin_l2 / (nl * nl);
                    let g2 = 1.0 / (1.0 + a / (2.0 * (1.0 + (1.0 + a).sqrt())));
                    *o = 0.25 * a2 * inv_pi / (t * t) * g2;
                    any = true;
                }
            }
        }
        any
    }

    /// Over the sphere the kernel is zonal about the view (a function of n·l = v·l and of
    /// |v − l|², both unchanged by mirroring both polar angles); the hemisphere's is not.
    fn mirror_symmetric(&self) -> bool {
        self.domain == Domain::Sphere
    }
}

/// The quadrature on `rows`, placed in a full output image (zero elsewhere).
fn fft_image(
    q: &crate::azimuthal::Quadrature,
    grid: LatLong,
    rows: std::ops::Range<usize>,
    sub: usize,
    kernel: &dyn crate::azimuthal::RowKernel,
) -> Vec<[f64; 3]> {
    let mut image = vec![[0.0; 3]; grid.width * grid.height];
    for (k, v) in q.integrate_rows(rows.clone(), sub, kernel).into_iter().enumerate() {
        image[rows.start * grid.width + k] = v;
    }
    image
}

/// The *basis-limited* specular images of several modes: the exact GGX
/// integral of each mode's reconstructed radiance — given at the output grid's texel
/// centres, read bilinearly like the map — by the same azimuthal quadrature as the
/// reference, with half the subdivision [`subdivision`] gives the grid, rounded up to even
/// (at least 2), or 1 where the grid's texels are already below α/16; the kernel is folded
/// once for all modes. Compared with the reference
/// it is the error of the basis; the runtime path's image compared with it is what the
/// runtime approximation adds. None when the grid does not allow the quadrature.
pub fn basis_limited(ctx: &Context, radiances: &[&[[f64; 3]]], alpha: f64) -> Option<Vec<Vec<[f64; 3]>>> {
    // The quadrature's geometry is the output grid's (its own row spectra are unused).
    let first = LatLongImage::new(ctx.grid.width, ctx.grid.height, vec![[0.0; 3]; ctx.grid.texel_count()]).ok()?;
    let q = crate::azimuthal::Quadrature::new(&first, ctx.grid).ok()?;
    let spectra: Vec<crate::azimuthal::Spectra> = radiances.iter().map(|r| q.spectra_f64(r).ok()).collect::<Option<_>>()?;
    let full = subdivision(alpha, ctx.grid.height);
    let half = full / 2;
    let sub = if full == 1 { 1 } else { (half + half % 2).max(2) };
    let (rows, kernel) = fft_setup(ctx.grid, ctx.domain, alpha, ctx.convention);
    let refs: Vec<&crate::azimuthal::Spectra> = spectra.iter().collect();
    let parts = q.integrate_many(&refs, &rows.clone().collect::<Vec<_>>(), sub, &kernel);
    Some(
        parts
            .into_iter()
            .map(|p| {
                let mut image = vec![[0.0; 3]; ctx.grid.width * ctx.grid.height];
                image[rows.start * ctx.grid.width..rows.start * ctx.grid.width + p.len()].copy_from_slice(&p);
                image
            })
            .collect(),
    )
}

/// A deterministic specular reference and its estimated error.
#[derive(Debug, Clone)]
pub struct FftReference {
    pub image: Vec<[f64; 3]>,
    /// Estimated RMS quadrature error (4/3 × RMS of R_S − R_2S on the checked rows) and
    /// the signal's RMS there.
    pub error_rms: f64,
    pub signal_rms: f64,
    pub texels_checked: usize,
    /// Sub-cells per texel side.
    pub subdivision: usize,
    /// Texels of the map merged per side before the quadrature ([`coarsening`]).
    pub coarsening: usize,
}

/// Texel stride of the reference's convergence check.
pub const CHECK_STRIDE: usize = 101;
/// Sample-count multiplier of the convergence check.
pub const CHECK_FACTOR: u32 = 16;

/// Estimated error of a [`reference()`] image: on every [`CHECK_STRIDE`]-th texel where
/// the signal is defined, the RMS difference (unweighted, over channels) between the
/// estimate with `samples` and with [`CHECK_FACTOR`]× as many points of the same
/// Halton sequence (whose own error is far smaller for a QMC rule), and the RMS of
/// the 16× estimate itself. Returns (error RMS, signal RMS, texels checked).
pub fn reference_error(ctx: &Context, alpha: f64, samples: u32, reference: &[[f64; 3]]) -> (f64, f64, usize) {
    let ks: Vec<usize> = (0..ctx.dirs.len()).step_by(CHECK_STRIDE).filter(|k| geometry(ctx, *k).is_some()).collect();
    let sampler = MapSampler::new(&ctx.map);
    let fine: Vec<[f64; 3]> =
        ks.par_iter().map(|&k| reference_texel(ctx, sampler.as_ref(), k, alpha, samples.saturating_mul(CHECK_FACTOR))).collect();
    let (mut e2, mut s2) = (0.0, 0.0);
    for (i, &k) in ks.iter().enumerate() {
        for c in 0..3 {
            e2 += (reference[k][c] - fine[i][c]).powi(2);
            s2 += fine[i][c].powi(2);
        }
    }
    let m = (3 * ks.len()).max(1) as f64;
    ((e2 / m).sqrt(), (s2 / m).sqrt(), ks.len())
}

pub fn is_sh(id: &str) -> bool {
    id.starts_with("shl")
}
fn is_sg(id: &str) -> bool {
    matches!(id, "sg" | "sgls" | "sglsa" | "sgnnls" | "sgra" | "sgnnra" | "sgpls" | "sgpnnls" | "sg9h" | "sg12h" | "sgnnlsc" | "sgpnnlsc")
}
fn is_ad(id: &str) -> bool {
    matches!(id, "adrbf" | "adrbf-tangent" | "ad9" | "adpls" | "adpnnls" | "adnnlsc" | "adpnnlsc")
}

/// A GGX-prefiltered cube map paired with SH L2 ([`crate::modes::prefiltered`]).
pub fn is_pf(id: &str) -> bool {
    crate::modes::prefiltered::parse(id).is_some()
}

/// Whether a mode reconstructs specular.
pub fn supported(id: &str) -> bool {
    is_sh(id) || is_sg(id) || is_ad(id) || is_pf(id)
}

/// Specular image of a mode for roughness `alpha`, or `None` for irradiance-only modes.
/// Lobe modes on the table runtime share each lobe's response per texel with every mode of
/// the same lobe layout (`lobe_responses`); the image is the runtime's own sum over them,
/// bit for bit (a test compares it with the runtime texel by texel).
pub fn reconstruct(r: &ModeResult, ctx: &Context, alpha: f64) -> Option<Vec<[f64; 3]>> {
    let texel = texel_fn(r, ctx, alpha)?;
    let Some(table) = lobe_table(r, ctx) else { return Some((0..ctx.dirs.len()).into_par_iter().map(&texel).collect()) };
    let axes32: Vec<sbf::glam::Vec3> = r.lobes.iter().map(|(a, _)| a.as_vec3()).collect();
    let resp = lobe_responses(ctx, table, &axes32, alpha);
    let resp = resp.get().expect("computed");
    let c = &r.coefficients;
    let c32: Vec<sbf::glam::Vec3> = c.iter().map(|x| sbf::glam::Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32)).collect();
    let nl = axes32.len();
    let dfg = sbf::recon::tables::dfg();
    Some(
        (0..ctx.dirs.len())
            .into_par_iter()
            .map(|k| {
                let Some((n, v)) = geometry(ctx, k) else { return [0.0; 3] };
                let mut s = sbf::glam::Vec3::ZERO;
                for (i, ci) in c32[..nl].iter().enumerate() {
                    s += *ci * resp[k * nl + i];
                }
                let mut e = [s.x as f64, s.y as f64, s.z as f64];
                add_ambient(&mut e, c, nl, dfg, n, v, alpha);
                e
            })
            .collect(),
    )
}

/// The runtime's specular at every output texel, evaluated texel by texel without shared
/// work (the oracle of [`reconstruct`]'s shared responses; slow).
pub fn runtime_image(r: &ModeResult, ctx: &Context, alpha: f64) -> Option<Vec<[f64; 3]>> {
    let texel = texel_fn(r, ctx, alpha)?;
    Some((0..ctx.dirs.len()).map(texel).collect())
}

/// The response table of a lobe mode on the table runtime (None otherwise). Every SG mode
/// here uses λ = 6, the one sharpness with a table; another would take the fit path.
fn lobe_table(r: &ModeResult, ctx: &Context) -> Option<&'static sbf::recon::lobe_ggx::Table> {
    // The tables integrate the physical BRDF: under Appendix C Roughton's fits run instead.
    if ctx.convention != Convention::Physical {
        return None;
    }
    let table = match ctx.specular_runtime {
        SpecularRuntime::Table if is_sg(r.id) => Some(sbf::recon::tables::lobe_ggx_sg6()),
        SpecularRuntime::Table if is_ad(r.id) => Some(sbf::recon::tables::lobe_ggx_ad()),
        _ => None,
    };
    table.filter(|_| !(is_sg(r.id) && r.lobes.iter().any(|(_, l)| *l != 6.0)))
}

/// Every output texel's per-lobe responses (`texels × lobes`, f32, as the runtime computes
/// them; 0 outside the signal's domain) for one lobe layout, table and α — computed once per
/// run and shared by the modes with that layout.
fn lobe_responses(
    ctx: &Context,
    table: &'static sbf::recon::lobe_ggx::Table,
    axes: &[sbf::glam::Vec3],
    alpha: f64,
) -> std::sync::Arc<std::sync::OnceLock<Vec<f32>>> {
    let key = format!("lobe responses {:p} α {alpha} axes {:?}", table as *const _, axes);
    // Serial on purpose: a thread computing a memo value must not enter rayon — waiting for
    // its own tasks, it could steal another mode's task that asks for this same value and
    // wait on itself. (Other keys are computed on other threads meanwhile.)
    ctx.shared.get(&key, || {
        let nl = axes.len();
        let mut out = vec![0.0f32; ctx.dirs.len() * nl];
        for (k, row) in out.chunks_mut(nl).enumerate() {
            if let Some((n, v)) = geometry(ctx, k) {
                sbf::recon::runtime::lobe_ggx_responses(table, axes, n.as_vec3(), v.as_vec3(), alpha as f32, 1.0, 1.0, |i, x| row[i] = x);
            }
        }
        out
    })
}

/// An ambient (constant) function, stored after the `lobes` lobe coefficients, reflects its
/// value times the albedo (the DFG terms at n·v, α).
fn add_ambient(e: &mut [f64; 3], c: &[[f64; 3]], lobes: usize, dfg: &sbf::recon::lut::Lut2, n: DVec3, v: DVec3, alpha: f64) {
    if c.len() > lobes {
        let d = dfg.sample2(n.dot(v).clamp(0.0, 1.0) as f32, alpha as f32);
        for ch in 0..3 {
            e[ch] += c[lobes][ch] * (d[0] + d[1]) as f64;
        }
    }
}

/// The job that measures the steady-state CPU cost of a mode's specular runtime path at
/// roughness `alpha` over the output texels where the signal is defined ([`crate::cost`]),
/// or `None` for irradiance-only modes.
pub fn cost_job<'a>(r: &'a ModeResult, ctx: &'a Context, alpha: f64) -> Option<crate::cost::CostJob<'a>> {
    let texel = texel_fn(r, ctx, alpha)?;
    let ks: Vec<usize> = (0..ctx.dirs.len()).filter(|k| geometry(ctx, *k).is_some()).collect();
    Some(crate::cost::CostJob::over_items(ks, ctx.eval_work, texel))
}

/// The specular runtime path of a mode as a function of the output texel index.
fn texel_fn<'a>(r: &'a ModeResult, ctx: &'a Context, alpha: f64) -> Option<impl Fn(usize) -> [f64; 3] + Sync + 'a> {
    if !supported(r.id) {
        return None;
    }
    let c = &r.coefficients;
    let chan = |k: usize| c.iter().map(|v| v[k]).collect::<Vec<f64>>();
    let chans = [chan(0), chan(1), chan(2)];
    let dfg = sbf::recon::tables::dfg();
    let (f0, f90) = ctx.convention.fresnel().unwrap_or((1.0, 1.0));
    let lut = sbf::recon::tables::ad_specular_2d();
    // Appendix C's AD runtime computes its table per pixel from n·v, which is constant along
    // an output row: once per row.
    let fork_rows: Vec<[f64; 2]> = if ctx.convention == Convention::AppendixC && !is_sh(r.id) && !is_sg(r.id) {
        (0..ctx.grid.height)
            .into_par_iter()
            .map(|j| {
                geometry(ctx, j * ctx.grid.width)
                    .map_or([0.0; 2], |(n, v)| crate::appendix_c::ad_table(n.dot(v), alpha, crate::appendix_c::AD_TABLE_SAMPLES))
            })
            .collect()
    } else {
        Vec::new()
    };
    let sh = sbf::ShBasis::new(if is_sh(r.id) { (c.len() as f64).sqrt().round() as usize - 1 } else { 0 }).ok()?;
    // SH: n·v is constant along an output row in both domains, so is the band filter.
    let sh_filters: Vec<Vec<f64>> = if is_sh(r.id) {
        let order = (c.len() as f64).sqrt().round() as usize - 1;
        (0..ctx.grid.height)
            .map(|j| geometry(ctx, j * ctx.grid.width).map_or_else(Vec::new, |(n, v)| shr::specular_zonal_filter(order, n.dot(v), alpha)))
            .collect()
    } else {
        Vec::new()
    };
    let axes: Vec<DVec3> = r.lobes.iter().map(|(a, _)| *a).collect();
    let table = lobe_table(r, ctx);
    let cube = crate::modes::prefiltered::cube_of(r.id, c);
    // The table path runs the f32 runtime (the WGSL's CPU twin), as the fit paths of the
    // runtime module do in an engine.
    let axes32: Vec<sbf::glam::Vec3> = axes.iter().map(|a| a.as_vec3()).collect();
    let c32: Vec<sbf::glam::Vec3> = c.iter().map(|x| sbf::glam::Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32)).collect();
    Some(move |k: usize| {
        if let Some(t) = table {
            let Some((n, v)) = geometry(ctx, k) else { return [0.0; 3] };
            let e32 = sbf::recon::runtime::lobe_ggx_specular(t, &axes32, &c32, n.as_vec3(), v.as_vec3(), alpha as f32, 1.0, 1.0);
            let mut e = [e32.x as f64, e32.y as f64, e32.z as f64];
            add_ambient(&mut e, c, r.lobes.len(), dfg, n, v, alpha);
            return e;
        }
        let Some((n, v)) = geometry(ctx, k) else { return [0.0; 3] };
        let nv = n.dot(v).clamp(0.0, 1.0);
        if let Some(cube) = &cube {
            // The split sum: the map at the reflected direction × the DFG terms.
            let d = dfg.sample2(nv as f32, alpha as f32);
            cube.specular(n, v, alpha, f0, f90, [d[0] as f64, d[1] as f64])
        } else if is_sh(r.id) {
            let d = dfg.sample2(nv as f32, alpha as f32);
            shr::specular_zonal_rgb(&sh, c, &sh_filters[k / ctx.grid.width], n, v, alpha, f0, f90, [d[0] as f64, d[1] as f64])
                .unwrap_or([f64::NAN; 3])
        } else if is_sg(r.id) {
            let d = dfg.sample2(nv as f32, alpha as f32);
            // The runtime's split sum; Roughton's Appendix C convention keeps its ASG warp.
            let (split, asg) = match ctx.convention {
                Convention::Physical => (Some(sgr::SplitSumWarp::new(n, v, alpha, f0, f90, [d[0] as f64, d[1] as f64])), None),
                Convention::AppendixC => (None, Some(crate::appendix_c::asg_warp(n, v, alpha, f0, f90))),
            };
            // Each lobe's warped integral once, then RGB (the runtime's form).
            let mut e = [0.0; 3];
            for ((axis, lam), ci) in r.lobes.iter().zip(c) {
                let lobe = sbf::Sg { axis: *axis, sharpness: *lam, amplitude: 1.0 };
                let w = split.map_or_else(|| asg.map_or(0.0, |a| a.lobe(&lobe)), |s| s.lobe(&lobe));
                for ch in 0..3 {
                    e[ch] += w * ci[ch];
                }
            }
            // An ambient (constant) function reflects its value times the albedo.
            if c.len() > r.lobes.len() {
                for ch in 0..3 {
                    e[ch] += c[r.lobes.len()][ch] * (f0 * d[0] as f64 + f90 * d[1] as f64);
                }
            }
            e
        } else if ctx.convention == Convention::AppendixC {
            let t = fork_rows[k / ctx.grid.width];
            let mut e = [0.0; 3];
            for (axis, ci) in axes.iter().zip(c) {
                let w = crate::appendix_c::ad_lobe_fit(*axis, n, v, alpha) * (f0 * t[0] + f90 * t[1]);
                for ch in 0..3 {
                    e[ch] += w * ci[ch];
                }
            }
            e
        } else {
            let l = lut.sample2(nv as f32, alpha as f32);
            [0, 1, 2].map(|ch| adr::specular(&axes, &chans[ch], n, v, alpha, f0, f90, [l[0] as f64, l[1] as f64]))
        }
    })
}
