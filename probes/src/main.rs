//! probes: compare spherical bases and solvers on HDR maps; error against run time.

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

use clap::{Parser, Subcommand};
use probes::compare::{compare, Settings};
use probes::outdir::OutDir;
use probes::{input, modes, report};
use sbf::envmap::{LatLongImage, ProceduralSky};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    version,
    about = "Compare spherical bases and solvers on HDR environment maps: error against run time.",
    after_help = "With no command, runs the default comparison on the built-in procedural sky and writes ./probes-report/.\n\nExamples:\n  probes\n  probes list\n  probes compare ../shared/probes/pisa.hdr\n  probes compare a.hdr b.exr --modes shl2,adrbf,sgls --out report --json\n  probes env --preset sky --out sky.hdr\n\nExit status: 0 on success; 1 when an argument, a map or the output folder is unusable (checked before any work; the message names the file and the problem) or the run fails; 2 for a command line that does not parse or a lighting profile it cannot use (as in every tool of the workspace)."
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
    Compare(Box<CompareArgs>),
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
    /// Lambert-only profile), and its specular runtime path (`runtime.specular`; a profile
    /// naming both gets one report folder per path, OUT/fit and OUT/tables). Replaces
    /// --modes, --alphas, --no-specular and --specular-runtime.
    #[arg(long, conflicts_with_all = ["modes", "alphas", "no_specular"])]
    profile: Option<PathBuf>,
    /// Where errors are measured: `sphere`, or `hemisphere` (upper, +Y; seed
    /// Appendix C; fits still use the whole sphere). Default modes follow the domain.
    /// [default: sphere; hemisphere with --reference appendix-c]
    #[arg(long)]
    domain: Option<String>,
    /// The specular reference: `physical` (the single-scattering GGX integral, light from
    /// above the surface) or `appendix-c` ([Roughton19 Appendix C]'s pipeline as its code reads:
    /// the environment black below the horizon, G2·G1 visibility, Schlick f0 0.9 / f90 1,
    /// Roughton's runtimes with
    /// its Listing 8.2 table, SG fits point-sampled; to compare with Roughton's printed
    /// figures — every report says which). appendix-c implies --domain hemisphere,
    /// --specular-runtime fit and the modes ad9, adrbf-tangent, sg9h, sg12h.
    #[arg(long, default_value = "physical", conflicts_with = "profile")]
    reference: String,
    /// Output folder.
    #[arg(long, default_value = "probes-report")]
    out: PathBuf,
    /// Also print results.json to stdout.
    #[arg(long)]
    json: bool,
    /// Replace NaN/Inf/negative texels by 0 (and report how many) instead of failing.
    #[arg(long)]
    sanitize: bool,
    /// The error, in % of the reference's RMS, above which a mode is not usable: a signal whose
    /// best mode exceeds it is reported as having no mode that fits.
    #[arg(long, default_value_t = probes::decide::USABLE_ERROR_PERCENT)]
    usable_error: f64,
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
    /// split sum over the warped NDF for SG — the ASG warp with --reference appendix-c —,
    /// [Roughton19 Listing 8.1] × its LUT for AD). [default: table; fit with
    /// --reference appendix-c]
    #[arg(long)]
    specular_runtime: Option<String>,
    /// How each mode's coefficients are stored before they are reconstructed: `f32`, `f16`
    /// (a half-float texture) or `bc6h` (1 byte per RGB coefficient, a uniform 4×4 block of
    /// the probe through BC6H — the precision floor under distant light; engine formats'
    /// directions in BC1/BC7). Errors and the storage axis are the stored data's.
    #[arg(long, default_value = "f32")]
    storage: String,
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

/// Default roughness values of the specular signal ([Roughton19 Appendix C]).
use probes::profile::DEFAULT_ALPHAS;

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
    profile: Option<&sbf::profile::Profile>,
    usable_error_percent: f64,
) -> Result<(), String> {
    probes::compare::unique_slugs(maps);
    // The previous run's files go first, so the folder holds this run's files only.
    out.remove_previous()?;
    let results: Vec<probes::results::MapResults> = maps
        .iter()
        .map(|m| {
            let mut r = probes::results::from_report(m, exr, gpu);
            r.profile = profile.map(|p| p.summary()).unwrap_or_default();
            r.usable_error_percent = usable_error_percent;
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

/// What a profile makes `probes compare` run and leave out, printed before the run.
fn print_profile_plan(
    p: &sbf::profile::Profile,
    ids: &[String],
    default: &[&str],
    alphas: &[f64],
    runtimes: &[probes::specular::SpecularRuntime],
) {
    let left: Vec<&str> = default.iter().copied().filter(|d| !ids.iter().any(|i| i == d)).collect();
    let per_mode = 2 + alphas.len(); // irradiance, radiance and one specular image set per α
    println!(
        "profile '{}': runs {} mode(s) ({}); left out {} of the {} default modes{} ({} image sets per map not computed or written){}",
        p.name,
        ids.len(),
        ids.join(", "),
        left.len(),
        default.len(),
        if left.is_empty() { String::new() } else { format!(" ({}: bases and variants the profile does not name)", left.join(", ")) },
        left.len() * per_mode,
        if alphas.is_empty() {
            "; specular signal left out (Lambert only: no GGX reference, no specular column)".to_string()
        } else {
            format!(
                "; specular at α {} through the {} path{}",
                alphas.iter().map(|a| a.to_string()).collect::<Vec<_>>().join(", "),
                runtimes.iter().map(|r| r.name()).collect::<Vec<_>>().join(" and "),
                if runtimes.len() > 1 { "s (one report folder each)" } else { "" }
            )
        }
    );
}

/// The maps of `probes compare`: every path checked first (cheap), then each decoded and
/// validated; what `--sanitize` zeroed is reported per map. (label, map, channels sanitised)
fn load_maps(paths: &[std::path::PathBuf], sanitize: bool) -> Result<Vec<(String, sbf::envmap::LatLongImage, usize)>, String> {
    for path in paths {
        input::check_path(path).map_err(|e| e.to_string())?;
    }
    paths
        .iter()
        .map(|path| {
            let (map, rep) = input::load_map(path, sanitize).map_err(|e| e.to_string())?;
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
        .collect()
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
    let convention = match a.reference.as_str() {
        "physical" => sbf::ggx::Convention::Physical,
        "appendix-c" => sbf::ggx::Convention::AppendixC,
        other => return Err(format!("--reference {other}: expected `physical` or `appendix-c`")),
    };
    let storage = probes::storage::Storage::parse(&a.storage)?;
    let seed = convention == sbf::ggx::Convention::AppendixC;
    if seed && storage != probes::storage::Storage::F32 {
        return Err("--reference appendix-c reproduces Roughton's figures, made from f32 coefficients: leave --storage at f32".into());
    }
    let spec_rt = match (a.specular_runtime.as_deref(), seed) {
        (None, false) => probes::specular::SpecularRuntime::Table,
        (None, true) => probes::specular::SpecularRuntime::Fit,
        (Some(x), _) => probes::specular::SpecularRuntime::parse(x)?,
    };
    if seed && spec_rt != probes::specular::SpecularRuntime::Fit {
        return Err("--reference appendix-c runs Roughton's runtimes: --specular-runtime must be `fit`".into());
    }
    let images = images_flag(&a.images)?;
    let prof = a.profile.as_deref().map(sbf::profile::Profile::load).transpose()?;
    if prof.as_ref().is_some_and(|p| p.multiple_scattering) {
        eprintln!(
            "note: the profile compensates GGX multiple scattering (sbf::recon::multiscatter); the specular signal here is single scattering, references and runtimes alike, so its errors do not include the compensation"
        );
    }
    let (m, alphas) = match &prof {
        Some(p) => (probes::profile::modes(p), probes::profile::alphas(p)),
        None => (a.modes, if a.no_specular { Vec::new() } else { a.alphas }),
    };
    // The specular runtime path(s): the profile's (each measured in its own report folder
    // when it names both), else --specular-runtime.
    let runtimes = match &prof {
        Some(p) if p.specular => probes::profile::specular_runtimes(p),
        _ => vec![spec_rt],
    };
    if let Some(x) = alphas.iter().find(|x| !(x.is_finite() && **x >= 1e-4 && **x <= 1.0)) {
        return Err(format!("--alphas: {x} is outside [1e-4, 1]"));
    }
    if a.specular_samples == 0 {
        return Err("--specular-samples must be > 0".into());
    }
    if !(a.usable_error.is_finite() && a.usable_error > 0.0) {
        return Err(format!("--usable-error must be a percentage > 0, not {}", a.usable_error));
    }
    if a.repeats == 0 {
        return Err("--repeats must be ≥ 1".into());
    }
    if a.gpu_cost && a.gpu_count == 0 {
        return Err("--gpu-count must be > 0".into());
    }
    let dom = match a.domain.as_deref().unwrap_or(if seed { "hemisphere" } else { "sphere" }) {
        "sphere" if seed => return Err("--reference appendix-c measures the upper hemisphere: --domain must be `hemisphere`".into()),
        "sphere" => sbf::Domain::Sphere,
        "hemisphere" => sbf::Domain::UpperHemisphere,
        other => return Err(format!("--domain {other}: expected `sphere` or `hemisphere`")),
    };
    if a.maps.is_empty() {
        return Err("give at least one map (see --help)".into());
    }
    let seed_modes: Vec<&str> = probes::appendix_c::MODES.iter().map(|(_, id)| *id).collect();
    let default: &[&str] = if seed {
        &seed_modes
    } else if dom == sbf::Domain::Sphere {
        modes::DEFAULT_MODES
    } else {
        modes::HEMISPHERE_MODES
    };
    let ids: Vec<String> = if m.is_empty() { default.iter().map(|s| s.to_string()).collect() } else { m };
    for id in &ids {
        if modes::mode(id).is_none() {
            return Err(format!("unknown mode '{id}' (see `probes list`)"));
        }
    }
    // 2. Every map: the path (all of them first: cheap), then decoded and validated.
    let maps = load_maps(&a.maps, a.sanitize)?;
    // 3. The output folder(s): one per specular runtime path.
    let outs: Vec<(probes::specular::SpecularRuntime, OutDir)> = if runtimes.len() == 1 {
        vec![(runtimes[0], OutDir::claim(&a.out, force)?)]
    } else {
        // Folders named as the profile names the paths (`fit`, `tables`).
        let folder = |rt: &probes::specular::SpecularRuntime| if rt.name() == "fit" { "fit" } else { "tables" };
        runtimes.iter().map(|rt| Ok((*rt, OutDir::claim(&a.out.join(folder(rt)), force)?))).collect::<Result<_, String>>()?
    };
    if let Some(p) = &prof {
        print_profile_plan(p, &ids, default, &alphas, &runtimes);
    }
    let gpu = if a.gpu_cost {
        let g = probes::gpu_cost::measure(a.gpu_count, 10).map_err(|e| format!("--gpu-cost: {e}"))?;
        eprintln!("GPU costs measured on {}{}", g.adapter, if g.software { " (a software adapter: not a GPU's figures)" } else { "" });
        Some(g)
    } else {
        None
    };
    for (rt, out) in &outs {
        let settings = Settings {
            ids: ids.clone(),
            repeats: a.repeats,
            domain: dom,
            alphas: alphas.clone(),
            specular_samples: a.specular_samples,
            sg_irradiance: sgi,
            specular_runtime: *rt,
            convention,
            storage,
            seed_estimator: None,
        };
        let mut reports = Vec::new();
        for (label, map, sanitized) in &maps {
            reports.push(compare(label, map.clone(), *sanitized, &settings)?);
        }
        write_reports(out, &mut reports, a.json, images, gpu.as_ref(), prof.as_ref(), a.usable_error)?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // A profile it cannot use exits with 2, as in every tool.
    if let Some(Cmd::Compare(a)) = &cli.cmd {
        if let Some(p) = &a.profile {
            if let Err(e) = sbf::profile::Profile::load(p) {
                eprintln!("probes: {e}");
                return ExitCode::from(2);
            }
        }
    }
    let result = match cli.cmd {
        Some(Cmd::List) => {
            // A closed pipe (`probes list | head`) ends the listing quietly.
            let mut out = std::io::stdout().lock();
            for modes::Mode { id, description: d, .. } in modes::MODES {
                if std::io::Write::write_fmt(&mut out, format_args!("{id:<10} {d}\n")).is_err() {
                    break;
                }
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
        Some(Cmd::Compare(args)) => compare_command(*args, cli.force),
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
            let settings = Settings {
                ids,
                repeats: 3,
                domain: sbf::Domain::Sphere,
                alphas: DEFAULT_ALPHAS.to_vec(),
                specular_samples: 256,
                sg_irradiance: modes::SgIrradiance::Auto,
                specular_runtime: Default::default(),
                convention: Default::default(),
                storage: probes::storage::Storage::F32,
                seed_estimator: None,
            };
            let rep = compare("procedural-sky", map, 0, &settings)?;
            write_reports(&out, &mut [rep], false, (true, false), None, None, probes::decide::USABLE_ERROR_PERCENT)
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
