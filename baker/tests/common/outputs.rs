//! A bake's written files compared by content: SHA-256 of every file, bake.json without
//! the fields that measure the run.

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The shared scenes folder, or None (printed) when it is absent — unless
/// `SBF_REQUIRE_PROBES=1` (CI), where a missing folder fails the test.
pub fn scenes_dir() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes");
    if p.is_dir() {
        return Some(p);
    }
    assert!(std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"), "SBF_REQUIRE_PROBES=1 but {} is missing", p.display());
    println!("skipped: {} is missing", p.display());
    None
}

/// Removes the fields of bake.json that measure this run rather than describe the bake
/// (wall times, peak memory, the device and its thread count) or name the engine (the GPU
/// pipeline).
pub fn strip_run_fields(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(m) => {
            for k in ["seconds", "stage_seconds", "device", "pipeline", "peak_memory_bytes"] {
                m.remove(k);
            }
            m.values_mut().for_each(strip_run_fields);
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(strip_run_fields),
        _ => {}
    }
}

pub fn sha(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// A bake spec's file paths (`scene` when a file, `environment`) cut to their file names:
/// where this machine keeps the data is not what was baked (a clone elsewhere bakes the
/// same spec with other absolute paths).
pub fn strip_spec_paths(spec: &mut serde_json::Value) {
    for k in ["scene", "environment"] {
        if let Some(serde_json::Value::String(p)) = spec.get_mut(k) {
            if let Some((_, name)) = p.rsplit_once('/') {
                *p = name.to_string();
            }
        }
    }
}

/// (file, SHA-256) of every file a bake wrote, sorted by name; bake.json stripped first
/// (canonical form: keys sorted, numbers round-trip exact), bake.json's and spec.json's
/// spec without the folders of its files.
pub fn hashes(dir: &Path) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        let bytes = std::fs::read(&p).unwrap();
        let h = if name == "bake.json" || name == "spec.json" {
            let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
            strip_run_fields(&mut v);
            if name == "bake.json" {
                strip_spec_paths(&mut v["spec"]);
            } else {
                strip_spec_paths(&mut v);
            }
            sha(serde_json::to_string(&v).unwrap().as_bytes())
        } else {
            sha(&bytes)
        };
        out.push((name, h));
    }
    out.sort();
    out
}
