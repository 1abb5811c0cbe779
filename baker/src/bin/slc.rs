//! slc: render single-bounce indirect light from virtual point lights with stochastic
//! light culling ([TH17; TH17-supp; FTH22-supp]), on the GPU or the CPU, beside its brute-force reference.

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

use baker::slc::harness::{self, SlcOptions};
use baker::slc::media::Medium;
use baker::slc::Bound;
use baker::slc::Filter;
use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    version,
    about = "Render single-bounce indirect light from virtual point lights (VPLs) with stochastic light culling: each VPL gets a random range, tiles keep only the VPLs whose bounds reach them, pixels shade the kept ones unbiasedly.",
    after_help = "Writes slc.exr/png (culled, filtered), slc_vpls_per_pixel.exr, slc_fdr.exr and slc.json (VPL counts, false discovery rate, frame time) into --out.\n\nExamples:\n  slc\n  slc --vpls 4000 --brute\n  slc --scene room.glb --interleave 1 --medium 0.2,0.3,0.5,4\n  slc --scene slit --sky\n  slc --scene sunbeam --rsm 256\n  slc --delta 0.05 --medium 0.2,0.3,0.5,4 --point-lights 2560"
)]
struct Cli {
    #[arg(long, default_value = "cornell", help = baker::scene::load::SCENE_HELP)]
    scene: String,
    /// Lat-long .hdr/.exr environment map replacing the scene's environment.
    #[arg(long)]
    env: Option<PathBuf>,
    /// Light paths traced from the scene's emitters; each hit becomes a VPL.
    #[arg(long, default_value_t = 1000)]
    vpls: usize,
    /// Also start light paths at the environment (the scene's sky or --env): a direction
    /// by the environment's importance, entering over a disk that covers the scene.
    #[arg(long)]
    sky: bool,
    /// VPLs from a reflective shadow map of N × N texels per punctual light instead of light
    /// paths (Tokuyoshi & Harada's 256: one ray per texel from the light, its hit a VPL with the texel's
    /// flux; six N × N cube faces for a point light); needs a directional, spot or point
    /// light, and takes the place of --vpls and --sky.
    #[arg(long, value_name = "N")]
    rsm: Option<usize>,
    /// Continue the light paths (or the shadow maps' rays) this many diffuse bounces past
    /// the first hit, each hit a VPL too: multi-bounce indirect light (0: Tokuyoshi & Harada's
    /// single-bounce VPLs). Only the Lambert layer reflects on.
    #[arg(long, default_value_t = 0)]
    bounces: usize,
    /// Image size, WIDTHxHEIGHT pixels.
    #[arg(long, default_value = "960x540")]
    size: String,
    /// Variance control δ of the random light ranges: a VPL's range ends where its
    /// intensity falls to δ·ξ of its peak (smaller: longer ranges, less noise, more work).
    #[arg(long, default_value_t = 1e-3)]
    delta: f32,
    /// Also render the brute-force reference (every VPL at every pixel, no interleaving, no
    /// filter) and report the culled image's error against it, before and after the filter.
    #[arg(long)]
    brute: bool,
    /// Also cull with each glossy bound (tight, sphere, th16) and report their false
    /// discovery rates and frame times side by side.
    #[arg(long)]
    compare_bounds: bool,
    /// Also time tiled culling (Tokuyoshi & Harada's Modified HalfZ) against clustered shading (32
    /// depth slices per tile) on the diffuse VPLs and on them made glossy ([TH17 Table 2]),
    /// and report each one's culling + shading time, VPLs per pixel and false discovery rate.
    #[arg(long)]
    compare_culling: bool,
    /// With --medium: also scatter this many point lights uniformly through the scene's
    /// bounds, sharing 4πR² W (R the bounding radius) — the 2 560-point-light
    /// experiment of [FTH22-supp Fig. 1] (`--medium … --point-lights 2560`: its false discovery rate image).
    #[arg(long, default_value_t = 0)]
    point_lights: usize,
    /// The equal-time experiment ([TH17-supp Fig. 2]): render with each of these δ (comma
    /// separated, e.g. 1e-4,3e-4,1e-3,3e-3,1e-2; include --delta) by the spheroid, the
    /// enclosing sphere and the biased range cut, and report each one's error against brute
    /// force at the time the spheroid takes at --delta. Implies --brute.
    #[arg(long)]
    sweep: Option<String>,
    /// Also render single scattering in a homogeneous medium filling the view depths
    /// NEAR..FAR (scene units), lit by the scene's point lights and the diffuse VPLs,
    /// culled and brute force (on the GPU or the CPU, as --device), with its false discovery
    /// rate image: SIGMA_S,SIGMA_T,NEAR,FAR in 1/unit (e.g. 0.2,0.3,0.5,4).
    #[arg(long)]
    medium: Option<String>,
    /// Interleaved sampling: I × I pixel subregions each shade 1/I² of the VPLs, then a
    /// filter joins them (1: off). Unbiased in expectation over VPL sets.
    #[arg(long, default_value_t = 8)]
    interleave: usize,
    /// The filter joining the subregions: bilateral (Tokuyoshi & Harada's cross-bilateral filter:
    /// depth and normal weights, radius --filter-radius) or box (one interleaving period,
    /// box weights, hard surface tests).
    #[arg(long, default_value = "bilateral")]
    filter: String,
    /// Kernel radius of the bilateral filter in pixels (Tokuyoshi & Harada's: 8); at least half the
    /// interleaving period.
    #[arg(long, default_value_t = 8)]
    filter_radius: usize,
    /// Bound of glossy VPLs: tight (the GGX lobe's spheroid), sphere (its enclosing
    /// sphere) or th16 (a sphere of radius r/α at the VPL), the last two for comparison.
    #[arg(long, default_value = "tight")]
    bound: String,
    /// Which VPLs: both, diffuse (glossy ones dropped) or glossy (every VPL made a GGX VPL
    /// of --glossy-alpha and F0 0.9).
    #[arg(long, default_value = "both")]
    kind: String,
    /// GGX α of the VPLs with --kind glossy, in (0, 1].
    #[arg(long, default_value_t = 0.2)]
    glossy_alpha: f32,
    /// Seed of the VPL light paths and the random ranges.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// auto (a hardware GPU if one exists, else the CPU), gpu (any adapter, software ones
    /// such as lavapipe included), or cpu.
    #[arg(long, default_value = "auto")]
    device: String,
    /// Output folder.
    #[arg(long, default_value = "slc-out")]
    out: PathBuf,
}

fn parse_medium(m: &str) -> Result<Medium, String> {
    let v: Vec<f32> = m.split(',').map(|x| x.trim().parse::<f32>().map_err(|e| format!("--medium {m}: {e}"))).collect::<Result<_, _>>()?;
    let [sigma_s, sigma_t, near, far] = v[..] else {
        return Err(format!("--medium takes SIGMA_S,SIGMA_T,NEAR,FAR, not {m}"));
    };
    let medium = Medium { sigma_s, sigma_t, near, far };
    medium.validate().map_err(|e| format!("--medium: {e}"))?;
    Ok(medium)
}

fn options(c: Cli) -> Result<SlcOptions, String> {
    let (w, h) = c.size.split_once('x').ok_or_else(|| format!("--size takes WIDTHxHEIGHT, not {}", c.size))?;
    let parse = |v: &str| v.parse::<usize>().map_err(|e| format!("--size {}: {e}", c.size));
    let (width, height) = (parse(w)?, parse(h)?);
    if width == 0 || height == 0 {
        return Err(format!("--size {}: both sides must be at least 1 pixel", c.size));
    }
    if c.vpls == 0 {
        return Err("--vpls must be at least 1".into());
    }
    if c.point_lights > 0 && c.medium.is_none() {
        return Err("--point-lights scatter lights in the medium: give --medium too".into());
    }
    if c.bounces > 16 {
        return Err(format!("--bounces {}: at most 16", c.bounces));
    }
    match c.rsm {
        Some(0) => return Err("--rsm must be at least 1 texel".into()),
        Some(n) if n > 4096 => return Err(format!("--rsm {n}: at most 4096 texels a side (16.8 M VPLs per map)")),
        Some(_) if c.sky => return Err("--sky starts light paths at the environment, which has no shadow map: use it without --rsm".into()),
        _ => {}
    }
    if !(c.delta > 0.0 && c.delta.is_finite()) {
        return Err(format!("--delta must be finite and > 0, not {}", c.delta));
    }
    if !(1..=16).contains(&c.interleave) {
        return Err(format!("--interleave must be 1 to 16, not {}", c.interleave));
    }
    if !(c.glossy_alpha > 0.0 && c.glossy_alpha <= 1.0) {
        return Err(format!("--glossy-alpha must be in (0, 1], not {}", c.glossy_alpha));
    }
    if !["both", "diffuse", "glossy"].contains(&c.kind.as_str()) {
        return Err(format!("--kind takes both, diffuse or glossy, not {}", c.kind));
    }
    let sweep = c
        .sweep
        .as_deref()
        .map(|v| {
            let d: Vec<f32> =
                v.split(',').map(|x| x.trim().parse::<f32>().map_err(|e| format!("--sweep {v}: {e}"))).collect::<Result<_, _>>()?;
            if let Some(x) = d.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
                return Err(format!("--sweep: every δ must be finite and > 0, not {x}"));
            }
            if !d.contains(&c.delta) {
                return Err(format!("--sweep {v}: include --delta ({}), the time the methods are compared at", c.delta));
            }
            Ok(d)
        })
        .transpose()?;
    let filter = match c.filter.as_str() {
        "box" => Filter::Box,
        "bilateral" => Filter::Bilateral { radius: c.filter_radius },
        f => return Err(format!("--filter takes bilateral or box, not {f}")),
    };
    if !(1..=64).contains(&c.filter_radius) {
        return Err(format!("--filter-radius must be 1 to 64 pixels, not {}", c.filter_radius));
    }
    filter.check(c.interleave).map_err(|e| format!("--filter-radius: {e}"))?;
    if !["auto", "gpu", "cpu"].contains(&c.device.as_str()) {
        return Err(format!("unknown --device '{}' (auto, gpu or cpu)", c.device));
    }
    Ok(SlcOptions {
        scene: c.scene,
        environment: c.env,
        seed: c.seed,
        out: c.out,
        vpls: c.vpls,
        width,
        height,
        delta: c.delta,
        brute: c.brute || sweep.is_some(),
        frames: 10,
        interleave: c.interleave,
        filter,
        bound: Bound::parse(&c.bound).map_err(|e| format!("--bound: {e}"))?,
        kind: c.kind,
        glossy_alpha: c.glossy_alpha,
        compare_bounds: c.compare_bounds,
        compare_culling: c.compare_culling,
        point_lights: c.point_lights,
        bounces: c.bounces,
        medium: c.medium.as_deref().map(parse_medium).transpose()?,
        sky: c.sky,
        rsm: c.rsm,
        sweep: sweep.unwrap_or_default(),
    })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let device = cli.device.clone();
    let o = match options(cli) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("slc: {e}");
            return ExitCode::from(2);
        }
    };
    let gpu = match device.as_str() {
        "cpu" => None,
        "gpu" => match shaders::gpu::Gpu::new() {
            Ok(g) => Some(g),
            Err(e) => {
                eprintln!("slc: --device gpu: {e}");
                return ExitCode::FAILURE;
            }
        },
        // auto: a hardware adapter (a software rasteriser is slower than the CPU path).
        _ => shaders::gpu::Gpu::new().ok().filter(|g| !g.software),
    };
    match harness::render(&o, gpu.as_ref(), &mut |m| eprintln!("{m}")) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("slc: {e}");
            ExitCode::FAILURE
        }
    }
}
