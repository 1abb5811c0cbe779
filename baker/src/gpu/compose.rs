//! Composition of WGSL modules with `naga_oil` (Bevy's composer), shared by the bake's
//! kernels ([`mod@super::kernel`]) and the GPU primitives ([`super::prims`]): a module is added
//! once, an entry shader is composed with its shader defs, validated by naga and written
//! back as WGSL with the composer's module suffixes removed from names where unique.

use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue, ShaderLanguage, ShaderType};
use std::collections::HashMap;

/// Shader defs by name.
pub type Defs = HashMap<String, ShaderDefValue>;

/// A composer that validates with every capability (subgroups included).
pub fn composer() -> Composer {
    Composer::default().with_capabilities(naga::valid::Capabilities::all())
}

/// Adds module `file` (`as_name`: its import path where the source names none).
pub fn add_module(c: &mut Composer, file: &str, source: &str, as_name: Option<String>) -> Result<(), String> {
    let added = c
        .add_composable_module(ComposableModuleDescriptor {
            source,
            file_path: file,
            language: ShaderLanguage::Wgsl,
            as_name,
            additional_imports: &[],
            shader_defs: HashMap::new(),
        })
        .map(|_| ());
    added.map_err(|e| format!("{file}: {}", e.emit_to_string(c)))
}

/// Composes entry shader `source` with `defs` and writes it back as WGSL (validated).
pub fn compose(c: &mut Composer, (file, source): (&str, &str), defs: &Defs) -> Result<String, String> {
    let module = c
        .make_naga_module(NagaModuleDescriptor {
            source,
            file_path: file,
            shader_type: ShaderType::Wgsl,
            shader_defs: defs.clone(),
            additional_imports: &[],
        })
        .map_err(|e| format!("{file}: {}", e.emit_to_string(c)))?;
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(&module)
        .map_err(|e| format!("{file}: {e:?}"))?;
    let wgsl =
        naga::back::wgsl::write_string(&module, &info, naga::back::wgsl::WriterFlags::empty()).map_err(|e| format!("{file}: {e}"))?;
    Ok(undecorate(&wgsl))
}

/// The composer's module suffix (`X_naga_oil_mod_X` + the module path in base32 + `X`)
/// removed from every name whose plain form is unique in `wgsl`.
fn undecorate(wgsl: &str) -> String {
    const PRE: &str = "X_naga_oil_mod_X";
    let is_ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    // Every identifier token, and the decorated ones' plain forms.
    let tokens: Vec<&str> = wgsl.split(|c: char| !is_ident(c)).filter(|t| !t.is_empty()).collect();
    let mut plain_of: HashMap<&str, String> = HashMap::new();
    let mut owners: HashMap<String, std::collections::BTreeSet<&str>> = HashMap::new();
    for t in &tokens {
        let plain = match t.find(PRE) {
            Some(i)
                if t.ends_with('X')
                    && t[i + PRE.len()..t.len() - 1].bytes().all(|b| b.is_ascii_uppercase() || (b'2'..=b'7').contains(&b)) =>
            {
                let p = t[..i].to_string();
                plain_of.insert(t, p.clone());
                p
            }
            _ => t.to_string(),
        };
        owners.entry(plain).or_default().insert(t);
    }
    let mut out = String::with_capacity(wgsl.len());
    let mut token = String::new();
    let flush = |token: &mut String, out: &mut String| {
        match plain_of.get(token.as_str()) {
            Some(p) if owners[p].len() == 1 => out.push_str(p),
            _ => out.push_str(token),
        }
        token.clear();
    };
    for ch in wgsl.chars() {
        if is_ident(ch) {
            token.push(ch);
        } else {
            flush(&mut token, &mut out);
            out.push(ch);
        }
    }
    flush(&mut token, &mut out);
    out
}
