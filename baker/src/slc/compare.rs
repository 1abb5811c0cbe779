//! The side-by-side comparisons of the `slc` command: the glossy bounds ([TH17 §7, Fig. 9])
//! and the culling schemes ([TH17 Table 2]), each on the run's VPLs with the same ξ.

use super::options::SlcOptions;
use serde_json::json;
use std::time::Instant;

/// The glossy bounds side by side ([TH17 §7, Fig. 9]): the same VPLs and ξ culled by the
/// spheroid, the sphere enclosing it and the TH16 sphere of radius r/α; their times (GPU:
/// the frame's span by timestamps, `SlcGpu::time_frame`), VPLs per pixel and false
/// discoveries.
pub fn bounds(
    s: &SlcOptions,
    gpu: Option<&shaders::gpu::Gpu>,
    g: &crate::slc::GBuffer,
    vpls: &[crate::slc::Vpl],
    log: &mut dyn FnMut(String),
) -> Result<serde_json::Map<String, serde_json::Value>, String> {
    use super::options::gpu_xi_seed;
    use crate::slc::{self, Mode};
    let n = (s.width * s.height) as f64;
    let mut bounds = serde_json::Map::new();
    for b in [slc::Bound::Tight, slc::Bound::Sphere, slc::Bound::Th16] {
        let (r, sec) = match gpu {
            Some(gp) => {
                let mut r = crate::slc::gpu::SlcGpu::new(gp, g, vpls, s.delta, s.interleave)?;
                r.set_xi_seed(Some(gpu_xi_seed(s.seed)));
                r.set_bound(b);
                (r.run(Mode::Culled)?, r.time_frame(Mode::Culled, s.frames)?)
            }
            None => {
                let t = Instant::now();
                (slc::render_with(g, vpls, s.delta, Mode::Culled, s.interleave, b), t.elapsed().as_secs_f64())
            }
        };
        let shaded: u64 = r.lights_per_pixel.iter().map(|x| *x as u64).sum();
        log(format!(
            "slc bound {b:?}: {:.3} ms per frame, {:.1} VPLs per pixel, false discovery rate {:.3}, {} false discoveries",
            sec * 1e3,
            shaded as f64 / n,
            r.pixel_fdr(),
            r.false_discoveries()
        ));
        bounds.insert(
            format!("{b:?}").to_lowercase(),
            json!({"seconds_per_frame": sec, "vpls_per_pixel": shaded as f64 / n, "false_discovery_rate": r.pixel_fdr(),
                   "false_discoveries": r.false_discoveries(), "shaded": shaded, "kept_pairs": r.kept, "pairs_accepted_by_no_pixel": r.false_positives}),
        );
    }
    Ok(bounds)
}

/// [TH17 Table 2]'s comparison: the culling and shading pass of tiled culling (Modified
/// HalfZ, ours) against clustered shading (32 depth slices per 16 × 16 tile; compute, not
/// conservative rasterisation) for diffuse VPLs only (spheres) and glossy VPLs only
/// (spheroids: the run's diffuse VPLs made GGX VPLs of α `glossy_alpha`, F0 0.9, as
/// `--kind glossy`), with the run's interleaving. GPU: the culling + shading stage's
/// timestamps (median); CPU: wall time of the render. Splatting (rasterised bounding
/// geometry) is not built.
pub fn culling(
    s: &SlcOptions,
    gpu: Option<&shaders::gpu::Gpu>,
    g: &crate::slc::GBuffer,
    vpls: &[crate::slc::Vpl],
    log: &mut dyn FnMut(String),
) -> Result<serde_json::Value, String> {
    use crate::slc::{self, Culling, Mode, Vpl};
    use sbf::glam::Vec3;
    let diffuse: Vec<Vpl> = vpls.iter().filter(|v| v.is_diffuse()).copied().collect();
    let glossy: Vec<Vpl> = diffuse.iter().map(|v| Vpl { diffuse: Vec3::ZERO, alpha: s.glossy_alpha, f0: Vec3::splat(0.9), ..*v }).collect();
    let n = (s.width * s.height) as f64;
    let mut rows = Vec::new();
    for (set, v) in [("diffuse", &diffuse), ("glossy", &glossy)] {
        for c in [Culling::HalfZ, Culling::Clustered(32)] {
            let name = match c {
                Culling::HalfZ => "tiled (Modified HalfZ)".to_string(),
                Culling::Clustered(k) => format!("clustered ({k} slices)"),
            };
            let (r, ms) = match gpu {
                Some(gp) => {
                    let mut r = slc::gpu::SlcGpu::new(gp, g, v, s.delta, s.interleave)?;
                    r.set_xi_seed(Some(super::options::gpu_xi_seed(s.seed)));
                    r.set_culling(c)?;
                    r.set_filter(false);
                    let st = r.time_stages(Mode::Culled, s.frames)?;
                    let ms = match st {
                        Some(st) => st.culling_shading * 1e3,
                        None => r.time(Mode::Culled, s.frames)? * 1e3,
                    };
                    (r.run(Mode::Culled)?, ms)
                }
                None => {
                    let t = Instant::now();
                    let r = slc::render_culled(g, v, s.delta, Mode::Culled, s.interleave, slc::Bound::Tight, s.filter, c);
                    (r, t.elapsed().as_secs_f64() * 1e3)
                }
            };
            let shaded: u64 = r.lights_per_pixel.iter().map(|x| *x as u64).sum();
            log(format!(
                "slc culling, {set} VPLs ({}), {name}: {ms:.3} ms culling + shading, {:.2} VPLs per pixel, false discovery rate {:.3}",
                v.len(),
                shaded as f64 / n,
                r.pixel_fdr()
            ));
            rows.push(json!({"vpls": set, "count": v.len(), "culling": name, "culling_and_shading_ms": ms,
                "vpls_per_pixel": shaded as f64 / n, "false_discovery_rate": r.pixel_fdr(), "kept_pairs": r.kept}));
        }
    }
    Ok(
        json!({"rows": rows, "timing": if gpu.is_some() { "GPU timestamps of the culling + shading pass (median)" } else { "CPU wall time of culling, shading and the filter (one thread)" },
        "note": "[TH17 Table 2]'s comparison with its clustered-shading baseline in compute form; splatting not built"}),
    )
}
