//! naga validation of composed WGSL and export to HLSL, GLSL and MSL through naga's
//! back ends. GLSL output is per entry point, so exports append a trivial compute
//! entry point (`sbf_export_main`); the back ends write every library function.

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

/// Target languages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lang {
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
            Lang::Glsl => "comp.glsl",
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

/// The trivial entry point appended for export.
pub const EXPORT_ENTRY: &str = "\n@compute @workgroup_size(1)\nfn sbf_export_main() {}\n";

/// Translates composed WGSL to `lang`.
pub fn export(source: &str, lang: Lang) -> Result<String, String> {
    if lang == Lang::Wgsl {
        validate(source)?;
        return Ok(source.to_string());
    }
    let full = format!("{source}{EXPORT_ENTRY}");
    let (module, info) = validate(&full)?;
    match lang {
        Lang::Hlsl => {
            let mut out = String::new();
            let options = naga::back::hlsl::Options::default();
            let pipeline = naga::back::hlsl::PipelineOptions::default();
            let mut w = naga::back::hlsl::Writer::new(&mut out, &options, &pipeline);
            w.write(&module, &info, None).map_err(|e| format!("HLSL: {e}"))?;
            Ok(out)
        }
        Lang::Glsl => {
            let mut out = String::new();
            let options = naga::back::glsl::Options { version: naga::back::glsl::Version::Desktop(450), ..Default::default() };
            let pipeline = naga::back::glsl::PipelineOptions {
                shader_stage: naga::ShaderStage::Compute,
                entry_point: "sbf_export_main".into(),
                multiview: None,
            };
            let mut w =
                naga::back::glsl::Writer::new(&mut out, &module, &info, &options, &pipeline, naga::proc::BoundsCheckPolicies::default())
                    .map_err(|e| format!("GLSL: {e}"))?;
            w.write().map_err(|e| format!("GLSL: {e}"))?;
            Ok(out)
        }
        Lang::Msl => {
            let options = naga::back::msl::Options::default();
            let pipeline = naga::back::msl::PipelineOptions::default();
            let (out, _) = naga::back::msl::write_string(&module, &info, &options, &pipeline).map_err(|e| format!("MSL: {e}"))?;
            Ok(out)
        }
        Lang::Wgsl => unreachable!("handled above"),
    }
}
