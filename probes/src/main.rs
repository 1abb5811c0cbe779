//! probes: compare spherical bases and solvers on HDR maps; error against run time.

use clap::{Parser, Subcommand};
use probes::outdir::OutDir;
use probes::{input, metrics, modes, report};
use sbf::envmap::{LatLongImage, ProceduralSky};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    version,
    about = "Compare spherical bases and solvers on HDR environment maps: error against run time.",
    after_help = "With no command, runs the default comparison on the built-in procedural sky and writes ./probes-report/.\n\nExamples:\n  probes\n  probes list\n  probes compare ../shared/probes/pisa.hdr\n  probes compare a.hdr b.exr --modes shl2,adrbf,sgls --out report --json\n  probes env --preset sky --out sky.hdr\n\nExit status: 0 on success; 1 when an argument, a map or the output folder is unusable (checked before any work; the message names the file and the problem) or the run fails; 2 for a command line that does not parse."
)]
struct Cli {
    #[command(subcommand)]
    cmd: Option<Cmd>,
    /// Write into an output folder that holds files no probes run wrote (they are kept;
    /// without it such a folder is refused before any work).
    #[arg(long, global = true)]
    force: bool,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Every mode with a one-line description.
    List,
    /// Compare modes on one or more lat-long maps (.hdr or .exr, 2:1).
    Compare(CompareArgs),
    /// Measure every mode's CPU evaluation costs (irradiance, specular per runtime) on the
    /// built-in sky, side by side in several batches, and write the calibration the
    /// decisions use (commit it as probes/data/cpu_costs.json).
    Calibrate {
        /// Side-by-side measurements of all evaluators (15 rounds each), combined per key.
        #[arg(long, default_value_t = 5)]
        batches: usize,
        /// Output file.
        #[arg(long, default_value = "probes/data/cpu_costs.json")]
        out: PathBuf,
        /// What the machine is (CPU model, cores), recorded in the file.
        #[arg(long)]
        machine: String,
    },
    /// Write a procedural environment map.
    Env {
        /// Preset: `sky` (sun, sky gradient, ground) or `sky-nosun`.
        #[arg(long, default_value = "sky")]
        preset: String,
        /// Output file (.hdr or .exr).
        #[arg(long)]
        out: PathBuf,
        /// Width (height is half).
        #[arg(long, default_value_t = 256)]
        width: usize,
    },
}

#[derive(clap::Args, Debug)]
struct CompareArgs {
    maps: Vec<PathBuf>,
    /// Comma-separated mode ids (default: every mode with a peer figure).
    #[arg(long, value_delimiter = ',')]
    modes: Vec<String>,
    /// A lighting profile (TOML, see profiles/): run only the modes of its bases, and
    /// the specular signal only at roughness values inside its GGX range (none for a
    /// Lambert-only profile). Replaces --modes, --alphas and --no-specular.
    #[arg(long, conflicts_with_all = ["modes", "alphas", "no_specular"])]
    profile: Option<PathBuf>,
    /// Where errors are measured: `sphere`, or `hemisphere` (upper, +Y; seed
    /// Appendix C; fits still use the whole sphere). Default modes follow the domain.
    #[arg(long, default_value = "sphere")]
    domain: String,
    /// Output folder.
    #[arg(long, default_value = "probes-report")]
    out: PathBuf,
    /// Also print results.json to stdout.
    #[arg(long)]
    json: bool,
    /// Replace NaN/Inf/negative texels by 0 (and report how many) instead of failing.
    #[arg(long)]
    sanitize: bool,
    /// Encode repeats for the median timing (fewer once they take 0.1 s together).
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// GGX roughness values of the specular signal (empty to skip it).
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_ALPHAS)]
    alphas: Vec<f64>,
    /// Visible-normal samples (and as many map samples, MIS) per texel of the specular reference.
    #[arg(long, default_value_t = 256)]
    specular_samples: u32,
    /// Skip the specular signal (irradiance and radiance only).
    #[arg(long)]
    no_specular: bool,
    /// Irradiance of sg, sgls, sglsa, sgnnls: `hill` (Hill's fit, the WGSL runtime path),
    /// `peer` (Probulator's cosine-as-SG kernel, λ 8.5 after naive projection, 3.0
    /// otherwise; reproduces its published figures), `prior` (the best linear estimate
    /// under an isotropic radiance prior, C_l ∝ l⁻²), or `auto`: the peer's kernel for
    /// `sg` and `sgnnls`, the prior estimate for `sgls` and `sglsa`.
    #[arg(long, default_value = "auto")]
    sg_irradiance: String,
    /// Specular runtime of the SG and AD modes: `table` (per-lobe GGX response tables,
    /// luts/lobe_ggx_*.sbflut; interpolation is the only approximation) or `fit` (the
    /// ASG warp for SG, seed Listing 8.1 × its LUT for AD).
    #[arg(long, default_value = "table")]
    specular_runtime: String,
    /// Images written per mode and signal: `png` (previews), `exr` (PNG and float EXR),
    /// or `none`.
    #[arg(long, default_value = "png")]
    images: String,
    /// Also measure each mode's GPU cost: the `shaders` runtime kernels of `shaders bench`
    /// on the best adapter (ns per evaluation; a fourth Pareto axis).
    #[arg(long)]
    gpu_cost: bool,
    /// Evaluations per dispatch of the GPU cost measurement.
    #[arg(long, default_value_t = 1 << 20)]
    gpu_count: usize,
}

fn preset(name: &str) -> Result<ProceduralSky, String> {
    match name {
        "sky" => Ok(ProceduralSky::default()),
        "sky-nosun" => Ok(ProceduralSky { sun_radiance: [0.0; 3], ..ProceduralSky::default() }),
        _ => Err(format!("unknown preset '{name}' (sky, sky-nosun)")),
    }
}

/// Default roughness values of the specular signal (seed Appendix C).
use probes::profile::DEFAULT_ALPHAS;

/// One map through every mode: reference, fits, metrics (irradiance, radiance, specular).
fn compare(
    label: &str,
    map: LatLongImage,
    sanitized: usize,
    ids: &[String],
    repeats: usize,
    domain: sbf::Domain,
    alphas: &[f64],
    spec_samples: u32,
    sg_irradiance: modes::SgIrradiance,
    specular_runtime: probes::specular::SpecularRuntime,
) -> Result<report::MapReport, String> {
    let (w, h) = (map.geometry.width, map.geometry.height);
    let t = std::time::Instant::now();
    let mut ctx = modes::Context::with_domain(map, domain);
    ctx.sg_irradiance = sg_irradiance;
    ctx.specular_runtime = specular_runtime;
    let ref_s = t.elapsed().as_secs_f64();
    let method = format!("{}, at every {}×{} output texel centre ({ref_s:.2} s)", ctx.reference_method, ctx.grid.width, ctx.grid.height);
    let pb = indicatif::ProgressBar::new(ids.len() as u64);
    pb.set_style(indicatif::ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} {msg}").unwrap().progress_chars("=> "));
    pb.set_prefix(label.to_string());
    let radiance = ctx.radiance();
    let ts = std::time::Instant::now();
    // The deterministic azimuthal-FFT quadrature where the grids allow it (always for
    // maps up to 512 wide), the Monte Carlo MIS estimate otherwise.
    // Every α at once (each reference is itself parallel over output rows).
    use rayon::prelude::*;
    pb.set_message("specular references");
    let refs: Vec<(report::SpecularReference, Result<String, String>)> = alphas
        .par_iter()
        .map(|&alpha| match probes::specular::reference_fft(&ctx, alpha) {
            Ok(r) => {
                let sub = if r.coarsening > 1 { format!("1/{}", r.coarsening) } else { r.subdivision.to_string() };
                let sr = report::SpecularReference {
                    alpha,
                    image: r.image,
                    error_rms: r.error_rms,
                    signal_rms: r.signal_rms,
                    texels_checked: r.texels_checked,
                };
                (sr, Ok(sub))
            }
            Err(why) => {
                let image = probes::specular::reference(&ctx, alpha, spec_samples);
                let (error_rms, signal_rms, texels_checked) = probes::specular::reference_error(&ctx, alpha, spec_samples, &image);
                (report::SpecularReference { alpha, image, error_rms, signal_rms, texels_checked }, Err(why))
            }
        })
        .collect();
    let subdivisions: Vec<String> = refs.iter().filter_map(|(_, s)| s.as_ref().ok().cloned()).collect();
    let fallback: Option<String> = refs.iter().find_map(|(_, s)| s.as_ref().err().cloned());
    let spec_refs: Vec<report::SpecularReference> = refs.into_iter().map(|(r, _)| r).collect();
    let specular_method = if alphas.is_empty() {
        String::new()
    } else {
        let worst = spec_refs.iter().map(|r| r.error_rms / r.signal_rms.max(f64::MIN_POSITIVE)).fold(0.0, f64::max);
        match &fallback {
            None => format!(
                "azimuthal FFT quadrature of the bilinear radiance (the BRDF is invariant about the pole), cells per texel side {} for α {:?} (1/D: D×D texels box-filtered into one cell, where they are below α/16) ({:.2} s for {} α, including the check); estimated error (4/3 × the difference to cells of half the size on 1 in {} output rows) ≤ {:.3}% of the signal's RMS, per α in results.json",
                subdivisions.join(", "),
                alphas,
                ts.elapsed().as_secs_f64(),
                alphas.len(),
                probes::specular::FFT_CHECK_STRIDE,
                100.0 * worst
            ),
            Some(why) => format!(
                "{spec_samples} visible-normal (Halton) + {spec_samples} map-importance (R2) samples per texel, balance-heuristic MIS, bilinear radiance ({:.2} s for {} α, including the check; no FFT quadrature: {why}); estimated error (vs {}× the samples on 1 in {} texels) ≤ {:.2}% of the signal's RMS, per α in results.json",
                ts.elapsed().as_secs_f64(),
                alphas.len(),
                probes::specular::CHECK_FACTOR,
                probes::specular::CHECK_STRIDE,
                100.0 * worst
            ),
        }
    };
    let spec_s = ts.elapsed().as_secs_f64();
    let tm = std::time::Instant::now();
    // Modes run in parallel on every core, untimed; their encodes and steady-state costs
    // are timed at the end (`probes::cost`). Rows come back in the order of `ids`, and no
    // value depends on the thread count.
    pb.set_message("modes");
    type Jobs<'a> = (Option<probes::cost::CostJob<'a>>, Option<probes::cost::EncodeJob<'a>>, bool);
    let (rows, jobs): (Vec<report::Row>, Vec<Jobs>) = ids
        .par_iter()
        .map(|id| -> Result<(report::Row, Jobs), String> {
            let modes::Prepared { result: r, eval, encode, eval_from_encode } = modes::prepare(id, &ctx, repeats)?;
            let mut irradiance = metrics::compute_rows(ctx.grid, &r.irradiance, &ctx.irradiance, ctx.metric_rows());
            if let Some(neg) = r.clamped_negative_fraction {
                irradiance.negative_fraction = neg;
            }
            let rad = r.radiance.as_ref().map(|x| metrics::compute_rows(ctx.grid, x, &radiance, ctx.metric_rows()));
            let (mut specular, mut specular_images) = (Vec::new(), Vec::new());
            for sr in &spec_refs {
                if let Some(img) = probes::specular::reconstruct(&r, &ctx, sr.alpha) {
                    specular.push((sr.alpha, metrics::compute_rows(ctx.grid, &img, &sr.image, ctx.metric_rows())));
                    specular_images.push(img);
                }
            }
            pb.inc(1);
            let row = report::Row {
                result: r,
                radiance: rad,
                irradiance,
                specular,
                specular_images,
                specular_parts: Vec::new(),
                specular_cost: None,
            };
            Ok((row, (eval, encode, eval_from_encode)))
        })
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    let mut rows = rows;
    let modes_s = tm.elapsed().as_secs_f64();
    let tb = std::time::Instant::now();
    // Basis-limited error (the exact GGX integral of each reconstructed radiance against the
    // reference) and what each runtime path adds (runtime against basis-limited), all modes
    // of one α in one quadrature pass.
    pb.set_message("specular decomposition");
    // Per α (all α at once): the modes with a radiance and this α, and the basis-limited
    // image of each distinct radiance. Modes that store the same radiance (the SH L1
    // variants share their coefficients) share one image: the quadrature runs once per
    // distinct image.
    let parts: Vec<Vec<(usize, f64, f64)>> = spec_refs
        .par_iter()
        .map(|sr| {
            let idx: Vec<usize> = (0..rows.len())
                .filter(|k| rows[*k].result.radiance.is_some() && rows[*k].specular.iter().any(|(a, _)| *a == sr.alpha))
                .collect();
            let mut unique: Vec<&[[f64; 3]]> = Vec::new();
            let which: Vec<usize> = idx
                .iter()
                .map(|k| {
                    let r = rows[*k].result.radiance.as_deref().expect("filtered");
                    unique.iter().position(|u| *u == r).unwrap_or_else(|| {
                        unique.push(r);
                        unique.len() - 1
                    })
                })
                .collect();
            let Some(basis) = probes::specular::basis_limited(&ctx, &unique, sr.alpha) else { return Vec::new() };
            idx.into_iter()
                .zip(which)
                .map(|(k, u)| {
                    let b = &basis[u];
                    let row = &rows[k];
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
    let decomposition_s = tb.elapsed().as_secs_f64();
    // The encodes (one per core), then the steady-state costs (every mode's irradiance and
    // specular runtime at the first α, side by side on this thread), now that nothing else
    // runs.
    pb.set_message("costs");
    let tc = std::time::Instant::now();
    let (mut eval_jobs, mut encode_jobs): (Vec<_>, Vec<_>) = jobs.into_iter().map(|(e, c, f)| (e, (c, f))).unzip();
    let with_encode: Vec<usize> = (0..rows.len()).filter(|k| encode_jobs[*k].0.is_some()).collect();
    let mut timed: Vec<probes::cost::EncodeJob> = encode_jobs.iter_mut().filter_map(|(j, _)| j.take()).collect();
    for (k, t) in with_encode.into_iter().zip(probes::cost::time_encodes(&mut timed)) {
        modes::Prepared::set_encode(&mut rows[k].result, t, encode_jobs[k].1, ctx.dirs.len());
    }
    drop(timed);
    let (irradiance_costs, specular_costs) = {
        let spec_jobs: Vec<Option<probes::cost::CostJob>> =
            rows.iter().map(|r| alphas.first().and_then(|a| probes::specular::cost_job(&r.result, &ctx, *a))).collect();
        let slots: Vec<(usize, bool)> = (0..rows.len())
            .flat_map(|k| [(k, false), (k, true)])
            .filter(|(k, spec)| if *spec { spec_jobs[*k].is_some() } else { eval_jobs[*k].is_some() })
            .collect();
        let mut jobs: Vec<probes::cost::CostJob> =
            eval_jobs.iter_mut().map(Option::take).zip(spec_jobs).flat_map(|(a, b)| [a, b]).flatten().collect();
        let stats = probes::cost::measure_side_by_side(&mut jobs);
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
    pb.finish_and_clear();
    let stage_s = report::StageTimes {
        reference_irradiance: ref_s,
        specular_reference: spec_s,
        modes: modes_s,
        specular_decomposition: decomposition_s,
        costs: tc.elapsed().as_secs_f64(),
    };
    let domain_name = if domain == sbf::Domain::Sphere { "sphere" } else { "upper hemisphere" };
    Ok(report::MapReport {
        path: label.to_string(),
        width: w,
        height: h,
        domain: domain_name,
        reference_method: method,
        sanitized,
        rows,
        specular_method,
        specular_runtime: if alphas.is_empty() { String::new() } else { specular_runtime.describe().to_string() },
        runtime: specular_runtime,
        specular_samples: spec_samples,
        specular_reference: spec_refs,
        grid: ctx.grid,
        reference: ctx.irradiance.clone(),
        radiance,
        slug: slug(label),
        stages: stage_s,
    })
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
fn unique_slugs(maps: &mut [report::MapReport]) {
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

/// `--images`: (PNG previews, float EXR too).
fn images_flag(images: &str) -> Result<(bool, bool), String> {
    match images {
        "png" => Ok((true, false)),
        "exr" => Ok((true, true)),
        "none" => Ok((false, false)),
        other => Err(format!("--images {other}: expected `png`, `exr` or `none`")),
    }
}

fn write_reports(
    out: &OutDir,
    maps: &mut [report::MapReport],
    print_json: bool,
    (png, exr): (bool, bool),
    gpu: Option<&probes::gpu_cost::GpuCosts>,
) -> Result<(), String> {
    unique_slugs(maps);
    // The previous run's files go first, so the folder holds this run's files only.
    out.remove_previous()?;
    let results: Vec<probes::results::MapResults> = maps
        .iter()
        .map(|m| {
            let mut r = probes::results::from_report(m, exr, gpu);
            r.decision = probes::decide::decide(&r);
            r
        })
        .collect();
    let json = probes::results::to_json(&results);
    let md = report::markdown(maps, &results, png);
    let write = |name: &str, text: &str| std::fs::write(out.file(out.path().join(name)), text).map_err(|e| format!("writing {name}: {e}"));
    write("results.json", &json)?;
    write("report.md", &md)?;
    // report.html (its interactive view's data) alongside the images.
    let maps: &[report::MapReport] = maps;
    let (html, images) = rayon::join(
        || write("report.html", &report::html(maps, &results)),
        || if png { maps.iter().try_for_each(|m| report::write_images(out, m, exr)) } else { Ok(()) },
    );
    html?;
    images?;
    out.finish()?;
    let out = out.path();
    if print_json {
        print!("{json}");
    } else {
        for r in &results {
            for line in report::summary_lines(r) {
                println!("{line}");
            }
        }
        println!(
            "wrote {0}/report.md (decision tables first), {0}/report.html, {0}/results.json{1}",
            out.display(),
            if png { " and the images" } else { "" }
        );
    }
    Ok(())
}

/// `probes compare`: every argument, map and the output folder are checked before any
/// work (a bad input fails in milliseconds, naming the file and the problem); then the GPU
/// costs, each map through every mode, and the reports.
fn compare_command(a: CompareArgs, force: bool) -> Result<(), String> {
    // 1. Every flag.
    let sgi = match a.sg_irradiance.as_str() {
        "auto" => modes::SgIrradiance::Auto,
        "hill" => modes::SgIrradiance::Hill,
        "peer" => modes::SgIrradiance::Peer,
        "prior" => modes::SgIrradiance::Prior,
        other => return Err(format!("--sg-irradiance {other}: expected `auto`, `hill`, `peer` or `prior`")),
    };
    let spec_rt = probes::specular::SpecularRuntime::parse(&a.specular_runtime)?;
    let images = images_flag(&a.images)?;
    let prof = a.profile.as_deref().map(sbf::profile::Profile::load).transpose()?;
    let (m, alphas) = match &prof {
        Some(p) => (probes::profile::modes(p), probes::profile::alphas(p)),
        None => (a.modes, if a.no_specular { Vec::new() } else { a.alphas }),
    };
    if let Some(x) = alphas.iter().find(|x| !(x.is_finite() && **x >= 1e-4 && **x <= 1.0)) {
        return Err(format!("--alphas: {x} is outside [1e-4, 1]"));
    }
    if a.specular_samples == 0 {
        return Err("--specular-samples must be > 0".into());
    }
    if a.repeats == 0 {
        return Err("--repeats must be ≥ 1".into());
    }
    if a.gpu_cost && a.gpu_count == 0 {
        return Err("--gpu-count must be > 0".into());
    }
    let dom = match a.domain.as_str() {
        "sphere" => sbf::Domain::Sphere,
        "hemisphere" => sbf::Domain::UpperHemisphere,
        other => return Err(format!("--domain {other}: expected `sphere` or `hemisphere`")),
    };
    if a.maps.is_empty() {
        return Err("give at least one map (see --help)".into());
    }
    let default: &[&str] = if dom == sbf::Domain::Sphere { modes::DEFAULT_MODES } else { modes::HEMISPHERE_MODES };
    let ids: Vec<String> = if m.is_empty() { default.iter().map(|s| s.to_string()).collect() } else { m };
    for id in &ids {
        if !modes::MODES.iter().any(|(x, _)| x == id) {
            return Err(format!("unknown mode '{id}' (see `probes list`)"));
        }
    }
    // 2. Every map: the path (all of them first: cheap), then decoded and validated.
    for path in &a.maps {
        input::check_path(path).map_err(|e| e.to_string())?;
    }
    let maps = a
        .maps
        .iter()
        .map(|path| {
            let (map, rep) = input::load_map(path, a.sanitize).map_err(|e| e.to_string())?;
            if rep.total() > 0 {
                eprintln!(
                    "{}: sanitised {} NaN, {} infinite, {} negative texel channels to 0",
                    path.display(),
                    rep.nan,
                    rep.infinite,
                    rep.negative
                );
            }
            Ok((path.display().to_string(), map, rep.total()))
        })
        .collect::<Result<Vec<_>, String>>()?;
    // 3. The output folder.
    let out = OutDir::claim(&a.out, force)?;
    if let Some(p) = &prof {
        let left: Vec<&str> = default.iter().copied().filter(|d| !ids.iter().any(|i| i == d)).collect();
        let per_mode = 2 + alphas.len(); // irradiance, radiance and one specular image set per α
        println!(
            "profile '{}': runs {} mode(s) ({}); left out {} of the {} default modes ({} image sets per map not computed or written){}",
            p.name,
            ids.len(),
            ids.join(", "),
            left.len(),
            default.len(),
            left.len() * per_mode,
            if alphas.is_empty() {
                "; specular signal left out (Lambert only: no GGX reference, no specular column)".to_string()
            } else {
                format!("; specular at α {}", alphas.iter().map(|a| a.to_string()).collect::<Vec<_>>().join(", "))
            }
        );
    }
    let gpu = if a.gpu_cost {
        let g = probes::gpu_cost::measure(a.gpu_count, 10).map_err(|e| format!("--gpu-cost: {e}"))?;
        eprintln!("GPU costs measured on {}{}", g.adapter, if g.software { " (a software adapter: not a GPU's figures)" } else { "" });
        Some(g)
    } else {
        None
    };
    let mut reports = Vec::new();
    for (label, map, sanitized) in maps {
        reports.push(compare(&label, map, sanitized, &ids, a.repeats, dom, &alphas, a.specular_samples, sgi, spec_rt)?);
    }
    write_reports(&out, &mut reports, a.json, images, gpu.as_ref())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.cmd {
        Some(Cmd::List) => {
            for (id, d) in modes::MODES {
                println!("{id:<10} {d}");
            }
            Ok(())
        }
        Some(Cmd::Env { preset: p, out, width }) => (|| {
            let sky = preset(&p)?;
            if width < 2 || width % 2 != 0 {
                return Err(format!("--width must be even and ≥ 2, got {width}"));
            }
            let map = LatLongImage::from_fn(width, width / 2, |d| sky.radiance(d)).map_err(|e| e.to_string())?;
            let img = image::Rgb32FImage::from_raw(width as u32, (width / 2) as u32, map.texels.iter().flatten().copied().collect())
                .ok_or("image size")?;
            img.save(&out).map_err(|e| format!("writing {}: {e}", out.display()))?;
            println!("wrote {} ({}×{}, preset {p})", out.display(), width, width / 2);
            Ok(())
        })(),
        Some(Cmd::Compare(args)) => compare_command(args, cli.force),
        Some(Cmd::Calibrate { batches, out, machine }) => (|| {
            if batches == 0 {
                return Err("--batches must be ≥ 1".to_string());
            }
            let mut c = probes::calibration::calibrate(batches, &|m| eprintln!("calibrate: {m}"))?;
            c.machine = machine;
            c.date = probes::calibration::today();
            let text = serde_json::to_string_pretty(&c).map_err(|e| e.to_string())? + "\n";
            std::fs::write(&out, text).map_err(|e| format!("writing {}: {e}", out.display()))?;
            println!("wrote {} ({} evaluators)", out.display(), c.costs.len());
            Ok(())
        })(),
        None => (|| {
            let out = OutDir::claim(Path::new("probes-report"), cli.force)?;
            let sky = ProceduralSky::default();
            let map = LatLongImage::from_fn(256, 128, |d| sky.radiance(d)).map_err(|e| e.to_string())?;
            let ids: Vec<String> = modes::DEFAULT_MODES.iter().map(|s| s.to_string()).collect();
            let rep = compare(
                "procedural-sky",
                map,
                0,
                &ids,
                3,
                sbf::Domain::Sphere,
                &DEFAULT_ALPHAS,
                256,
                modes::SgIrradiance::Auto,
                Default::default(),
            )?;
            write_reports(&out, &mut [rep], false, (true, false), None)
        })(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("probes: {e}");
            ExitCode::FAILURE
        }
    }
}
