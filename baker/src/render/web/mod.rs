//! The bake viewer for the browser (`render --web DIR`): a self-contained, offline folder —
//! `index.html`, one JavaScript module without dependencies, the scene's triangles with their
//! lightmap UVs, the bake's lightmaps (RGB f16, the rounding's effect on the image stated),
//! the SH L2 probes, the path-traced reference (diffuse and specular, f16) and results.json —
//! shaded by the exported runtime library, not a re-implementation:
//!
//! - **WebGL 2**: the GLSL ES 3.0 export of the library (`sbf.es.glsl`, written by
//!   `shaders::export` for the renderer's features) under `viewer.es.glsl`, the fragment
//!   stage of `wgsl/render.wgsl` in GLSL ES (lightmap footprint, per-basis loop over the
//!   lobes, probes) calling the library's `sbf_*` functions;
//! - **WebGPU** (where the browser has it): `viewer.wgsl`, the WGSL export of the same
//!   library followed by `wgsl/render.wgsl` itself with the library's names prefixed as the
//!   export prefixes them — the renderer's own shader, compiled by the browser's WGSL
//!   compiler.
//!
//! Both shade diffuse and specular apart into f32 targets; a display pass applies the
//! exposure (the report's: the reference's mean luminance to 0.18, × 2^EV), the report's
//! tone curve x/(1 + x) and sRGB, and the split view against the reference.
//!
//! Files (all little-endian): `mesh.bin` the vertices (position, normal, atlas UV, material | flags, face normal: 48 bytes,
//! unindexed), `materials.bin` two RGBA f32 rows per material, `probes.bin` nine RGBA f32
//! rows per probe (row 0's w: valid), `lightmap-NAME.bin` RGB f16 per texel, lobe after lobe,
//! `lut-dfg.bin` and `lut-ad.bin` the specular tables (RG f32), `reference.bin` the
//! reference's diffuse then specular (RGB f16 per pixel, row-major from the top).

//!
//! | module | holds |
//! |---|---|
//! | [`library`] | the library's GLSL ES and WGSL exports for the viewer, its own stages |
//! | [`texels`] | f16 data, the atlas downsampled to a browser's texture limit, the errors both cost |

pub mod library;
pub mod texels;

use super::atlas::Atlas;
use super::bindings::{depth_range, material_rows, probe_rows, scene_vertices};
use super::lighting::{lobe_axes, Encoding, Lighting, LightmapFilter, Storage};
use super::probes::ProbeField;
use super::session::Outcome;
use super::shade::Shader;
use crate::layout::lightmap::Lightmap;
use crate::scene::camera::ViewCamera;
use crate::scene::Scene;
use sbf::glam::DVec3;
use sbf::profile::SpecularPath;
use serde_json::json;
use std::path::Path;
use texels::{downsample, downsample_error, f16_bytes, relative_rms};

const INDEX_HTML: &str = include_str!("index.html");
const VIEWER_JS: &str = include_str!("viewer.js");

/// The largest texture side the viewer uploads: WebGL 2 guarantees 2048, desktop browsers
/// give 8192–16384 (SwiftShader 8192). A larger atlas is downsampled by 2 until it fits.
pub const MAX_TEXTURE: usize = 8192;

/// What the viewer shows.
#[derive(Debug, Clone, Copy)]
pub struct Viewer<'a> {
    pub scene: &'a Scene,
    pub lm: &'a Lightmap,
    /// The bake folder the lightmaps are read from.
    pub bake_dir: &'a Path,
    pub probes: Option<&'a ProbeField>,
    /// The reference's camera (the viewer's first view).
    pub camera: ViewCamera,
    /// The comparison `render` made (the reference, the visible surfaces).
    pub outcome: &'a Outcome,
    /// The λ of the bake's SG lobes.
    pub sg_sharpness: f64,
    /// The comparison's results.json (copied for the viewer's error and storage table).
    pub results: &'a super::report::ResultsJson,
    /// The largest texture side to write (a larger atlas is downsampled).
    pub max_texture: usize,
}

/// What [`write()`] wrote.
#[derive(Debug, Clone)]
pub struct Written {
    pub files: usize,
    pub bytes: u64,
    /// The atlas' downsampling factor (1: none) and, where > 1, the relative RMS error of
    /// the plain E/π lightmap it causes at the valid texels.
    pub downsampled: (usize, Option<f64>),
    /// Per configuration: its name and the relative RMS change of the image (reference
    /// camera, lightmapped pixels) from storing the lightmap as f16.
    pub f16_error: Vec<(String, f64)>,
}

/// The configurations the viewer switches between: the plain E/π lightmap and every
/// lightmap basis `rendered`, each once, on the fit path (the profile's default runtime),
/// stored as f16.
pub fn configurations(rendered: &[Lighting], sg_sharpness: f64) -> Vec<Lighting> {
    let mut out = vec![Lighting { encoding: Encoding::Irradiance, specular: SpecularPath::Fit, storage: Storage::F16, sg_sharpness }];
    for l in rendered {
        if !out.iter().any(|o| o.encoding == l.encoding) {
            out.push(Lighting { encoding: l.encoding, specular: SpecularPath::Fit, storage: Storage::F16, sg_sharpness });
        }
    }
    out
}

/// The lightmap file of every configuration (f16, downsampled by `f`) and its scene.json
/// entry; the E/π lightmap's downsampling error where `f` > 1.
#[allow(clippy::type_complexity)]
fn lightmaps(
    v: &Viewer,
    configurations: &[Lighting],
    f: usize,
) -> Result<(Vec<(String, Vec<u8>)>, Vec<serde_json::Value>, Option<f64>, Vec<(String, f64)>), String> {
    let lm = v.lm;
    // The visible surfaces' shading with f32 and f16 lightmaps: the storage's stated error.
    let lit: Vec<_> = v
        .outcome
        .visible
        .iter()
        .filter(|s| s.is_some_and(|s| s.lightmapped))
        .map(|s| {
            s.map(|mut s| {
                s.uv = s.uv.map(|u| u / f as f32);
                s
            })
        })
        .collect();
    let (mut files, mut confs, mut f16_error, mut downsampled_error) = (Vec::new(), Vec::new(), Vec::new(), None);
    for l in configurations {
        let full = Atlas::read(v.bake_dir, l.encoding, lm.width, lm.height)?;
        let small = downsample(&full, &lm.texel_charts, f);
        if f > 1 && l.encoding == Encoding::Irradiance {
            downsampled_error = Some(downsample_error(&full, &small, &lm.texel_charts, f));
        }
        let stored = small.stored(Storage::F16)?;
        let shader = Shader::new(*l);
        let shade = |a: &Atlas| -> Vec<DVec3> {
            super::visible::shade_pixels(&shader, a, LightmapFilter::Exact, v.probes, v.scene, v.camera.eye, &lit)
                .iter()
                .map(|t| t.total())
                .collect()
        };
        let err = relative_rms(&shade(&stored), &shade(&small));
        f16_error.push((l.name(), err));
        let (name, label, encoding, lut) = match l.encoding {
            Encoding::Irradiance => ("none".to_string(), "plain E/π lightmap".to_string(), 0, None),
            Encoding::Basis(b) => (
                b.name().to_string(),
                b.info().title.to_string(),
                1 + b.gpu_kind().ok_or_else(|| format!("{b} has no GPU slot"))?,
                Some(if b.is_sh() {
                    "dfg"
                } else if b.is_sg() {
                    "none"
                } else {
                    "ad"
                }),
            ),
        };
        let file = format!("lightmap-{name}.bin");
        files.push((file.clone(), f16_bytes(stored.lobes.iter().flatten().flat_map(|t| t.iter().copied()))));
        let axes: Vec<[f64; 3]> = lobe_axes(l.encoding).iter().map(|a| a.to_array()).collect();
        confs.push(json!({
            "name": name, "label": label, "encoding": encoding, "lobes": l.lobes(), "file": file, "axes": axes,
            "sg_sharpness": v.sg_sharpness, "lut": lut, "bytes_per_texel": l.lobes() * 6, "f16_relative_rms": err,
        }));
    }
    Ok((files, confs, downsampled_error, f16_error))
}

/// The reference's diffuse then specular, RGB f16 (0 where it took no sample), and the
/// report's exposure (the reference's mean luminance to 0.18).
fn reference(o: &Outcome) -> (Vec<u8>, f64) {
    let r = &o.reference;
    let px = |img: &[DVec3]| -> Vec<f32> {
        img.iter().zip(&r.accepted).flat_map(|(c, n)| if *n > 0 { c.to_array().map(|x| x as f32) } else { [0.0; 3] }).collect()
    };
    let mut bytes = f16_bytes(px(&r.diffuse).into_iter());
    bytes.extend(f16_bytes(px(&r.specular).into_iter()));
    let lum: Vec<f32> =
        r.diffuse.iter().zip(&r.specular).map(|(a, b)| *a + *b).map(|c| (0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) as f32).collect();
    (bytes, crate::output::exposure_scale(&lum) as f64)
}

/// A specular table as RG f32 texels.
fn lut_bytes(l: &sbf::recon::lut::Lut2) -> Vec<u8> {
    (0..l.width * l.height)
        .flat_map(|k| {
            let a = l.data[k * l.channels];
            let b = if l.channels > 1 { l.data[k * l.channels + 1] } else { a };
            [a, b]
        })
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// Writes the viewer folder `dir` (created; the viewer's own files replaced).
pub fn write(dir: &Path, v: &Viewer, configurations: &[Lighting], log: &mut dyn FnMut(String)) -> Result<Written, String> {
    if v.max_texture < 16 {
        return Err(format!("the viewer's largest texture side is {}: at least 16 (WebGL 2 guarantees 2048)", v.max_texture));
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let (lm, cam) = (v.lm, v.camera);
    // The atlas' downsampling factor: the smallest power of two that fits the limit.
    let mut f = 1;
    while lm.width.div_ceil(f) > v.max_texture || lm.height.div_ceil(f) > v.max_texture {
        f *= 2;
    }
    let (mut verts, bounds) = scene_vertices(v.scene, lm)?;
    verts.iter_mut().for_each(|x| x.uv = x.uv.map(|u| u / f as f32));
    let (rows, (dims, first, last)) = probe_rows(v.probes);
    let (dfg, ad) = (sbf::recon::tables::dfg(), sbf::recon::tables::ad_specular_2d());
    let (mut files, confs, downsampled_error, f16_error) = lightmaps(v, configurations, f)?;
    let (reference, exposure) = reference(v.outcome);
    // The near plane as far out as the reference view allows — half the nearest visible
    // surface's distance — rather than the renderer's far × 1e-5: WebGL 2 and WebGPU keep
    // depth as f32 with the usual mapping (no reversed Z in WebGL 2), whose resolution at
    // distance d is ≈ d²/near × 2⁻²⁴: at 1e-5 of a 100 m far plane, 2.4 cm at 20 m, and the
    // atrium's banners and walls then fight.
    let (near0, far) = depth_range(bounds, &cam);
    let nearest = v.outcome.visible.iter().flatten().map(|s| (s.position - cam.eye).length()).fold(f32::INFINITY, f32::min);
    let near = if nearest.is_finite() { (0.5 * nearest).max(near0) } else { near0 };
    let scene_json = json!({
        "format": "sbf-web 1",
        "scene": v.scene.name,
        "atlas": [lm.width.div_ceil(f), lm.height.div_ceil(f)],
        "downsampled": { "factor": f, "irradiance_relative_rms": downsampled_error },
        "exposure": exposure,
        "camera": {
            "eye": cam.eye.to_array(), "target": cam.target.to_array(), "up": cam.up.to_array(),
            "fov_y_degrees": cam.fov_y.to_degrees(), "width": cam.width, "height": cam.height, "near": near, "far": far,
            "view_proj": cam.view_proj([0.0; 2], near, far).to_cols_array(),
        },
        "bounds": [bounds.0.to_array(), bounds.1.to_array()],
        "vertices": verts.len(),
        "materials": v.scene.materials.len(),
        "probes": { "dims": dims, "first": first, "last": last },
        "configurations": confs,
        "luts": { "dfg": [dfg.width, dfg.height], "ad": [ad.width, ad.height] },
        "reference": { "width": cam.width, "height": cam.height, "samples_per_pixel": v.outcome.reference.samples },
        "storage": "lightmaps RGB f16 (each configuration's f16_relative_rms: the image's relative RMS change from f32 storage at the reference camera)",
    });
    files.extend([
        ("mesh.bin".to_string(), bytemuck::cast_slice(&verts).to_vec()),
        ("materials.bin".into(), bytemuck::cast_slice(&material_rows(v.scene)).to_vec()),
        ("probes.bin".into(), bytemuck::cast_slice(&rows).to_vec()),
        ("lut-dfg.bin".into(), lut_bytes(dfg)),
        ("lut-ad.bin".into(), lut_bytes(ad)),
        ("reference.bin".into(), reference),
        ("scene.json".into(), serde_json::to_vec_pretty(&scene_json).map_err(|e| e.to_string())?),
        ("results.json".into(), serde_json::to_vec_pretty(v.results).map_err(|e| e.to_string())?),
        ("sbf.es.glsl".into(), library::library_glsl_es()?.into_bytes()),
        ("viewer.es.glsl".into(), library::VIEWER_ES_GLSL.as_bytes().to_vec()),
        ("viewer.wgsl".into(), library::viewer_wgsl()?.into_bytes()),
        ("display.wgsl".into(), library::DISPLAY_WGSL.as_bytes().to_vec()),
        ("viewer.js".into(), VIEWER_JS.as_bytes().to_vec()),
        ("index.html".into(), INDEX_HTML.as_bytes().to_vec()),
    ]);
    let mut bytes = 0u64;
    for (name, data) in &files {
        std::fs::write(dir.join(name), data).map_err(|e| format!("{}: {e}", dir.join(name).display()))?;
        bytes += data.len() as u64;
    }
    log(format!(
        "web: {} files, {:.2} MB in {}{}",
        files.len(),
        bytes as f64 / 1e6,
        dir.display(),
        downsampled_error.map(|e| format!(" (atlas downsampled {f}×: E/π relative RMS {e:.4})")).unwrap_or_default()
    ));
    Ok(Written { files: files.len(), bytes, downsampled: (f, downsampled_error), f16_error })
}
