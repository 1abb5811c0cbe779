//! The texture maps of glTF materials (glTF 2.0 §3.8–3.9): base colour, metallic-roughness
//! and emissive maps with their samplers and KHR_texture_transform, their images decoded
//! from a buffer view, a data URI or a file next to the asset (PNG or JPEG, through the
//! `image` crate) into 8-bit RGBA. Images wider or taller than [`MAX_TEXTURE_SIZE`] are
//! reduced by whole halvings (a 2×2 box in linear light per step), and the report says so;
//! an image that cannot be read or decoded leaves its map out, with a note.
//! Alpha mode MASK makes the base colour's alpha below the cutoff a hole rays pass
//! through. Normal maps are loaded into their own list for the renderer's shading (the bake
//! does not read them). Not used, and noted: occlusion maps, alpha mode BLEND (opaque), and
//! texture coordinate sets above 1.

use super::texture::{AlphaMask, Filter, Maps, NormalMap, Texture, TextureRef, Wrap};
use std::path::Path;

/// The largest texture side kept (larger images are halved until they fit).
pub const MAX_TEXTURE_SIZE: u32 = 4096;
/// The largest image file read (bytes).
const MAX_IMAGE_FILE: u64 = 512 << 20;

/// The maps of every material, and the textures they read (one per glTF texture used):
/// those the bake samples, and the normal maps' apart (the renderer's shading alone reads
/// them, so a bake never uploads them).
pub(crate) struct Loaded {
    pub maps: Vec<Maps>,
    pub textures: Vec<Texture>,
    pub normal_textures: Vec<Texture>,
}

/// Reads the maps of `doc`'s materials; `data` are its buffers, `base` the asset's folder.
pub(crate) fn load(doc: &gltf::Document, data: &[Vec<u8>], base: &Path, notes: &mut Vec<String>) -> Result<Loaded, String> {
    let mut textures = Vec::new();
    // glTF texture index → index into `textures`.
    let mut index: Vec<Option<usize>> = vec![None; doc.textures().len()];
    let mut normal_textures = Vec::new();
    let mut normal_index: Vec<Option<usize>> = vec![None; doc.textures().len()];
    let mut maps = Vec::new();
    for m in doc.materials() {
        let name = m.name().unwrap_or("?").to_string();
        let pbr = m.pbr_metallic_roughness();
        let mut map = |info: Option<gltf::texture::Info>, what: &str| -> Result<Option<TextureRef>, String> {
            let Some(info) = info else { return Ok(None) };
            let t = info.texture();
            let k = match index[t.index()] {
                Some(k) => k,
                None => match texture(&t, what != "metallic-roughness", data, base, notes) {
                    Ok(tex) => {
                        textures.push(tex);
                        index[t.index()] = Some(textures.len() - 1);
                        textures.len() - 1
                    }
                    // An image that cannot be read or decoded (KTX2, say) leaves the map out.
                    Err(e) => {
                        notes.push(format!("material '{name}': its {what} map is not used: {e}; its factor stands alone"));
                        return Ok(None);
                    }
                },
            };
            let mut r = TextureRef { texcoord: info.tex_coord(), ..TextureRef::new(k) };
            if let Some(x) = info.texture_transform() {
                r = r.with_transform(x.offset(), x.rotation(), x.scale());
                r.texcoord = x.tex_coord().unwrap_or(r.texcoord);
            }
            if r.texcoord > 1 {
                notes.push(format!("material '{name}': its {what} map reads TEXCOORD_{}: not used (sets 0 and 1 only)", r.texcoord));
                return Ok(None);
            }
            Ok(Some(r))
        };
        let mut maps_of = Maps {
            base_color: map(pbr.base_color_texture(), "base colour")?,
            metallic_roughness: map(pbr.metallic_roughness_texture(), "metallic-roughness")?,
            emissive: map(m.emissive_texture(), "emissive")?,
            mask: (m.alpha_mode() == gltf::material::AlphaMode::Mask)
                .then(|| AlphaMask { factor: pbr.base_color_factor()[3], cutoff: m.alpha_cutoff().unwrap_or(0.5) }),
            normal: None,
        };
        if let Some(nt) = m.normal_texture() {
            let t = nt.texture();
            let k = match normal_index[t.index()] {
                Some(k) => Some(k),
                None => match texture(&t, false, data, base, notes) {
                    Ok(tex) => {
                        normal_textures.push(tex);
                        normal_index[t.index()] = Some(normal_textures.len() - 1);
                        Some(normal_textures.len() - 1)
                    }
                    Err(e) => {
                        notes.push(format!("material '{name}': its normal map is not used: {e}"));
                        None
                    }
                },
            };
            if let Some(k) = k {
                let mut r = TextureRef { texcoord: nt.tex_coord(), ..TextureRef::new(k) };
                // gltf 1.4 has no accessor for a normal texture's KHR_texture_transform: read
                // the extension's JSON (offset, rotation, scale, texCoord; glTF defaults).
                if let Some(x) = nt.extension_value("KHR_texture_transform") {
                    let pair = |key: &str, d: [f32; 2]| {
                        x[key].as_array().map_or(d, |a| [0, 1].map(|i| a.get(i).and_then(|v| v.as_f64()).map_or(d[i], |v| v as f32)))
                    };
                    let rotation = x["rotation"].as_f64().unwrap_or(0.0) as f32;
                    r = r.with_transform(pair("offset", [0.0, 0.0]), rotation, pair("scale", [1.0, 1.0]));
                    r.texcoord = x["texCoord"].as_u64().map_or(r.texcoord, |v| v as u32);
                }
                if r.texcoord > 1 {
                    notes.push(format!("material '{name}': its normal map reads TEXCOORD_{}: not used (sets 0 and 1 only)", r.texcoord));
                } else {
                    maps_of.normal = Some(NormalMap { texture: r, scale: nt.scale() });
                    notes.push(format!("material '{name}': its normal map is used by the renderer's shading (render --normal-maps), not at the bake's path vertices"));
                }
            }
        }
        if m.occlusion_texture().is_some() {
            notes.push(format!("material '{name}': its occlusion map is not used"));
        }
        if m.alpha_mode() == gltf::material::AlphaMode::Blend {
            notes.push(format!("material '{name}': alpha mode BLEND taken as opaque (MASK is honoured)"));
        }
        maps.push(maps_of);
    }
    if !textures.is_empty() {
        let bytes: usize = textures.iter().map(Texture::bytes).sum();
        notes.push(format!(
            "{} textures sampled (mip 0, the samplers' magnification filter): {:.1} MB",
            textures.len(),
            bytes as f64 / 1e6
        ));
    }
    Ok(Loaded { maps, textures, normal_textures })
}

/// One glTF texture: its image decoded to RGBA8 (halved to fit: in linear light when
/// `srgb`, as its first use reads it) with its sampler.
fn texture(t: &gltf::Texture, srgb: bool, data: &[Vec<u8>], base: &Path, notes: &mut Vec<String>) -> Result<Texture, String> {
    let img = t.source();
    let name = img.name().or(t.name()).map_or_else(|| format!("image {}", img.index()), str::to_string);
    let bytes: Vec<u8> = match img.source() {
        gltf::image::Source::View { view, .. } => {
            let buf = data
                .get(view.buffer().index())
                .ok_or_else(|| format!("texture '{name}': buffer {} was not loaded", view.buffer().index()))?;
            let end = view.offset().checked_add(view.length()).filter(|e| *e <= buf.len());
            let end = end.ok_or_else(|| format!("texture '{name}': bufferView {} lies outside its buffer", view.index()))?;
            buf[view.offset()..end].to_vec()
        }
        gltf::image::Source::Uri { uri, .. } => match uri.strip_prefix("data:") {
            Some(rest) => {
                let (_, payload) = rest.split_once(";base64,").ok_or_else(|| format!("texture '{name}': data URI is not base64"))?;
                super::uri::base64(payload).map_err(|e| format!("texture '{name}': {e}"))?
            }
            None => read_image_file(&base.join(super::uri::percent_decode(uri)), &name)?,
        },
    };
    let decoded = image::load_from_memory(&bytes).map_err(|e| format!("texture '{name}': {e}"))?.to_rgba8();
    let (mut w, mut h) = decoded.dimensions();
    let mut texels: Vec<[u8; 4]> = decoded.pixels().map(|p| p.0).collect();
    let (w0, h0) = (w, h);
    while w > MAX_TEXTURE_SIZE || h > MAX_TEXTURE_SIZE {
        (texels, w, h) = halve(&texels, w, h, srgb);
    }
    if (w, h) != (w0, h0) {
        notes.push(format!("texture '{name}': {w0}×{h0} reduced to {w}×{h} (at most {MAX_TEXTURE_SIZE} per side)"));
    }
    let s = t.sampler();
    let wrap = |m: gltf::texture::WrappingMode| match m {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    };
    let filter = match s.mag_filter() {
        Some(gltf::texture::MagFilter::Nearest) => Filter::Nearest,
        _ => Filter::Bilinear,
    };
    Ok(Texture { name, width: w, height: h, texels, wrap: [wrap(s.wrap_s()), wrap(s.wrap_t())], filter })
}

/// An image file next to the asset (a regular file, at most MAX_IMAGE_FILE bytes).
fn read_image_file(p: &Path, name: &str) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(p).map_err(|e| format!("texture '{name}': {}: {e}", p.display()))?;
    if !meta.is_file() || meta.len() > MAX_IMAGE_FILE {
        return Err(format!("texture '{name}': {}: not a regular file of at most {} MB", p.display(), MAX_IMAGE_FILE >> 20));
    }
    std::fs::read(p).map_err(|e| format!("texture '{name}': {}: {e}", p.display()))
}

/// The image at half size (odd sides round up; edge texels repeat), each 2×2 block
/// averaged — RGB in linear light when `srgb` (and re-encoded), alpha and data directly.
fn halve(texels: &[[u8; 4]], w: u32, h: u32, srgb: bool) -> (Vec<[u8; 4]>, u32, u32) {
    let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
    let at = |x: u32, y: u32| texels[(y.min(h - 1) * w + x.min(w - 1)) as usize];
    let encode = |l: f32| -> u8 {
        let s = if l <= 0.0031308 { 12.92 * l } else { 1.055 * l.powf(1.0 / 2.4) - 0.055 };
        (s * 255.0).round().clamp(0.0, 255.0) as u8
    };
    let mut out = Vec::with_capacity((nw * nh) as usize);
    for y in 0..nh {
        for x in 0..nw {
            let q = [at(2 * x, 2 * y), at(2 * x + 1, 2 * y), at(2 * x, 2 * y + 1), at(2 * x + 1, 2 * y + 1)];
            let mut px = [0u8; 4];
            for c in 0..4 {
                px[c] = if srgb && c < 3 {
                    encode(q.iter().map(|t| super::texture::srgb_to_linear(t[c])).sum::<f32>() / 4.0)
                } else {
                    (q.iter().map(|t| t[c] as u32).sum::<u32>() as f32 / 4.0).round() as u8
                };
            }
            out.push(px);
        }
    }
    (out, nw, nh)
}
