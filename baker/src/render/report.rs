//! What a comparison writes into its folder: the reference and every configuration as
//! EXR (linear RGB, alpha = compared) and PNG (one exposure for all, x/(1 + x), sRGB),
//! the absolute difference from the reference at +3 EV (×8, as [Roughton19 Fig. 8.8]),
//! results.json (every number) and report.html (the table and the images side by side).

use super::session::{FrameTime, Outcome};
use crate::output::{save_png, srgb8, write_exr};
use crate::scene::camera::ViewCamera;
use sbf::glam::DVec3;
use serde::Serialize;
use std::path::Path;

/// results.json.
#[derive(Debug, Serialize)]
pub struct ResultsJson {
    pub scene: String,
    pub bake: String,
    pub camera: CameraJson,
    /// "GPU: adapter" or "CPU (the shading's twin)".
    pub device: String,
    /// How the lightmap was interpolated: `exact` (four loads weighted in f32),
    /// `hardware` (the sampler's bilinear filter) or `bicubic` (the cubic B-spline).
    pub lightmap_filter: &'static str,
    pub reference: ReferenceJson,
    pub configurations: Vec<ConfigurationJson>,
    /// The bake viewer's index.html (`render --web`), relative to this folder.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub viewer: Option<String>,
}

#[derive(Debug, Serialize)]
pub struct CameraJson {
    pub eye: [f32; 3],
    pub target: [f32; 3],
    pub fov_y_degrees: f32,
    pub width: u32,
    pub height: u32,
}

#[derive(Debug, Serialize)]
pub struct ReferenceJson {
    pub samples_per_pixel: u32,
    /// √mean σ² of the total over its RMS (what `--reference-noise` bounds).
    pub relative_noise: f64,
    pub estimator: &'static str,
    pub seconds: f64,
    /// √mean σ² of the reference's total over the lightmapped pixels.
    pub noise_rms: f64,
    pub file: &'static str,
}

#[derive(Debug, Serialize)]
pub struct ConfigurationJson {
    pub name: String,
    pub lobes: usize,
    pub storage: &'static str,
    pub specular_path: &'static str,
    /// SG: the lobes' sharpness λ.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sg_sharpness: Option<f64>,
    pub bytes_per_texel: usize,
    pub shaded_on: &'static str,
    pub pixels: usize,
    pub diffuse: super::compare::Errors,
    pub specular: super::compare::Errors,
    pub total: super::compare::Errors,
    /// The dynamic objects' pixels (shaded from the probes): errors of the total.
    pub dynamic: Option<super::compare::Errors>,
    /// Errors of the total where the B-spline's 4 × 4 footprint reads a texel outside the
    /// pixel's chart (another chart or the gutter: where filtering can leak), and elsewhere;
    /// the same pixels for every filter.
    pub chart_border: super::compare::Errors,
    pub chart_border_pixels: usize,
    pub interior: super::compare::Errors,
    pub interior_pixels: usize,
    /// With `--normal-maps`: errors of the total where the map moved the shading normal.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal_mapped: Option<super::compare::Errors>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal_mapped_pixels: Option<usize>,
    /// The forward path's frame (the raster pass shades).
    pub frame: Option<FrameTime>,
    /// Median frame time minus the plain E/π configuration's (same storage), ms.
    pub overhead_ms: Option<f64>,
    /// The deferred path's frame (G-buffer, then shading in a compute pass) and its overhead.
    pub frame_deferred: Option<FrameTime>,
    pub overhead_deferred_ms: Option<f64>,
    pub image: String,
    pub difference: String,
}

/// A linear RGB image × `exposure`, tone mapped x/(1 + x) per channel, sRGB-encoded.
pub fn tonemap_rgb(width: usize, height: usize, v: &[DVec3], exposure: f64) -> image::RgbImage {
    image::RgbImage::from_fn(width as u32, height as u32, |x, y| {
        let c = v[y as usize * width + x as usize].max(DVec3::ZERO) * exposure;
        image::Rgb([c.x, c.y, c.z].map(|c| srgb8((c / (1.0 + c)) as f32)))
    })
}

fn write_images(dir: &Path, name: &str, cam: &ViewCamera, v: &[DVec3], mask: &[f32], exposure: f64) -> Result<(), String> {
    let (w, h) = (cam.width as usize, cam.height as usize);
    let rgb: Vec<[f32; 3]> = v.iter().map(|c| [c.x as f32, c.y as f32, c.z as f32]).collect();
    write_exr(&dir.join(format!("{name}.exr")), w, h, &rgb, mask)?;
    save_png(&dir.join(format!("{name}.png")), &tonemap_rgb(w, h, v, exposure))
}

/// Writes the images, results.json and report.html; returns results.json's record.
/// `viewer`: the folder of the bake viewer written beside the report (linked from it).
pub fn write(
    dir: &Path,
    scene: &str,
    bake: &Path,
    cam: &ViewCamera,
    device: &str,
    o: &Outcome,
    viewer: Option<&Path>,
) -> Result<ResultsJson, String> {
    let refs: Vec<DVec3> = o.reference.diffuse.iter().zip(&o.reference.specular).map(|(a, b)| *a + *b).collect();
    // Alpha: 1 where the reference has samples (lightmapped surfaces and dynamic objects).
    let mask: Vec<f32> = o.reference.accepted.iter().map(|n| if *n > 0 { 1.0 } else { 0.0 }).collect();
    // One exposure for every image: the reference's mean luminance to 0.18.
    let lum: Vec<f32> = refs.iter().map(|c| (0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) as f32).collect();
    let exposure = crate::output::exposure_scale(&lum) as f64;
    write_images(dir, "reference", cam, &refs, &mask, exposure)?;
    let mut configurations = Vec::new();
    for r in &o.rendered {
        let name = r.lighting.name();
        let img: Vec<DVec3> = r.terms.iter().map(|t| t.total()).collect();
        write_images(dir, &name, cam, &img, &mask, exposure)?;
        let diff: Vec<DVec3> =
            img.iter().zip(&refs).zip(&mask).map(|((a, b), m)| if *m > 0.0 { (*a - *b).abs() * 8.0 } else { DVec3::ZERO }).collect();
        save_png(&dir.join(format!("{name}_diff.png")), &tonemap_rgb(cam.width as usize, cam.height as usize, &diff, exposure))?;
        let none = o
            .rendered
            .iter()
            .find(|n| n.lighting.encoding == super::lighting::Encoding::Irradiance && n.lighting.storage == r.lighting.storage);
        configurations.push(ConfigurationJson {
            name: name.clone(),
            lobes: r.lighting.lobes(),
            storage: r.lighting.storage.name(),
            sg_sharpness: matches!(r.lighting.encoding, super::lighting::Encoding::Basis(b) if b.is_sg())
                .then_some(r.lighting.sg_sharpness),
            specular_path: r.lighting.specular.name(),
            bytes_per_texel: r.lighting.bytes_per_texel(),
            shaded_on: r.shaded_on,
            pixels: r.pixels,
            diffuse: r.diffuse,
            specular: r.specular,
            total: r.total,
            dynamic: r.dynamic,
            chart_border: r.chart_border.0,
            chart_border_pixels: r.chart_border.1,
            interior: r.interior.0,
            interior_pixels: r.interior.1,
            normal_mapped: r.normal_mapped.map(|x| x.0),
            normal_mapped_pixels: r.normal_mapped.map(|x| x.1),
            frame: r.frame,
            overhead_ms: match (r.frame, none.and_then(|n| n.frame)) {
                (Some(f), Some(n)) => Some(f.median_ms - n.median_ms),
                _ => None,
            },
            frame_deferred: r.frame_deferred,
            overhead_deferred_ms: match (r.frame_deferred, none.and_then(|n| n.frame_deferred)) {
                (Some(f), Some(n)) => Some(f.median_ms - n.median_ms),
                _ => None,
            },
            image: format!("{name}.png"),
            difference: format!("{name}_diff.png"),
        });
    }
    let noise = {
        let (s, n) = o
            .reference
            .var_total
            .iter()
            .zip(&mask)
            .filter(|(_, m)| **m > 0.0)
            .fold((0.0, 0usize), |(s, n), (v, _)| (s + v.element_sum() / 3.0, n + 1));
        if n > 0 {
            (s / n as f64).sqrt()
        } else {
            0.0
        }
    };
    let results = ResultsJson {
        scene: scene.to_string(),
        bake: bake.display().to_string(),
        camera: CameraJson { eye: cam.eye.to_array(), target: cam.target.to_array(), fov_y_degrees: cam.fov_y.to_degrees(), width: cam.width, height: cam.height },
        device: device.to_string(),
        lightmap_filter: o.lightmap_filter.name(),
        reference: ReferenceJson {
            samples_per_pixel: o.reference.samples,
            relative_noise: super::reference::relative_noise(&o.reference),
            estimator: "path tracing of the reflected radiance with the bake's incident-radiance estimator (BSDF-sampled point sample, NEE, power-heuristic MIS), independent random numbers",
            seconds: o.reference_seconds,
            noise_rms: noise,
            file: "reference.exr",
        },
        configurations,
        viewer: viewer.map(|v| relative(&v.join("index.html"), dir)),
    };
    let json = serde_json::to_string_pretty(&results).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("results.json"), json).map_err(|e| format!("results.json: {e}"))?;
    std::fs::write(dir.join("report.html"), html(&results)).map_err(|e| format!("report.html: {e}"))?;
    Ok(results)
}

/// `target` relative to the folder `base` (both made absolute; `/`-separated, for a link).
fn relative(target: &Path, base: &Path) -> String {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (t, b) = (abs(target), abs(base));
    let (tc, bc): (Vec<_>, Vec<_>) = (t.components().collect(), b.components().collect());
    let common = tc.iter().zip(&bc).take_while(|(a, b)| a == b).count();
    let mut parts: Vec<String> = vec!["..".to_string(); bc.len() - common];
    parts.extend(tc[common..].iter().map(|c| c.as_os_str().to_string_lossy().to_string()));
    parts.join("/")
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// report.html: the table, then the reference and each configuration with its difference.
fn html(r: &ResultsJson) -> String {
    let mut rows = String::new();
    for c in &r.configurations {
        let ms = |f: Option<f64>| f.map(|x| format!("{x:.3}")).unwrap_or_else(|| "–".into());
        rows += &format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.4e}</td><td>{:.4e}</td><td>{:.4e}</td><td>{:.3}</td><td>{:.4e} ({} px)</td><td>{:.4e} ({} px)</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            esc(&c.name),
            c.lobes,
            c.bytes_per_texel,
            c.shaded_on,
            c.diffuse.rmse,
            c.specular.rmse,
            c.total.rmse,
            c.total.relative_rmse,
            c.chart_border.rmse,
            c.chart_border_pixels,
            c.interior.rmse,
            c.interior_pixels,
            ms(c.frame.map(|f| f.median_ms)),
            ms(c.overhead_ms),
            ms(c.frame_deferred.map(|f| f.median_ms)),
            ms(c.overhead_deferred_ms),
            ms(c.frame_deferred.map(|f| f.shading_ms))
        );
    }
    let mut figs = String::from("<figure><img src=\"reference.png\"><figcaption>reference</figcaption></figure>\n");
    for c in &r.configurations {
        figs += &format!(
            "<figure><img src=\"{0}\"><figcaption>{1}</figcaption></figure><figure><img src=\"{2}\"><figcaption>{1}: |difference| at +3 EV</figcaption></figure>\n",
            esc(&c.image),
            esc(&c.name),
            esc(&c.difference)
        );
    }
    format!(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>render: {scene}</title>\n<style>body{{font-family:sans-serif;max-width:1400px;margin:1em auto}}table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}}figure{{display:inline-block;margin:4px}}img{{width:320px;image-rendering:pixelated}}</style></head><body>\n<h1>{scene}: baked lightmaps shaded in real time against the path-traced reference</h1>\n<p>Camera {w}×{h}; reference {spp} samples per pixel (noise {noise:.3e} RMS, subtracted from every RMSE); shading on {device}, lightmap filter {filter}. Quantity: light reflected by the visible surface (diffuse + single-scattering GGX), emission excluded.</p>\n{viewer}<table><tr><th>configuration</th><th>lobes</th><th>bytes/texel</th><th>shaded on</th><th>RMSE diffuse</th><th>RMSE specular</th><th>RMSE total</th><th>relative</th><th>RMSE at chart borders</th><th>RMSE inside charts</th><th>forward frame ms</th><th>forward overhead ms</th><th>deferred frame ms</th><th>deferred overhead ms</th><th>deferred compute pass ms</th></tr>\n{rows}</table>\n{figs}<script>\n// Self-check for headless browsers: images that fail to load and script errors, on <body>.\nlet errors = 0;\nwindow.addEventListener('error', () => {{ errors += 1; }}, true);\nwindow.addEventListener('load', () => {{\n  const imgs = [...document.images];\n  document.body.dataset.images = imgs.length;\n  document.body.dataset.broken = imgs.filter(i => !i.complete || i.naturalWidth === 0).length;\n  document.body.dataset.errors = errors;\n}});\n</script>\n</body></html>\n",
        scene = esc(&r.scene),
        w = r.camera.width,
        h = r.camera.height,
        spp = r.reference.samples_per_pixel,
        noise = r.reference.noise_rms,
        device = esc(&r.device),
        filter = r.lightmap_filter,
        viewer = r.viewer.as_ref().map_or(String::new(), |v| format!(
            "<p><a href=\"{}\">The bake viewer</a>: the scene in your browser (WebGL 2 or WebGPU), every basis, orbit and fly, the split view against this reference. It loads its files by fetch: serve its folder (e.g. <code>python3 -m http.server</code> in it) rather than opening it from disk.</p>\n",
            esc(v)
        ))
    )
}
