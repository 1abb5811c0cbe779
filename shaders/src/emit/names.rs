//! The names the exported library gives its items, so that it can sit in an engine's shader
//! next to the engine's own code and next to other exported configurations.
//!
//! - **Prefix**: every function takes `sbf_`, every struct `Sbf`, every constant `SBF_`
//!   (`sh_l2_irradiance` → `sbf_sh_l2_irradiance`, `LobeGgxPixel` → `SbfLobeGgxPixel`, `PI`
//!   → `SBF_PI`), in every language, WGSL included. A name that already carries its prefix
//!   keeps it. Parameters, locals and struct members keep their WGSL names (they cannot
//!   collide with an engine's module-scope names). The WGSL sources (`shaders/wgsl/`) and
//!   their comments use the bare names; the comments are carried over as written.
//! - **Guards**: in HLSL, GLSL and MSL each item is wrapped in `#ifndef SBF_DEFINED_<name>`,
//!   so that two configurations included in one shader define a shared helper once (an
//!   item of a given name is the same text in every configuration: composition prunes whole
//!   items). WGSL has no preprocessor: compose one configuration with every feature needed
//!   (`shaders export --config a,b`).

use std::collections::{BTreeMap, BTreeSet};

/// What kind of module-scope item a name belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ItemKind {
    Function,
    Struct,
    Constant,
}

/// The name an item is exported under (see the module note).
pub fn exported(kind: ItemKind, name: &str) -> String {
    let prefix = match kind {
        ItemKind::Function => "sbf_",
        ItemKind::Struct => "Sbf",
        ItemKind::Constant => "SBF_",
    };
    if name.starts_with(prefix) {
        name.to_string()
    } else {
        format!("{prefix}{name}")
    }
}

/// The macro that guards the definition of the item exported as `exported_name`.
pub fn guard(exported_name: &str) -> String {
    format!("SBF_DEFINED_{exported_name}")
}

/// `text` wrapped in the item guard of `exported_name`.
pub fn guarded(exported_name: &str, text: &str) -> String {
    let g = guard(exported_name);
    format!("#ifndef {g}\n#define {g}\n{text}#endif\n")
}

/// The exported name of every function, struct and constant of a WGSL module, keyed by
/// its WGSL name.
pub fn renames(m: &naga::Module) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for (_, f) in m.functions.iter() {
        if let Some(n) = &f.name {
            out.insert(n.clone(), exported(ItemKind::Function, n));
        }
    }
    for (_, t) in m.types.iter() {
        if let (Some(n), naga::TypeInner::Struct { .. }) = (&t.name, &t.inner) {
            out.insert(n.clone(), exported(ItemKind::Struct, n));
        }
    }
    for (_, c) in m.constants.iter() {
        if let Some(n) = &c.name {
            out.insert(n.clone(), exported(ItemKind::Constant, n));
        }
    }
    out
}

/// `source` (WGSL) with every identifier in `renames` replaced by its exported name, except
/// in comments and after `.` (a member). An error if a struct member of `m` has the name of
/// an item: its accesses could not be told from uses of the item.
pub fn prefix_wgsl(source: &str, m: &naga::Module, renames: &BTreeMap<String, String>) -> Result<String, String> {
    let members: BTreeSet<&str> = m
        .types
        .iter()
        .filter_map(|(_, t)| match &t.inner {
            naga::TypeInner::Struct { members, .. } => Some(members.iter().filter_map(|x| x.name.as_deref())),
            _ => None,
        })
        .flatten()
        .collect();
    if let Some(clash) = members.iter().find(|n| renames.contains_key(**n)) {
        return Err(format!("struct member '{clash}' has the name of a module-scope item: rename one in the WGSL source"));
    }
    let b = source.as_bytes();
    let mut out = String::with_capacity(source.len() + source.len() / 8);
    let (mut i, mut last) = (0, 0);
    let mut prev_code: Option<u8> = None; // the last non-space byte outside comments
    while i < b.len() {
        if b[i..].starts_with(b"//") {
            i += b[i..].iter().position(|&c| c == b'\n').unwrap_or(b.len() - i);
            continue;
        }
        if b[i..].starts_with(b"/*") {
            // WGSL block comments nest.
            let mut depth = 0;
            while i < b.len() {
                if b[i..].starts_with(b"/*") {
                    depth += 1;
                    i += 2;
                } else if b[i..].starts_with(b"*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            continue;
        }
        let c = b[i];
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            let word = &source[start..i];
            if prev_code != Some(b'.') {
                if let Some(new) = renames.get(word) {
                    out.push_str(&source[last..start]);
                    out.push_str(new);
                    last = i;
                }
            }
            prev_code = Some(b'a');
            continue;
        }
        if c.is_ascii_digit() {
            // A number (its exponent or suffix letters are not identifiers).
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'.' || b[i] == b'_') {
                i += 1;
            }
            prev_code = Some(b'0');
            continue;
        }
        if !c.is_ascii_whitespace() {
            prev_code = Some(c);
        }
        i += 1;
    }
    out.push_str(&source[last..]);
    Ok(out)
}
