//! fitgen: derive the fits and LUTs into `luts/`, or check the committed ones.

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;

/// Derives the polynomial fits and look-up tables that sbf and the shaders read.
#[derive(Parser, Debug)]
#[command(
    version,
    after_help = "Examples:\n  fitgen list\n  fitgen all\n  fitgen all --only dfg,ad-specular-2d\n  fitgen --check --profile profiles/mobile-sh-l1.toml\n  fitgen dfg --out /tmp/luts\n  fitgen --check\n  fitgen --plots target/plots"
)]
struct Cli {
    /// `list` (with --profile: what the profile reads), `all`, or one output name (see
    /// `fitgen list`). Default with --check: all.
    what: Option<String>,
    /// Regenerate in memory and compare with the committed files; non-zero exit and
    /// a summary naming each differing file.
    #[arg(long)]
    check: bool,
    /// Comma-separated subset of outputs (with `all` or --check).
    #[arg(long, value_delimiter = ',', conflicts_with = "profile")]
    only: Vec<String>,
    /// A lighting profile (TOML, see profiles/): generate or check only the tables and
    /// fits its runtime paths read, and say what it leaves out.
    #[arg(long)]
    profile: Option<PathBuf>,
    /// Folder of the tables (default: the workspace's luts/).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write PNG plots of the fits and LUT error heat maps into DIR.
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let dir = cli.out.clone().unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../luts"));
    let what = cli.what.clone().unwrap_or_else(|| if cli.check { "all".into() } else { String::new() });
    if let Some(dir) = &cli.plots {
        match fitgen::plots::write_all(dir, &fitgen::outputs::fits::derive()) {
            Ok(files) => files.iter().for_each(|f| println!("plot: {f}")),
            Err(e) => {
                eprintln!("fitgen --plots: {e}");
                return ExitCode::FAILURE;
            }
        }
        if cli.what.is_none() && !cli.check {
            return ExitCode::SUCCESS;
        }
    }
    let profile = match cli.profile.as_deref().map(sbf::profile::Profile::load).transpose() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("fitgen: {e}");
            return ExitCode::from(2);
        }
    };
    if what == "list" {
        // With a profile: only the tables and fits its runtime paths read.
        let needed = profile.as_ref().map(|p| p.tables());
        for (name, desc) in fitgen::OUTPUT_NAMES {
            if needed.as_ref().is_none_or(|n| n.contains(&name)) {
                println!("{name:<18} {desc}");
            }
        }
        return ExitCode::SUCCESS;
    }
    let only = match what.as_str() {
        "all" if profile.is_some() => {
            let p = profile.as_ref().expect("checked");
            let needed = p.tables();
            let left: Vec<(&str, &str, usize)> =
                fitgen::outputs::table_sizes().into_iter().filter(|(n, _, _)| !needed.contains(n)).collect();
            let bytes: usize = left.iter().map(|t| t.2).sum();
            println!(
                "profile '{}': left out {} ({bytes} bytes of embedded LUTs); sbf features for it: default-features = false, features = [{}]",
                p.name,
                if left.is_empty() { "no table".to_string() } else { left.iter().map(|(n, f, b)| format!("{n} ({f}, {b} bytes)")).collect::<Vec<_>>().join(", ") },
                p.cargo_features().iter().map(|f| format!("\"{f}\"")).collect::<Vec<_>>().join(", ")
            );
            needed.iter().map(|s| s.to_string()).collect()
        }
        "all" => cli.only.clone(),
        "" => {
            eprintln!("nothing to do: give `list`, `all`, an output name, or --check (see --help)");
            return ExitCode::from(2);
        }
        name => vec![name.to_string()],
    };
    let multi = indicatif::MultiProgress::new();
    let t = std::time::Instant::now();
    let outputs = match fitgen::generate(&only, &multi) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("fitgen: {e}");
            return ExitCode::from(2);
        }
    };
    if cli.check {
        let problems = fitgen::check::check(&outputs, &dir, only.is_empty() || profile.is_some());
        if problems.is_empty() {
            println!(
                "fitgen --check: {} outputs match the committed files in {} ({:.1} s)",
                outputs.len(),
                dir.display(),
                t.elapsed().as_secs_f64()
            );
            return ExitCode::SUCCESS;
        }
        eprintln!("fitgen --check: {} problem(s); regenerate with `cargo run --release --bin fitgen -- all`:", problems.len());
        for p in problems {
            eprintln!("  {p}");
        }
        return ExitCode::FAILURE;
    }
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("fitgen: creating {}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    for o in &outputs {
        let path = dir.join(&o.file);
        if let Err(e) = std::fs::write(&path, &o.bytes) {
            eprintln!("fitgen: writing {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        println!("{:<28} rms {:.3e}  max {:.3e}  ({:.2} s)  vs {}", o.file, o.error.0, o.error.1, o.wall_time_s, o.error.2);
    }
    let mpath = dir.join("MANIFEST");
    let existing = std::fs::read_to_string(&mpath).unwrap_or_default();
    let mut lines: Vec<String> = outputs.iter().map(fitgen::manifest::line).collect();
    if only.is_empty() {
        lines.push(fitgen::manifest::total_line(t.elapsed().as_secs_f64()));
    }
    // `all` rewrites the manifest (entries of outputs it no longer makes disappear); a
    // single output merges its line into the existing manifest.
    let text = if only.is_empty() { lines.iter().map(|l| format!("{l}\n")).collect() } else { fitgen::manifest::merge(&existing, &lines) };
    if let Err(e) = std::fs::write(&mpath, text) {
        eprintln!("fitgen: writing {}: {e}", mpath.display());
        return ExitCode::FAILURE;
    }
    println!("wrote {} outputs and MANIFEST to {} in {:.1} s", outputs.len(), dir.display(), t.elapsed().as_secs_f64());
    ExitCode::SUCCESS
}
