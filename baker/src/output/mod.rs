//! What a bake writes: EXR images (plain E/π and one per basis lobe, RGB + a validity
//! alpha), JSON metadata, probe coefficients, the runtime WGSL
//! composed for the scene (with only the LUTs it needs), and a preview PNG of the scene
//! lit by the baked irradiance (CPU ray cast through the same BVH); [`bake_json`] holds
//! bake.json's and probes.json's records; [`engine`] repackages the SH L1 lightmap in the
//! directional formats engines ship; [`compress`] writes BC6H DDS copies with their error.
//!
//! Uses: [`crate::scene`], [`crate::layout`], [`crate::accumulate`], [`crate::post`].

pub mod bake_json;
pub mod compress;
pub mod engine;

use crate::accumulate::{BakeConfig, BasisId};
use crate::layout::lightmap::Lightmap;
use crate::post::images::LightmapImages;
use crate::scene::bvh::Bvh;
use crate::scene::Scene;
use sbf::glam::Vec3;
use serde_json::json;
use std::path::Path;

/// Writes RGB + alpha (validity) as a 32-bit float OpenEXR file.
pub fn write_exr(path: &Path, width: usize, height: usize, rgb: &[[f32; 3]], alpha: &[f32]) -> Result<(), String> {
    let data: Vec<f32> = rgb.iter().zip(alpha).flat_map(|(c, a)| [c[0], c[1], c[2], *a]).collect();
    let img = image::Rgba32FImage::from_raw(width as u32, height as u32, data).ok_or("image size mismatch")?;
    img.save_with_format(path, image::ImageFormat::OpenExr).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// The EXR files of a lightmap bake: `irradiance.exr`, `irradiance_se.exr` and
/// `{basis}_{lobe:02}.exr`; returns their names.
pub fn write_lightmap(dir: &Path, img: &LightmapImages, config: &BakeConfig) -> Result<Vec<String>, String> {
    let mut names = vec!["irradiance.exr".to_string(), "irradiance_se.exr".to_string(), "normals.exr".to_string()];
    write_exr(&dir.join(&names[0]), img.width, img.height, &img.irradiance, &img.validity)?;
    write_exr(&dir.join(&names[1]), img.width, img.height, &img.standard_error, &img.validity)?;
    write_exr(&dir.join(&names[2]), img.width, img.height, &img.normals, &img.validity)?;
    for (b, kind) in config.bases.iter().enumerate() {
        for (l, lobe) in img.coefficients[b].iter().enumerate() {
            let name = format!("{}_{l:02}.exr", kind.name());
            write_exr(&dir.join(&name), img.width, img.height, lobe, &img.validity)?;
            names.push(name);
        }
    }
    Ok(names)
}

/// The runtime features for the baked bases (lightmap and probe bases alike): Lambert
/// irradiance always, and specular on each of `paths` (empty: none — no glossy material,
/// or a Lambert-only profile) as [`sbf::profile::specular_runtime`] says (the profile's
/// one truth, read by fitgen, shaders and probes too), with GGX's energy compensation and
/// the DFG table it reads where `energy_compensation` (a profile's `multiple_scattering =
/// "compensated"`) and there is specular. Returns (features, table files the shader
/// functions read).
pub fn runtime_features(
    bases: &[BasisId],
    paths: &[sbf::profile::SpecularPath],
    energy_compensation: bool,
) -> (Vec<&'static str>, Vec<String>) {
    let mut f = Vec::new();
    let mut luts = Vec::new();
    if energy_compensation && !paths.is_empty() {
        f.push("ggx-energy-compensation");
        luts.push(sbf::profile::table_file("dfg"));
    }
    for b in bases {
        f.push(b.irradiance_feature().expect("a lightmap basis has a Lambert runtime"));
        for p in paths {
            if let (Some(feature), table) = sbf::profile::specular_runtime(*b, *p) {
                f.push(feature);
                luts.extend(table.map(sbf::profile::table_file));
            }
        }
    }
    f.sort_unstable();
    f.dedup();
    luts.sort_unstable();
    luts.dedup();
    (f, luts)
}

/// A preview of the scene lit by the baked E/π (diffuse albedo × E/π + emission; the
/// environment where rays leave), ray cast from a view camera, exposed to a mean of 0.18
/// and tone mapped with x/(1 + x), sRGB-encoded.
/// `camera`: the view (camera-based sampling's), else the default one
/// ([`crate::scene::camera::ViewCamera::preview`]); either is rendered `width` wide at 4:3.
pub fn preview(
    scene: &Scene,
    bvh: &Bvh,
    lm: &Lightmap,
    img: &LightmapImages,
    width: usize,
    camera: Option<crate::scene::camera::ViewCamera>,
) -> image::RgbImage {
    let height = (width * 3 / 4).max(1);
    let (w, h) = (width as u32, height as u32);
    let cam = match camera {
        Some(c) => crate::scene::camera::ViewCamera { width: w, height: h, ..c },
        None => crate::scene::camera::ViewCamera::preview(bvh, w, h),
    };
    let mut hdr = vec![Vec3::ZERO; width * height];
    for y in 0..height {
        for x in 0..width {
            let (eye, d) = cam.ray(x as f32 + 0.5, y as f32 + 0.5);
            hdr[y * width + x] = match bvh.intersect(eye, d, 0.0, f32::INFINITY) {
                None => scene.environment.radiance(d),
                Some(h) => {
                    let tri = &bvh.tris[h.tri as usize];
                    let m = &scene.material_at(tri, h.u, h.v);
                    let mesh = &scene.meshes[tri.mesh as usize];
                    let lit = if mesh.lightmapped {
                        let uv = lm.triangle_uv[tri.mesh as usize][tri.prim as usize];
                        let a = uv[0] * (1.0 - h.u - h.v) + uv[1] * h.u + uv[2] * h.v;
                        m.diffuse_albedo() * img.sample(a)
                    } else {
                        Vec3::ZERO
                    };
                    let front = d.dot(tri.normal()) < 0.0;
                    lit + if front { m.emissive } else { Vec3::ZERO }
                }
            };
        }
    }
    tonemap_rgb(width, height, &hdr, exposure_scale(&luminances(&hdr)))
}

/// Each colour's luminance (Rec. 709 weights).
pub fn luminances(v: &[Vec3]) -> Vec<f32> {
    v.iter().map(|c| c.dot(Vec3::new(0.2126, 0.7152, 0.0722))).collect()
}

/// An RGB radiance image × `exposure`, tone mapped x/(1 + x) per channel and sRGB-encoded.
pub fn tonemap_rgb(width: usize, height: usize, hdr: &[Vec3], exposure: f32) -> image::RgbImage {
    image::RgbImage::from_fn(width as u32, height as u32, |x, y| {
        let c = hdr[y as usize * width + x as usize].max(Vec3::ZERO) * exposure;
        let t = c / (Vec3::ONE + c);
        image::Rgb([srgb8(t.x), srgb8(t.y), srgb8(t.z)])
    })
}

/// The exposure that maps the mean of the finite non-negative values of `v` to 0.18
/// (1 when there are none, or their mean is 0).
pub fn exposure_scale(v: &[f32]) -> f32 {
    let (sum, n) = v.iter().filter(|x| x.is_finite() && **x >= 0.0).fold((0.0f64, 0usize), |(s, n), x| (s + *x as f64, n + 1));
    if n == 0 || sum <= 0.0 {
        1.0
    } else {
        (0.18 / (sum / n as f64)) as f32
    }
}

/// A linear value in [0, 1] (clamped) as an 8-bit sRGB code.
pub fn srgb8(v: f32) -> u8 {
    let v = if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 };
    let s = if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// A gray radiance image × `exposure`, tone mapped x/(1 + x) and sRGB-encoded.
pub fn tonemap(width: usize, height: usize, v: &[f32], exposure: f32) -> image::RgbImage {
    image::RgbImage::from_fn(width as u32, height as u32, |x, y| {
        let c = v[y as usize * width + x as usize].max(0.0) * exposure;
        let g = srgb8(c / (1.0 + c));
        image::Rgb([g, g, g])
    })
}

/// A rate in [0, 1] per pixel as hue (blue 0 → red 1, through cyan, green and yellow) with
/// the brightness of `weight` / its maximum — [TH17 Fig. 9]'s false-discovery picture.
pub fn heat(width: usize, height: usize, rate: &[f32], weight: &[f32]) -> image::RgbImage {
    let top = weight.iter().copied().filter(|w| w.is_finite()).fold(0.0f32, f32::max);
    image::RgbImage::from_fn(width as u32, height as u32, |x, y| {
        let k = y as usize * width + x as usize;
        let h = 4.0 * rate[k].clamp(0.0, 1.0);
        // Piecewise-linear hue: 0 blue, 1 cyan, 2 green, 3 yellow, 4 red.
        let rgb = [(h - 2.0).clamp(0.0, 1.0), (h.min(4.0 - h)).clamp(0.0, 1.0), (2.0 - h).clamp(0.0, 1.0)];
        let b = if top > 0.0 { weight[k] / top } else { 0.0 };
        image::Rgb(rgb.map(|c| srgb8(c * b)))
    })
}

/// Saves an 8-bit image as PNG.
pub fn save_png(path: &Path, img: &image::RgbImage) -> Result<(), String> {
    img.save_with_format(path, image::ImageFormat::Png).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// Per-mesh lightmap mapping for the metadata: scale/bias from TEXCOORD_1 to the atlas
/// (normalised), or the generated per-triangle atlas UVs.
pub fn mesh_mapping(scene: &Scene, lm: &Lightmap) -> serde_json::Value {
    let (w, h) = (lm.width as f32, lm.height as f32);
    let meshes: Vec<serde_json::Value> = scene
        .meshes
        .iter()
        .enumerate()
        .map(|(mi, m)| {
            if !m.lightmapped {
                return json!({"name": m.name, "lightmapped": false});
            }
            if let Some(c) = lm.charts.iter().find(|c| c.mesh == Some(mi)) {
                // atlas uv = TEXCOORD_1 · scale + bias (the block maps uv_min to its corner).
                let s = c.uv_scale;
                let corner = ((c.offset.0 + lm.padding) as f32 - c.uv_min.x * s, (c.offset.1 + lm.padding) as f32 - c.uv_min.y * s);
                return json!({"name": m.name, "lightmapped": true, "uv": "TEXCOORD_1",
                    "scale": [s / w, s / h], "bias": [corner.0 / w, corner.1 / h]});
            }
            let uvs: Vec<[f32; 6]> =
                lm.triangle_uv[mi].iter().map(|t| [t[0].x / w, t[0].y / h, t[1].x / w, t[1].y / h, t[2].x / w, t[2].y / h]).collect();
            json!({"name": m.name, "lightmapped": true, "uv": "generated", "triangle_uv": uvs})
        })
        .collect();
    serde_json::Value::Array(meshes)
}
