//! `fitgen --profile`: only the tables a profile's runtime paths read, and the left-out line.
use std::path::Path;
use std::process::Command;

fn profile(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../profiles").join(format!("{name}.toml"))
}

/// A Lambert-only SH profile generates the fit constants and no table, and says which
/// tables (and bytes) it left out and which sbf features it needs; the AD9 + GGX profile
/// generates the AD specular LUT (and, for its SH probes' zonal specular, the DFG); --check
/// with a profile checks only those against the committed luts/.
#[test]
fn profile_generates_only_what_it_needs() {
    let out = std::env::temp_dir().join(format!("fitgen-profile-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_fitgen"))
        .args(["all", "--profile"])
        .arg(profile("mobile-sh-l1"))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("profile 'mobile diffuse SH L1': left out dfg (dfg.sbflut") && stdout.contains("ad-specular-2d"), "{stdout}");
    assert!(stdout.contains("features = [\"sh\"]"), "{stdout}");
    let mut files: Vec<String> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    files.sort();
    assert_eq!(files, ["MANIFEST", "fits.rs", "fits.wgsl"]);
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_fitgen"))
        .args(["all", "--profile"])
        .arg(profile("ad9-diffuse-specular"))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success());
    for f in ["ad_specular_2d.sbflut", "ad_specular_2d.exr", "dfg.sbflut"] {
        assert!(out.join(f).exists(), "{f}");
    }
    std::fs::remove_dir_all(&out).ok();
    let o = Command::new(env!("CARGO_BIN_EXE_fitgen")).args(["--check", "--profile"]).arg(profile("mobile-sh-l1")).output().unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && stdout.contains("2 outputs match"), "{stdout}{}", String::from_utf8_lossy(&o.stderr));
}

/// A profile with an unknown basis: the tool exits with 2 (as every tool does for a profile
/// it cannot use) and names the key with its line and column.
#[test]
fn bad_profile_exits_2_naming_key_line_and_column() {
    let p = std::env::temp_dir().join(format!("{}-bad-profile-{}.toml", env!("CARGO_PKG_NAME"), std::process::id()));
    std::fs::write(&p, "name = \"bad\"\n[lightmap]\nbases = [\"sh3\"]\n[brdf]\nmodels = [\"lambert\"]\n[runtime]\nprecision = \"f32\"\nlanguage = \"wgsl\"\n").unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_fitgen")).args(["all", "--profile"]).arg(&p).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("line 3, column 9") && err.contains("lightmap.bases"), "{err}");
    std::fs::remove_file(&p).unwrap();
}
