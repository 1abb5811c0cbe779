//! One map through every mode — the run `probes compare` makes per map: the references
//! (irradiance, then GGX specular per α, all α at once), every mode in parallel (fit once,
//! images, metrics), the specular error split, then the timings (encodes one per core, CPU
//! costs side by side) once nothing else runs. Rows come back in the order of the mode ids,
//! and no value but the timings depends on the thread count.

use crate::cost::{CostJob, EncodeJob};
use crate::metrics;
use crate::modes::{self, Context, SgIrradiance, SpecularRuntime};
use crate::outcome::{MapReport, Row, SpecularReference, StageTimes};
use rayon::prelude::*;
use sbf::envmap::LatLongImage;
use sbf::recon::prefiltered::PrefilterKernel;
use std::path::Path;
use std::time::Instant;

/// What every map of a run shares.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Mode ids, in report order.
    pub ids: Vec<String>,
    /// Encode runs timed per mode (fewer once they take [`crate::cost::ENCODE_BUDGET_S`]).
    pub repeats: usize,
    pub domain: sbf::Domain,
    /// GGX roughness values of the specular signal (empty: none).
    pub alphas: Vec<f64>,
    /// Samples per texel of the Monte Carlo specular reference (where the FFT quadrature
    /// does not apply).
    pub specular_samples: u32,
    pub sg_irradiance: SgIrradiance,
    pub specular_runtime: SpecularRuntime,
    /// Which GGX integral the specular reference computes (`--reference`).
    pub convention: sbf::ggx::Convention,
    /// How every mode's coefficients are stored (`--storage`).
    pub storage: crate::storage::Storage,
    /// Appendix C only: the GGX reference by \[RoughtonFork\]'s own Monte Carlo estimator with this
    /// many samples per texel ([`crate::appendix_c::monte_carlo_reference`]; \[RoughtonFork\] used
    /// 8192) instead of the exact integral of its kernel — Roughton's reference noise
    /// included. None: the exact integral.
    pub seed_estimator: Option<u32>,
}

/// A mode's timing jobs, kept until the end of the run: its evaluation, its encode, and
/// whether its CPU cost is its encode (the Monte Carlo mode).
type Jobs<'a> = (Option<CostJob<'a>>, Option<EncodeJob<'a>>, bool);

/// One map through every mode (see the module docs). `label` names the map (its path).
pub fn compare(label: &str, map: LatLongImage, sanitized: usize, s: &Settings) -> Result<MapReport, String> {
    let (w, h) = (map.geometry.width, map.geometry.height);
    if s.convention == sbf::ggx::Convention::AppendixC {
        if s.domain != sbf::Domain::UpperHemisphere {
            return Err("--reference appendix-c measures the upper hemisphere ([Roughton19 Appendix C]): use --domain hemisphere".into());
        }
        if s.specular_runtime != SpecularRuntime::Fit {
            return Err("--reference appendix-c runs Roughton's runtimes (the fits): use --specular-runtime fit".into());
        }
        crate::appendix_c::resized(&map)?;
    } else if s.seed_estimator.is_some() {
        return Err("Roughton's Monte Carlo estimator is the Appendix C reference's: it needs --reference appendix-c".into());
    }
    // Appendix C's environment is black below the horizon (see `appendix_c`).
    let map = if s.convention == sbf::ggx::Convention::AppendixC { crate::appendix_c::clip_below_horizon(&map) } else { map };
    let t = Instant::now();
    let mut ctx = Context::with_domain(map, s.domain);
    ctx.sg_irradiance = s.sg_irradiance;
    ctx.specular_runtime = s.specular_runtime;
    ctx.convention = s.convention;
    ctx.storage = s.storage;
    ctx.seed_estimator = s.seed_estimator;
    let ref_s = t.elapsed().as_secs_f64();
    let method = format!("{}, at every {}×{} output texel centre ({ref_s:.2} s)", ctx.reference_method, ctx.grid.width, ctx.grid.height);
    let pb = indicatif::ProgressBar::new(s.ids.len() as u64);
    pb.set_style(indicatif::ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} {msg}").unwrap().progress_chars("=> "));
    pb.set_prefix(label.to_string());
    let radiance = ctx.radiance();
    // The specular references and the modes are independent until the metrics: both run at
    // once, so that neither's last stragglers leave cores idle.
    pb.set_message("modes and specular references");
    let tm = Instant::now();
    let ((spec, spec_s), modes) = rayon::join(
        || {
            let ts = Instant::now();
            let r = specular_references(&ctx, &s.alphas, s.specular_samples);
            (r, ts.elapsed().as_secs_f64())
        },
        || run_modes(&ctx, s, &radiance, &pb),
    );
    let (spec_refs, specular_method) = spec?;
    let (mut rows, jobs) = modes?;
    specular_metrics(&ctx, &mut rows, &spec_refs);
    let modes_s = tm.elapsed().as_secs_f64();
    let tb = Instant::now();
    pb.set_message("specular decomposition");
    decompose(&ctx, &mut rows, &spec_refs);
    split_sum(&ctx, &mut rows, &spec_refs)?;
    let decomposition_s = tb.elapsed().as_secs_f64();
    pb.set_message("costs");
    let tc = Instant::now();
    time_costs(&ctx, &mut rows, jobs, s.alphas.first().copied());
    pb.finish_and_clear();
    let stages = StageTimes {
        reference_irradiance: ref_s,
        specular_reference: spec_s,
        modes: modes_s,
        specular_decomposition: decomposition_s,
        costs: tc.elapsed().as_secs_f64(),
    };
    Ok(MapReport {
        path: label.to_string(),
        width: w,
        height: h,
        domain: if s.domain == sbf::Domain::Sphere { "sphere" } else { "upper hemisphere" },
        reference_method: method,
        storage: s.storage,
        sanitized,
        rows,
        specular_method,
        specular_runtime: match (s.alphas.is_empty(), s.convention) {
            (true, _) => String::new(),
            (false, sbf::ggx::Convention::AppendixC) => crate::appendix_c::RUNTIMES.to_string(),
            (false, sbf::ggx::Convention::Physical) => s.specular_runtime.describe().to_string(),
        },
        convention: s.convention,
        runtime: s.specular_runtime,
        specular_samples: s.specular_samples,
        specular_reference: spec_refs,
        grid: ctx.grid,
        reference: ctx.irradiance.clone(),
        radiance,
        slug: slug(label),
        stages,
    })
}

/// The GGX specular reference of every α, all at once (each is itself parallel over output
/// rows), and the sentence that says how they were made: the deterministic azimuthal-FFT
/// quadrature where the grids allow it (always for maps up to 512 wide), the Monte Carlo
/// MIS estimate otherwise.
fn specular_references(ctx: &Context, alphas: &[f64], spec_samples: u32) -> Result<(Vec<SpecularReference>, String), String> {
    use crate::specular;
    let ts = Instant::now();
    let refs: Vec<(SpecularReference, Result<String, String>)> = alphas
        .par_iter()
        .map(|&alpha| match specular::reference_fft(ctx, alpha) {
            Ok(r) => {
                let sub = if r.coarsening > 1 { format!("1/{}", r.coarsening) } else { r.subdivision.to_string() };
                let sr = match ctx.seed_estimator {
                    // Roughton's estimator, its error measured against the exact integral.
                    Some(n) => {
                        let views: Vec<Option<sbf::glam::DVec3>> =
                            (0..ctx.dirs.len()).map(|k| specular::geometry(ctx, k).map(|(_, v)| v)).collect();
                        let image = crate::appendix_c::monte_carlo_reference(&ctx.map, &views, alpha, n)
                            .expect("compare checked that the map resizes");
                        let (mut e2, mut s2, mut m) = (0.0, 0.0, 0usize);
                        for (k, _) in views.iter().enumerate().filter(|(_, v)| v.is_some()) {
                            for c in 0..3 {
                                e2 += (image[k][c] - r.image[k][c]).powi(2);
                                s2 += r.image[k][c].powi(2);
                            }
                            m += 1;
                        }
                        let m3 = (3 * m).max(1) as f64;
                        SpecularReference { alpha, image, error_rms: (e2 / m3).sqrt(), signal_rms: (s2 / m3).sqrt(), texels_checked: m }
                    }
                    None => SpecularReference {
                        alpha,
                        image: r.image,
                        error_rms: r.error_rms,
                        signal_rms: r.signal_rms,
                        texels_checked: r.texels_checked,
                    },
                };
                (sr, Ok(sub))
            }
            Err(why) => {
                let image = specular::reference(ctx, alpha, spec_samples);
                let (error_rms, signal_rms, texels_checked) = specular::reference_error(ctx, alpha, spec_samples, &image);
                (SpecularReference { alpha, image, error_rms, signal_rms, texels_checked }, Err(why))
            }
        })
        .collect();
    let subdivisions: Vec<String> = refs.iter().filter_map(|(_, s)| s.as_ref().ok().cloned()).collect();
    let fallback: Option<String> = refs.iter().find_map(|(_, s)| s.as_ref().err().cloned());
    let spec_refs: Vec<SpecularReference> = refs.into_iter().map(|(r, _)| r).collect();
    if alphas.is_empty() {
        return Ok((spec_refs, String::new()));
    }
    if let (Some(why), sbf::ggx::Convention::AppendixC) = (&fallback, ctx.convention) {
        // The Monte Carlo fallback integrates the physical BRDF only.
        return Err(format!("--reference appendix-c needs the quadrature reference: {why}"));
    }
    let worst = spec_refs.iter().map(|r| r.error_rms / r.signal_rms.max(f64::MIN_POSITIVE)).fold(0.0, f64::max);
    let method = match (&fallback, ctx.seed_estimator) {
        (None, Some(n)) => format!(
            "[RoughtonFork]'s Monte Carlo estimator (ExperimentMonteCarlo.h: {n} Hammersley visible normals per texel by Heitz's 2017 routine, the map resized to 512×256 read bilinearly) — Roughton's reference with its noise; its RMS difference from the exact integral (the azimuthal quadrature) ≤ {:.3}% of the signal's RMS, per α in results.json ({:.2} s for {} α)",
            100.0 * worst,
            ts.elapsed().as_secs_f64(),
            alphas.len()
        ),
        (None, None) => format!(
            "azimuthal FFT quadrature of the bilinear radiance (the BRDF is invariant about the pole), cells per texel side {} for α {:?} (1/D: D×D texels box-filtered into one cell, where they are below α/16) ({:.2} s for {} α, including the check); estimated error (4/3 × the difference to cells of half the size on 1 in {} output rows) ≤ {:.3}% of the signal's RMS, per α in results.json",
            subdivisions.join(", "),
            alphas,
            ts.elapsed().as_secs_f64(),
            alphas.len(),
            specular::FFT_CHECK_STRIDE,
            100.0 * worst
        ),
        (Some(why), _) => format!(
            "{spec_samples} visible-normal (Halton) + {spec_samples} map-importance (R2) samples per texel, balance-heuristic MIS, bilinear radiance ({:.2} s for {} α, including the check; no FFT quadrature: {why}); estimated error (vs {}× the samples on 1 in {} texels) ≤ {:.2}% of the signal's RMS, per α in results.json",
            ts.elapsed().as_secs_f64(),
            alphas.len(),
            specular::CHECK_FACTOR,
            specular::CHECK_STRIDE,
            100.0 * worst
        ),
    };
    Ok((spec_refs, method))
}

/// Every mode in parallel on every core, untimed: its fit, images, irradiance metrics and
/// specular images (their metrics follow once the references exist), and its timing jobs
/// for the end of the run.
fn run_modes<'a>(
    ctx: &'a Context,
    s: &Settings,
    radiance: &[[f64; 3]],
    pb: &indicatif::ProgressBar,
) -> Result<(Vec<Row>, Vec<Jobs<'a>>), String> {
    let out: Vec<(Row, Jobs)> = s
        .ids
        .par_iter()
        .map(|id| -> Result<(Row, Jobs), String> {
            let modes::Prepared { result: r, eval, encode, eval_from_encode } = modes::prepare(id, ctx, s.repeats)?;
            let mut irradiance = metrics::compute_rows(ctx.grid, &r.irradiance, &ctx.irradiance, ctx.metric_rows());
            if let Some(neg) = r.clamped_negative_fraction {
                irradiance.negative_fraction = neg;
            }
            let rad = r.radiance.as_ref().map(|x| metrics::compute_rows(ctx.grid, x, radiance, ctx.metric_rows()));
            let specular_images: Vec<(f64, Vec<[f64; 3]>)> =
                s.alphas.iter().filter_map(|&a| crate::specular::reconstruct(&r, ctx, a).map(|img| (a, img))).collect();
            pb.inc(1);
            let row = Row {
                result: r,
                radiance: rad,
                irradiance,
                specular: Vec::new(),
                specular_images: specular_images.into_iter().map(|(_, img)| img).collect(),
                specular_parts: Vec::new(),
                split_sum_parts: Vec::new(),
                specular_cost: None,
            };
            Ok((row, (eval, encode, eval_from_encode)))
        })
        .collect::<Result<_, _>>()?;
    Ok(out.into_iter().unzip())
}

/// Each mode's specular error against the reference, per α (its images are in the order of
/// the references' α, one per α the mode reconstructs — every α or none).
fn specular_metrics(ctx: &Context, rows: &mut [Row], spec_refs: &[SpecularReference]) {
    rows.par_iter_mut().for_each(|row| {
        row.specular = spec_refs
            .iter()
            .zip(&row.specular_images)
            .map(|(sr, img)| (sr.alpha, metrics::compute_rows(ctx.grid, img, &sr.image, ctx.metric_rows())))
            .collect();
    });
}

/// The specular error split, per α (all α at once): the basis-limited error (the exact GGX
/// integral of each reconstructed radiance against the reference) and what each runtime
/// path adds (runtime against basis-limited). Modes that store the same radiance (the SH L1
/// variants share their coefficients) share one basis-limited image: the quadrature runs
/// once per distinct image.
fn decompose(ctx: &Context, rows: &mut [Row], spec_refs: &[SpecularReference]) {
    let rows_ro: &[Row] = rows;
    let parts: Vec<Vec<(usize, f64, f64)>> = spec_refs
        .par_iter()
        .map(|sr| {
            let idx: Vec<usize> = (0..rows_ro.len())
                .filter(|k| rows_ro[*k].result.radiance.is_some() && rows_ro[*k].specular.iter().any(|(a, _)| *a == sr.alpha))
                .collect();
            let mut unique: Vec<&[[f64; 3]]> = Vec::new();
            let which: Vec<usize> = idx
                .iter()
                .map(|k| {
                    let r = rows_ro[*k].result.radiance.as_deref().expect("filtered");
                    unique.iter().position(|u| *u == r).unwrap_or_else(|| {
                        unique.push(r);
                        unique.len() - 1
                    })
                })
                .collect();
            let Some(basis) = crate::specular::basis_limited(ctx, &unique, sr.alpha) else { return Vec::new() };
            idx.into_iter()
                .zip(which)
                .map(|(k, u)| {
                    let b = &basis[u];
                    let row = &rows_ro[k];
                    let i = row.specular.iter().position(|(a, _)| *a == sr.alpha).expect("filtered");
                    let basis_rms = metrics::compute_rows(ctx.grid, b, &sr.image, ctx.metric_rows()).rms;
                    let runtime_rms = metrics::compute_rows(ctx.grid, &row.specular_images[i], b, ctx.metric_rows()).rms;
                    (k, basis_rms, runtime_rms)
                })
                .collect()
        })
        .collect();
    for (sr, p) in spec_refs.iter().zip(parts) {
        for (k, basis_rms, runtime_rms) in p {
            rows[k].specular_parts.push((sr.alpha, basis_rms, runtime_rms));
        }
    }
}

/// The prefiltered maps' error split, per α (see [`Row::split_sum_parts`]): the map
/// prefiltered exactly at α on the output grid ([`crate::prefilter::prefiltered_latlong`]),
/// read at each texel's reflected direction (bilinear; over the sphere that is the texel
/// itself) and multiplied by the DFG terms at (n·v, α) — the split sum without a map's
/// limits. Runs only where a prefiltered mode is in the run, under the physical reference.
fn split_sum(ctx: &Context, rows: &mut [Row], spec_refs: &[SpecularReference]) -> Result<(), String> {
    use crate::specular;
    let pf: Vec<usize> = (0..rows.len()).filter(|k| specular::is_pf(rows[*k].result.id)).collect();
    if pf.is_empty() || ctx.convention != sbf::ggx::Convention::Physical {
        return Ok(());
    }
    for sr in spec_refs {
        for kernel in [PrefilterKernel::Karis, PrefilterKernel::NormalIncidence] {
            let mine: Vec<usize> = pf
                .iter()
                .copied()
                .filter(|k| crate::modes::prefiltered::parse(rows[*k].result.id).is_some_and(|v| v.kernel == kernel))
                .collect();
            if !mine.is_empty() {
                split_sum_alpha(ctx, rows, sr, kernel, &mine)?;
            }
        }
    }
    Ok(())
}

/// [`split_sum`] for one α and one kernel, on the rows `pf` prefiltered with it.
fn split_sum_alpha(ctx: &Context, rows: &mut [Row], sr: &SpecularReference, kernel: PrefilterKernel, pf: &[usize]) -> Result<(), String> {
    use crate::specular;
    let dfg = sbf::recon::tables::dfg();
    let (f0, f90) = ctx.convention.fresnel().unwrap_or((1.0, 1.0));
    {
        let p = crate::prefilter::prefiltered_latlong(&ctx.map, ctx.grid, sr.alpha, kernel)?;
        let p = LatLongImage::new(ctx.grid.width, ctx.grid.height, p.iter().map(|v| v.map(|x| x as f32)).collect())
            .map_err(|e| e.to_string())?;
        let exact: Vec<[f64; 3]> = (0..ctx.dirs.len())
            .into_par_iter()
            .map(|k| {
                let Some((n, v)) = specular::geometry(ctx, k) else { return [0.0; 3] };
                let d = dfg.sample2(n.dot(v).clamp(0.0, 1.0) as f32, sr.alpha as f32);
                let scale = f0 * d[0] as f64 + f90 * d[1] as f64;
                p.bilinear(sbf::ggx::reflect(v, n)).map(|x| x * scale)
            })
            .collect();
        let split_rms = metrics::compute_rows(ctx.grid, &exact, &sr.image, ctx.metric_rows()).rms;
        for &k in pf {
            let Some(i) = rows[k].specular.iter().position(|(a, _)| *a == sr.alpha) else { continue };
            let map_rms = metrics::compute_rows(ctx.grid, &rows[k].specular_images[i], &exact, ctx.metric_rows()).rms;
            rows[k].split_sum_parts.push((sr.alpha, split_rms, map_rms));
        }
    }
    Ok(())
}

/// The timings, now that nothing else runs: the encodes (one per core), then the
/// steady-state CPU costs — every mode's irradiance and specular runtime (at `alpha`, the
/// first α) side by side on this thread ([`crate::cost`]).
fn time_costs(ctx: &Context, rows: &mut [Row], jobs: Vec<Jobs<'_>>, alpha: Option<f64>) {
    let (mut eval_jobs, mut encode_jobs): (Vec<_>, Vec<_>) = jobs.into_iter().map(|(e, c, f)| (e, (c, f))).unzip();
    let with_encode: Vec<usize> = (0..rows.len()).filter(|k| encode_jobs[*k].0.is_some()).collect();
    let mut timed: Vec<EncodeJob> = encode_jobs.iter_mut().filter_map(|(j, _)| j.take()).collect();
    for (k, t) in with_encode.into_iter().zip(crate::cost::time_encodes(&mut timed)) {
        modes::Prepared::set_encode(&mut rows[k].result, t, encode_jobs[k].1, ctx.dirs.len());
    }
    drop(timed);
    let (irradiance_costs, specular_costs) = {
        let spec_jobs: Vec<Option<CostJob>> =
            rows.iter().map(|r| alpha.and_then(|a| crate::specular::cost_job(&r.result, ctx, a))).collect();
        let slots: Vec<(usize, bool)> = (0..rows.len())
            .flat_map(|k| [(k, false), (k, true)])
            .filter(|(k, spec)| if *spec { spec_jobs[*k].is_some() } else { eval_jobs[*k].is_some() })
            .collect();
        let mut jobs: Vec<CostJob> = eval_jobs.iter_mut().map(Option::take).zip(spec_jobs).flat_map(|(a, b)| [a, b]).flatten().collect();
        let stats = crate::cost::measure_side_by_side(&mut jobs);
        let mut irr = vec![None; rows.len()];
        let mut spec = vec![None; rows.len()];
        for ((k, is_spec), s) in slots.into_iter().zip(stats) {
            if is_spec {
                spec[k] = Some(s);
            } else {
                irr[k] = Some(s);
            }
        }
        (irr, spec)
    };
    for ((row, irr), spec) in rows.iter_mut().zip(irradiance_costs).zip(specular_costs) {
        if let Some(s) = irr {
            row.result.eval = s;
        }
        row.specular_cost = spec;
    }
}

/// A file-name-safe folder name from a map's path (its file stem).
fn slug(label: &str) -> String {
    Path::new(label)
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "map".into())
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' })
        .collect()
}

/// Makes the maps' image folders unique: the second `pisa` becomes `pisa-2`, and so on.
pub fn unique_slugs(maps: &mut [MapReport]) {
    let mut seen = std::collections::BTreeSet::new();
    for m in maps.iter_mut() {
        let base = m.slug.clone();
        let mut k = 1;
        while !seen.insert(m.slug.clone()) {
            k += 1;
            m.slug = format!("{base}-{k}");
        }
    }
}
