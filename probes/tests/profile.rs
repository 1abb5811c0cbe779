//! `probes compare --profile`: only the modes of the profile's bases, no specular signal
//! for a Lambert-only profile, and the left-out line.
use std::path::Path;
use std::process::Command;

#[test]
fn profile_runs_only_its_modes_and_signals() {
    let d = std::env::temp_dir().join(format!("probes-profile-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let sky = d.join("sky.hdr");
    let env = Command::new(env!("CARGO_BIN_EXE_probes")).args(["env", "--width", "64", "--out"]).arg(&sky).output().unwrap();
    assert!(env.status.success());
    let profiles = Path::new(env!("CARGO_MANIFEST_DIR")).join("../profiles");
    let run = |name: &str| {
        let out = d.join(name);
        let o = Command::new(env!("CARGO_BIN_EXE_probes"))
            .args(["compare", "--images", "none", "--profile"])
            .arg(profiles.join(format!("{name}.toml")))
            .arg(&sky)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let results: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("results.json")).unwrap()).unwrap();
        let md = std::fs::read_to_string(out.join("report.md")).unwrap();
        (String::from_utf8_lossy(&o.stdout).into_owned(), results, md)
    };
    let (log, results, md) = run("mobile-sh-l1");
    assert!(log.contains("profile 'mobile diffuse SH L1': runs 1 mode(s) (shl1)"), "{log}");
    assert!(log.contains("specular signal left out"), "{log}");
    let ids: Vec<&str> = results[0]["modes"].as_array().unwrap().iter().map(|m| m["id"].as_str().unwrap()).collect();
    assert_eq!(ids, ["shl1"]);
    // No specular field anywhere but the stage timings (which record that the specular
    // stages did no work).
    let mut r = results.clone();
    r[0]["stage_seconds"] = serde_json::Value::Null;
    let text = r.to_string().to_lowercase();
    assert!(!text.contains("specular"), "no specular field in results.json of a Lambert-only profile: {text}");
    assert!(!md.to_lowercase().contains("specular"), "no specular column in report.md");
    let (log, results, md) = run("ad9-diffuse-specular");
    assert!(log.contains("specular at α 0.1, 0.2, 0.4, 0.6, 0.8"), "{log}");
    assert!(results.to_string().contains("specular") && md.to_lowercase().contains("specular"));
    std::fs::remove_dir_all(&d).ok();
}

/// A profile with an unknown basis: the tool exits with 2 (as every tool does for a profile
/// it cannot use) and names the key with its line and column.
#[test]
fn bad_profile_exits_2_naming_key_line_and_column() {
    let p = std::env::temp_dir().join(format!("{}-bad-profile-{}.toml", env!("CARGO_PKG_NAME"), std::process::id()));
    std::fs::write(&p, "name = \"bad\"\n[lightmap]\nbases = [\"sh3\"]\n[brdf]\nmodels = [\"lambert\"]\n[runtime]\nprecision = \"f32\"\nlanguage = \"wgsl\"\n").unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_probes")).args(["compare", "--profile"]).arg(&p).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("line 3, column 9") && err.contains("lightmap.bases"), "{err}");
    std::fs::remove_file(&p).unwrap();
}
