//! What one rendered configuration shades with: the plain E/π lightmap (diffuse only —
//! Table 8.1's "none") or one baked basis with a specular runtime path, stored as f32 or
//! f16 texels.

use crate::accumulate::BasisId;
use sbf::glam::DVec3;
use sbf::profile::SpecularPath;

/// The lightmap a configuration reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// `irradiance.exr`: E/π per texel; diffuse only.
    Irradiance,
    /// The basis's coefficients (`{basis}_{lobe}.exr`), in the texel's tangent frame.
    Basis(BasisId),
}

/// Texel storage on the GPU (and the CPU twin rounds the same way).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    F32,
    F16,
}

impl Storage {
    pub fn name(self) -> &'static str {
        match self {
            Storage::F32 => "f32",
            Storage::F16 => "f16",
        }
    }
    /// Bytes per lobe and texel (RGBA texels: the fourth channel is padding a GPU format has).
    pub fn bytes_per_lobe(self) -> usize {
        match self {
            Storage::F32 => 16,
            Storage::F16 => 8,
        }
    }
}

/// How a frame is shaded on the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FramePath {
    /// A depth pre-pass, then every visible pixel shaded in the raster pass's fragment
    /// shader (`fs_frame`).
    Forward,
    /// A depth pre-pass and a G-buffer pass (the fragments' inputs in f32), then shading in
    /// a compute pass over 8×8-pixel tiles (`cs_frame`), as current engines light a frame.
    Deferred,
}

impl FramePath {
    pub fn name(self) -> &'static str {
        match self {
            FramePath::Forward => "forward",
            FramePath::Deferred => "deferred",
        }
    }
}

/// How the raster pass interpolates the lightmap between texel centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LightmapFilter {
    /// Four `textureLoad`s weighted in f32 — what the CPU twin computes in f64.
    #[default]
    Exact,
    /// The sampler's bilinear filter, one fetch per lobe, as engines sample lightmaps: the
    /// weights carry the GPU's sub-texel precision (Vulkan guarantees ≥ 4 bits; 8 is usual).
    /// f32 lightmaps need the adapter's `FLOAT32_FILTERABLE`.
    Hardware,
    /// Cubic B-spline over the 4×4 nearest texels, smoother than bilinear (C² across texel
    /// borders) at the price of blurring, reaching one texel further (closer to a chart's
    /// border: the bake's padding must cover it). On the GPU by four bilinear taps of the
    /// sampler placed so their weights make the B-spline's (Sigg and Hadwiger 2005, GPU Gems 2
    /// ch. 20), as engines sample it; the CPU twin sums the 16 texels exactly.
    Bicubic,
}

impl LightmapFilter {
    pub fn parse(s: &str) -> Option<LightmapFilter> {
        match s {
            "exact" => Some(LightmapFilter::Exact),
            "hardware" => Some(LightmapFilter::Hardware),
            "bicubic" => Some(LightmapFilter::Bicubic),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            LightmapFilter::Exact => "exact",
            LightmapFilter::Hardware => "hardware",
            LightmapFilter::Bicubic => "bicubic",
        }
    }
    /// Whether the GPU reads the lightmap through a filtering sampler.
    pub fn samples(self) -> bool {
        self != LightmapFilter::Exact
    }
}

/// One configuration of the comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lighting {
    pub encoding: Encoding,
    /// The specular runtime (ignored for [`Encoding::Irradiance`]).
    pub specular: SpecularPath,
    pub storage: Storage,
    /// The SG lobes' sharpness λ the bake encoded with (bake.json; ignored for other
    /// encodings).
    pub sg_sharpness: f64,
}

impl Lighting {
    /// A name for files and reports: `none`, `sh2`, `ad9-tables`, `sg12-f16`, ….
    pub fn name(&self) -> String {
        let mut s = match self.encoding {
            Encoding::Irradiance => "none".to_string(),
            Encoding::Basis(b) => b.name().to_string(),
        };
        if matches!(self.encoding, Encoding::Basis(b) if !b.is_sh()) && self.specular == SpecularPath::Tables {
            s.push_str("-tables");
        }
        if self.storage == Storage::F16 {
            s.push_str("-f16");
        }
        s
    }

    /// Refuses what the runtime cannot shade: a basis that is not a lightmap basis, and SG's
    /// per-lobe tables at another than the default sharpness (luts/lobe_ggx_sg6.sbflut).
    pub fn check(&self) -> Result<(), String> {
        if let Encoding::Basis(b) = self.encoding {
            if !b.info().lightmap {
                return Err(format!("{b} is not a lightmap basis: the renderer shades the registry's lightmap bases"));
            }
        }
        let sg = matches!(self.encoding, Encoding::Basis(b) if b.is_sg());
        if sg && self.specular == SpecularPath::Tables && self.sg_sharpness != crate::accumulate::SG_HEMISPHERE_SHARPNESS {
            return Err(format!(
                "{}: the SG per-lobe GGX table is for λ {} (luts/lobe_ggx_sg6.sbflut), the bake's λ is {}: use the fits (--specular fit)",
                self.name(),
                crate::accumulate::SG_HEMISPHERE_SHARPNESS,
                self.sg_sharpness
            ));
        }
        Ok(())
    }

    /// Lobes per texel (1 for the plain E/π).
    pub fn lobes(&self) -> usize {
        match self.encoding {
            Encoding::Irradiance => 1,
            Encoding::Basis(b) => lobe_count(b),
        }
    }

    /// Bytes per texel at this storage (RGBA texels).
    pub fn bytes_per_texel(&self) -> usize {
        self.lobes() * self.storage.bytes_per_lobe()
    }
}

/// Lobes of a basis.
pub fn lobe_count(b: BasisId) -> usize {
    b.lobes()
}

/// The lobe axes of the SG and AD layouts in the texel's tangent frame (empty for SH and
/// the plain E/π), from the same `sbf` layouts the bake encoded with.
pub fn lobe_axes(e: Encoding) -> Vec<DVec3> {
    match e {
        Encoding::Irradiance => Vec::new(),
        Encoding::Basis(b) => b.axes(),
    }
}

/// A surface's material as the shading reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceMaterial {
    /// Lambert albedo.
    pub albedo: DVec3,
    /// GGX α.
    pub alpha: f64,
    /// Schlick F0 (f90 = 1); zero: no specular layer.
    pub f0: DVec3,
}

impl SurfaceMaterial {
    pub fn of(m: &crate::scene::Material) -> SurfaceMaterial {
        SurfaceMaterial { albedo: m.diffuse_albedo().as_dvec3(), alpha: m.alpha() as f64, f0: m.specular_f0().as_dvec3() }
    }
    pub fn glossy(&self) -> bool {
        self.f0.max_element() > 0.0
    }
}
