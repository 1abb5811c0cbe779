//! The wave's pass graph as a value: every pass with its WGSL file, entry point, the
//! buffers it binds (read from the composed kernel by naga, not declared by hand), how it
//! is dispatched and how often it runs in a wave. It prints itself (`Display`), so the
//! graph a bake runs can be logged and checked against the one `ARCHITECTURE.md` shows.

use std::fmt;

/// One pass of a wave.
#[derive(Debug, Clone, PartialEq)]
pub struct GraphPass {
    pub name: &'static str,
    /// The file holding its logic.
    pub wgsl: &'static str,
    /// The entry point (None: a primitive recorded from the host).
    pub entry: Option<&'static str>,
    /// The buffers it binds, by name, in (group, binding) order.
    pub buffers: Vec<&'static str>,
    /// "jobs" (one thread per job of the wave), "queue" (indirect, one thread per active
    /// path), "one" (a single thread) or "host" (a primitive).
    pub dispatch: &'static str,
    /// "once" or "per bounce" (bounce 0 ..= max; compact and wave_args not after the last).
    pub repeat: &'static str,
}

/// The passes of one wave, in the order [`super::Wavefront::record`] runs them.
#[derive(Debug, Clone, PartialEq)]
pub struct PassGraph {
    pub passes: Vec<GraphPass>,
}

/// The name of the buffer at (group, binding) of the bake kernel (group 0: the megakernel's
/// bindings; group 1: the path pool of `wave.wgsl`).
pub fn buffer_name(group: u32, binding: u32) -> &'static str {
    match (group, binding) {
        (0, 0) => "params",
        (0, 1) => "bvh nodes",
        (0, 2) => "triangles",
        (0, 3) => "scene data",
        (0, 4) => "items",
        (0, 5) => "sample points",
        (0, 6) => "moments",
        (0, 7) => "encoder states",
        (0, 8) => "ray counters",
        (0, 9) => "guide records",
        (0, 10) => "guide distributions",
        (0, 11) => "batch items",
        (0, 12) => "batch length",
        (0, 13) => "batch samples",
        (0, 14) => "filter records",
        (0, 18) => "filter params",
        (0, 20) => "material maps",
        (1, 0) => "paths",
        (1, 1) => "hits",
        (1, 2) => "sampler keys",
        (1, 3) => "queue",
        (1, 4) => "path flags",
        (1, 5) => "wave counters",
        (1, 6) => "jobs",
        (1, 7) => "wave args",
        _ => "unnamed binding",
    }
}

impl fmt::Display for PassGraph {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let width = self.passes.iter().map(|p| p.name.len()).max().unwrap_or(0);
        for (k, p) in self.passes.iter().enumerate() {
            let entry = p.entry.map_or_else(|| "host".to_string(), |e| format!("{}::{e}", p.wgsl));
            writeln!(
                f,
                "{k:>2}. {:<width$}  {:<10} {:<5} {entry:<40} binds {}",
                p.name,
                p.repeat,
                p.dispatch,
                if p.buffers.is_empty() { "nothing".to_string() } else { p.buffers.join(", ") }
            )?;
        }
        Ok(())
    }
}
