//! render: shade a baked scene in real time with the exported runtime — every lightmap
//! basis side by side — against a path-traced reference of the same quantity (\[Roughton19\]
//! §8.4.3, Figs. 8.6–8.8, Table 8.1).

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

use baker::accumulate::{BakeConfig, BasisId};
use baker::layout::lightmap::Lightmap;
use baker::render::lighting::{Encoding, Lighting, LightmapFilter, Storage};
use baker::render::session::{self, Setup};
use baker::render::web::{self, Viewer};
use baker::run::{self, Device, Options};
use baker::scene::bvh::Bvh;
use baker::scene::camera::{SceneCamera, ViewCamera};
use clap::Parser;
use sbf::profile::SpecularPath;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    version,
    about = "Shade a baked scene in real time from its lightmaps — in every basis, with the runtime functions the shaders crate exports — next to a path-traced reference of the same light, with the error and GPU frame time of each.",
    after_help = "Bakes the scene into OUT/bake (or reads an existing bake with --bake), then writes reference.exr/png, one image and one +3 EV difference image per configuration, results.json and report.html into OUT.\n\nThe rendered quantity is the light the visible surface reflects (Lambert + single-scattering GGX) of the incident light the lightmap encodes (the baked lights' direct light and the indirect light); the reference estimates the same with the bake's own path tracer, so the difference is the lightmap's error: texel size, basis, runtime.\n\nExamples:\n  render\n  render --bases sh2,ad9,sg12 --specular both --storage both\n  render --scene room.glb --camera 0,1.5,3:0,1,0:60 --reference-samples 1024\n  render --bake bake-out --scene cornell"
)]
struct Cli {
    #[arg(long, default_value = "cornell", help = baker::scene::load::SCENE_HELP)]
    scene: String,
    /// Lat-long .hdr/.exr environment map replacing the scene's environment.
    #[arg(long)]
    env: Option<PathBuf>,
    /// Use this bake folder (made by `baker` from the same --scene and --env) instead of baking.
    #[arg(long)]
    bake: Option<PathBuf>,
    /// Bake passes (without --bake).
    #[arg(long, default_value_t = 256)]
    passes: u64,
    /// Lightmap texels per scene unit (without --bake).
    #[arg(long, default_value_t = 16.0)]
    texels_per_unit: f32,
    /// Lightmap bases to render (without --bake: also the bases baked). `none` (the plain
    /// E/π lightmap, diffuse only) is always rendered.
    #[arg(long, value_delimiter = ',', default_value = "sh1,sh2,sg9,sg12,ad9,ad12")]
    bases: Vec<String>,
    /// Probe grid NX,NY,NZ over the scene's bounds (without --bake), baked in SH L2 when
    /// the scene has dynamic objects (meshes without a lightmap that do not emit): they
    /// are shaded from the probes, trilinearly.
    #[arg(long, value_delimiter = ',', default_value = "8,4,4")]
    probes: Vec<usize>,
    /// Probes' deringing: `none` keeps the bake's coefficients; `sinc4` windows a probe's
    /// SH L2 radiance where its irradiance rings negative (Sloan 2017; per probe and
    /// channel, only where needed).
    #[arg(long, default_value = "none")]
    probe_window: String,
    /// Specular runtime path of SG and AD: fit, tables or both.
    #[arg(long, default_value = "fit")]
    specular: String,
    /// Sharpness λ of the SG lobes baked (without --bake; an existing bake's is read from
    /// its bake.json), in [2, 64]. The thesis' Fig. 8.6 compares NNLS SG 12 at λ 8.
    #[arg(long, default_value_t = baker::accumulate::SG_HEMISPHERE_SHARPNESS)]
    sg_sharpness: f64,
    /// Bake (without --bake) and compare indirect light only: the light reaching a surface
    /// straight from an emitter, a delta light or the sky is in neither the lightmap nor
    /// the reference ([Roughton19 Fig. 8.6]: indirect light from baked lightmaps). With
    /// --bake, the bake's own setting (bake.json) is used.
    #[arg(long)]
    indirect_only: bool,
    /// How the lightmap is interpolated: `exact` (bilinear by four loads weighted in f32,
    /// what the CPU twin computes), `hardware` (the sampler's bilinear filter, one fetch per
    /// lobe, as engines sample lightmaps; its weights have the GPU's sub-texel precision;
    /// GPU only) or `bicubic` (the cubic B-spline over 4×4 texels: four bilinear taps on the
    /// GPU, the 16 texels exactly on the CPU).
    #[arg(long, default_value = "exact")]
    lightmap_filter: String,
    /// Shade with the materials' glTF normal maps (MikkTSpace tangents): every basis is
    /// evaluated at the perturbed normal, and the reference path-traces with it. The images
    /// are then shaded by the CPU twin (the raster pass does not read normal maps).
    #[arg(long)]
    normal_maps: bool,
    /// Lightmap texel storage on the GPU: f32, f16 or both.
    #[arg(long, default_value = "f32")]
    storage: String,
    /// View: `EYE:TARGET[:FOV]` in scene units and degrees (vertical, +Y up), e.g.
    /// 0,0,3.4:0,0,0:55; or `gltf` (the scene file's first perspective camera), `gltf:N`
    /// (its N-th, from 0) or `gltf:NAME`. Default: the scene file's first camera if it has
    /// one, else the preview's camera at the front of the scene's bounds.
    #[arg(long)]
    camera: Option<String>,
    /// Image size of the comparison, WIDTHxHEIGHT.
    #[arg(long, default_value = "480x270")]
    size: String,
    /// The most reference samples per pixel (the default keeps a 2-core run of the built-in
    /// scene near a minute; the reference's noise is subtracted from every error either way).
    #[arg(long, default_value_t = 256)]
    reference_samples: u32,
    /// Progressive reference: batches of samples (16, then doubling) until its relative
    /// noise — √(mean variance of the pixel means) over the image's RMS — is at most this,
    /// or --reference-samples are taken; 0 takes all --reference-samples.
    #[arg(long, default_value_t = 0.01)]
    reference_noise: f64,
    /// GPU frames timed per configuration (timestamp queries; after 20 warm-up frames); 0: no timing.
    #[arg(long, default_value_t = 100)]
    frames: usize,
    /// Frame size of the timing, WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080")]
    frame_size: String,
    /// Where to shade (and bake): auto (a hardware GPU if there is one, else the CPU), gpu, cpu.
    #[arg(long, default_value = "auto")]
    device: String,
    /// Where to path-trace the reference: auto (the GPU when the images are shaded on one),
    /// gpu, cpu. Both run the bake's estimator on the same visible surfaces.
    #[arg(long, default_value = "auto")]
    reference_device: String,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[arg(long, default_value = "render-out")]
    out: PathBuf,
    /// Also write a bake viewer for the browser into this folder: index.html, its script,
    /// the scene, the lightmaps (RGB f16), the probes and the reference — offline; serve
    /// the folder (e.g. `python3 -m http.server`) and open it. WebGL 2 shades with the
    /// library's GLSL ES export, WebGPU with its WGSL export.
    #[arg(long)]
    web: Option<PathBuf>,
    /// The largest lightmap texture side the viewer may upload (WebGL 2 guarantees 2048;
    /// desktop browsers give 8192–16384): a larger atlas is downsampled by 2 until it fits,
    /// its E/π error stated in the viewer.
    #[arg(long, default_value_t = baker::render::web::MAX_TEXTURE)]
    web_max_texture: usize,
}

fn size(s: &str, what: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once('x').ok_or_else(|| format!("{what} '{s}': expected WIDTHxHEIGHT, e.g. 640x360"))?;
    let p = |v: &str| v.trim().parse::<u32>().ok().filter(|v| (1..=8192).contains(v));
    match (p(w), p(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!("{what} '{s}': width and height must be 1 to 8192")),
    }
}

fn configurations(bases: &[BasisId], specular: &str, storage: &str, sg_sharpness: f64) -> Result<Vec<Lighting>, String> {
    let paths = match specular {
        "fit" => vec![SpecularPath::Fit],
        "tables" => vec![SpecularPath::Tables],
        "both" => vec![SpecularPath::Fit, SpecularPath::Tables],
        s => return Err(format!("--specular '{s}': expected fit, tables or both")),
    };
    let storages = match storage {
        "f32" => vec![Storage::F32],
        "f16" => vec![Storage::F16],
        "both" => vec![Storage::F32, Storage::F16],
        s => return Err(format!("--storage '{s}': expected f32, f16 or both")),
    };
    let mut v = Vec::new();
    for st in &storages {
        v.push(Lighting { encoding: Encoding::Irradiance, specular: SpecularPath::Fit, storage: *st, sg_sharpness });
        for b in bases {
            // SH has one specular runtime: rendered once.
            let sh = b.is_sh();
            for p in paths.iter().take(if sh { 1 } else { paths.len() }) {
                v.push(Lighting { encoding: Encoding::Basis(*b), specular: *p, storage: *st, sg_sharpness });
            }
        }
    }
    v.iter().try_for_each(Lighting::check)?;
    Ok(v)
}

/// What the renderer needs of a bake.
struct Baked {
    dir: PathBuf,
    texels_per_unit: f32,
    padding: usize,
    bounces: u32,
    sg_sharpness: f64,
    indirect_only: bool,
}

/// The bake: an existing one's folder and settings (bake.json), or a fresh bake into
/// OUT/bake.
fn bake(c: &Cli, bases: &[BasisId], device: Device, probes: Option<[usize; 3]>) -> Result<Baked, String> {
    if let Some(dir) = &c.bake {
        let path = dir.join("bake.json");
        let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e} (is --bake a bake folder?)", path.display()))?;
        let j: serde_json::Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let tpu = j["layout"]["texels_per_unit"].as_f64().ok_or("bake.json: no layout.texels_per_unit")? as f32;
        let padding = j["layout"]["padding"].as_u64().ok_or("bake.json: no layout.padding")? as usize;
        let bounces = j["max_bounces"].as_u64().ok_or("bake.json: no max_bounces")? as u32;
        // The raster pass and the references shade the materials' factors (load_scene): a
        // bake that sampled texture maps holds the light of another scene.
        if let Some(m) = j.get("material_maps").filter(|m| !m.is_null()) {
            return Err(format!(
                "{}: the bake sampled the materials' texture maps ({} materials with maps); the renderer and its reference shade the factors alone, so the images would compare two scenes — bake with `baker --material-maps factors`",
                path.display(),
                m["materials"].as_u64().unwrap_or(0)
            ));
        }
        if j["scene"].as_str() != Some(scene_name(&c.scene).as_str()) {
            eprintln!("notice: bake.json names scene '{}', --scene is '{}'", j["scene"].as_str().unwrap_or("?"), c.scene);
        }
        // The SG bases' sharpness (bakes before bake.json recorded it used the default).
        let sg_sharpness = j["bases"]
            .as_array()
            .and_then(|b| b.iter().find_map(|b| b["sg_sharpness"].as_f64()))
            .unwrap_or(baker::accumulate::SG_HEMISPHERE_SHARPNESS);
        let indirect_only = j["indirect_only"].as_bool().unwrap_or(false);
        return Ok(Baked { dir: dir.clone(), texels_per_unit: tpu, padding, bounces, sg_sharpness, indirect_only });
    }
    let o = Options {
        spec: run::BakeSpec {
            scene: c.scene.clone(),
            environment: c.env.clone(),
            material_maps: false,
            texels_per_unit: c.texels_per_unit,
            passes: c.passes,
            config: BakeConfig {
                bases: bases.to_vec(),
                sg_sharpness: c.sg_sharpness,
                indirect_only: c.indirect_only,
                ..BakeConfig::default()
            },
            probes,
            probe_bases: vec![BasisId::Sh2],
            ..run::BakeSpec::default()
        },
        run: run::RunOptions { device, out: c.out.join("bake"), checkpoint_every: 0, ..run::RunOptions::default() },
    };
    run::bake(&o, &mut |m| eprintln!("{m}"))?;
    Ok(Baked {
        dir: o.run.out.clone(),
        texels_per_unit: o.spec.texels_per_unit,
        padding: o.spec.padding,
        bounces: o.spec.config.max_bounces,
        sg_sharpness: o.spec.config.sg_sharpness,
        indirect_only: o.spec.config.indirect_only,
    })
}

/// The scene of `--scene` (and `--env`) with its cameras, its materials' factors alone:
/// the raster pass shades factors (texture maps are not built into it yet), so the bake
/// and the reference take the factors too and the comparison stays the same quantity.
/// With `--normal-maps`, the materials' normal maps (with their meshes' tangents), else None.
type Loaded = (baker::scene::Scene, Vec<SceneCamera>, Option<baker::render::normal_map::NormalMaps>);
fn load_scene(c: &Cli) -> Result<Loaded, String> {
    let (scene, cameras) = baker::scene::load::load_with_cameras(&c.scene, c.env.as_deref(), &mut |m| eprintln!("{m}"))?;
    let has_normal_maps = scene.materials.iter().any(|m| m.maps.normal.is_some());
    let normal_maps = match (c.normal_maps, has_normal_maps) {
        (true, true) => {
            let maps = baker::render::normal_map::NormalMaps::build(&scene, &mut |m| eprintln!("render: {m}"));
            if !maps.as_ref().is_some_and(|m| (0..scene.meshes.len()).any(|k| m.applies_to(k))) {
                return Err("--normal-maps: no mesh of the scene is shaded with a normal map (the materials that have one are unused, or their meshes lack the texture coordinates)".into());
            }
            maps
        }
        (true, false) => return Err("--normal-maps: the scene's materials have no normal map".into()),
        (false, true) => {
            eprintln!("notice: the scene's materials have normal maps; --normal-maps shades with them");
            None
        }
        (false, false) => None,
    };
    if !scene.has_textures() && !has_normal_maps {
        return Ok((scene, cameras, normal_maps));
    }
    if scene.has_textures() {
        eprintln!(
            "render: the materials' texture maps are not shaded by the renderer yet: the bake, the reference and the raster pass use their factors"
        );
    }
    Ok((scene.without_maps(), cameras, normal_maps))
}

/// The scene's name as bake.json records it (a file's stem for glTF).
fn scene_name(s: &str) -> String {
    match Path::new(s).extension() {
        Some(_) => Path::new(s).file_stem().map(|x| x.to_string_lossy().to_string()).unwrap_or_default(),
        None => s.to_string(),
    }
}

/// The view `--camera` names (see its help), at `w` × `h`.
fn view(arg: Option<&str>, cameras: &[SceneCamera], bvh: &Bvh, w: u32, h: u32) -> Result<ViewCamera, String> {
    let names = || cameras.iter().enumerate().map(|(k, c)| format!("{k}: '{}'", c.name)).collect::<Vec<_>>().join(", ");
    let chosen = match arg {
        None if cameras.is_empty() => return Ok(ViewCamera::preview(bvh, w, h)),
        None | Some("gltf") => cameras.first().ok_or("--camera gltf: the scene defines no perspective camera")?,
        Some(s) if s.starts_with("gltf:") => {
            let key = &s[5..];
            let found = match key.parse::<usize>() {
                Ok(k) => cameras.get(k),
                Err(_) => cameras.iter().find(|c| c.name == key),
            };
            found.ok_or_else(|| {
                format!(
                    "--camera {s}: no such camera in the scene (it has {})",
                    if cameras.is_empty() { "none".to_string() } else { names() }
                )
            })?
        }
        Some(s) => return ViewCamera::parse(s, w, h),
    };
    if let Some(a) = chosen.aspect.filter(|a| (a / (w as f32 / h as f32) - 1.0).abs() > 1e-3) {
        eprintln!("notice: camera '{}' states aspect ratio {a:.4}; the image is {w}×{h} (its vertical field of view is kept)", chosen.name);
    }
    eprintln!("render: camera '{}' of the scene file", chosen.name);
    Ok(ViewCamera::from_scene(chosen, w, h))
}

/// `--lightmap-filter`, checked against where the images are shaded.
fn lightmap_filter(c: &Cli, device: Device) -> Result<LightmapFilter, String> {
    let f = LightmapFilter::parse(&c.lightmap_filter)
        .ok_or_else(|| format!("--lightmap-filter '{}': expected exact, hardware or bicubic", c.lightmap_filter))?;
    if f == LightmapFilter::Hardware && c.normal_maps {
        return Err(
            "--lightmap-filter hardware is the raster pass's sampler, and --normal-maps shades on the CPU twin: use exact or bicubic"
                .into(),
        );
    }
    if f == LightmapFilter::Hardware && device == Device::Cpu {
        return Err("--lightmap-filter hardware is the GPU's sampler: it needs --device gpu or auto".into());
    }
    Ok(f)
}

/// The options that only a fresh bake takes, and --sg-sharpness' range.
fn check_bake_flags(c: &Cli) -> Result<(), String> {
    let (lo, hi) = baker::accumulate::SG_SHARPNESS_RANGE;
    if !(lo..=hi).contains(&c.sg_sharpness) {
        return Err(format!(
            "--sg-sharpness {}: must be in [{lo}, {hi}] (the range the SG runtime's fits are stated over)",
            c.sg_sharpness
        ));
    }
    if c.bake.is_some() && c.sg_sharpness != baker::accumulate::SG_HEMISPHERE_SHARPNESS {
        return Err("--sg-sharpness applies to a fresh bake; with --bake the bake's own (bake.json) is used".into());
    }
    if c.bake.is_some() && c.indirect_only {
        return Err("--indirect-only applies to a fresh bake; with --bake the bake's own setting (bake.json) is used".into());
    }
    Ok(())
}

fn render(c: Cli) -> Result<(), String> {
    let bases = c.bases.iter().map(|s| baker::accumulate::lightmap_basis(s.trim())).collect::<Result<Vec<_>, _>>()?;
    check_bake_flags(&c)?;
    // Checked here with the λ to be baked (an existing bake's is checked once read).
    configurations(&bases, &c.specular, &c.storage, c.sg_sharpness)?;
    let (w, h) = size(&c.size, "--size")?;
    let (fw, fh) = size(&c.frame_size, "--frame-size")?;
    let device = match c.device.as_str() {
        "auto" => Device::Auto,
        "gpu" => Device::Gpu,
        "cpu" => Device::Cpu,
        s => return Err(format!("--device '{s}': expected auto, gpu or cpu")),
    };
    let dering = match c.probe_window.as_str() {
        "sinc4" => true,
        "none" => false,
        s => return Err(format!("--probe-window '{s}': expected sinc4 or none")),
    };
    let lightmap_filter = lightmap_filter(&c, device)?;
    if c.reference_samples == 0 {
        return Err("--reference-samples must be at least 1".into());
    }
    if !(c.reference_noise.is_finite() && (0.0..1.0).contains(&c.reference_noise)) {
        return Err(format!("--reference-noise must be in [0, 1), not {}", c.reference_noise));
    }
    run::limits::check_writable(&c.out)?;
    let (scene, scene_cameras, normal_maps) = load_scene(&c)?;
    let dynamic = scene.meshes.iter().filter(|m| !m.lightmapped && scene.materials[m.material].emissive.max_element() <= 0.0).count();
    let grid = match c.probes.as_slice() {
        [x, y, z] if *x > 0 && *y > 0 && *z > 0 => [*x, *y, *z],
        p => return Err(format!("--probes takes NX,NY,NZ (all > 0), not {p:?}")),
    };
    // The view before any work: a bad --camera is refused at once.
    let bvh = Bvh::build(&scene);
    let camera = view(c.camera.as_deref(), &scene_cameras, &bvh, w, h)?;
    let baked = bake(&c, &bases, device, (dynamic > 0).then_some(grid))?;
    let configurations = configurations(&bases, &c.specular, &c.storage, baked.sg_sharpness)?;
    let Baked { dir: bake_dir, texels_per_unit: tpu, padding, bounces, sg_sharpness, indirect_only } = baked;
    if indirect_only {
        eprintln!("render: indirect light only (the bake's and the reference's)");
    }
    if bases.iter().any(|b| b.is_sg()) {
        eprintln!("render: SG lobes of sharpness λ {sg_sharpness}");
    }
    let probe_field = if dynamic > 0 {
        eprintln!("render: {dynamic} dynamic object(s) (no lightmap) shaded from the SH L2 probes");
        let field = baker::render::probes::ProbeField::read(&bake_dir)?;
        if dering {
            let (f, n) = field.deringed()?;
            eprintln!(
                "render: probes deringed (sinc⁴ window) in {n} of {} probe channels whose irradiance rings",
                3 * f.coefficients.len()
            );
            Some(f)
        } else {
            Some(field)
        }
    } else {
        None
    };
    let lm = Lightmap::build(&scene, tpu, padding).map_err(|e| e.to_string())?;
    let gpu = match device {
        Device::Cpu => None,
        _ => match shaders::gpu::Gpu::new() {
            Ok(g) if device == Device::Gpu || !g.software => Some(g),
            Ok(g) => {
                eprintln!("notice: {} is a software rasteriser: shading on the CPU twin (--device gpu to use it)", g.adapter);
                None
            }
            Err(e) if device == Device::Gpu => return Err(e),
            Err(_) => None,
        },
    };
    if lightmap_filter == LightmapFilter::Hardware && gpu.is_none() {
        return Err(
            "--lightmap-filter hardware needs the images shaded on a GPU (no hardware GPU here: --device gpu uses a software one)".into()
        );
    }
    let reference_on_gpu = match c.reference_device.as_str() {
        "auto" => gpu.is_some(),
        "gpu" if gpu.is_some() => true,
        "gpu" => return Err("--reference-device gpu needs the images shaded on a GPU (--device gpu)".into()),
        "cpu" => false,
        s => return Err(format!("--reference-device '{s}': expected auto, gpu or cpu")),
    };
    let device_name = gpu.as_ref().map_or("CPU (the shading's f64 twin)".to_string(), |g| format!("GPU: {}", g.adapter));
    let setup = Setup {
        camera,
        configurations,
        reference_samples: c.reference_samples,
        reference_noise: c.reference_noise,
        seed: c.seed,
        max_bounces: bounces,
        reference_on_gpu,
        lightmap_filter,
        indirect_only,
        timing: (c.frames > 0 && gpu.as_ref().is_some_and(|g| g.timestamps)).then_some((fw, fh, 20, c.frames)),
        normal_maps: normal_maps.map(std::sync::Arc::new),
    };
    let outcome = session::run(&scene, &bvh, &lm, &bake_dir, probe_field.as_ref(), &setup, gpu.as_ref(), &mut |m| eprintln!("{m}"))?;
    std::fs::create_dir_all(&c.out).map_err(|e| format!("{}: {e}", c.out.display()))?;
    let results = baker::render::report::write(&c.out, &scene.name, &bake_dir, &camera, &device_name, &outcome, c.web.as_deref())?;
    eprintln!("wrote {} (results.json, report.html, images)", c.out.display());
    if let Some(dir) = &c.web {
        let viewer = Viewer {
            scene: &scene,
            lm: &lm,
            bake_dir: &bake_dir,
            probes: probe_field.as_ref(),
            camera,
            outcome: &outcome,
            sg_sharpness,
            results: &results,
            max_texture: c.web_max_texture,
        };
        write_web(dir, &viewer, &setup.configurations)?;
    }
    Ok(())
}

/// `--web DIR`: the bake viewer of what was rendered.
fn write_web(dir: &Path, viewer: &Viewer, rendered: &[Lighting]) -> Result<(), String> {
    baker::render::web::write(dir, viewer, &web::configurations(rendered, viewer.sg_sharpness), &mut |m| eprintln!("{m}")).map(|_| ())
}

fn main() -> ExitCode {
    match render(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("render: {e}");
            ExitCode::from(2)
        }
    }
}
