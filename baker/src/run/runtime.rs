//! The runtime a bake writes beside its images: `runtime.wgsl` composed for the bases and
//! the scene's BRDF (with a profile, also exported to its language, and what its
//! Lambert-only BRDF set left out), and the look-up tables that runtime reads.

use super::Options;
use crate::output;
use crate::output::bake_json::RuntimeJson;

/// Writes the runtime shader library the bake needs (and, with a profile, its export and
/// what its Lambert-only BRDF set left out) and its LUTs; bake.json's account of them.
pub(super) fn write_runtime(o: &Options, glossy: bool, log: &mut dyn FnMut(String)) -> Result<RuntimeJson, String> {
    // Specular runtime: only for a scene with a glossy material and a profile (if any) whose
    // BRDF set has GGX.
    let specular = glossy && o.spec.profile.as_ref().is_none_or(|p| p.specular);
    // The profile's specular paths (without a profile: the fits, the library's default).
    let paths: Vec<sbf::profile::SpecularPath> = match (&o.spec.profile, specular) {
        (_, false) => Vec::new(),
        (Some(p), true) => p.specular_paths.clone(),
        (None, true) => vec![sbf::profile::SpecularPath::Fit],
    };
    // Every basis the bake wrote: the lightmap's and, when probes were baked, theirs.
    let mut bases = o.spec.config.bases.clone();
    if o.spec.probes.is_some() {
        bases.extend(o.spec.probe_bases.iter().filter(|b| !o.spec.config.bases.contains(b)));
    }
    let compensated = o.spec.profile.as_ref().is_some_and(|p| p.multiple_scattering);
    let (features, luts) = output::runtime_features(&bases, &paths, compensated);
    let cfg = shaders::compose::Config::parse(&features.join(","))?;
    let runtime = shaders::compose::compose(&cfg)?;
    // As the library exports it: the items under their sbf_/Sbf/SBF_ names.
    let runtime_wgsl = shaders::export::export_with(&runtime.source, shaders::export::Lang::Wgsl, &shaders::emit::Options::default())?;
    std::fs::write(o.run.out.join("runtime.wgsl"), runtime_wgsl).map_err(|e| format!("runtime.wgsl: {e}"))?;
    let mut runtime_files = vec!["runtime.wgsl".to_string()];
    if let Some(p) = &o.spec.profile {
        let lang = shaders::export::Lang::parse(&p.language)?;
        if p.language != "wgsl" {
            let name = format!("runtime.{}", lang.extension());
            let opts = shaders::emit::Options {
                title: format!("bake runtime for profile '{}' ({})", p.name, features.join(", ")),
                roots: shaders::library::roots(&cfg),
                ..Default::default()
            };
            std::fs::write(o.run.out.join(&name), shaders::export::export_with(&runtime.source, lang, &opts)?)
                .map_err(|e| format!("{name}: {e}"))?;
            runtime_files.push(name);
        }
        if glossy && !p.specular {
            let (spec_features, spec_luts) = output::runtime_features(&bases, &[sbf::profile::SpecularPath::Fit], false);
            let with = shaders::compose::compose(&shaders::compose::Config::parse(&spec_features.join(","))?)?;
            let lut_bytes: usize = spec_luts.iter().map(|l| embedded_lut(l).map_or(0, |d| d.len())).sum();
            let saved = with.source.len() - runtime.source.len();
            log(if saved + lut_bytes == 0 {
                format!(
                    "profile '{}': Lambert only — the scene is glossy, but these bases have no specular runtime path to leave out",
                    p.name
                )
            } else {
                format!("profile '{}': Lambert only — specular runtime left out although the scene is glossy: {saved} WGSL bytes and {lut_bytes} LUT bytes not written", p.name)
            });
        }
    }
    for l in &luts {
        let data = embedded_lut(l)?;
        std::fs::write(o.run.out.join(l), data).map_err(|e| format!("{l}: {e}"))?;
    }
    // The same tables as KTX 2.0 textures in the layouts the runtime's functions read.
    let mut textures = Vec::new();
    for t in shaders::tables::for_runtime(&luts, &features) {
        let name = format!("{}.ktx2", t.name);
        std::fs::write(o.run.out.join(&name), shaders::tables::ktx2(&t)?).map_err(|e| format!("{name}: {e}"))?;
        textures.push(name);
    }
    Ok(RuntimeJson {
        wgsl: "runtime.wgsl",
        files: runtime_files,
        features,
        luts,
        textures,
        specular_paths: paths.iter().map(|p| p.name()).collect(),
        left_out_bytes: runtime.left_out_bytes(),
        specular: if specular {
            "included"
        } else if glossy {
            "left out: the profile's BRDF set is Lambert only"
        } else {
            "left out: no glossy material"
        },
    })
}

/// The committed bytes of a table file the shader runtime reads.
fn embedded_lut(file: &str) -> Result<&'static [u8], String> {
    Ok(match file {
        "dfg.sbflut" => sbf::luts::committed::DFG_DATA,
        "ad_specular_2d.sbflut" => sbf::luts::committed::AD_SPECULAR_2D_DATA,
        "lobe_ggx_sg6.sbflut" => sbf::luts::committed::LOBE_GGX_SG6_DATA,
        "lobe_ggx_ad.sbflut" => sbf::luts::committed::LOBE_GGX_AD_DATA,
        other => return Err(format!("no embedded LUT named {other}")),
    })
}
