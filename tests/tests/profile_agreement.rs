//! One profile, one truth: every profile in profiles/ run through the four tools — fitgen
//! (the tables it generates), shaders (the functions it exports), the baker (the runtime
//! features, tables and paths it writes beside a bake) and probes (the specular runtime
//! path it measures, and the profile in its reports) — and what they did compared.
//!
//! The expectations are written here, per path, from the runtime's definition (not read
//! from `sbf::profile`, which the tools share): the `fit` path reads the ASG warp (SG) and
//! Listing 8.1 + the `ad-specular-2d` table (AD); the `tables` path the per-lobe tables
//! `lobe-ggx-sg6` (SG) and `lobe-ggx-ad` (AD) through `lobe_ggx_*`; SH's specular is the
//! zonal filter with the `dfg` table on either (`sh-specular`).
//!
//! Needs the workspace's binaries next to this test's (`cargo test --workspace` builds
//! them); fails naming the missing one otherwise. Mutation tried: probes ignoring the
//! profile's path (its `--specular-runtime` default, the tables) fails on the
//! AD 9 + GGX profile (a fit profile).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// A workspace binary in this test's target folder.
fn bin(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().and_then(|d| d.parent()).unwrap();
    let p = dir.join(name);
    assert!(p.exists(), "{} is missing: run `cargo build --workspace --release --bins` (or cargo test --workspace)", p.display());
    p
}

fn run(cmd: &mut Command) -> String {
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{cmd:?}: {}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sbf-agreement-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The functions a library file defines (`sbf_*` names at the start of a definition line, in
/// any language).
fn defined(text: &str) -> BTreeSet<String> {
    text.lines()
        .filter(|l| !l.starts_with(' ') && !l.starts_with("//") && l.trim_end().ends_with('{'))
        .filter_map(|l| l.split_once('(').map(|(head, _)| head))
        .filter_map(|head| head.rsplit(' ').next())
        .filter(|n| n.starts_with("sbf_"))
        .map(str::to_string)
        .collect()
}

/// The specular shader features whose functions a WGSL export defines (under the library's
/// `sbf_` prefix).
fn exported_specular(wgsl: &str) -> BTreeSet<String> {
    [
        ("sg-specular", "sg_split_sum_lobe"),
        ("sh-specular", "sh_l1_specular"),
        ("ad9-specular", "ad9_specular"),
        ("ad12-specular", "ad12_specular"),
        ("lobe-ggx-specular", "lobe_ggx_lobe"),
        ("lobe-ggx-filtered", "lobe_ggx_filtered_lobe"),
    ]
    .iter()
    .filter(|(_, f)| wgsl.contains(&format!("fn sbf_{f}(")))
    .map(|(feat, _)| feat.to_string())
    .collect()
}

#[test]
fn every_profile_means_the_same_to_fitgen_shaders_baker_and_probes() {
    let map = tmp("map").join("sky.hdr");
    run(Command::new(bin("probes")).args(["env", "--preset", "sky", "--width", "32", "--out"]).arg(&map));
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("profiles"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 3);
    for prof in files {
        let stem = prof.file_stem().unwrap().to_string_lossy().into_owned();
        let p = sbf::profile::Profile::load(&prof).unwrap();
        let paths: BTreeSet<String> = p.specular_paths.iter().map(|x| x.name().to_string()).collect();
        // Names, not the registry's facts: the expectations below are written from the
        // runtime's definition.
        let all_bases: Vec<&str> = p.all_bases().iter().map(|b| b.name()).collect();
        let has = |prefix: &str| all_bases.iter().any(|b| b.starts_with(prefix));

        // What the paths mean, written here.
        let mut want_tables: BTreeSet<String> = ["fits", "fits-wgsl"].iter().map(|s| s.to_string()).collect();
        let mut want_features = BTreeSet::new();
        if p.specular && has("sh") {
            want_tables.insert("dfg".into());
            want_features.insert("sh-specular".to_string());
        }
        if paths.contains("fit") {
            if has("sg") {
                want_features.insert("sg-specular".to_string());
            }
            if all_bases.contains(&"ad9") {
                want_features.insert("ad9-specular".to_string());
            }
            if all_bases.contains(&"ad12") {
                want_features.insert("ad12-specular".to_string());
            }
            if has("ad") {
                want_tables.insert("ad-specular-2d".into());
            }
        }
        if paths.contains("tables") && (has("sg") || has("ad")) {
            want_features.insert("lobe-ggx-filtered".to_string());
            if has("sg") {
                want_tables.insert("lobe-ggx-sg6".into());
            }
            if has("ad") {
                want_tables.insert("lobe-ggx-ad".into());
            }
        }

        // fitgen: the tables it would generate for the profile.
        let listed = run(Command::new(bin("fitgen")).args(["list", "--profile"]).arg(&prof));
        let fitgen_tables: BTreeSet<String> = listed.lines().filter_map(|l| l.split_whitespace().next()).map(str::to_string).collect();
        assert_eq!(fitgen_tables, want_tables, "{stem}: fitgen's tables");

        // shaders: the specular functions it exports, and one irradiance function per basis.
        let wgsl = run(Command::new(bin("shaders")).args(["export", "--lang", "wgsl", "--profile"]).arg(&prof));
        assert_eq!(exported_specular(&wgsl), want_features, "{stem}: shaders' specular functions");
        let irradiance = |b: &str| match b {
            "sh1" => "sh_l1_irradiance",
            "sh2" => "sh_l2_irradiance",
            "sg9" | "sg12" => "sg_hill_irradiance",
            "ad9" => "ad9_irradiance",
            _ => "ad12_irradiance",
        };
        let want_irr: BTreeSet<&str> = all_bases.iter().map(|b| irradiance(b)).collect();
        let all_irr = [
            "sh_l1_irradiance",
            "sh_l2_irradiance",
            "sh_l4_irradiance",
            "sh_l1_geomerics_irradiance",
            "sh_l1_zh3_irradiance",
            "sg_hill_irradiance",
            "ad9_irradiance",
            "ad12_irradiance",
        ];
        let got_irr: BTreeSet<&str> = all_irr.iter().copied().filter(|f| wgsl.contains(&format!("fn sbf_{f}("))).collect();
        assert_eq!(got_irr, want_irr, "{stem}: shaders' irradiance functions");
        // probes: one mode per basis, the one that evaluates that runtime function (a
        // lightmap basis in tangent space, a probe basis on the sphere).
        let mut want_modes: BTreeSet<&str> = BTreeSet::new();
        for (b, probe) in p.lightmap_bases.iter().map(|b| (b.name(), false)).chain(p.probe_bases.iter().map(|b| (b.name(), true))) {
            want_modes.insert(match (b, probe) {
                ("sh1", _) => "shl1",
                ("sh2", _) => "shl2",
                ("sg9", _) => "sg9h",
                ("sg12", _) => "sg12h",
                ("ad9", _) => "ad9",
                ("ad12", false) => "adrbf-tangent",
                _ => "adrbf",
            });
        }

        // baker: a small CPU bake of the glossy built-in scene, with probes.
        let out = tmp(&format!("bake-{stem}"));
        run(Command::new(bin("baker"))
            .args(["--device", "cpu", "--passes", "1", "--texels-per-unit", "3", "--probes", "2,2,2", "--denoise", "off", "--profile"])
            .arg(&prof)
            .arg("--out")
            .arg(&out));
        let bake: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("bake.json")).unwrap()).unwrap();
        let strings =
            |v: &serde_json::Value| -> BTreeSet<String> { v.as_array().unwrap().iter().map(|x| x.as_str().unwrap().to_string()).collect() };
        let rt = &bake["runtime"];
        let baked_spec: BTreeSet<String> =
            strings(&rt["features"]).into_iter().filter(|f| f.contains("specular") || f.starts_with("lobe-ggx")).collect();
        // The bake ships the whole profile's runtime: its probes' bases too.
        assert_eq!(baked_spec, want_features, "{stem}: the baker's runtime features");
        let shader_tables: BTreeSet<String> = want_tables
            .iter()
            .filter(|t| !["fits", "fits-wgsl"].contains(&t.as_str()))
            .map(|t| format!("{}.sbflut", t.replace('-', "_")))
            .collect();
        assert_eq!(strings(&rt["luts"]), shader_tables, "{stem}: the tables the baker ships");
        for t in &shader_tables {
            assert!(out.join(t).exists(), "{stem}: {t} listed but not written");
        }
        // Function for function, the baker's runtime is `shaders export` of the profile: in
        // WGSL, and in the profile's own language.
        let baked_wgsl = std::fs::read_to_string(out.join("runtime.wgsl")).unwrap();
        assert_eq!(defined(&baked_wgsl), defined(&wgsl), "{stem}: the baker's runtime.wgsl and `shaders export --profile`");
        if p.language != "wgsl" {
            let ext = match p.language.as_str() {
                "glsl-gl" => "gl.glsl",
                "glsl-es" => "es.glsl",
                "msl" => "metal",
                other => other,
            };
            let baked = std::fs::read_to_string(out.join(format!("runtime.{ext}"))).unwrap();
            let exported = run(Command::new(bin("shaders")).args(["export", "--profile"]).arg(&prof));
            assert!(!defined(&exported).is_empty(), "{stem}: nothing defined in the {ext} export");
            assert_eq!(defined(&baked), defined(&exported), "{stem}: the baker's runtime.{ext} and `shaders export --profile`");
        }
        assert_eq!(strings(&rt["specular_paths"]), paths, "{stem}: the baker's paths");

        // probes: the path it measures, one report folder per path when there are two.
        let rep = tmp(&format!("probes-{stem}"));
        run(Command::new(bin("probes"))
            .arg("--force")
            .arg("compare")
            .arg(&map)
            .args(["--repeats", "1", "--specular-samples", "16", "--images", "none", "--profile"])
            .arg(&prof)
            .arg("--out")
            .arg(&rep));
        let folders: Vec<(String, PathBuf)> = if paths.len() > 1 {
            paths.iter().map(|x| (x.clone(), rep.join(x))).collect()
        } else {
            vec![(paths.iter().next().cloned().unwrap_or_default(), rep.clone())]
        };
        for (path, dir) in folders {
            let results: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("results.json")).unwrap()).unwrap();
            let r = &results[0];
            assert!(r["profile"].as_str().unwrap().starts_with(&p.name), "{stem}: results.json names the profile: {}", r["profile"]);
            let measured = r["specular_runtime"].as_str().unwrap_or("");
            let measured = if measured.is_empty() {
                ""
            } else if measured.starts_with("SG and AD lobes through per-lobe") {
                "tables"
            } else if measured.starts_with("SG lobes through the split sum") {
                "fit"
            } else {
                panic!("{stem}: unknown runtime description {measured}")
            };
            assert_eq!(measured, path, "{stem}: the path probes measured");
            let modes: BTreeSet<&str> = r["modes"].as_array().unwrap().iter().map(|m| m["id"].as_str().unwrap()).collect();
            assert_eq!(modes, want_modes, "{stem}: the modes probes measured");
            let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
            assert!(md.contains(&format!("Lighting profile: {}", p.name)), "{stem}: report.md names the profile");
        }
    }
}
