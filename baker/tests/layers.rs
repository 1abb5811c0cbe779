//! The crate's shape, checked on its source: every layer (a folder of `src/`) imports only
//! the layers below it (the table in `src/lib.rs`), no two modules of a layer import each
//! other in a cycle, and no source file (Rust or WGSL) grows past 600 lines.
//!
//! Imports are read from code, not comments: every `crate::…` and `super::…` path, braced
//! use groups included (`the_import_parser_reads_every_form`), resolved to the deepest
//! module file that exists. Mutations tried: a
//! `use crate::gpu::GpuBake;` added to `scene/bvh.rs` (an upward import), and
//! `use super::probes::probe_grid;` in `layout/lightmap.rs` with
//! `use super::lightmap::Lightmap;` in `layout/probes.rs` (a cycle inside a layer) —
//! both fail, naming the files.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Each layer and the layers it may import (the rest of the crate is off limits).
const ALLOWED: &[(&str, &[&str])] = &[
    ("scene", &[]),
    ("layout", &["scene"]),
    ("sampling", &["scene", "layout"]),
    ("estimator", &["scene", "layout", "sampling"]),
    ("accumulate", &["scene", "layout", "sampling", "estimator"]),
    ("checkpoint", &["scene", "layout", "sampling", "estimator", "accumulate"]),
    ("gpu", &["scene", "layout", "sampling", "estimator", "accumulate"]),
    ("post", &["scene", "layout", "sampling", "estimator", "accumulate"]),
    ("output", &["scene", "layout", "sampling", "estimator", "accumulate", "post"]),
    ("render", &["scene", "layout", "sampling", "estimator", "accumulate", "gpu", "output"]),
    ("run", &["scene", "layout", "sampling", "estimator", "accumulate", "checkpoint", "gpu", "post", "output"]),
    ("slc", &["scene", "sampling", "output"]),
];

/// The longest source file the crate accepts.
const MAX_LINES: usize = 600;

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The module path of a file (`src/gpu/bake.rs` → ["gpu", "bake"], `src/gpu/mod.rs` → ["gpu"]).
fn module_of(file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src()).unwrap();
    let mut parts: Vec<String> = rel.iter().map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string()).collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// Whether `path` (module components) names a module file of the crate.
fn is_module(path: &[String]) -> bool {
    let base = path.iter().fold(src(), |p, c| p.join(c));
    base.with_extension("rs").is_file() || base.join("mod.rs").is_file()
}

/// The code of a file with comments removed (line comments and doc comments; the crate
/// has no block comments in code).
fn code_of(text: &str) -> String {
    text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

/// Module paths named right after each `prefix` (`crate::` or `super::`) in `code`: a
/// plain path (`a::b::C`) or a use tree with braces at any depth and whitespace or
/// newlines anywhere (`{a::B, c::{d, e}}`); `self` in a group names the group's path.
fn paths_after(code: &str, prefix: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(i) = code[at..].find(prefix) {
        let start = at + i;
        at = start + prefix.len();
        // Not the tail of a longer path or identifier (`super::super::` is read from its
        // first `super::`).
        if code[..start].chars().next_back().is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let mut rest = code[at..].chars().peekable();
        out.extend(use_tree(&mut rest));
    }
    out
}

/// Parses one use tree (see [`paths_after`]) from `it`.
fn use_tree(it: &mut std::iter::Peekable<std::str::Chars>) -> Vec<Vec<String>> {
    let skip_ws = |it: &mut std::iter::Peekable<std::str::Chars>| {
        while it.peek().is_some_and(|c| c.is_whitespace()) {
            it.next();
        }
    };
    let mut segs: Vec<String> = Vec::new();
    loop {
        skip_ws(it);
        if it.peek() == Some(&'{') {
            it.next();
            let mut out = Vec::new();
            loop {
                skip_ws(it);
                match it.peek() {
                    Some('}') => {
                        it.next();
                        break;
                    }
                    Some(',') => {
                        it.next();
                    }
                    None => break,
                    _ => {
                        let before = it.clone().count();
                        for p in use_tree(it) {
                            out.push(segs.iter().cloned().chain(p).collect());
                        }
                        if it.clone().count() == before {
                            it.next(); // not a path: step over it
                        }
                    }
                }
            }
            return out;
        }
        let ident: String = std::iter::from_fn(|| it.next_if(|c| c.is_alphanumeric() || *c == '_')).collect();
        if ident.is_empty() {
            break;
        }
        if ident == "self" {
            // The group's own path (`a::{self, b}` names `a`).
            return vec![segs];
        }
        segs.push(ident);
        skip_ws(it);
        let mut ahead = it.clone();
        if ahead.next() == Some(':') && ahead.next() == Some(':') {
            it.next();
            it.next();
        } else {
            break;
        }
    }
    if segs.is_empty() {
        Vec::new()
    } else {
        vec![segs]
    }
}

/// The module files a file imports (deepest existing module of each path), itself excluded.
fn imports(file: &Path) -> BTreeSet<Vec<String>> {
    let code = code_of(&std::fs::read_to_string(file).unwrap());
    let me = module_of(file);
    // `super` of a module file is its parent module; of a crate root, nothing.
    let parent: Vec<String> = me[..me.len().saturating_sub(1)].to_vec();
    let mut out = BTreeSet::new();
    let absolute = paths_after(&code, "crate::").into_iter();
    // `super::super::x` climbs once per `super`.
    let relative = paths_after(&code, "super::").into_iter().map(|p| {
        let ups = p.iter().take_while(|s| *s == "super").count();
        let base = &parent[..parent.len().saturating_sub(ups)];
        base.iter().cloned().chain(p.into_iter().skip(ups)).collect::<Vec<_>>()
    });
    for p in absolute.chain(relative) {
        let mut m = p;
        while !m.is_empty() && !is_module(&m) {
            m.pop();
        }
        if !m.is_empty() && m != me {
            out.insert(m);
        }
    }
    out
}

fn library_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    // The binaries are the crate's users, not part of the layer graph.
    files.retain(|f| {
        let m = module_of(f);
        !(m == ["lib"] || m == ["main"] || m.first().is_some_and(|c| c == "bin"))
    });
    files
}

#[test]
fn layers_import_only_downwards() {
    let allowed: BTreeMap<&str, &[&str]> = ALLOWED.iter().copied().collect();
    let mut bad = Vec::new();
    for f in library_files() {
        let me = module_of(&f);
        let layer = me[0].as_str();
        let Some(ok) = allowed.get(layer) else {
            bad.push(format!("{}: top-level module '{layer}' is not a layer of the table", f.display()));
            continue;
        };
        for m in imports(&f) {
            let to = m[0].as_str();
            if to != layer && !ok.contains(&to) {
                bad.push(format!("{}: {layer} imports {} ({to} is not below {layer})", f.display(), m.join("::")));
            }
        }
    }
    assert!(bad.is_empty(), "{} upward or sideways imports:\n{}", bad.len(), bad.join("\n"));
}

#[test]
fn no_import_cycle_between_modules() {
    let graph: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = library_files().iter().map(|f| (module_of(f), imports(f))).collect();
    // A module's parent (`mod.rs`) declares it, so parent → child arrows are the tree, not
    // imports: only arrows to non-descendants count for cycles.
    let edges = |m: &Vec<String>| -> Vec<Vec<String>> { graph[m].iter().filter(|t| !t.starts_with(m)).cloned().collect() };
    // Depth-first search with colours; a grey node reached again closes a cycle.
    let mut colour: BTreeMap<Vec<String>, u8> = BTreeMap::new();
    let mut cycles = Vec::new();
    fn visit(
        m: &Vec<String>,
        edges: &dyn Fn(&Vec<String>) -> Vec<Vec<String>>,
        colour: &mut BTreeMap<Vec<String>, u8>,
        stack: &mut Vec<Vec<String>>,
        cycles: &mut Vec<String>,
    ) {
        colour.insert(m.clone(), 1);
        stack.push(m.clone());
        for t in edges(m) {
            match colour.get(&t).copied().unwrap_or(0) {
                0 => visit(&t, edges, colour, stack, cycles),
                1 => {
                    let from = stack.iter().position(|s| *s == t).unwrap();
                    let names: Vec<String> = stack[from..].iter().chain([&t]).map(|s| s.join("::")).collect();
                    cycles.push(names.join(" → "));
                }
                _ => {}
            }
        }
        stack.pop();
        colour.insert(m.clone(), 2);
    }
    for m in graph.keys() {
        if colour.get(m).copied().unwrap_or(0) == 0 {
            visit(m, &edges, &mut colour, &mut Vec::new(), &mut cycles);
        }
    }
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}

/// Every `.wgsl` file under `dir`, sorted.
fn wgsl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            wgsl_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "wgsl") {
            out.push(p);
        }
    }
}

#[test]
fn no_source_file_is_too_long() {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    wgsl_files(&src(), &mut files);
    let long: Vec<String> = files
        .iter()
        .map(|f| (f, std::fs::read_to_string(f).unwrap().lines().count()))
        .filter(|(_, n)| *n > MAX_LINES)
        .map(|(f, n)| format!("{} ({n} lines)", f.display()))
        .collect();
    assert!(long.is_empty(), "files over {MAX_LINES} lines: {long:?}");
}

/// The import parser on the forms rustfmt and people write: plain paths, braced groups
/// (nested, over several lines), `self`, `super::super::` chains, paths in expressions.
#[test]
fn the_import_parser_reads_every_form() {
    let p = |code: &str, prefix: &str| paths_after(code, prefix);
    let v = |s: &[&str]| s.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    assert_eq!(p("use crate::gpu::GpuBake;", "crate::"), [v(&["gpu", "GpuBake"])]);
    assert_eq!(p("use crate::{gpu::GpuBake};", "crate::"), [v(&["gpu", "GpuBake"])]);
    assert_eq!(
        p("use crate::{\n    scene::Scene,\n    gpu::{GpuBake, self},\n};", "crate::"),
        [v(&["scene", "Scene"]), v(&["gpu", "GpuBake"]), v(&["gpu"])]
    );
    assert_eq!(p("let b = crate::gpu::GpuBake::new(x);", "crate::"), [v(&["gpu", "GpuBake", "new"])]);
    assert_eq!(p("use super::{probes::probe_grid};", "super::"), [v(&["probes", "probe_grid"])]);
    assert_eq!(p("use super::super::gpu::GpuBake;", "super::"), [v(&["super", "gpu", "GpuBake"])]);
    assert_eq!(p("x.super_thing(); my_crate::a", "crate::"), Vec::<Vec<String>>::new());
}
