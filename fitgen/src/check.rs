//! `fitgen --check`: regenerate in memory and compare with the committed files.

use crate::manifest;
use crate::outputs::Output;
use std::path::Path;

/// Differences found by [`check`], one readable line each (empty = all match).
pub fn check(outputs: &[Output], dir: &Path) -> Vec<String> {
    let mut problems = Vec::new();
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
