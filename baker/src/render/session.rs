//! One comparison as the `render` command runs it: a baked scene, a camera, the
//! configurations to shade; the visible surfaces and the path-traced reference once, then
//! per configuration the image (GPU raster pass where an adapter is given, else the CPU
//! twin), its errors against the reference, and its GPU frame times (forward and deferred).

use super::atlas::Atlas;
use super::compare::{errors, Errors};
use super::lighting::{FramePath, Lighting, LightmapFilter};
use super::probes::ProbeField;
use super::raster::Renderer;
use super::reference::{self, Reference};
use super::reference_gpu::GpuReference;
use super::shade::{Shader, Terms};
use super::visible::{self, Visible};
use crate::estimator::trace::Tracer;
use crate::layout::lightmap::Lightmap;
use crate::scene::bvh::Bvh;
use crate::scene::camera::ViewCamera;
use crate::scene::Scene;
use sbf::glam::DVec3;
use std::path::Path;

/// What a comparison is given.
#[derive(Debug, Clone)]
pub struct Setup {
    pub camera: ViewCamera,
    pub configurations: Vec<Lighting>,
    /// Reference samples per pixel: the most taken.
    pub reference_samples: u32,
    /// Stop the reference once its relative noise (√mean σ² over the image's RMS) is at
    /// most this (0: take all `reference_samples`).
    pub reference_noise: f64,
    pub seed: u64,
    pub max_bounces: u32,
    /// Path-trace the reference on the GPU (the adapter `run` is given) rather than the CPU.
    pub reference_on_gpu: bool,
    /// How the GPU interpolates the lightmap (the CPU twin is always exact).
    pub lightmap_filter: LightmapFilter,
    /// The bake holds indirect light only: the reference leaves out the same direct light.
    pub indirect_only: bool,
    /// Frame-time measurement: (width, height, warm-up frames, measured frames); None: off.
    pub timing: Option<(u32, u32, usize, usize)>,
    /// Normal maps perturbing the shading normals (`--normal-maps`): the images are then
    /// shaded by the CPU twin (the raster pass does not read normal maps).
    pub normal_maps: Option<std::sync::Arc<super::normal_map::NormalMaps>>,
}

/// Frame times of one configuration (ms, GPU timestamps).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FrameTime {
    pub width: u32,
    pub height: u32,
    pub frames: usize,
    pub median_ms: f64,
    pub p10_ms: f64,
    pub p90_ms: f64,
    /// Median of the shading pass alone (the forward pass; the deferred path's compute pass).
    pub shading_ms: f64,
    /// Median frame, and its shading pass, with the shading only fetching the lobes and
    /// summing them, no runtime: the configuration's lightmap-bandwidth floor.
    pub fetch_only_ms: Option<f64>,
    pub fetch_only_shading_ms: Option<f64>,
}

/// One configuration's image and errors.
#[derive(Debug, Clone)]
pub struct Rendered {
    pub lighting: Lighting,
    /// "GPU" (raster pass) or "CPU" (the twin).
    pub shaded_on: &'static str,
    pub terms: Vec<Terms>,
    /// Pixels compared (lightmapped and the same surface in the image and the reference).
    pub pixels: usize,
    pub diffuse: Errors,
    pub specular: Errors,
    pub total: Errors,
    /// Errors of the total over the dynamic objects' pixels (shaded from the probes, the
    /// same in every configuration); None where none is visible.
    pub dynamic: Option<Errors>,
    /// The compared pixels split where light can leak across chart borders: those whose
    /// B-spline footprint reads a texel of another chart or of the gutter
    /// ([`super::atlas::reaches_outside_chart`]; the same pixels whatever the filter) and the
    /// rest — errors of the total and how many pixels each.
    pub chart_border: (Errors, usize),
    pub interior: (Errors, usize),
    /// With normal maps: errors of the total over the pixels whose shading normal the map
    /// moved, and how many.
    pub normal_mapped: Option<(Errors, usize)>,
    /// Frame times on the forward path (the raster pass shades) and on the deferred path
    /// (a G-buffer, then shading in a compute pass).
    pub frame: Option<FrameTime>,
    pub frame_deferred: Option<FrameTime>,
}

/// The whole comparison.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub visible: Vec<Option<Visible>>,
    pub reference: Reference,
    pub reference_seconds: f64,
    pub rendered: Vec<Rendered>,
    /// How the GPU interpolated the lightmap.
    pub lightmap_filter: LightmapFilter,
}

/// Runs the comparison of the bake in `bake_dir` (its layout `lm`, rebuilt from the same
/// scene and settings); `gpu` None shades on the CPU.
#[allow(clippy::too_many_arguments)]
pub fn run(
    scene: &Scene,
    bvh: &Bvh,
    lm: &Lightmap,
    bake_dir: &Path,
    probes: Option<&ProbeField>,
    setup: &Setup,
    gpu: Option<&shaders::gpu::Gpu>,
    log: &mut dyn FnMut(String),
) -> Result<Outcome, String> {
    if scene.has_textures() {
        // The raster pass and the references shade the visible surface with its material's
        // factors: a textured scene's image would not be the bake's.
        return Err(
            "the scene's materials have texture maps: the renderer shades material factors only (textured shading is not built yet)".into(),
        );
    }
    let cam = setup.camera;
    let visible = visible::cast_mapped(scene, bvh, lm, setup.normal_maps.as_deref(), &cam);
    let lit = visible.iter().filter(|v| v.is_some_and(|v| v.lightmapped)).count();
    let dynamic = visible.iter().filter(|v| v.is_some_and(|v| v.probed)).count();
    if lit == 0 {
        return Err("no lightmapped surface is visible from the camera (--camera)".into());
    }
    if dynamic > 0 && probes.is_none() {
        return Err(format!("{dynamic} pixels see dynamic objects (meshes without a lightmap), but the bake has no SH L2 probes"));
    }
    log(format!("render: {}×{} pixels, {lit} see a lightmapped surface, {dynamic} a dynamic object (probes)", cam.width, cam.height));
    let tracer = Tracer::new(scene, bvh, setup.max_bounces).with_indirect_only(setup.indirect_only);
    let t = std::time::Instant::now();
    let reference = reference_image(&tracer, scene, &visible, setup, gpu, log)?;
    let reference_seconds = t.elapsed().as_secs_f64();
    log(format!(
        "reference: {} samples per pixel in {reference_seconds:.1} s, relative noise {:.4}",
        reference.samples,
        reference::relative_noise(&reference)
    ));
    let raster_gpu = match (gpu, &setup.normal_maps) {
        (Some(_), Some(_)) => {
            log("render: normal maps: the images are shaded by the CPU twin (the raster pass does not read normal maps; no frame times)"
                .into());
            None
        }
        _ => gpu,
    };
    let renderer = raster_gpu.map(|g| Renderer::new(g, scene, lm, probes).map(|r| r.with_filter(setup.lightmap_filter))).transpose()?;
    let border: Vec<bool> = visible
        .iter()
        .map(|v| {
            v.is_some_and(|v| {
                v.lightmapped && super::atlas::reaches_outside_chart(&lm.texel_charts, lm.width, lm.height, v.uv.map(f64::from))
            })
        })
        .collect();
    let mut rendered = Vec::new();
    for l in &setup.configurations {
        let atlas = Atlas::read(bake_dir, l.encoding, lm.width, lm.height)?.stored(l.storage)?;
        let r = render_one(scene, &visible, &border, &reference, &atlas, probes, l, renderer.as_ref(), setup)?;
        log(format!(
            "{:<16} {}: RMSE diffuse {:.4e} specular {:.4e} total {:.4e} (relative {:.3}; mean ×{:.4} of the reference; chart borders {:.4e}, inside {:.4e}{}){}",
            l.name(),
            r.shaded_on,
            r.diffuse.rmse,
            r.specular.rmse,
            r.total.rmse,
            r.total.relative_rmse,
            r.total.mean_ratio,
            r.chart_border.0.rmse,
            r.interior.0.rmse,
            r.normal_mapped.map(|(e, n)| format!("; normal-mapped pixels ({n}) {:.4e}", e.rmse)).unwrap_or_default(),
            [(FramePath::Forward, r.frame), (FramePath::Deferred, r.frame_deferred)]
                .iter()
                .filter_map(|(p, f)| f.map(|f| format!(
                    ", {} frame {:.3} ms, shading pass {:.3} ms (lobes fetched only: {:.3}, {:.3} ms)",
                    p.name(),
                    f.median_ms,
                    f.shading_ms,
                    f.fetch_only_ms.unwrap_or(f64::NAN),
                    f.fetch_only_shading_ms.unwrap_or(f64::NAN)
                )))
                .collect::<String>()
        ));
        rendered.push(r);
    }
    Ok(Outcome { visible, reference, reference_seconds, rendered, lightmap_filter: setup.lightmap_filter })
}

/// The path-traced reference on the CPU or the GPU, progressive to the setup's noise or
/// with all its samples.
fn reference_image(
    tracer: &Tracer,
    scene: &Scene,
    visible: &[Option<Visible>],
    setup: &Setup,
    gpu: Option<&shaders::gpu::Gpu>,
    log: &mut dyn FnMut(String),
) -> Result<Reference, String> {
    let (eye, noise, samples) = (setup.camera.eye, setup.reference_noise, setup.reference_samples);
    if setup.reference_on_gpu {
        let g = gpu.ok_or("the reference on the GPU needs a GPU adapter")?;
        let r = GpuReference::new(g, tracer, visible, eye, setup.seed)?;
        log(format!("reference: path-traced on the GPU ({})", g.adapter));
        let mut report = |n: u32, e: f64| log(format!("reference: {n} samples per pixel, relative noise {e:.4} (target {noise})"));
        return if noise > 0.0 { r.render_to_noise(noise, 16, samples, &mut report) } else { r.render(samples) };
    }
    let mut report = |n: u32, e: f64| log(format!("reference: {n} samples per pixel, relative noise {e:.4} (target {noise})"));
    if noise > 0.0 {
        return Ok(reference::render_to_noise(tracer, scene, visible, eye, noise, 16, samples, setup.seed, &mut report));
    }
    let total_px = visible.len();
    let r = reference::render(tracer, scene, visible, eye, samples, setup.seed, &|n| {
        eprint!("\rreference: {:.0}% of {total_px} pixels", 100.0 * n as f64 / total_px as f64)
    });
    eprintln!();
    Ok(r)
}

/// One configuration: image, errors, frame time.
#[allow(clippy::too_many_arguments)]
fn render_one(
    scene: &Scene,
    visible: &[Option<Visible>],
    border: &[bool],
    reference: &Reference,
    atlas: &Atlas,
    probes: Option<&ProbeField>,
    l: &Lighting,
    renderer: Option<&Renderer>,
    setup: &Setup,
) -> Result<Rendered, String> {
    let cam = setup.camera;
    // (kind, material) of the CPU's visible surface: 1 lightmapped, 2 dynamic.
    let kind = |v: &Option<Visible>| match v {
        Some(v) if v.lightmapped => Some((1, v.material)),
        Some(v) if v.probed => Some((2, v.material)),
        _ => None,
    };
    type Frames = [Option<FrameTime>; 2];
    let (terms, kinds, shaded_on, frames): (Vec<Terms>, Vec<u8>, &'static str, Frames) = match renderer {
        Some(r) => {
            let a = r.analysis(l, atlas, &cam)?;
            let terms: Vec<Terms> = (0..a.diffuse.len())
                .map(|k| {
                    let v = |x: [f32; 4]| DVec3::new(x[0] as f64, x[1] as f64, x[2] as f64);
                    Terms { diffuse: v(a.diffuse[k]), specular: v(a.specular[k]) }
                })
                .collect();
            // The raster and the ray cast may pick different surfaces at silhouettes:
            // compare where both see the same material the same way.
            let kinds = (0..terms.len())
                .map(|k| match kind(&visible[k]) {
                    Some((c, m)) if a.diffuse[k][3] >= 0.0 && a.diffuse[k][3] as u32 == m && a.specular[k][3] as u8 == c => c,
                    _ => 0,
                })
                .collect();
            let mut frames = [None; 2];
            if let Some((w, h, warm, n)) = setup.timing.filter(|t| t.3 > 0) {
                let big = ViewCamera { width: w, height: h, ..cam };
                for (k, path) in [FramePath::Forward, FramePath::Deferred].into_iter().enumerate() {
                    let floor = r.frame_times(path, l, atlas, &big, (warm, n), true)?.map(|t| frame_stats(w, h, t));
                    frames[k] = r.frame_times(path, l, atlas, &big, (warm, n), false)?.map(|t| FrameTime {
                        fetch_only_ms: floor.map(|f| f.median_ms),
                        fetch_only_shading_ms: floor.map(|f| f.shading_ms),
                        ..frame_stats(w, h, t)
                    });
                }
            }
            (terms, kinds, "GPU", frames)
        }
        None => {
            let shader = Shader::new(*l);
            let terms = visible::shade_pixels(&shader, atlas, setup.lightmap_filter, probes, scene, cam.eye, visible);
            (terms, visible.iter().map(|v| kind(v).map_or(0, |k| k.0)).collect(), "CPU", [None; 2])
        }
    };
    let d: Vec<DVec3> = terms.iter().map(|t| t.diffuse).collect();
    let s: Vec<DVec3> = terms.iter().map(|t| t.specular).collect();
    let tot: Vec<DVec3> = terms.iter().map(|t| t.total()).collect();
    let ref_tot: Vec<DVec3> = reference.diffuse.iter().zip(&reference.specular).map(|(a, b)| *a + *b).collect();
    let mask: Vec<bool> = kinds.iter().zip(&reference.accepted).map(|(k, n)| *k == 1 && *n > 0).collect();
    let dyn_mask: Vec<bool> = kinds.iter().zip(&reference.accepted).map(|(k, n)| *k == 2 && *n > 0).collect();
    let moved: Vec<bool> = visible.iter().map(|v| v.is_some_and(|v| v.normal != v.frame_normal)).collect();
    let normal_mapped = setup.normal_maps.as_ref().map(|_| {
        let m: Vec<bool> = mask.iter().zip(&moved).map(|(a, b)| *a && *b).collect();
        (errors(&tot, &ref_tot, &reference.var_total, &m), m.iter().filter(|x| **x).count())
    });
    let split = |at_border: bool| {
        let m: Vec<bool> = mask.iter().zip(border).map(|(m, b)| *m && *b == at_border).collect();
        (errors(&tot, &ref_tot, &reference.var_total, &m), m.iter().filter(|x| **x).count())
    };
    Ok(Rendered {
        lighting: *l,
        shaded_on,
        pixels: mask.iter().filter(|m| **m).count(),
        diffuse: errors(&d, &reference.diffuse, &reference.var_diffuse, &mask),
        specular: errors(&s, &reference.specular, &reference.var_specular, &mask),
        total: errors(&tot, &ref_tot, &reference.var_total, &mask),
        dynamic: dyn_mask.iter().any(|m| *m).then(|| errors(&tot, &ref_tot, &reference.var_total, &dyn_mask)),
        chart_border: split(true),
        interior: split(false),
        normal_mapped,
        terms,
        frame: frames[0],
        frame_deferred: frames[1],
    })
}

/// Median and 10th/90th percentiles of the measured frames ([frame, shading pass] each),
/// and the shading pass's median.
fn frame_stats(width: u32, height: u32, t: Vec<[f64; 2]>) -> FrameTime {
    let sorted = |i: usize| {
        let mut v: Vec<f64> = t.iter().map(|x| x[i]).collect();
        v.sort_by(f64::total_cmp);
        v
    };
    let (f, s) = (sorted(0), sorted(1));
    let q = |v: &[f64], p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
    FrameTime {
        width,
        height,
        frames: t.len(),
        median_ms: q(&f, 0.5),
        p10_ms: q(&f, 0.1),
        p90_ms: q(&f, 0.9),
        shading_ms: q(&s, 0.5),
        fetch_only_ms: None,
        fetch_only_shading_ms: None,
    }
}
