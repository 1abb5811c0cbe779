//! Measurements of a GPU bake: rays per second (primary and secondary) and GPU time per
//! wavefront pass.

use super::GpuBake;

/// Rays traced and the time they took.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RayStats {
    pub primary: u64,
    pub extension: u64,
    pub shadow: u64,
    /// Seconds of the primary-only dispatches and of the full ones.
    pub primary_seconds: f64,
    pub full_seconds: f64,
}

impl RayStats {
    /// Primary rays per second (first segments only, closest hit).
    pub fn primary_rate(&self) -> f64 {
        self.primary as f64 / self.primary_seconds
    }
    /// Secondary (extension + shadow) rays per second: their count over the full
    /// passes' time minus the primary-only time.
    pub fn secondary_rate(&self) -> f64 {
        (self.extension + self.shadow) as f64 / (self.full_seconds - self.primary_seconds).max(1e-9)
    }
}

impl GpuBake<'_> {
    /// GPU time per wavefront pass over `passes` passes, from timestamps at every pass's
    /// start and end: (pass, seconds in all, times run), in the order first run. Needs the
    /// wavefront pipeline and `Features::TIMESTAMP_QUERY`; the bake's state is modified
    /// (use a throw-away bake).
    pub fn profile_passes(&mut self, passes: u64) -> Result<Vec<(&'static str, f64, u64)>, String> {
        let Some(w) = self.wavefront.as_mut() else {
            return Err("per-pass GPU times are measured for the wavefront pipeline (--pipeline wavefront)".into());
        };
        w.enable_profiling(self.gpu.device())?;
        self.profile = Some(Vec::new());
        let r = self.run(passes);
        let totals = self.profile.take().unwrap_or_default();
        if let Some(w) = self.wavefront.as_mut() {
            w.disable_profiling();
        }
        r.map(|_| totals)
    }

    /// Measures rays per second over `passes` passes: primary-only dispatches (closest
    /// hit of each path's first segment, no shading, no encoding) and full ones (paths,
    /// shadow rays, and the per-sample encoders), counted in a separate run with ray
    /// counters on. Secondary rays/s = (extension + shadow) / (full − primary time), so
    /// shading and encoding are charged to the secondary rays. The bake's state is
    /// modified (use a throw-away bake).
    pub fn time_rays(&mut self, passes: u64) -> Result<RayStats, String> {
        let mut s = RayStats::default();
        let q = self.gpu.queue();
        let read_counters = |b: &wgpu::Buffer| -> Result<[u32; 4], String> { Ok(bytemuck::pod_read_unaligned(&self.gpu.read_back(b)?)) };
        // Warm-up (pipeline compilation, caches).
        self.run(1)?;
        for primary in [true, false] {
            q.write_buffer(&self.counters_buf, 0, &[0u8; 16]);
            self.params.primary_only = primary as u32;
            self.params.count_rays = 1;
            self.run(passes)?;
            let c = read_counters(&self.counters_buf)?;
            if primary {
                s.primary = c[0] as u64;
            } else {
                (s.extension, s.shadow) = (c[1] as u64, c[2] as u64);
            }
            // Timed without counters (atomics would perturb the timing).
            self.params.count_rays = 0;
            let t = std::time::Instant::now();
            self.run(passes)?;
            let secs = t.elapsed().as_secs_f64();
            if primary {
                s.primary_seconds = secs;
            } else {
                s.full_seconds = secs;
            }
        }
        self.params.primary_only = 0;
        Ok(s)
    }
}
