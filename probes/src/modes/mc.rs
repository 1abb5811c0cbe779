//! The Monte Carlo mode (`mcis`): the peer's importance-sampled estimate of each output texel's
//! E/π, its cost its encode.

use super::common::*;
use super::context::*;
use sbf::glam::DVec3;

/// Runs mode `id` of this family up to its cost measurement ([`super::prepare`]).
pub(super) fn prepare<'a>(id: &'static str, ctx: &'a Context, _repeats: usize) -> Result<Prepared<'a>, String> {
    let dirs = &ctx.dirs;
    match id {
        "mcis" => {
            // As the peer's MCIS: texels drawn by luminance × solid angle (one discrete
            // distribution over the map), MCIS_SAMPLES draws from one fixed-seed sequence
            // shared by every output texel (the peer's non-jittered default), each draw
            // contributing L·Ω·max(0, n·ω)/p at the texel centre; E/π = mean/π.
            // One timed run on one thread, like every other mode's encode.
            let (irr, t) = timed(1, move || {
                let g = ctx.map.geometry;
                let weights: Vec<f64> = (0..g.texel_count())
                    .map(|k| {
                        let t = ctx.map.texel(k % g.width, k / g.width);
                        (0.2126 * t[0] as f64 + 0.7152 * t[1] as f64 + 0.0722 * t[2] as f64) * g.texel_solid_angle(k / g.width)
                    })
                    .collect();
                let total: f64 = weights.iter().sum();
                if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                    return vec![[0.0; 3]; dirs.len()];
                }
                let mut cdf = Vec::with_capacity(weights.len());
                let mut acc = 0.0;
                for w in &weights {
                    acc += w;
                    cdf.push(acc / total);
                }
                let mut rng = sbf::sampling::Pcg32::new(0, 0);
                // (direction, L·Ω/p) of each draw.
                let draws: Vec<(DVec3, [f64; 3])> = (0..MCIS_SAMPLES)
                    .map(|_| {
                        let u = rng.next_f64();
                        let k = cdf.partition_point(|c| *c <= u).min(weights.len() - 1);
                        let (i, j) = (k % g.width, k / g.width);
                        let p = weights[k] / total;
                        let l = ctx.map.texel(i, j);
                        let s = g.texel_solid_angle(j) / p;
                        (g.texel_direction(i, j), [l[0] as f64 * s, l[1] as f64 * s, l[2] as f64 * s])
                    })
                    .collect();
                // Four output texels per pass over the draws (independent accumulators, each
                // summed in draw order: the same result as one texel at a time, but the four
                // lanes vectorise).
                const LANES: usize = 4;
                let norm = MCIS_SAMPLES as f64 * std::f64::consts::PI;
                dirs.chunks(LANES)
                    .flat_map(|ns| {
                        let mut nx = [0.0; LANES];
                        let mut ny = [0.0; LANES];
                        let mut nz = [0.0; LANES];
                        for (k, n) in ns.iter().enumerate() {
                            (nx[k], ny[k], nz[k]) = (n.x, n.y, n.z);
                        }
                        let mut e = [[0.0f64; LANES]; 3];
                        for (d, v) in &draws {
                            for k in 0..LANES {
                                let c = (nx[k] * d.x + ny[k] * d.y + nz[k] * d.z).max(0.0);
                                e[0][k] += v[0] * c;
                                e[1][k] += v[1] * c;
                                e[2][k] += v[2] * c;
                            }
                        }
                        (0..ns.len()).map(move |k| [e[0][k] / norm, e[1][k] / norm, e[2][k] / norm])
                    })
                    .collect::<Vec<_>>()
            });
            let mut r = mk!(id, ctx; "none".into(), "Monte Carlo", Vec::new(), Vec::new(), None, irr, t, None);
            r.eval_from_encode = true;
            Ok(r)
        }
        _ => Err(format!("mode '{id}' is not one of this family's")),
    }
}
