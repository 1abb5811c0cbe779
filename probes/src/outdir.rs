//! The output folder a run owns. A run writes a manifest (`probes-manifest.json`) listing
//! every file it wrote; the next run into the same folder removes exactly those files
//! before writing its own, so a folder never mixes two runs' images. A non-empty folder
//! without a manifest belongs to someone else: the run refuses it before any work unless
//! `--force`, and then still removes nothing it did not write.

use serde::{Deserialize, Serialize};
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

/// The manifest's file name inside the output folder.
pub const MANIFEST: &str = "probes-manifest.json";

#[derive(Debug, Serialize, Deserialize)]
struct Manifest {
    tool: String,
    version: String,
    /// Paths relative to the folder, sorted.
    files: Vec<String>,
}

/// An output folder checked at the start of a run (see the module docs).
#[derive(Debug)]
pub struct OutDir {
    path: PathBuf,
    /// Files the previous run wrote (relative paths from its manifest).
    previous: Vec<String>,
    written: Mutex<Vec<PathBuf>>,
}

impl OutDir {
    /// Checks that `path` can be this run's folder, creating it when absent; writes nothing
    /// else and removes nothing.
    pub fn claim(path: &Path, force: bool) -> Result<OutDir, String> {
        let shown = path.display();
        let mut previous = Vec::new();
        match std::fs::metadata(path) {
            Ok(m) if !m.is_dir() => return Err(format!("--out {shown}: exists and is not a folder")),
            Ok(_) => {
                let manifest = path.join(MANIFEST);
                if manifest.exists() {
                    let text = std::fs::read_to_string(&manifest).map_err(|e| format!("reading {}: {e}", manifest.display()))?;
                    let m: Manifest =
                        serde_json::from_str(&text).map_err(|e| format!("{}: not a probes manifest ({e})", manifest.display()))?;
                    previous = m.files;
                } else {
                    let mut entries = std::fs::read_dir(path).map_err(|e| format!("--out {shown}: {e}"))?;
                    if entries.next().is_some() && !force {
                        return Err(format!(
                            "--out {shown}: the folder is not empty and no probes run wrote it (no {MANIFEST}); choose another --out, or pass --force to write into it (nothing already there is removed)"
                        ));
                    }
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                std::fs::create_dir_all(path).map_err(|e| format!("--out {shown}: cannot create it: {e}"))?;
            }
            Err(e) => return Err(format!("--out {shown}: {e}")),
        }
        Ok(OutDir { path: path.to_path_buf(), previous, written: Mutex::new(Vec::new()) })
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Removes the previous run's files (and the folders they leave empty). Paths that are
    /// not plain relative paths inside the folder are ignored.
    pub fn remove_previous(&self) -> Result<usize, String> {
        let mut removed = 0;
        let mut dirs = std::collections::BTreeSet::new();
        for f in &self.previous {
            let rel = Path::new(f);
            if !rel.components().all(|c| matches!(c, Component::Normal(_))) {
                continue;
            }
            let p = self.path.join(rel);
            match std::fs::remove_file(&p) {
                Ok(()) => removed += 1,
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => return Err(format!("removing {}: {e}", p.display())),
            }
            let mut parent = rel.parent();
            while let Some(d) = parent.filter(|d| !d.as_os_str().is_empty()) {
                dirs.insert(d.to_path_buf());
                parent = d.parent();
            }
        }
        // Deepest first; a folder that still holds something stays.
        for d in dirs.iter().rev() {
            let _ = std::fs::remove_dir(self.path.join(d));
        }
        Ok(removed)
    }

    /// Records a file this run writes and returns its path (call before writing it).
    pub fn file(&self, path: PathBuf) -> PathBuf {
        self.written.lock().unwrap_or_else(|e| e.into_inner()).push(path.clone());
        path
    }

    /// Writes the manifest of every recorded file.
    pub fn finish(&self) -> Result<(), String> {
        let mut files: Vec<String> = self
            .written
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .iter()
            .filter_map(|p| p.strip_prefix(&self.path).ok())
            .map(|p| p.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/"))
            .collect();
        files.sort();
        files.dedup();
        let m = Manifest { tool: "probes".into(), version: env!("CARGO_PKG_VERSION").into(), files };
        let text = serde_json::to_string_pretty(&m).expect("manifest serialises") + "\n";
        let p = self.path.join(MANIFEST);
        std::fs::write(&p, text).map_err(|e| format!("writing {}: {e}", p.display()))
    }
}
