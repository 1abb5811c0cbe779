//! `shaders export --profile`: only the modules a profile needs, in its language.
use std::path::Path;
use std::process::Command;

/// A Lambert-only SH L1 profile exports GLSL with the SH L1 irradiance function and no
/// specular, SG or Ambient Dice code, and prints the left-out line; the AD9 + GGX profile
/// keeps the AD9 specular function.
#[test]
fn profile_export_leaves_out_specular() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../profiles");
    let export = |name: &str| {
        let o = Command::new(env!("CARGO_BIN_EXE_shaders"))
            .args(["export", "--profile"])
            .arg(dir.join(format!("{name}.toml")))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        (String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (code, log) = export("mobile-sh-l1");
    assert!(log.contains("profile 'mobile diffuse SH L1': left out") && log.contains("bytes"), "{log}");
    assert!(code.contains("sh_l1_irradiance") && code.contains("Language: GLSL"), "a GLSL include file with the SH L1 function expected");
    for never in ["specular", "sg_", "ad9_", "ad12_", "ggx"] {
        assert!(!code.contains(never), "{never} in a Lambert-only SH L1 export");
    }
    let (code, _) = export("ad9-diffuse-specular");
    assert!(code.contains("ad9_specular") && code.contains("ad9_irradiance") && code.contains("sh_l2_irradiance"));
}

/// An export says what it left out in one line; `-v` lists the items. Mutation tried: the
/// list printed without `-v` — the first assertion fails (the list is ~4 KB).
#[test]
fn exports_are_quiet_unless_verbose() {
    let run = |extra: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_shaders"))
            .args(["export", "--config", "sh-l2-irradiance", "--lang", "wgsl"])
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let quiet = run(&[]);
    assert_eq!(quiet.lines().count(), 1, "one summary line expected: {quiet}");
    assert!(quiet.contains("left out") && quiet.contains("-v lists them"), "{quiet}");
    let verbose = run(&["-v"]);
    let list = verbose.lines().find(|l| l.starts_with("left out: ")).expect("-v lists the items");
    assert!(list.contains("::"), "{list}");
}

/// A profile with an unknown basis: the tool exits with 2 (as every tool does for a profile
/// it cannot use) and names the key with its line and column.
#[test]
fn bad_profile_exits_2_naming_key_line_and_column() {
    let p = std::env::temp_dir().join(format!("{}-bad-profile-{}.toml", env!("CARGO_PKG_NAME"), std::process::id()));
    std::fs::write(&p, "name = \"bad\"\n[lightmap]\nbases = [\"sh3\"]\n[brdf]\nmodels = [\"lambert\"]\n[runtime]\nprecision = \"f32\"\nlanguage = \"wgsl\"\n").unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_shaders")).args(["export", "--profile"]).arg(&p).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("line 3, column 9") && err.contains("lightmap.bases"), "{err}");
    std::fs::remove_file(&p).unwrap();
}

/// Every shader feature and table the basis registry names for a runtime exists: a
/// composition feature of this crate, a table committed in luts/ (a misspelt or removed
/// feature in `sbf::registry::BASES` fails here, not in an engine's build).
#[test]
fn the_registry_names_features_and_tables_that_exist() {
    let features: Vec<&str> = shaders::compose::Feature::ALL.iter().map(|(_, n)| *n).collect();
    let luts = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../luts");
    for b in sbf::registry::BASES {
        let named = b.irradiance_feature.into_iter().chain(b.specular.iter().filter_map(|s| s.0));
        for f in named {
            assert!(features.contains(&f), "{}: shader feature '{f}' is not one of {features:?}", b.name);
        }
        for t in b.specular.iter().filter_map(|s| s.1) {
            let file = luts.join(sbf::profile::table_file(t));
            assert!(file.is_file(), "{}: table '{t}' has no {}", b.name, file.display());
        }
    }
}
