//! The filter that joins the interleaving subregions ([TH17 §6]: "the variance is visible
//! as noise … removed using a cross bilateral filter [PSA*04, ED04]"; §7: "cross bilateral
//! filtering of kernel radius 8"). CPU twin of `slc_filter` in `filter.wgsl`.
//!
//! Both filters average the irradiance E and the GGX layer's radiance S ([`Layers`]) of a
//! pixel's neighbours on its own surface and compose them with the pixel's own albedo
//! (ρ/π·E + S): the albedo's detail is kept. Each pixel of subregion s carries I²
//! times subset s's light, so on a plane a filter that gives every subregion the same total
//! weight returns the full VPL set's light (the subsets recombine exactly), up to the
//! irradiance's change over the window.

use super::{GBuffer, Layers};
use sbf::glam::Vec3;

/// Which filter joins the I × I interleaving subregions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    /// One interleaving period (offsets −⌊I/2⌋ ..= I − 1 − ⌊I/2⌋: every subregion once),
    /// box weights, hard surface tests: normals within 25°, plane distance within the
    /// window's lateral extent at the pixel.
    Box,
    /// Tokuyoshi & Harada's cross-bilateral filter of kernel radius `radius` ([TH17 §7]: 8). The
    /// papers name the filter and its radius, not its weights; ours: per axis the trapezoid
    /// box_I ∗ box_(2R+2−I) over offsets −R..=R — a box of one interleaving period
    /// convolved with another box, so every residue mod I gets the same total weight and
    /// the subsets recombine exactly on a plane (a Gaussian would weigh some subsets more
    /// than others and leave their pattern) — times a depth weight exp(−½(d/σ_d)²) on the
    /// plane distance d = |n_p·(x_q − x_p)| with σ_d = R/2 pixel footprints at p (ED04's
    /// range weight on the guide's geometry), times the normal weight max(0, n_p·n_q)^32
    /// (0.04 at 25°); in two 1D passes, rows then columns (`bilateral_pass`).
    Bilateral {
        /// Kernel radius R in pixels, ≥ (I − 1)/2.
        radius: usize,
    },
}

/// The normal weight's exponent of [`Filter::Bilateral`].
pub const NORMAL_POWER: i32 = 32;

/// cos 25°: the largest normal difference [`Filter::Box`] averages over.
pub const FILTER_COS: f32 = 0.906_307_8;

impl Filter {
    /// Tokuyoshi & Harada's filter: cross-bilateral, kernel radius 8.
    pub const SEED: Filter = Filter::Bilateral { radius: 8 };

    /// `box` or `bilateral`.
    pub fn name(self) -> &'static str {
        match self {
            Filter::Box => "box",
            Filter::Bilateral { .. } => "bilateral",
        }
    }

    /// Checks the filter against the interleaving period I: the bilateral kernel's
    /// trapezoid needs 2R + 2 − I ≥ 1.
    pub fn check(self, interleave: usize) -> Result<(), String> {
        match self {
            Filter::Bilateral { radius } if 2 * radius + 1 < interleave => Err(format!(
                "a bilateral filter of radius {radius} cannot join {interleave}×{interleave} interleaving: the radius must be at least {} (every subregion within reach)",
                interleave / 2
            )),
            _ => Ok(()),
        }
    }

    /// The GPU's encoding (`SlcParams.filter_radius`): 0 for the box, else R.
    pub fn gpu_radius(self) -> u32 {
        match self {
            Filter::Box => 0,
            Filter::Bilateral { radius } => radius as u32,
        }
    }
}

/// Spatial weight of offset `d` along one axis of [`Filter::Bilateral`]: the number of ways
/// to write d = i + j with i in box A = [a, a + I − 1], a = −⌊I/2⌋, and j in box B =
/// [−R − a, −R − a + m − 1], m = 2R + 2 − I — the trapezoid A ∗ B, nonzero on −R..=R and
/// symmetric. Σ over d ≡ r (mod I) is m for every residue r.
pub fn spatial_weight(d: i64, interleave: i64, radius: i64) -> f32 {
    let a = -(interleave / 2);
    let a_end = a + interleave - 1;
    let b = -radius - a;
    let b_end = b + (2 * radius + 2 - interleave) - 1;
    (a_end.min(d - b) - a.max(d - b_end) + 1).max(0) as f32
}

/// The radiance after `f` joins `layers` over the interleaving period `interleave` (I = 1:
/// the layers composed unchanged — nothing to join). Each layer is filtered with the same
/// weights (the specular layer only where some receiver has a GGX layer), then composed
/// with the pixel's own albedo (ρ/π·E + S). Pixels without a G-buffer sample are 0; a pixel
/// with no neighbour that passes keeps its own layers.
pub fn filter(g: &GBuffer, layers: &Layers, interleave: usize, f: Filter) -> Vec<Vec3> {
    let il = interleave.max(1) as i64;
    if il == 1 {
        return super::compose(g, layers);
    }
    let specular = g.has_glossy();
    let one = |layer: &[Vec3]| -> Vec<Option<Vec3>> {
        match f {
            Filter::Box => box_filter(g, layer, il),
            Filter::Bilateral { radius } => {
                let e: Vec<Option<Vec3>> = g.texels.iter().zip(layer).map(|(t, x)| t.map(|_| *x)).collect();
                let rows = bilateral_pass(g, &e, il, radius as i64, (1, 0));
                bilateral_pass(g, &rows, il, radius as i64, (0, 1))
            }
        }
    };
    let e = one(&layers.irradiance);
    let s = if specular { one(&layers.specular) } else { vec![Some(Vec3::ZERO); layers.specular.len()] };
    (0..g.texels.len())
        .map(|k| match (g.texels[k], e[k], s[k]) {
            (None, ..) => Vec3::ZERO,
            (Some(t), Some(e), Some(s)) => t.radiance(e, s),
            (Some(t), ..) => t.radiance(layers.irradiance[k], layers.specular[k]),
        })
        .collect()
}

/// One 1D pass of [`Filter::Bilateral`] along `axis` ((1, 0): rows, (0, 1): columns) over
/// the layer `e` (None: no sample): each pixel p with a sample gets the weighted mean of
/// the samples at offsets −R..=R, weights trapezoid × depth × normal against p's own
/// G-buffer sample (None where none passes or p has no sample). Rows then columns: the 2D
/// trapezoid (a product) and each subregion's weight equal on a plane, at 2(2R + 1) taps
/// instead of (2R + 1)² — the separable approximation of the 2D cross-bilateral weights
/// (Pham and van Vliet 2005): a neighbour off both axes is weighed through the pixel
/// between them.
fn bilateral_pass(g: &GBuffer, e: &[Option<Vec3>], il: i64, r: i64, axis: (i64, i64)) -> Vec<Option<Vec3>> {
    let pixel = 2.0 * g.tan_xy.0 / g.width as f32;
    let weights: Vec<f32> = (-r..=r).map(|d| spatial_weight(d, il, r)).collect();
    (0..g.width * g.height)
        .map(|k| {
            let p = g.texels[k]?;
            let (px, py) = ((k % g.width) as i64, (k / g.width) as i64);
            let sd = 0.5 * r as f32 * pixel * p.position.length();
            let (mut sum, mut total) = (Vec3::ZERO, 0.0f32);
            for d in -r..=r {
                let (qx, qy) = (px + d * axis.0, py + d * axis.1);
                if qx < 0 || qy < 0 || qx >= g.width as i64 || qy >= g.height as i64 {
                    continue;
                }
                let q = (qy as usize) * g.width + qx as usize;
                let (Some(sq), Some(eq)) = (g.texels[q], e[q]) else { continue };
                let (cos, plane) = (p.normal.dot(sq.normal), p.normal.dot(sq.position - p.position).abs());
                let w = weights[(d + r) as usize] * (-0.5 * (plane / sd).powi(2)).exp() * cos.max(0.0).powi(NORMAL_POWER);
                sum += w * eq;
                total += w;
            }
            (total > 0.0).then(|| sum / total)
        })
        .collect()
}

/// [`Filter::Box`] of one layer (None: no sample, or no neighbour passed).
fn box_filter(g: &GBuffer, layer: &[Vec3], il: i64) -> Vec<Option<Vec3>> {
    let pixel = 2.0 * g.tan_xy.0 / g.width as f32;
    let (lo, hi) = (-(il / 2), il - 1 - il / 2);
    (0..g.width * g.height)
        .map(|k| {
            let p = g.texels[k]?;
            let (px, py) = ((k % g.width) as i64, (k / g.width) as i64);
            let tau = pixel * p.position.length() * il as f32;
            let (mut sum, mut count) = (Vec3::ZERO, 0u32);
            for dy in lo..=hi {
                for dx in lo..=hi {
                    let (qx, qy) = (px + dx, py + dy);
                    if qx < 0 || qy < 0 || qx >= g.width as i64 || qy >= g.height as i64 {
                        continue;
                    }
                    let q = (qy as usize) * g.width + qx as usize;
                    let Some(sq) = g.texels[q] else { continue };
                    if p.normal.dot(sq.normal) < FILTER_COS || p.normal.dot(sq.position - p.position).abs() > tau {
                        continue;
                    }
                    sum += layer[q];
                    count += 1;
                }
            }
            (count > 0).then(|| sum / count as f32)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The trapezoid's defining identities, counted independently: symmetric, nonzero on
    /// exactly −R..=R, and every residue mod I sums to m = 2R + 2 − I (so every interleaving
    /// subregion gets the same weight); too small a radius is refused.
    #[test]
    fn trapezoid_weighs_every_residue_the_same() {
        for il in 1..=16i64 {
            for r in (il - 1 + 1) / 2..=12 {
                let w = |d: i64| spatial_weight(d, il, r);
                for d in -r - 3..=r + 3 {
                    assert_eq!(w(d), w(-d), "I {il} R {r} d {d}: not symmetric");
                    assert_eq!(w(d) > 0.0, d.abs() <= r, "I {il} R {r} d {d}: support");
                }
                for res in 0..il {
                    let sum: f32 = (-r..=r).filter(|d| (d - res).rem_euclid(il) == 0).map(w).sum();
                    assert_eq!(sum, (2 * r + 2 - il) as f32, "I {il} R {r} residue {res}");
                }
            }
        }
        assert!(Filter::Bilateral { radius: 3 }.check(8).is_err());
        assert!(Filter::Bilateral { radius: 4 }.check(8).is_ok());
        assert!(Filter::Box.check(16).is_ok());
    }

    /// The bilateral weights by value, against the documented filter written out here: one
    /// row of 31 pixels on the plane z = −5 (normal +Z, albedo 0.5), irradiance zero except an
    /// impulse E₀ at pixel 15 whose normal is tilted by θ and whose position is lifted by h off
    /// the plane. At pixel p = 15 + dx (its window inside the row) the row pass gives
    ///   Ẽ = w(dx)·c·g·E₀ / (Σ_{d=−R..R} w(d) − w(dx) + w(dx)·c·g),
    /// c = cos^32 θ (normal weight), g = exp(−½(h/σ_d)²) with σ_d = R/2 pixel footprints
    /// (2·tan_x/width·|x_p|), w the trapezoid counted here by brute force (the ways to write d =
    /// i + j, i in a box of I, j in one of 2R + 2 − I, both centred as documented); the column
    /// pass of a one-row image returns it; the radiance is ρ/π·Ẽ. Tolerance: f32 sums of 17
    /// terms (1e-5 relative; a normal turned away, θ = 180°, weighs exactly 0). Mutations
    /// tried: normal power 32 → 16, σ_d = R (not R/2), the depth weight without ½, |cos| for
    /// max(cos, 0) — each fails (this pins the CPU twin by value; the GPU twin is
    /// held to it by the wavy-wall test in tests/slc.rs).
    #[test]
    fn bilateral_weights_by_value() {
        let (w, il, r) = (31usize, 4i64, 8i64);
        let tan_x = 0.4f32;
        let trapezoid = |d: i64| {
            let a = -(il / 2);
            let b = -r - a;
            let mut n = 0;
            for i in a..a + il {
                for j in b..b + 2 * r + 2 - il {
                    n += i32::from(i + j == d);
                }
            }
            n as f64
        };
        let total: f64 = (-r..=r).map(trapezoid).sum();
        for (theta, h) in [(0.0f64, 0.0f64), (20f64.to_radians(), 0.0), (0.0, 0.5), (15f64.to_radians(), 0.3), (std::f64::consts::PI, 0.0)]
        {
            let texels: Vec<Option<super::super::Surface>> = (0..w)
                .map(|k| {
                    let x = (k as f32 - 15.0) * 0.1;
                    Some(if k == 15 {
                        super::super::Surface::lambert(
                            Vec3::new(x, 0.0, -5.0 + h as f32),
                            Vec3::new(theta.sin() as f32, 0.0, theta.cos() as f32),
                            0.5,
                        )
                    } else {
                        super::super::Surface::lambert(Vec3::new(x, 0.0, -5.0), Vec3::Z, 0.5)
                    })
                })
                .collect();
            let g = GBuffer { width: w, height: 1, tan_xy: (tan_x, tan_x), texels };
            let e0 = Vec3::new(1.0, 2.0, 3.0);
            let layers =
                Layers { irradiance: (0..w).map(|k| if k == 15 { e0 } else { Vec3::ZERO }).collect(), specular: vec![Vec3::ZERO; w] };
            let out = filter(&g, &layers, il as usize, Filter::SEED);
            for dx in [-3i64, 1, 2, 5] {
                let p = (15 + dx) as usize;
                let xp = g.texels[p].unwrap().position.as_dvec3();
                let sigma = 0.5 * r as f64 * (2.0 * tan_x as f64 / w as f64) * xp.length();
                let c = theta.cos().max(0.0).powi(32);
                let gw = (-0.5 * (h / sigma).powi(2)).exp();
                let wd = trapezoid(dx);
                let e = wd * c * gw / (total - wd + wd * c * gw);
                for ch in 0..3 {
                    let want = 0.5 / std::f64::consts::PI * e * e0[ch] as f64;
                    let got = out[p][ch] as f64;
                    assert!((got - want).abs() <= 1e-5 * want.max(1e-30), "θ {theta:.3} h {h} dx {dx} channel {ch}: {got} vs {want}");
                }
            }
        }
    }
}
