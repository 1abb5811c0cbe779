//! naga validation of composed WGSL and its export: WGSL as composed, HLSL, GLSL and MSL
//! as include files written by [`crate::emit`].

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

/// Target languages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Lang {
    #[default]
    Wgsl,
    Hlsl,
    Glsl,
    Msl,
}

impl Lang {
    pub const ALL: [Lang; 4] = [Lang::Wgsl, Lang::Hlsl, Lang::Glsl, Lang::Msl];

    pub fn parse(s: &str) -> Result<Lang, String> {
        match s {
            "wgsl" => Ok(Lang::Wgsl),
            "hlsl" => Ok(Lang::Hlsl),
            "glsl" => Ok(Lang::Glsl),
            "msl" => Ok(Lang::Msl),
            _ => Err(format!("unknown language '{s}' (wgsl, hlsl, glsl, msl)")),
        }
    }

    pub fn extension(self) -> &'static str {
        match self {
            Lang::Wgsl => "wgsl",
            Lang::Hlsl => "hlsl",
            Lang::Glsl => "glsl",
            Lang::Msl => "metal",
        }
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

/// Translates composed WGSL to `lang`: WGSL as composed (validated), the other
/// languages through [`crate::emit`] as an include file headed by `opts`.
pub fn export_with(source: &str, lang: Lang, opts: &crate::emit::Options) -> Result<String, String> {
    let (module, info) = validate(source)?;
    if lang == Lang::Wgsl {
        return Ok(source.to_string());
    }
    crate::emit::library(source, &module, &info, lang, opts)
}

/// [`export_with`] with a header that names no configuration.
pub fn export(source: &str, lang: Lang) -> Result<String, String> {
    export_with(source, lang, &crate::emit::Options { title: "library".into(), ..Default::default() })
}
