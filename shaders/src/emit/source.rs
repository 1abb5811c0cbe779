//! What the WGSL source text says beyond what naga keeps: the comments above each item, the
//! formulas of constants, the items' order and the modules' notes.

use std::collections::HashMap;

/// The comment lines directly above each top-level declaration of `source`, by name.
pub(super) fn item_comments(source: &str) -> HashMap<String, Vec<String>> {
    let mut out = HashMap::new();
    let mut pending: Vec<String> = Vec::new();
    for line in source.lines() {
        if line.starts_with("//") {
            pending.push(line.to_string());
            continue;
        }
        let name = ["fn ", "const ", "struct ", "alias "]
            .iter()
            .find_map(|k| line.strip_prefix(k))
            .map(|rest| rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect::<String>());
        if let Some(n) = name {
            out.insert(n, std::mem::take(&mut pending));
        } else {
            pending.clear();
        }
    }
    out
}

/// The source text of each one-line `const NAME: T = EXPR;` whose EXPR is a formula (not a
/// plain number), by name: written next to the evaluated value.
pub(super) fn const_formulas(source: &str) -> HashMap<String, String> {
    let mut out = HashMap::new();
    for line in source.lines() {
        let Some(rest) = line.strip_prefix("const ") else { continue };
        let Some((head, expr)) = rest.split_once(" = ") else { continue };
        let Some(expr) = expr.strip_suffix(';') else { continue };
        let name: String = head.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        let plain = expr.parse::<f64>().is_ok() || expr.trim_end_matches('u').parse::<i64>().is_ok();
        let constructor = expr.contains('<');
        if !plain && !constructor {
            out.insert(name, expr.to_string());
        }
    }
    out
}

/// The byte offset of each top-level declaration in `source` (the preferred order).
pub(super) fn item_offsets(source: &str) -> HashMap<String, usize> {
    let mut out = HashMap::new();
    let mut at = 0;
    for line in source.split_inclusive('\n') {
        if let Some(rest) = ["fn ", "const ", "struct ", "alias "].iter().find_map(|k| line.strip_prefix(k)) {
            let n: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            out.entry(n).or_insert(at);
        }
        at += line.len();
    }
    out
}

/// The WGSL sources' comments that belong to no item (each module's opening comment: its
/// conventions, sources and CPU twins; fitgen's note), in source order, for the top of an
/// export — so that a reader of the HLSL, GLSL or MSL file has what a reader of the WGSL has.
pub(super) fn module_notes(source: &str) -> String {
    let mut blocks: Vec<Vec<&str>> = Vec::new();
    let mut pending: Vec<&str> = Vec::new();
    for line in source.lines() {
        if line.starts_with("//") {
            pending.push(line);
            continue;
        }
        let item = ["fn ", "const ", "struct ", "alias "].iter().any(|k| line.starts_with(k));
        if !item && !pending.is_empty() && !pending[0].starts_with("// Composed by") {
            blocks.push(std::mem::take(&mut pending));
        }
        pending.clear();
    }
    if blocks.is_empty() {
        return String::new();
    }
    let mut s = String::from("// ---- Notes from the WGSL sources (the modules this file holds) ----\n");
    for b in blocks {
        for l in b {
            s.push_str(l);
            s.push('\n');
        }
        s.push_str("//\n");
    }
    s.push('\n');
    s
}
