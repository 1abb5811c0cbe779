//! The workspace's shape, checked on its source, crate by crate: every top-level module
//! (a layer) imports only the layers its crate's table puts below it, no two modules import
//! each other in a cycle, and no source file (Rust or WGSL, hand-written) grows past 600
//! lines. The tables below are the crates' layer orders (each crate root's doc and
//! ARCHITECTURE.md say what each layer holds).
//!
//! Imports are read from code, not comments: every `crate::…` and `super::…` path, braced
//! use groups included (`the_import_parser_reads_every_form`), resolved to the deepest
//! module file that exists. `the_checks_fail_on_planted_defects` builds a small crate in a
//! temporary folder with an upward import, a cycle and a 601-line file and asserts that
//! each check names it; beyond that, mutations tried on the real tree: `use
//! crate::recon::lut::Lut2;` in `sbf/src/luts/format.rs` (upward, and a cycle with
//! `recon`), `use crate::report::Report;` in `probes/src/metrics.rs`, and 601 blank lines
//! appended to `fitgen/src/plots.rs` — each fails, naming the file.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The longest source file any crate accepts.
const MAX_LINES: usize = 600;

/// A crate's layers, bottom first, each with the layers it may import. `BELOW` stands for
/// "every layer listed before this one".
type Layers = &'static [(&'static str, &'static [&'static str])];
const BELOW: &[&str] = &["*below*"];

/// `sbf`: quadrature and frames, bases and their layouts, sampling, GGX, maps, Gram
/// matrices and solvers, the committed tables (bytes) below the reconstruction that
/// parses them, then I/O, block compression, probes and profiles, and serde of the named
/// values above.
const SBF: Layers = &[
    ("error", BELOW),
    ("quadrature", BELOW),
    ("frame", BELOW),
    ("ktx", BELOW),
    ("basis", BELOW),
    ("layout", BELOW),
    ("sampling", BELOW),
    ("ggx", BELOW),
    ("envmap", BELOW),
    ("gram", BELOW),
    ("solve", BELOW),
    ("luts", BELOW),
    ("recon", BELOW),
    ("slc", BELOW),
    ("io", BELOW),
    ("bc", BELOW),
    ("registry", BELOW),
    ("probe", BELOW),
    ("profile", BELOW),
    ("serial", BELOW),
];

/// `shaders`: the languages and the WGSL modules, the WGSL → HLSL/GLSL/MSL emitter and
/// export below composition and profiles, the committed library, then the GPU and what
/// runs on it (the sampler, the benchmarks).
const SHADERS: Layers = &[
    ("lang", BELOW),
    ("modules", BELOW),
    ("layout", BELOW),
    ("tables", BELOW),
    ("progressive", BELOW),
    ("emit", BELOW),
    ("export", BELOW),
    ("compose", BELOW),
    ("profile", BELOW),
    ("library", BELOW),
    ("gpu", BELOW),
    ("sampler", BELOW),
    ("bench", BELOW),
];

/// `probes`: measurement (frame, azimuthal, cost, metrics, storage) ← modes ← specular,
/// gpu_cost ← outcome ← compare, results ← decide ← decision_text, viewer, report
/// (ARCHITECTURE.md, "Layout of probes").
const PROBES: Layers = &[
    ("frame", BELOW),
    ("azimuthal", BELOW),
    ("cost", BELOW),
    ("memo", BELOW),
    ("metrics", BELOW),
    ("storage", BELOW),
    ("images", BELOW),
    ("outdir", BELOW),
    ("appendix_c", BELOW),
    ("reference", BELOW),
    ("prefilter", BELOW),
    ("modes", BELOW),
    ("specular", BELOW),
    ("profile", BELOW),
    ("gpu_cost", BELOW),
    ("outcome", BELOW),
    ("calibration", BELOW),
    ("compare", BELOW),
    ("results", BELOW),
    ("decide", BELOW),
    ("decision_text", BELOW),
    ("viewer", BELOW),
    ("report", BELOW),
];

/// `fitgen`: the file writer and the optimiser below the outputs (fits and tables), then
/// the manifest, the check and the plots that read them.
const FITGEN: Layers = &[("exr", BELOW), ("optimise", BELOW), ("outputs", BELOW), ("manifest", BELOW), ("check", BELOW), ("plots", BELOW)];

/// `baker` (baker/src/lib.rs's table): `slc` beside the bake's layers, with its own few.
const BAKER: Layers = &[
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

/// Every crate of the workspace with its folder and layers.
const CRATES: &[(&str, Layers)] =
    &[("sbf", SBF), ("shaders", SHADERS), ("probes", PROBES), ("fitgen", FITGEN), ("baker", BAKER), ("tests", &[])];

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// One crate's source tree.
struct Crate {
    src: PathBuf,
}

impl Crate {
    /// The module path of a file (`src/gpu/bake.rs` → ["gpu", "bake"], `src/gpu/mod.rs` → ["gpu"]).
    fn module_of(&self, file: &Path) -> Vec<String> {
        let rel = file.strip_prefix(&self.src).unwrap();
        let mut parts: Vec<String> = rel.iter().map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string()).collect();
        if parts.last().is_some_and(|p| p == "mod") {
            parts.pop();
        }
        parts
    }

    /// Whether `path` (module components) names a module file of the crate.
    fn is_module(&self, path: &[String]) -> bool {
        let base = path.iter().fold(self.src.clone(), |p, c| p.join(c));
        base.with_extension("rs").is_file() || base.join("mod.rs").is_file()
    }

    /// The module files a file imports (deepest existing module of each path), itself excluded.
    fn imports(&self, file: &Path) -> BTreeSet<Vec<String>> {
        let code = code_of(&std::fs::read_to_string(file).unwrap());
        let me = self.module_of(file);
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
            while !m.is_empty() && !self.is_module(&m) {
                m.pop();
            }
            if !m.is_empty() && m != me {
                out.insert(m);
            }
        }
        out
    }

    /// The library's module files: the crate roots and binaries are the crate's users, not
    /// part of the layer graph.
    fn library_files(&self) -> Vec<PathBuf> {
        let mut files = Vec::new();
        files_with(&self.src, "rs", &mut files);
        files.retain(|f| {
            let m = self.module_of(f);
            !(m == ["lib"] || m == ["main"] || m.first().is_some_and(|c| c == "bin"))
        });
        files
    }

    /// Imports that leave a layer for one its table does not put below it.
    fn upward_imports(&self, layers: Layers) -> Vec<String> {
        let allowed: BTreeMap<&str, Vec<&str>> = layers
            .iter()
            .enumerate()
            .map(|(i, (l, below))| (*l, if *below == BELOW { layers[..i].iter().map(|x| x.0).collect() } else { below.to_vec() }))
            .collect();
        let mut bad = Vec::new();
        for f in self.library_files() {
            let me = self.module_of(&f);
            let layer = me[0].as_str();
            let Some(ok) = allowed.get(layer) else {
                bad.push(format!("{}: top-level module '{layer}' is not a layer of the crate's table", f.display()));
                continue;
            };
            for m in self.imports(&f) {
                let to = m[0].as_str();
                if to != layer && !ok.contains(&to) {
                    bad.push(format!("{}: {layer} imports {} ({to} is not below {layer})", f.display(), m.join("::")));
                }
            }
        }
        bad
    }

    /// Import cycles between module files, each as "a → b → a".
    fn cycles(&self) -> Vec<String> {
        let graph: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> =
            self.library_files().iter().map(|f| (self.module_of(f), self.imports(f))).collect();
        // A module's parent (`mod.rs`) declares it, so parent → child arrows are the tree,
        // not imports: only arrows to non-descendants count for cycles.
        let edges =
            |m: &Vec<String>| -> Vec<Vec<String>> { graph.get(m).into_iter().flatten().filter(|t| !t.starts_with(m)).cloned().collect() };
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
        cycles
    }

    /// The top-level modules each layer imports (a map of the crate, printed on failure).
    fn layer_graph(&self) -> BTreeMap<String, BTreeSet<String>> {
        let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for f in self.library_files() {
            let me = self.module_of(&f)[0].clone();
            let to: BTreeSet<String> = self.imports(&f).into_iter().map(|m| m[0].clone()).filter(|t| *t != me).collect();
            g.entry(me).or_default().extend(to);
        }
        g
    }
}

/// Hand-written source files over [`MAX_LINES`] under `dir` (Rust and WGSL; generated
/// files, which say "do not edit" in their first lines, are exempt).
fn long_files(dir: &Path) -> Vec<String> {
    let mut files = Vec::new();
    files_with(dir, "rs", &mut files);
    files_with(dir, "wgsl", &mut files);
    files
        .iter()
        .map(|f| (f, std::fs::read_to_string(f).unwrap()))
        .filter(|(_, text)| !text.lines().take(5).any(|l| l.contains("do not edit")))
        .map(|(f, text)| (f, text.lines().count()))
        .filter(|(_, n)| *n > MAX_LINES)
        .map(|(f, n)| format!("{} ({n} lines)", f.display()))
        .collect()
}

/// Every file under `dir` whose extension is `ext`, sorted; `target` folders skipped.
fn files_with(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            if !p.ends_with("target") {
                files_with(&p, ext, out);
            }
        } else if p.extension().is_some_and(|e| e == ext) {
            out.push(p);
        }
    }
}

/// The code of a file with comments removed (line comments and doc comments; the
/// workspace has no block comments in code).
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

#[test]
fn layers_import_only_downwards() {
    let mut bad = Vec::new();
    for (name, layers) in CRATES {
        let c = Crate { src: workspace().join(name).join("src") };
        let found = c.upward_imports(layers);
        if !found.is_empty() {
            bad.push(format!("{name}: {}\nits layers import: {:#?}", found.join("\n"), c.layer_graph()));
        }
    }
    assert!(bad.is_empty(), "upward or sideways imports:\n{}", bad.join("\n"));
}

#[test]
fn no_import_cycle_between_modules() {
    let cycles: Vec<String> = CRATES.iter().flat_map(|(name, _)| Crate { src: workspace().join(name).join("src") }.cycles()).collect();
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}

#[test]
fn no_source_file_is_too_long() {
    // Each crate's `src/` and the WGSL the shader library is exported from; tests are
    // not held to it.
    let dirs = CRATES.iter().map(|(name, _)| workspace().join(name).join("src")).chain([workspace().join("shaders/wgsl")]);
    let long: Vec<String> = dirs.flat_map(|d| long_files(&d)).collect();
    assert!(long.is_empty(), "files over {MAX_LINES} lines: {long:?}");
}

/// Where a basis name may be compared: the registry, and the `probes` files whose literals
/// are *mode* ids (`ad9` is also the Appendix C mode of that name, `ac` the ambient cube's), each compared with a
/// mode's id, not a basis's name.
const NAME_COMPARISONS_ALLOWED: &[&str] = &[
    "sbf/src/registry.rs",
    "probes/src/modes/hemisphere.rs",
    "probes/src/modes/cube.rs",
    "probes/src/specular.rs",
    "probes/src/gpu_cost.rs",
];

/// Comparisons of a basis by its name in `code` (a match arm or `==` on a name literal, a
/// family by prefix): what the registry's facts replace.
fn name_comparisons(code: &str) -> Vec<String> {
    let names = sbf::registry::BASES.map(|b| format!("\"{}\"", b.name));
    code.lines()
        .filter(|l| {
            let l = l.split("//").next().unwrap_or("");
            let arm = names.iter().any(|n| {
                l.contains(&format!("{n} =>"))
                    || ["_)", "true)", "false)", "SpecularPath"].iter().any(|t| l.contains(&format!("({n}, {t}")))
                    || l.contains(&format!("{n} |"))
                    || l.contains(&format!("| {n}"))
                    || l.contains(&format!("== {n}"))
            });
            let prefix = ["sh", "sg", "ad"]
                .iter()
                .any(|f| l.contains(&format!("b.starts_with(\"{f}\")")) || l.contains(&format!("basis.starts_with(\"{f}\")")));
            arm || prefix
        })
        .map(|l| l.trim().to_string())
        .collect()
}

/// No crate compares a basis by its name outside the registry.
#[test]
fn bases_are_compared_by_id_not_by_name() {
    let mut found = Vec::new();
    for (name, _) in CRATES {
        let mut files = Vec::new();
        files_with(&workspace().join(name).join("src"), "rs", &mut files);
        for f in files {
            let rel = f.strip_prefix(workspace()).unwrap().to_string_lossy().into_owned();
            if NAME_COMPARISONS_ALLOWED.contains(&rel.as_str()) {
                continue;
            }
            found.extend(name_comparisons(&std::fs::read_to_string(&f).unwrap()).into_iter().map(|l| format!("{rel}: {l}")));
        }
    }
    assert!(found.is_empty(), "basis names compared outside sbf::registry:\n{}", found.join("\n"));
    // The check itself: the forms it must catch.
    assert_eq!(
        name_comparisons("    (\"sh1\", _) => &[\"shl1\"],\n  \"sg9\" | \"sg12\" => 1,\n if b == \"ad9\" {}\n b.starts_with(\"sh\")").len(),
        4
    );
}

/// The arms of a `match` on basis variants in `code` (a line whose pattern, before `=>`,
/// names `BasisId::X` or `ProbeBasis::X`): the places a new basis must be added to.
fn basis_arms(code: &str) -> Vec<String> {
    code.lines()
        .filter(|l| {
            let Some((pattern, _)) = l.split_once("=>") else { return false };
            let p = pattern.trim_start().trim_start_matches("Encoding::Basis(");
            p.starts_with("BasisId::") || p.starts_with("ProbeBasis::")
        })
        .map(|l| l.trim().to_string())
        .collect()
}

/// Adding a basis touches the registry and the places docs/adding-a-basis.md lists: every
/// source file that matches on basis variants (where the compiler makes a new variant
/// touch it) is named in the guide.
/// Mutation tried: the guide without `sbf/src/probe.rs` (the state before this test) fails
/// naming it.
#[test]
fn every_match_on_basis_variants_is_in_the_guide() {
    let guide = std::fs::read_to_string(workspace().join("docs/adding-a-basis.md")).unwrap();
    let mut missing = Vec::new();
    for (name, _) in CRATES {
        let mut files = Vec::new();
        files_with(&workspace().join(name).join("src"), "rs", &mut files);
        for f in files {
            let rel = f.strip_prefix(workspace()).unwrap().to_string_lossy().into_owned();
            let arms = basis_arms(&code_of(&std::fs::read_to_string(&f).unwrap()));
            if !arms.is_empty() && !guide.contains(&format!("`{rel}`")) {
                missing.push(format!("{rel}: {}", arms[0]));
            }
        }
    }
    assert!(missing.is_empty(), "files that match on basis variants, not listed in docs/adding-a-basis.md:\n{}", missing.join("\n"));
    // The check itself: the forms it must catch, and what it must not.
    let arms = basis_arms("  BasisId::Sh1 | BasisId::Zh3 => 1,\n Encoding::Basis(BasisId::Ad9) if t => 2,\n ProbeBasis::H4 => {\n let x = BasisId::Sh2;\n Some(BasisId::Sg9) => 3,");
    assert_eq!(arms.len(), 3, "{arms:?}");
}

/// The checks on a crate built here with one defect of each kind: an upward import
/// (`low` imports `high`), a cycle inside a layer (`high::a` ⇄ `high::b`) and a 601-line file.
#[test]
fn the_checks_fail_on_planted_defects() {
    let dir = std::env::temp_dir().join(format!("sbf-shape-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let src = dir.join("src");
    std::fs::create_dir_all(src.join("high")).unwrap();
    let write = |p: &str, s: &str| std::fs::write(src.join(p), s).unwrap();
    write("lib.rs", "pub mod low;\npub mod high;\n");
    write("low.rs", "// crate::high::X in a comment is no import\npub fn f() -> u32 { crate::high::a::X }\n");
    write("high/mod.rs", "pub mod a;\npub mod b;\n");
    write("high/a.rs", "use super::b::Y;\npub const X: u32 = Y;\n");
    write("high/b.rs", "use crate::{low::f, high::a::X};\npub const Y: u32 = 1;\n");
    let layers: Layers = &[("low", &[]), ("high", BELOW)];
    let c = Crate { src: src.clone() };
    let up = c.upward_imports(layers);
    assert!(up.len() == 1 && up[0].contains("low.rs: low imports high::a"), "{up:?}");
    let cycles = c.cycles();
    assert!(cycles.iter().any(|s| s.contains("high::a → high::b → high::a")), "{cycles:?}");
    assert!(long_files(&dir).is_empty());
    write("long.rs", &"\n".repeat(MAX_LINES + 1));
    let long = long_files(&dir);
    assert!(long.len() == 1 && long[0].contains("long.rs (601 lines)"), "{long:?}");
    // The same length marked as generated is exempt.
    write("long.rs", &format!("// Generated by a tool; do not edit.{}", "\n".repeat(MAX_LINES + 1)));
    assert!(long_files(&dir).is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
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
