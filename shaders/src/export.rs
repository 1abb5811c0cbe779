//! The export of composed WGSL: WGSL as composed, HLSL, GLSL and MSL as include files
//! written by [`crate::emit`]; the languages and validation live in [`crate::lang`].

pub use crate::lang::{validate, validate_subgroups, Glsl, Lang};

/// Translates composed WGSL to `lang`: WGSL as composed with its items' exported names
/// ([`crate::emit::names`]; validated again), the other languages through [`crate::emit`]
/// as an include file headed by `opts`.
pub fn export_with(source: &str, lang: Lang, opts: &crate::emit::Options) -> Result<String, String> {
    let (module, info) = validate(source)?;
    if lang == Lang::Wgsl {
        let renames = crate::emit::names::renames(&module);
        let out = crate::emit::names::prefix_wgsl(source, &module, &renames)?;
        validate(&out).map_err(|e| format!("the WGSL with exported names: {e}"))?;
        return Ok(out);
    }
    crate::emit::library(source, &module, &info, lang, opts)
}

/// [`export_with`] with a header that names no configuration.
pub fn export(source: &str, lang: Lang) -> Result<String, String> {
    export_with(source, lang, &crate::emit::Options { title: "library".into(), ..Default::default() })
}
