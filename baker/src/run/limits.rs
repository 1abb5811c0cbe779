//! The bounds a bake's options must respect, checked before any work ([`Options::validate`]),
//! and the memory check once the atlas is laid out ([`check_memory`]). Each limit says
//! what it bounds (memory or time); a refusal names the option, the value and the limit.

use super::Options;
use crate::accumulate::BasisId;

/// Preview width: the preview is W × 3W/4 RGB f32 (8192 → 0.6 GB) and traces a path per
/// pixel.
pub const MAX_PREVIEW_WIDTH: usize = 8192;
/// Smallest preview width (a 8 × 6 image).
pub const MIN_PREVIEW_WIDTH: usize = 8;
/// Denoiser window radius: the non-local means compare (2r + 1)² neighbours per texel and
/// coefficient set (16 → 1 089, 9× the default radius 5's cost; the weights of texels
/// further away than a few texels are negligible on lightmap charts).
pub const MAX_DENOISE_RADIUS: usize = 16;
/// Probes in a grid: each holds its encoders and moments (≈ 1 KB with SH L2 + AD 12) and a
/// record in probes.json (≈ 1 KB of text): 262 144 probes ≈ 0.5 GB.
pub const MAX_PROBES: usize = 1 << 18;
/// Passes (and `--measure-rays` passes): a pass is a 32-bit sample index in the sample
/// sequences and on the GPU.
pub const MAX_PASSES: u64 = u32::MAX as u64;
/// Bounces per path: each costs a ray (and a shadow ray) per texel and pass.
pub const MAX_BOUNCES: u32 = 256;
/// Padding texels around a chart (and dilation rings).
pub const MAX_PADDING: usize = 64;

impl Options {
    /// Every bound of this module; the first violated one as an error naming the option.
    pub fn validate(&self) -> Result<(), String> {
        let w = self.spec.preview_width;
        if !(MIN_PREVIEW_WIDTH..=MAX_PREVIEW_WIDTH).contains(&w) {
            return Err(format!(
                "--preview-width {w}: must be {MIN_PREVIEW_WIDTH} to {MAX_PREVIEW_WIDTH} pixels (the preview is W × 3W/4 RGB f32, a path per pixel)"
            ));
        }
        if let Some(d) = &self.spec.denoise {
            if d.radius > MAX_DENOISE_RADIUS {
                return Err(format!(
                    "--denoise-radius {}: at most {MAX_DENOISE_RADIUS} texels (the window compares (2r + 1)² texels per texel)",
                    d.radius
                ));
            }
        }
        if let Some([x, y, z]) = self.spec.probes {
            let n = x.checked_mul(y).and_then(|v| v.checked_mul(z)).unwrap_or(usize::MAX);
            if n > MAX_PROBES {
                return Err(format!(
                    "--probes {x},{y},{z}: {} probes, at most {MAX_PROBES} (each holds its fits in memory and a record in probes.json)",
                    if n == usize::MAX { "too many".to_string() } else { n.to_string() }
                ));
            }
        }
        if self.spec.passes == 0 || self.spec.passes > MAX_PASSES {
            return Err(format!("--passes {}: must be 1 to {MAX_PASSES} (a pass is a 32-bit sample index)", self.spec.passes));
        }
        if let Some(p) = self.run.measure_rays {
            if p == 0 || p > MAX_PASSES {
                return Err(format!("--measure-rays {p}: must be 1 to {MAX_PASSES} passes"));
            }
        }
        if self.spec.config.max_bounces > MAX_BOUNCES {
            return Err(format!(
                "--bounces {}: at most {MAX_BOUNCES} (each bounce costs a ray per texel and pass)",
                self.spec.config.max_bounces
            ));
        }
        if self.spec.padding > MAX_PADDING {
            return Err(format!("--padding {}: at most {MAX_PADDING} texels", self.spec.padding));
        }
        if !(self.spec.texels_per_unit.is_finite() && self.spec.texels_per_unit > 0.0) {
            return Err(format!("--texels-per-unit {}: must be a finite number > 0", self.spec.texels_per_unit));
        }
        if self.run.gpus > 1 {
            let c = &self.spec.config;
            let needs_all = [
                (c.guiding.is_some(), "--guiding (its clusters learn from all their texels every pass)"),
                (c.filter.is_some(), "--filter (a texel gathers its neighbours' samples every pass)"),
                (c.adaptive.is_some(), "--adaptive (each batch draws from the whole atlas)"),
                (c.camera.is_some(), "--camera (each batch draws from the whole atlas)"),
            ];
            if let Some((_, why)) = needs_all.iter().find(|(on, _)| *on) {
                return Err(format!("--gpus {}: cannot split a bake with {why}; use one GPU", self.run.gpus));
            }
        }
        if let Some(sh) = &self.run.shard {
            if sh.count == 0 || sh.index >= sh.count {
                return Err(format!("--shard {}/{}: the index must be below the count (0/N to N-1/N)", sh.index, sh.count));
            }
            if sh.count > 1 {
                self.spec.config.check_partitionable().map_err(|e| format!("--shard {}/{}: {e}", sh.index, sh.count))?;
            }
            if self.run.measure_rays.is_some() {
                return Err("--measure-rays measures a whole bake; drop --shard".into());
            }
        }
        if let Some(a) = &self.spec.config.adaptive {
            if a.pilot_passes >= self.spec.passes {
                return Err(format!(
                    "--adaptive-pilot {}: must be below --passes {} (the pilot passes are uniform; the batches spend the rest)",
                    a.pilot_passes, self.spec.passes
                ));
            }
        }
        Ok(())
    }
}

/// Bytes a bake holds per item (texel or probe) with `bases`: its 16 sub-texel points,
/// moments and encoders (coefficients and the per-lobe update state, f64), and the f32
/// images written from them — doubled for the copies post-processing makes (denoiser,
/// seams, dilation).
pub fn bytes_per_item(bases: &[BasisId]) -> u64 {
    let points = crate::layout::lightmap::SUBSAMPLES * std::mem::size_of::<crate::layout::lightmap::SurfacePoint>();
    let moments = std::mem::size_of::<crate::accumulate::Moments>();
    let lobes: usize = bases.iter().map(|b| b.lobes()).sum();
    // Encoder: coefficients (lobes × 3) and the update's per-lobe state (lobes × 3), f64.
    let encoders = lobes * 6 * 8;
    // Images: irradiance, its standard error, normals, and every lobe's RGB, f32.
    let images = (3 + lobes) * 3 * 4;
    (points + moments + encoders + 2 * images) as u64
}

/// Refuses a bake whose state would not fit in the memory available now (Linux:
/// MemAvailable of /proc/meminfo; elsewhere not checked, and said so in the log).
pub fn check_memory(what: &str, items: usize, bases: &[BasisId], log: &mut dyn FnMut(String)) -> Result<(), String> {
    let need = items as u64 * bytes_per_item(bases);
    match available_memory() {
        Some(avail) if need > avail => Err(format!(
            "{what}: {items} items × {} B ≈ {:.1} GB of bake state, more than the {:.1} GB of memory available (lower --texels-per-unit, --probes or the bases)",
            bytes_per_item(bases),
            need as f64 * 1e-9,
            avail as f64 * 1e-9
        )),
        Some(_) => Ok(()),
        None => {
            log(format!("{what}: memory not checked (no /proc/meminfo); the bake state needs ≈ {:.2} GB", need as f64 * 1e-9));
            Ok(())
        }
    }
}

/// MemAvailable in bytes (Linux), or None.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The process's peak resident memory in bytes (Linux: VmHWM of /proc/self/status), or None.
pub fn peak_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = text.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Refuses an output folder the bake could not write, before any tracing: creates it and
/// a scratch file in it.
pub fn check_writable(dir: &std::path::Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("--out {}: cannot create the output folder: {e}", dir.display()))?;
    // Named per process: shards of one bake share their output folder.
    let probe = dir.join(format!(".baker-write-check-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| format!("--out {}: the output folder is not writable: {e}", dir.display()))?;
    std::fs::remove_file(&probe).map_err(|e| format!("--out {}: {e}", dir.display()))?;
    Ok(())
}

/// `--exit-with-parent`: a thread that ends the process (status 1, with a message) once the
/// process that started it has ended — Unix: the parent id changes when the parent dies and
/// the process is re-parented; checked every 0.5 s. Elsewhere it does nothing.
pub fn exit_with_parent() {
    #[cfg(unix)]
    {
        let parent = std::os::unix::process::parent_id();
        std::thread::spawn(move || loop {
            std::thread::sleep(std::time::Duration::from_millis(500));
            if std::os::unix::process::parent_id() != parent {
                eprintln!("baker: the process that started this bake (pid {parent}) has ended: exiting (--exit-with-parent)");
                std::process::exit(1);
            }
        });
    }
}
