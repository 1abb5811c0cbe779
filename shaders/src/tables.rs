//! The library's tables as textures an engine uploads as they are: KTX 2.0 files (Khronos,
//! "KTX File Format Specification 2.0") in the exact layout and format the library's
//! functions read, one level, no supercompression, with a Khronos data format descriptor
//! (from the `ktx2` crate) and the layout in words under the key `sbf.layout`.
//!
//! | file | texture | format | texel (x, y, layer or z) | read by |
//! |---|---|---|---|---|
//! | `dfg.ktx2` | 2D | rg32float | (n·v, GGX α) nodes | `sbf_sh_l*_specular`, `sbf_sg_split_sum_setup`, energy compensation |
//! | `ad_specular_2d.ktx2` | 2D | rg32float | (n·v, GGX α) nodes | `sbf_ad9_specular`, `sbf_ad12_specular` |
//! | `lobe_ggx_{sg6,ad}.ktx2` | 2D array | rg32float | (ψ, γ, n·v node × N√α + √α node) | `sbf_lobe_ggx_pixel`/`_lobe` |
//! | `lobe_ggx_{sg6,ad}_filtered.ktx2` | 3D | rg16float | (√α node × Nψ + ψ node, γ, n·v) | `sbf_lobe_ggx_filtered_*` (linear, clamp) |
//!
//! The 2D tables are read texel by texel (`texelFetch`/`Load`, bilinear by hand); the
//! filtered one through a linear clamp-to-edge sampler. Values are the committed tables'
//! (`luts/*.sbflut`): f32 as stored, f16 exactly (the lobe tables are committed as f16).

use sbf::luts::format::f32_to_f16;
use sbf::recon::lobe_ggx::Table;
use sbf::recon::lut::Lut2;

/// How a table texture is bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `texture_2d` / `texture2D` / `Texture2D`.
    D2,
    /// `texture_2d_array` (layers in `size[2]`).
    D2Array,
    /// `texture_3d` (depth in `size[2]`).
    D3,
}

/// Texel format: two channels, f32 or f16.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Rg32Float,
    Rg16Float,
}

/// One table as a texture.
#[derive(Debug, Clone)]
pub struct TableTexture {
    /// File stem (`dfg`, `lobe_ggx_sg6_filtered`, …).
    pub name: String,
    pub kind: Kind,
    /// Width, height, and layers (2D array) or depth (3D); 1 for a 2D texture.
    pub size: [u32; 3],
    pub format: Format,
    /// Texels, little-endian, x fastest, then y, then layer or z.
    pub data: Vec<u8>,
    /// The layout in words (axes, channels, how to sample, which functions read it).
    pub layout: String,
}

/// A fitgen 2D table (`dfg`, `ad_specular_2d`) as the rg32float 2D texture `lut2_sample`
/// reads: x along the table's first axis (n·v), y along the second (GGX α); a one-channel
/// table repeats its value in both channels.
pub fn lut2_texture(name: &str, l: &Lut2, what: &str) -> TableTexture {
    let mut data = Vec::with_capacity(l.width * l.height * 8);
    for k in 0..l.width * l.height {
        let a = l.data[k * l.channels];
        let b = if l.channels > 1 { l.data[k * l.channels + 1] } else { a };
        data.extend(a.to_le_bytes());
        data.extend(b.to_le_bytes());
    }
    TableTexture {
        name: name.to_string(),
        kind: Kind::D2,
        size: [l.width as u32, l.height as u32, 1],
        format: Format::Rg32Float,
        data,
        layout: format!(
            "{what}. 2D rg32float, {}x{} texel centres: x = n·v in [0, 1], y = GGX alpha (roughness squared, not perceptual roughness) in [0, 1]; r = f0 scale, g = f90 scale. Read texel by texel (texelFetch/Load), bilinear by hand (lut2_sample).",
            l.width, l.height
        ),
    }
}

/// A per-lobe GGX table as the rg32float 2D array `lobe_ggx_pixel`/`lobe_ggx_lobe` read:
/// x = ψ node, y = γ node, layer = n·v node × N_√α + √α node.
pub fn lobe_array_texture(name: &str, t: &Table) -> TableTexture {
    let g = t.grid;
    let mut data = Vec::with_capacity(t.values.len() * 4);
    // The table's order is already ψ fastest, then γ, √α, n·v.
    for v in &t.values {
        data.extend(v.to_le_bytes());
    }
    TableTexture {
        name: name.to_string(),
        kind: Kind::D2Array,
        size: [g.psi as u32, g.gamma as u32, (g.theta_v * g.alpha) as u32],
        format: Format::Rg32Float,
        data,
        layout: format!(
            "Per-lobe GGX response (R0, R1) of one radial lobe ({name}). 2D array rg32float: x = psi node ({} nodes over [0, pi], edge to edge), y = gamma node ({} over [0, pi]), layer = n·v node x {} + sqrt(alpha) node ({} n·v nodes and {} sqrt(alpha) nodes over [0, 1]). Read texel by texel, multilinear by hand (lobe_ggx_pixel, lobe_ggx_lobe).",
            g.psi, g.gamma, g.alpha, g.theta_v, g.alpha
        ),
    }
}

/// The texels of the filtered layout as f16 bits (two per texel): x = √α node × N_ψ + ψ
/// node, y = γ node, z = n·v node.
pub fn lobe_filtered_texels(t: &Table) -> ([u32; 3], Vec<u16>) {
    let g = t.grid;
    let (np, ng, na, nv) = (g.psi, g.gamma, g.alpha, g.theta_v);
    let mut out = Vec::with_capacity(2 * np * ng * na * nv);
    for i in 0..nv {
        for k in 0..ng {
            for j in 0..na {
                for l in 0..np {
                    // The table's order: ψ fastest, then γ, √α, n·v.
                    let at = 2 * (((i * na + j) * ng + k) * np + l);
                    out.extend([f32_to_f16(t.values[at]), f32_to_f16(t.values[at + 1])]);
                }
            }
        }
    }
    ([(na * np) as u32, ng as u32, nv as u32], out)
}

/// A per-lobe GGX table as the rg16float 3D texture `lobe_ggx_filtered_*` sample.
pub fn lobe_filtered_texture(name: &str, t: &Table) -> TableTexture {
    let g = t.grid;
    let (size, texels) = lobe_filtered_texels(t);
    TableTexture {
        name: format!("{name}_filtered"),
        kind: Kind::D3,
        size,
        format: Format::Rg16Float,
        data: texels.iter().flat_map(|h| h.to_le_bytes()).collect(),
        layout: format!(
            "Per-lobe GGX response (R0, R1) of one radial lobe ({name}), for the texture unit's filter. 3D rg16float: x = sqrt(alpha) node x {} + psi node ({} sqrt(alpha) tiles of {} psi nodes), y = gamma node ({}), z = n·v node ({}). Sample at mip 0 with a linear, clamp-to-edge sampler (lobe_ggx_filtered_pixel, lobe_ggx_filtered_lobe).",
            g.psi, g.alpha, g.psi, g.gamma, g.theta_v
        ),
    }
}

const DFG: &str = "Split-sum GGX table (Karis 2013), luts/dfg.sbflut";
const AD_SPECULAR: &str = "Ambient Dice specular scale ([Roughton19 Listing 8.2]), luts/ad_specular_2d.sbflut";

/// Every committed table in every layout the library reads.
pub fn all() -> Vec<TableTexture> {
    use sbf::recon::tables as c;
    vec![
        lut2_texture("dfg", c::dfg(), DFG),
        lut2_texture("ad_specular_2d", c::ad_specular_2d(), AD_SPECULAR),
        lobe_array_texture("lobe_ggx_sg6", c::lobe_ggx_sg6()),
        lobe_filtered_texture("lobe_ggx_sg6", c::lobe_ggx_sg6()),
        lobe_array_texture("lobe_ggx_ad", c::lobe_ggx_ad()),
        lobe_filtered_texture("lobe_ggx_ad", c::lobe_ggx_ad()),
    ]
}

/// The table textures a runtime with these composition features reads (a bake's runtime):
/// the 2D tables by their `.sbflut` names, and a lobe table in the layout of each lobe
/// feature present (`lobe-ggx-specular`: the 2D array, `lobe-ggx-filtered`: 3D).
pub fn for_runtime(luts: &[String], features: &[&str]) -> Vec<TableTexture> {
    use sbf::recon::tables as c;
    let mut out = Vec::new();
    for l in luts {
        let stem = l.trim_end_matches(".sbflut");
        match stem {
            "dfg" => out.push(lut2_texture(stem, c::dfg(), DFG)),
            "ad_specular_2d" => out.push(lut2_texture(stem, c::ad_specular_2d(), AD_SPECULAR)),
            "lobe_ggx_sg6" | "lobe_ggx_ad" => {
                let t = if stem == "lobe_ggx_sg6" { c::lobe_ggx_sg6() } else { c::lobe_ggx_ad() };
                if features.contains(&"lobe-ggx-specular") {
                    out.push(lobe_array_texture(stem, t));
                }
                if features.contains(&"lobe-ggx-filtered") {
                    out.push(lobe_filtered_texture(stem, t));
                }
            }
            _ => {}
        }
    }
    out
}

/// The KTX 2.0 file of a table texture ([`sbf::ktx`]), its layout under `sbf.layout`.
pub fn ktx2(t: &TableTexture) -> Result<Vec<u8>, String> {
    use sbf::ktx::{Dimension, Format as Vk, Ktx2Image};
    let format = match t.format {
        Format::Rg32Float => Vk::R32G32_SFLOAT,
        Format::Rg16Float => Vk::R16G16_SFLOAT,
    };
    let dimension = match t.kind {
        Kind::D2 => Dimension::D2,
        Kind::D2Array => Dimension::D2Array { layers: t.size[2] },
        Kind::D3 => Dimension::D3 { depth: t.size[2] },
    };
    Ktx2Image {
        format,
        size: [t.size[0], t.size[1]],
        dimension,
        key_values: vec![
            ("KTXwriter".into(), format!("sbf shaders {}", env!("CARGO_PKG_VERSION"))),
            ("sbf.layout".into(), t.layout.clone()),
        ],
        data: &t.data,
    }
    .to_bytes()
    .map_err(|e| format!("{}: {e}", t.name))
}
