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
