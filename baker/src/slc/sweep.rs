//! The equal-time experiment ([TH17-supp §2, Fig. 2]: "our ellipsoid-based approach can render
//! higher-quality images than the sphere-based approach when comparing at the same
//! computation time"): the variance control δ trades time for noise, so each method is
//! rendered over a range of δ and its error against brute force (every VPL at every pixel)
//! read at the time the reference configuration takes. Methods: stochastic culling with the
//! GGX spheroid ([TH17 §5]), with its enclosing sphere, and the deterministic range cut at
//! ξ = ½ (the classic clamped ranges: biased).

use super::{Bound, Filter, GBuffer, Mode, Vpl};
use sbf::glam::Vec3;
use serde_json::json;
use std::time::Instant;

/// One method at one δ.
#[derive(Debug, Clone)]
pub struct Point {
    pub method: &'static str,
    pub delta: f32,
    /// Seconds per frame: on the GPU the frame's span by timestamps
    /// (`SlcGpu::time_frame`), on the CPU the render's wall time.
    pub seconds: f64,
    /// Relative RMSE against brute force after the filter, and before it.
    pub filtered: f64,
    pub unfiltered: f64,
}

/// The methods compared: (name, mode, bound).
const METHODS: [(&str, Mode, Bound); 3] =
    [("spheroid", Mode::Culled, Bound::Tight), ("sphere", Mode::Culled, Bound::Sphere), ("range cut", Mode::RangeCut, Bound::Tight)];

/// Relative RMSE of `img` against `reference` over the valid pixels' RGB values.
fn relative_rmse(reference: &[Vec3], img: &[Vec3], valid: &[f32]) -> f64 {
    let (mut sq, mut mean, mut n) = (0.0f64, 0.0f64, 0usize);
    for ((r, x), v) in reference.iter().zip(img).zip(valid) {
        if *v > 0.0 {
            // Channel by channel, as the main run's error (the same sums to the bit).
            for c in 0..3 {
                sq += (x[c] as f64 - r[c] as f64).powi(2);
                mean += r[c] as f64;
                n += 1;
            }
        }
    }
    let n = n.max(1) as f64;
    (sq / n).sqrt() / (mean / n).max(f64::MIN_POSITIVE)
}

/// How the sweep renders: as the main run does.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    pub interleave: usize,
    pub filter: Filter,
    /// Timed GPU frames per point (median).
    pub frames: usize,
    /// The GPU's own ξ stream ([`super::gpu::SlcGpu::set_xi_seed`]).
    pub xi_seed: u32,
}

/// Renders every method at every δ of `deltas` (GPU frames timed as the main run's, or one
/// CPU render each) and measures its error against `reference`.
pub fn run(
    s: Settings,
    gpu: Option<&shaders::gpu::Gpu>,
    g: &GBuffer,
    vpls: &[Vpl],
    deltas: &[f32],
    (reference, valid): (&[Vec3], &[f32]),
    log: &mut dyn FnMut(String),
) -> Result<Vec<Point>, String> {
    let mut out = Vec::new();
    for &(method, mode, bound) in &METHODS {
        for &delta in deltas {
            let (r, seconds) = match gpu {
                Some(gp) => {
                    let mut r = super::gpu::SlcGpu::new(gp, g, vpls, delta, s.interleave)?;
                    r.set_xi_seed(Some(s.xi_seed));
                    r.set_bound(bound);
                    r.set_filter_kind(s.filter);
                    (r.run(mode)?, r.time_frame(mode, s.frames)?)
                }
                None => {
                    let t = Instant::now();
                    (super::render_filtered(g, vpls, delta, mode, s.interleave, bound, s.filter), t.elapsed().as_secs_f64())
                }
            };
            let p = Point {
                method,
                delta,
                seconds,
                filtered: relative_rmse(reference, &r.filtered, valid),
                unfiltered: relative_rmse(reference, &r.image, valid),
            };
            log(format!(
                "slc sweep {method} δ {delta:e}: {:.3} ms, relative RMSE {:.4} filtered, {:.4} unfiltered",
                seconds * 1e3,
                p.filtered,
                p.unfiltered
            ));
            out.push(p);
        }
    }
    Ok(out)
}

/// `method`'s filtered error at `seconds`, interpolated linearly in (log time, log error)
/// between the two δ that bracket it; None outside the times it reached.
pub fn error_at(points: &[Point], method: &str, seconds: f64) -> Option<f64> {
    let mut m: Vec<&Point> = points.iter().filter(|p| p.method == method).collect();
    m.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    m.windows(2).find(|w| w[0].seconds <= seconds && seconds <= w[1].seconds).map(|w| {
        let (t0, t1) = (w[0].seconds.ln(), w[1].seconds.ln());
        let f = if t1 > t0 { (seconds.ln() - t0) / (t1 - t0) } else { 0.0 };
        (w[0].filtered.ln() + f * (w[1].filtered.ln() - w[0].filtered.ln())).exp()
    })
}

/// slc.json's `sweep`: every point, and each method's error at the time the spheroid takes
/// at `delta` (the run's δ) — the equal-time comparison.
pub fn json(points: &[Point], delta: f32) -> serde_json::Value {
    let at = points.iter().find(|p| p.method == "spheroid" && p.delta == delta).map(|p| p.seconds);
    let equal: serde_json::Map<String, serde_json::Value> =
        METHODS.iter().map(|(m, _, _)| (m.to_string(), json!(at.and_then(|t| error_at(points, m, t))))).collect();
    json!({
        "points": points.iter().map(|p| json!({"method": p.method, "delta": p.delta, "seconds_per_frame": p.seconds,
            "relative_rmse_filtered": p.filtered, "relative_rmse_unfiltered": p.unfiltered})).collect::<Vec<_>>(),
        "equal_time": {"seconds_per_frame": at, "relative_rmse_filtered": equal,
            "note": "each method's filtered relative RMSE interpolated (log-log) at the spheroid's frame time at the run's δ; null: the method's δ range did not reach that time; GPU times: the frame's span by timestamp queries (host submission and wait left out)"},
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(method: &'static str, seconds: f64, filtered: f64) -> Point {
        Point { method, delta: 0.0, seconds, filtered, unfiltered: 0.0 }
    }

    /// Log-log interpolation between the bracketing points (a power law e = t^-½ is returned
    /// exactly between its samples), None outside them.
    #[test]
    fn error_at_interpolates_in_log_log() {
        let pts = [p("a", 1.0, 1.0), p("a", 4.0, 0.5), p("a", 16.0, 0.25), p("b", 2.0, 3.0)];
        let e = error_at(&pts, "a", 9.0).unwrap();
        assert!((e - 9f64.powf(-0.5)).abs() < 1e-12, "{e}");
        assert_eq!(error_at(&pts, "a", 0.5), None);
        assert_eq!(error_at(&pts, "b", 2.0), None);
        assert!((error_at(&pts, "a", 4.0).unwrap() - 0.5).abs() < 1e-12);
        // The ends of the range are inside it.
        assert!((error_at(&pts, "a", 16.0).unwrap() - 0.25).abs() < 1e-12);
        assert!((error_at(&pts, "a", 1.0).unwrap() - 1.0).abs() < 1e-12);
    }
}
