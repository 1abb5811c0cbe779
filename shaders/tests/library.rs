//! The exported include files (`shaders/library/`): the committed copy is what the sources
//! export, every WGSL item keeps its name behind the library's prefix in every language,
//! the GLSL and HLSL examples compile as fragment shaders with glslang — alone, and every
//! pair of configurations after an engine's own declarations (the functions' values on a
//! GPU are gpu_parity.rs's job: the same files, in compute kernels; OpenGL and ES are
//! gl_compile.rs's), WGSL examples validate with naga and tint, and MSL — which no compiler
//! here reads — is checked for structure only.

mod common;

use shaders::export::Lang;
use shaders::library::{self, Target};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("the workspace root").to_path_buf()
}

fn targets() -> Vec<Target> {
    library::targets(&root().join("profiles")).expect("presets and profiles")
}

#[test]
fn committed_library_is_what_the_sources_export() {
    let problems = library::check(&root().join("shaders/library"), &targets()).unwrap();
    assert!(
        problems.is_empty(),
        "shaders/library is stale ({} problems; run `cargo run --release --bin shaders -- library`):\n  {}",
        problems.len(),
        problems.join("\n  ")
    );
}

/// Text outside `//` comments.
fn code(text: &str) -> String {
    text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

/// Identifiers outside comments.
fn identifiers(code: &str) -> std::collections::BTreeSet<&str> {
    code.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| w.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_'))
        .collect()
}

/// Every item keeps its WGSL name behind the library's prefix (sbf_ functions, Sbf structs,
/// SBF_ constants), in every language; no bare item name is left in the code, where it could
/// meet an engine's own `PI` or `schlick_weight`.
#[test]
fn every_wgsl_function_struct_and_constant_is_exported_under_its_prefixed_name() {
    use shaders::emit::names::{exported, ItemKind};
    let mut checked = 0;
    for t in targets() {
        let comp = shaders::compose::compose(&t.config).unwrap();
        let (m, _) = shaders::export::validate(&comp.source).unwrap();
        let files = library::files(&t).unwrap();
        for lang in Lang::ALL {
            let name = library::file_name(&t.slug, lang);
            let text = code(&files.iter().find(|(n, _)| *n == name).unwrap().1);
            let ids = identifiers(&text);
            let mut bare = Vec::new();
            for (_, f) in m.functions.iter() {
                let f = f.name.as_deref().unwrap();
                let e = exported(ItemKind::Function, f);
                assert!(e.starts_with("sbf_"));
                let def = if lang == Lang::Wgsl { format!("fn {e}(") } else { format!(" {e}(") };
                assert!(text.contains(&def), "{name}: function {f} is not defined as {e}");
                bare.push(f);
                checked += 1;
            }
            for (_, ty) in m.types.iter() {
                if let (Some(s), naga::TypeInner::Struct { .. }) = (ty.name.as_deref(), &ty.inner) {
                    let e = exported(ItemKind::Struct, s);
                    assert!(e.starts_with("Sbf"));
                    assert!(text.contains(&format!("struct {e} {{")), "{name}: struct {s} is not declared as {e}");
                    bare.push(s);
                }
            }
            for (_, c) in m.constants.iter() {
                let c = c.name.as_deref().unwrap();
                let e = exported(ItemKind::Constant, c);
                assert!(e.starts_with("SBF_"));
                let found = if lang == Lang::Wgsl {
                    text.contains(&format!("const {e}:"))
                } else {
                    text.contains(&format!(" {e} =")) || text.contains(&format!(" {e}["))
                };
                assert!(found, "{name}: constant {c} is not declared as {e}");
                bare.push(c);
            }
            for b in bare {
                let prefixed = b.starts_with("sbf_") || b.starts_with("Sbf") || b.starts_with("SBF_");
                assert!(prefixed || !ids.contains(b), "{name}: the bare name `{b}` is left in the code");
            }
            // No entry point and no binding in a library.
            for bad in ["void main(", "layout(set", "register(", "[[buffer", "@compute", "@fragment"] {
                assert!(!text.contains(bad), "{name}: a library file contains `{bad}`");
            }
        }
    }
    assert!(checked > 500, "only {checked} function names checked");
}

/// glslangValidator, or None when it is missing and nothing requires it.
fn glslang() -> Option<&'static str> {
    let ok = std::process::Command::new(shaders::spirv::GLSLANG).arg("--version").output().is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("SBF_REQUIRE_GPU").is_err(),
            "SBF_REQUIRE_GPU is set but {} is not installed (apt-get install glslang-tools)",
            shaders::spirv::GLSLANG
        );
        eprintln!("skipping: {} is not installed", shaders::spirv::GLSLANG);
        return None;
    }
    Some(shaders::spirv::GLSLANG)
}

#[test]
fn glsl_and_hlsl_examples_compile_as_fragment_shaders() {
    let Some(glslang) = glslang() else { return };
    let dir = std::env::temp_dir().join(format!("sbf-library-{}", std::process::id()));
    let targets = targets();
    library::write(&dir, &targets).unwrap();
    for t in &targets {
        let d = dir.join(&t.slug);
        for (file, args) in [("example.frag", vec!["-V", "-S", "frag"]), ("example.hlsl", vec!["-D", "-V", "-S", "frag", "-e", "main"])] {
            let o = std::process::Command::new(glslang)
                .args(&args)
                .arg("-o")
                .arg(d.join(format!("{file}.spv")))
                .arg(d.join(file))
                .output()
                .unwrap();
            assert!(
                o.status.success(),
                "{}/{file} does not compile:\n{}{}",
                t.slug,
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn wgsl_examples_validate_after_their_library() {
    for t in targets() {
        let files = library::files(&t).unwrap();
        let get = |n: &str| files.iter().find(|(f, _)| f == n).unwrap().1.clone();
        let src = format!("{}\n{}", get(&library::file_name(&t.slug, Lang::Wgsl)), get("example.wgsl"));
        shaders::export::validate(&src).unwrap_or_else(|e| panic!("{}: {e}", t.slug));
    }
}

#[test]
fn msl_files_are_balanced_and_free_of_wgsl() {
    for t in targets() {
        for (name, text) in library::files(&t).unwrap() {
            if !name.ends_with(".metal") {
                continue;
            }
            let c = code(&text);
            for (open, close) in [('(', ')'), ('{', '}'), ('[', ']')] {
                let depth = c.chars().fold(0i64, |d, ch| {
                    let d = d + (ch == open) as i64 - (ch == close) as i64;
                    assert!(d >= 0, "{}/{name}: `{close}` before its `{open}`", t.slug);
                    d
                });
                assert_eq!(depth, 0, "{}/{name}: unbalanced `{open}{close}`", t.slug);
            }
            for wgsl in ["vec3<f32>", "fn ", "let ", "var ", "@group", "textureLoad", "select(0.0"] {
                assert!(!c.contains(wgsl), "{}/{name}: WGSL left in the MSL: `{wgsl}`", t.slug);
            }
            // Float literals carry MSL's f suffix (an unsuffixed one is a double).
            let bare = c
                .split(|ch: char| !(ch.is_ascii_alphanumeric() || ch == '.' || ch == '_'))
                .find(|w| w.chars().next().is_some_and(|ch| ch.is_ascii_digit()) && w.contains('.') && !w.ends_with('f'));
            assert!(bare.is_none(), "{}/{name}: float literal without f: {bare:?}", t.slug);
        }
    }
}

/// Every WGSL library file with its example through tint, the WGSL compiler of Chrome's
/// WebGPU (stricter than naga: a literal above the largest f32 is an error there, not
/// rounded). tint has no Debian or crates.io package: without it on PATH the test says so
/// and passes (naga's validation above still runs).
#[test]
fn wgsl_library_compiles_in_tint() {
    if std::process::Command::new("tint").arg("--version").output().is_err() {
        eprintln!("skipping: tint (Dawn's WGSL compiler) is not on PATH");
        return;
    }
    let dir = std::env::temp_dir().join(format!("sbf-tint-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for t in targets() {
        let files = library::files(&t).unwrap();
        let get = |n: &str| files.iter().find(|(f, _)| f == n).unwrap().1.clone();
        let src = dir.join(format!("{}.wgsl", t.slug));
        std::fs::write(&src, format!("{}\n{}", get(&library::file_name(&t.slug, Lang::Wgsl)), get("example.wgsl"))).unwrap();
        let o = std::process::Command::new("tint").args(["--format", "wgsl", "-o"]).arg(dir.join("out.wgsl")).arg(&src).output().unwrap();
        assert!(
            o.status.success(),
            "{}: tint rejects the WGSL library:\n{}{}",
            t.slug,
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every pair of configurations (each with itself too) in one Vulkan GLSL and one HLSL
/// fragment shader after an engine's declarations ([`common::ENGINE_GLSL`],
/// [`common::ENGINE_HLSL`]: its own `PI`, `schlick_weight`, `LobeGgxPixel`, a `lut2_sample`
/// macro, …), with the first one's example shading, through glslang (SPIR-V for Vulkan;
/// its HLSL front end).
#[test]
fn vulkan_glsl_and_hlsl_build_every_pair_of_presets_after_engine_declarations() {
    let Some(glslang) = glslang() else { return };
    let dir = std::env::temp_dir().join(format!("sbf-pairs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let slugs = common::slugs();
    let pairs = common::pairs(&slugs);
    let mut failures = Vec::new();
    for (a, b) in &pairs {
        for (example, lib, prelude, args) in [
            ("frag", "glsl", common::ENGINE_GLSL, vec!["-V", "-S", "frag"]),
            ("hlsl", "hlsl", common::ENGINE_HLSL, vec!["-D", "-V", "-S", "frag", "-e", "main"]),
        ] {
            let src = dir.join(format!("shader.{example}"));
            std::fs::write(&src, common::assemble(a, &[b.as_str()], example, lib, prelude)).unwrap();
            let o = std::process::Command::new(glslang).args(&args).arg("-o").arg(dir.join("shader.spv")).arg(&src).output().unwrap();
            if !o.status.success() {
                let log = String::from_utf8_lossy(&o.stdout);
                failures.push(format!(
                    "{a} + {b} ({lib}): {}",
                    log.lines().filter(|l| l.contains("ERROR")).take(3).collect::<Vec<_>>().join(" | ")
                ));
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(failures.is_empty(), "{} of {} builds fail:\n{}", failures.len(), 2 * pairs.len(), failures.join("\n"));
}

/// Every public function carries its comment in every language (directly above its
/// definition), the module comments travel with it — the SH sign convention wherever SH
/// code is exported — and a function that reads the split-sum table names its axes.
#[test]
fn every_public_function_is_documented_in_every_language() {
    use shaders::emit::names::{exported, ItemKind};
    let mut checked = 0;
    for t in targets() {
        let files = library::files(&t).unwrap();
        for lang in Lang::ALL {
            let name = library::file_name(&t.slug, lang);
            let text = &files.iter().find(|(n, _)| *n == name).unwrap().1;
            let lines: Vec<&str> = text.lines().collect();
            for r in library::roots(&t.config) {
                let e = exported(ItemKind::Function, &r);
                let at = lines
                    .iter()
                    .position(|l| !l.starts_with(' ') && !l.starts_with("//") && l.contains(&format!(" {e}(")) && l.ends_with('{'))
                    .unwrap_or_else(|| panic!("{name}: no definition of {e}"));
                assert!(at > 0 && lines[at - 1].starts_with("//"), "{name}: {e} has no comment above its definition");
                checked += 1;
            }
            if text.contains("sh_eval_l1(") || text.contains("sh_eval_l2(") {
                assert!(
                    text.contains("no Condon–Shortley phase") && text.contains("+K₁·(y, z, x)"),
                    "{name}: the SH convention is missing"
                );
            }
            if text.contains(" dfg") {
                assert!(text.contains("u = n·v, v = GGX α"), "{name}: the split-sum table's axes are missing");
            }
        }
    }
    assert!(checked > 500, "only {checked} definitions checked");
}

/// WGSL has no preprocessor, so two WGSL files cannot be included together: a WGSL engine
/// exports the union of the configurations it needs. Checked here: every configuration's
/// WGSL file with its example, and the union export of every pair of configurations, after
/// a WGSL engine's own declarations (`PI`, `INV_PI`, `HILL_C0`, `saturate`, `schlick_weight`,
/// `LobeGgxPixel`: the bare names of our sources), through naga and — when it is on PATH —
/// tint.
#[test]
fn wgsl_builds_after_engine_declarations_alone_and_as_the_union_of_every_pair() {
    const ENGINE_WGSL: &str = "// --- engine declarations ---\nconst PI: f32 = 3.14159265;\nconst INV_PI: f32 = 0.31830988618;\nconst HILL_C0: f32 = 0.0;\nfn saturate(x: f32) -> f32 { return clamp(x, 0.0, 1.0); }\nfn schlick_weight(v_dot_h: f32) -> f32 { let m = saturate(1.0 - v_dot_h); return m * m * m * m * m; }\nstruct LobeGgxPixel { engine_value: f32 }\n";
    let tint = std::process::Command::new("tint").arg("--help").output().is_ok();
    if !tint {
        eprintln!("tint (Dawn's WGSL compiler) is not on PATH: naga only");
    }
    let dir = std::env::temp_dir().join(format!("sbf-wgsl-engine-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let check = |label: &str, src: String| {
        shaders::export::validate(&src).unwrap_or_else(|e| panic!("{label}: naga: {e}"));
        if tint {
            let f = dir.join("shader.wgsl");
            std::fs::write(&f, &src).unwrap();
            let o = std::process::Command::new("tint").args(["--format", "wgsl", "-o"]).arg(dir.join("out.wgsl")).arg(&f).output().unwrap();
            assert!(o.status.success(), "{label}: tint: {}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
        }
    };
    let targets = targets();
    for t in &targets {
        let files = library::files(t).unwrap();
        let get = |n: &str| files.iter().find(|(f, _)| f == n).unwrap().1.clone();
        check(&t.slug, format!("{ENGINE_WGSL}{}\n{}", get(&library::file_name(&t.slug, Lang::Wgsl)), get("example.wgsl")));
    }
    let name = |f: &shaders::compose::Feature| shaders::compose::Feature::ALL.iter().find(|(g, _)| g == f).unwrap().1;
    for (i, a) in targets.iter().enumerate() {
        for b in &targets[i + 1..] {
            let feats: Vec<&str> = a.config.features.union(&b.config.features).map(name).collect();
            let cfg = shaders::compose::Config::parse(&feats.join(",")).unwrap();
            let src = shaders::compose::compose(&cfg).unwrap().source;
            let union = shaders::export::export_with(&src, Lang::Wgsl, &Default::default()).unwrap();
            check(&format!("{} ∪ {}", a.slug, b.slug), format!("{ENGINE_WGSL}{union}"));
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
