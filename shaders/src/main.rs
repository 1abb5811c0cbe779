//! shaders: compose, validate and export the WGSL runtime library.

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

use clap::{Parser, Subcommand};
use shaders::compose::{self, Config};
use shaders::export::{self, Lang};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    version,
    about = "Compose the WGSL runtime library for a configuration (only what it needs), validate it with naga, export it.",
    after_help = "Examples:\n  shaders list\n  shaders export --config ad9-irradiance --lang wgsl\n  shaders export --config sh-l2-irradiance,sg-specular --lang hlsl --out lighting.hlsl\n  shaders export --config all --lang msl --out all.metal\n  shaders library --check"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Presets and features, with the composed size of each preset.
    List,
    /// Compose, validate and write one configuration in one language: WGSL as composed,
    /// HLSL/GLSL/MSL as a readable include file (same names, loops, comments; no entry point).
    Export {
        /// A preset (see `list`) or a comma-separated feature list.
        #[arg(long, required_unless_present = "profile", conflicts_with = "profile")]
        config: Option<String>,
        /// A lighting profile (TOML, see profiles/): the features its bases and BRDF set
        /// need, in its language (unless --lang is given).
        #[arg(long)]
        profile: Option<PathBuf>,
        /// wgsl, hlsl, glsl (Vulkan), glsl-gl (OpenGL 3.3+ core), glsl-es (OpenGL ES 3.0) or msl (default: the profile's language, else wgsl).
        #[arg(long)]
        lang: Option<String>,
        /// Output file (default: stdout).
        #[arg(long)]
        out: Option<PathBuf>,
        /// List every WGSL item left out (by default one summary line counts them).
        #[arg(short, long)]
        verbose: bool,
    },
    /// Write (or check) the include files of every preset and profile in every language,
    /// each with an example shader (the committed copy: shaders/library/).
    Library {
        /// Folder to write into (one subfolder per preset or profile).
        #[arg(long, default_value = "shaders/library")]
        out: PathBuf,
        /// Compare with the folder instead of writing; exit 1 listing what differs.
        #[arg(long)]
        check: bool,
        /// Folder of lighting profiles (TOML).
        #[arg(long, default_value = "profiles")]
        profiles: PathBuf,
    },
    /// Write the committed tables as KTX 2.0 textures in the layouts the library's
    /// functions read (dfg, ad_specular_2d: 2D rg32float; lobe_ggx_*: 2D array rg32float
    /// and, `_filtered`, 3D rg16float), the layout in each file's `sbf.layout` key.
    Tables {
        /// Folder to write into.
        #[arg(long, default_value = "sbf-tables")]
        out: PathBuf,
    },
    /// GPU reconstruction throughput (evaluations per second) per basis, diffuse and
    /// diffuse + specular.
    #[cfg(feature = "gpu")]
    Bench {
        /// Evaluations per dispatch.
        #[arg(long, default_value_t = 1 << 22)]
        count: usize,
        /// Timed dispatches per kernel.
        #[arg(long, default_value_t = 20)]
        repeats: usize,
        /// `buffer` (normal, view, α read per evaluation), `generated` (made in the
        /// shader, unrelated between neighbouring invocations: arithmetic only, the worst
        /// case for table caches) or `screen` (made in the shader as a raster pass sees
        /// them: slowly varying normals and views, α per material patch).
        #[arg(long, default_value = "generated")]
        inputs: String,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // A profile it cannot use exits with 2, as in every tool.
    if let Cmd::Export { profile: Some(p), .. } = &cli.cmd {
        if let Err(e) = sbf::profile::Profile::load(p) {
            eprintln!("shaders: {e}");
            return ExitCode::from(2);
        }
    }
    let r = match cli.cmd {
        Cmd::List => (|| {
            println!("presets:");
            for (name, _) in compose::PRESETS {
                let c = compose::compose(&Config::parse(name)?)?;
                println!("  {:<16} {}", name, c.summary());
            }
            println!("features:");
            for (f, name) in compose::Feature::ALL {
                println!("  {:<18} {}", name, f.roots().join(", "));
            }
            Ok(())
        })(),
        Cmd::Tables { out } => (|| {
            std::fs::create_dir_all(&out).map_err(|e| format!("creating {}: {e}", out.display()))?;
            for t in shaders::tables::all() {
                let path = out.join(format!("{}.ktx2", t.name));
                let bytes = shaders::tables::ktx2(&t)?;
                std::fs::write(&path, &bytes).map_err(|e| format!("writing {}: {e}", path.display()))?;
                println!(
                    "{} ({:?} {:?} {}x{}x{}, {} bytes)",
                    path.display(),
                    t.kind,
                    t.format,
                    t.size[0],
                    t.size[1],
                    t.size[2],
                    bytes.len()
                );
            }
            Ok(())
        })(),
        Cmd::Library { out, check, profiles } => library_command(&out, check, &profiles),
        #[cfg(feature = "gpu")]
        Cmd::Bench { count, repeats, inputs } => (|| {
            let inputs = match inputs.as_str() {
                "buffer" => shaders::bench::Inputs::Buffer,
                "generated" => shaders::bench::Inputs::Generated,
                "screen" => shaders::bench::Inputs::Screen,
                other => return Err(format!("--inputs {other}: expected `buffer`, `generated` or `screen`")),
            };
            if count == 0 || repeats == 0 {
                return Err("--count and --repeats must be > 0".to_string());
            }
            let gpu = shaders::gpu::Gpu::new()?;
            eprintln!("benchmarking on {}", gpu.adapter);
            let rows = shaders::bench::run(&gpu, count, repeats, inputs)?;
            println!("{}", shaders::bench::table(&gpu, count, repeats, inputs, &rows));
            Ok(())
        })(),
        Cmd::Export { config, profile, lang, out, verbose } => export_command(config, profile, lang, out, verbose),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("shaders: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `shaders library`: every preset and profile in every language, written or checked.
fn library_command(out: &std::path::Path, check: bool, profiles: &std::path::Path) -> Result<(), String> {
    let targets = shaders::library::targets(profiles)?;
    if check {
        let problems = shaders::library::check(out, &targets)?;
        if !problems.is_empty() {
            return Err(format!(
                "{} is not what the sources export ({} problems; `shaders library` rewrites it):\n  {}",
                out.display(),
                problems.len(),
                problems.join("\n  ")
            ));
        }
        println!("{}: {} presets and profiles × 6 languages and dialects match the sources", out.display(), targets.len());
    } else {
        let n = shaders::library::write(out, &targets)?;
        println!("wrote {n} files for {} presets and profiles under {}", targets.len(), out.display());
    }
    Ok(())
}

/// `shaders export`: one preset or profile in one language.
fn export_command(
    config: Option<String>,
    profile: Option<PathBuf>,
    lang: Option<String>,
    out: Option<PathBuf>,
    verbose: bool,
) -> Result<(), String> {
    let prof = profile.as_deref().map(sbf::profile::Profile::load).transpose()?;
    let cfg = match (&config, &prof) {
        (Some(c), _) => Config::parse(c)?,
        (None, Some(p)) => shaders::profile::config(p)?,
        (None, None) => unreachable!("clap requires --config or --profile"),
    };
    let lang = Lang::parse(lang.as_deref().or(prof.as_ref().map(|p| p.language.as_str())).unwrap_or("wgsl"))?;
    let c = compose::compose(&cfg)?;
    let roots = shaders::library::roots(&cfg);
    let title = match &prof {
        Some(p) => format!("profile '{}'", p.name),
        None => format!("configuration '{}'", cfg.name),
    };
    // The committed library's guard for the same preset or profile file.
    let slug = match profile.as_deref() {
        Some(f) => format!("profile-{}", std::path::Path::new(f).file_stem().and_then(|s| s.to_str()).unwrap_or("profile")),
        None => cfg.name.clone(),
    };
    let guard = Some(shaders::library::guard(&slug, lang));
    let text = export::export_with(&c.source, lang, &shaders::emit::Options { title, roots, guard, ..Default::default() })?;
    if let Some(p) = &prof {
        let all = compose::compose(&Config::parse("all")?)?;
        let (_, notes) = shaders::profile::features(p);
        let families: std::collections::BTreeSet<&str> =
            c.left_out.iter().map(|(m, _, _)| m.as_str()).filter(|m| !c.included.iter().any(|(k, _)| k == m)).collect();
        eprintln!(
            "profile '{}': left out {} of {} WGSL items ({} of {} bytes{}){}",
            p.name,
            c.left_out.len(),
            all.included.len(),
            c.left_out_bytes(),
            all.source.len(),
            {
                // The features outside the profile: what the left-out items serve.
                let outside: Vec<&str> = compose::Feature::ALL.iter().filter(|(f, _)| !cfg.features.contains(f)).map(|(_, n)| *n).collect();
                let modules = if families.is_empty() {
                    String::new()
                } else {
                    format!("; whole modules: {}", families.into_iter().collect::<Vec<_>>().join(", "))
                };
                if outside.is_empty() {
                    modules
                } else {
                    format!("{modules}; features it does not use: {}", outside.join(", "))
                }
            },
            if notes.is_empty() { String::new() } else { format!("; not in WGSL: {}", notes.join("; ")) }
        );
    }
    eprintln!("{}{}", c.summary(), if c.left_out.is_empty() || verbose { "" } else { " (-v lists them)" });
    if verbose && !c.left_out.is_empty() {
        let names: Vec<String> = c.left_out.iter().map(|(m, n, _)| format!("{m}::{n}")).collect();
        eprintln!("left out: {}", names.join(", "));
    }
    match out {
        Some(p) => std::fs::write(&p, text).map_err(|e| format!("writing {}: {e}", p.display())),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}
