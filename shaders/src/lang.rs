//! The target languages (WGSL and the dialects the library is exported to) and naga's
//! validation of composed WGSL — what both the writer ([`crate::emit`]) and the export
//! ([`crate::export`]) start from.

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

/// Target languages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Lang {
    #[default]
    Wgsl,
    Hlsl,
    /// GLSL in one of its dialects.
    Glsl(Glsl),
    Msl,
}

/// The GLSL dialects: they differ in how a texture is declared and sampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Glsl {
    /// Vulkan GLSL 4.50 (glslang → SPIR-V): separate `texture2D`/`sampler` objects,
    /// `texelFetch` on a texture through `GL_EXT_samplerless_texture_functions`.
    #[default]
    Vulkan,
    /// OpenGL 3.3–4.6 core: combined `sampler2D`/`sampler3D`; a function that takes a
    /// texture and a sampler in the other languages takes the one combined sampler.
    Gl,
    /// OpenGL ES 3.0 (WebGL 2): as [`Glsl::Gl`], with `highp` samplers (ES fragment
    /// shaders have no default precision for 3D and array samplers).
    Es,
}

impl Lang {
    /// Every language and dialect the library is written in.
    pub const ALL: [Lang; 6] = [Lang::Wgsl, Lang::Hlsl, Lang::Glsl(Glsl::Vulkan), Lang::Glsl(Glsl::Gl), Lang::Glsl(Glsl::Es), Lang::Msl];
    /// Vulkan GLSL, the dialect `glsl` names.
    pub const GLSL: Lang = Lang::Glsl(Glsl::Vulkan);

    pub fn parse(s: &str) -> Result<Lang, String> {
        match s {
            "wgsl" => Ok(Lang::Wgsl),
            "hlsl" => Ok(Lang::Hlsl),
            "glsl" => Ok(Lang::Glsl(Glsl::Vulkan)),
            "glsl-gl" => Ok(Lang::Glsl(Glsl::Gl)),
            "glsl-es" => Ok(Lang::Glsl(Glsl::Es)),
            "msl" => Ok(Lang::Msl),
            _ => {
                Err(format!("unknown language '{s}' (wgsl, hlsl, glsl (Vulkan), glsl-gl (OpenGL 3.3+ core), glsl-es (OpenGL ES 3.0), msl)"))
            }
        }
    }

    /// The file extension of an include file in this language (`gl.glsl`, `es.glsl` for
    /// the OpenGL dialects).
    pub fn extension(self) -> &'static str {
        match self {
            Lang::Wgsl => "wgsl",
            Lang::Hlsl => "hlsl",
            Lang::Glsl(Glsl::Vulkan) => "glsl",
            Lang::Glsl(Glsl::Gl) => "gl.glsl",
            Lang::Glsl(Glsl::Es) => "es.glsl",
            Lang::Msl => "metal",
        }
    }

    /// Whether this is GLSL in any dialect.
    pub fn is_glsl(self) -> bool {
        matches!(self, Lang::Glsl(_))
    }

    /// Whether textures are combined samplers (the OpenGL dialects): a sampler parameter
    /// is dropped and a texture parameter is the combined sampler.
    pub fn combined_samplers(self) -> bool {
        matches!(self, Lang::Glsl(Glsl::Gl | Glsl::Es))
    }
}

/// Parses and validates WGSL; the error names the line and the problem.
pub fn validate(source: &str) -> Result<(naga::Module, ModuleInfo), String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let info = Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .map_err(|e| format!("validation: {}", e.emit_to_string(source)))?;
    Ok((module, info))
}

/// [`validate`] for a module that calls subgroup built-ins: validated with the subgroup
/// capabilities a device with `Features::SUBGROUP` has (naga 30 does not take
/// `enable subgroups;` yet; the built-ins need no directive).
pub fn validate_subgroups(source: &str) -> Result<(naga::Module, ModuleInfo), String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let caps = Capabilities::SUBGROUP;
    let mut v = Validator::new(ValidationFlags::all(), caps);
    v.subgroup_stages(naga::valid::ShaderStages::COMPUTE);
    v.subgroup_operations(naga::valid::SubgroupOperationSet::all());
    let info = v.validate(&module).map_err(|e| format!("validation: {}", e.emit_to_string(source)))?;
    Ok((module, info))
}
