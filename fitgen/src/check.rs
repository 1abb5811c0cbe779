//! `fitgen --check`: regenerate in memory and compare with the committed files.

use crate::manifest;
use crate::outputs::Output;
use std::path::Path;

/// Files in the tables folder that no generator writes.
const NOT_GENERATED: [&str; 2] = ["MANIFEST", "README.md"];

/// Differences found by [`check`], one readable line each (empty = all match). With
/// `stale`, files in `dir` that `fitgen all` does not produce, and MANIFEST entries for
/// such files, are problems too: a table nothing generates any more must not linger in the
/// folder sbf embeds from.
pub fn check(outputs: &[Output], dir: &Path, stale: bool) -> Vec<String> {
    let mut problems = Vec::new();
    if stale {
        let all = crate::outputs::committed_files();
        let produced: Vec<&str> = all.iter().map(|f| f.as_str()).collect();
        match std::fs::read_dir(dir) {
            Err(e) => problems.push(format!("{}: cannot list ({e})", dir.display())),
            Ok(entries) => {
                let mut names: Vec<String> = entries.filter_map(|e| e.ok()).map(|e| e.file_name().to_string_lossy().into_owned()).collect();
                names.sort();
                for n in names {
                    if !produced.contains(&n.as_str()) && !NOT_GENERATED.contains(&n.as_str()) {
                        problems.push(format!("{}: stale — `fitgen all` does not produce it; delete it", dir.join(&n).display()));
                    }
                }
            }
        }
        if let Ok(m) = std::fs::read_to_string(dir.join("MANIFEST")) {
            for f in m.lines().filter_map(crate::manifest::file_of) {
                if !produced.contains(&f) && f != "(all)" {
                    problems.push(format!("{}: stale entry for {f}, which `fitgen all` does not produce", dir.join("MANIFEST").display()));
                }
            }
        }
    }
    for o in outputs {
        let path = dir.join(&o.file);
        match std::fs::read(&path) {
            Err(e) => problems.push(format!("{}: cannot read ({e})", path.display())),
            Ok(committed) if committed != o.bytes => {
                let first = committed.iter().zip(&o.bytes).position(|(a, b)| a != b).unwrap_or(committed.len().min(o.bytes.len()));
                problems.push(format!(
                    "{}: differs from a fresh `fitgen {}` (committed {} bytes, regenerated {} bytes, first difference at byte {first}; sha256 {} vs {})",
                    path.display(),
                    o.name,
                    committed.len(),
                    o.bytes.len(),
                    manifest::sha256_hex(&committed),
                    manifest::sha256_hex(&o.bytes)
                ))
            }
            Ok(_) => {}
        }
    }
    let mpath = dir.join("MANIFEST");
    match std::fs::read_to_string(&mpath) {
        Err(e) => problems.push(format!("{}: cannot read ({e})", mpath.display())),
        Ok(m) => {
            for o in outputs {
                let fresh = manifest::without_wall_time(&manifest::line(o));
                let found = m.lines().find(|l| manifest::file_of(l) == Some(o.file.as_str()));
                match found {
                    None => problems.push(format!("{}: no entry for {}", mpath.display(), o.file)),
                    Some(l) if manifest::without_wall_time(l) != fresh => {
                        problems.push(format!("{}: entry for {} is stale (parameters, error or sha256 changed)", mpath.display(), o.file))
                    }
                    Some(_) => {}
                }
            }
        }
    }
    problems
}
