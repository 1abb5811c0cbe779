//! The distributed recipes (docs/distributed/) through the validators their platforms' users
//! run: the Kubernetes manifest against the Job schema of the minimum version it states
//! (`kubernetes-validate`, strict: unknown fields rejected), and the Slurm script through
//! `shellcheck`. What the recipes do when run is tested elsewhere (`shards.rs`: the Slurm loop
//! with a failing baker; `distributed.rs`: the Dask driver).
//!
//! Oracles: the validators themselves; the manifest must also *fail* against Kubernetes 1.27,
//! whose Job has no `backoffLimitPerIndex` — so the schema check reads the fields the stated
//! minimum (1.29) rests on. Without the tools the tests skip with a message, except under
//! `SBF_REQUIRE_DASK=1` (CI, which installs both with the distributed bake's Python).

use std::path::{Path, PathBuf};
use std::process::Command;

fn recipes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/distributed")
}

/// `tool` from the folder of `SBF_PYTHON` (a virtual environment's bin/) or the PATH.
fn tool(name: &str, install: &str) -> Option<PathBuf> {
    let beside = std::env::var("SBF_PYTHON").ok().and_then(|py| Path::new(&py).parent().map(|d| d.join(name))).filter(|p| p.is_file());
    let found =
        beside.or_else(|| Command::new(name).arg("--version").output().ok().filter(|o| o.status.success()).map(|_| PathBuf::from(name)));
    if found.is_none() {
        assert!(std::env::var("SBF_REQUIRE_DASK").map_or(true, |v| v != "1"), "SBF_REQUIRE_DASK=1 but `{name}` is missing: {install}");
        println!("skipped: no `{name}` ({install})");
    }
    found
}

fn validate(exe: &Path, version: &str) -> (bool, String) {
    let o = Command::new(exe)
        .args(["--kubernetes-version", version, "--strict"])
        .arg(recipes().join("k8s-indexed-job.yaml"))
        .output()
        .expect("kubernetes-validate runs");
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    (o.status.success() && !text.contains("ERROR"), text)
}

#[test]
fn the_kubernetes_manifest_validates_against_its_minimum_version() {
    let Some(exe) = tool("kubernetes-validate", "pip install -r docs/distributed/requirements-check.txt") else { return };
    let (ok, text) = validate(&exe, "1.29.0");
    assert!(ok, "k8s-indexed-job.yaml against Kubernetes 1.29:\n{text}");
    // Both Jobs (the shards and the merge) were checked.
    assert_eq!(text.matches("passed for resource job/").count(), 2, "{text}");
    let (ok_old, old) = validate(&exe, "1.27.0");
    assert!(!ok_old && old.contains("backoffLimitPerIndex"), "the manifest should not validate against 1.27:\n{old}");
}

#[test]
fn the_slurm_script_passes_shellcheck() {
    let Some(exe) = tool("shellcheck", "apt-get install shellcheck") else { return };
    let o = Command::new(exe).arg(recipes().join("slurm-array.sh")).output().expect("shellcheck runs");
    assert!(o.status.success(), "shellcheck slurm-array.sh:\n{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
}
