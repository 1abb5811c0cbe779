//! Error metrics between an approximation and a reference image on a lat-long grid.

use sbf::envmap::LatLong;

/// All metrics of one signal (averaged over RGB).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Metrics {
    /// RMS over texels, unweighted (comparable with Probulator).
    pub rms: f64,
    /// RMS weighted by texel solid angle (the integral norm).
    pub rms_weighted: f64,
    /// rms / RMS of the reference.
    pub rel_rms: f64,
    /// Largest absolute channel error.
    pub max_abs: f64,
    /// Symmetric mean absolute percentage error: mean of 2|a − r|/(|a| + |r|) (0 where both are 0).
    pub smape: f64,
    /// Fraction of texels with any negative channel in the approximation.
    pub negative_fraction: f64,
    /// The approximation's mean over the reference's (solid-angle weighted, RGB summed): its
    /// bias — a non-negative fit of a small source keeps more than its light (> 1). NaN
    /// where the reference is zero.
    pub mean_ratio: f64,
}

/// Metrics of `approx` against `reference`, both row-major on `grid`.
pub fn compute(grid: LatLong, approx: &[[f64; 3]], reference: &[[f64; 3]]) -> Metrics {
    compute_rows(grid, approx, reference, 0..grid.height)
}

/// Unweighted RMS error over the texel rows `rows` (the `rms` of [`compute_rows`], same
/// sum in the same order, without the other statistics; for convergence curves).
pub fn rms_rows(grid: LatLong, approx: &[[f64; 3]], reference: &[[f64; 3]], rows: std::ops::Range<usize>) -> f64 {
    assert_eq!(approx.len(), grid.texel_count());
    assert_eq!(reference.len(), grid.texel_count());
    assert!(rows.end <= grid.height && !rows.is_empty());
    let n = (3 * rows.len() * grid.width) as f64;
    let (a, r) = (&approx[rows.start * grid.width..rows.end * grid.width], &reference[rows.start * grid.width..rows.end * grid.width]);
    let mut se = 0.0;
    for (x, y) in a.iter().zip(r) {
        for c in 0..3 {
            let e = x[c] - y[c];
            se += e * e;
        }
    }
    (se / n).sqrt()
}

/// Metrics over the texel rows `rows` only (the upper hemisphere is rows
/// 0..height/2 of a lat-long grid with +Y up).
pub fn compute_rows(grid: LatLong, approx: &[[f64; 3]], reference: &[[f64; 3]], rows: std::ops::Range<usize>) -> Metrics {
    assert_eq!(approx.len(), grid.texel_count());
    assert_eq!(reference.len(), grid.texel_count());
    assert!(rows.end <= grid.height && !rows.is_empty());
    let (mut se, mut swe, mut sw, mut sref, mut max_abs, mut smape, mut neg) = (0.0, 0.0, 0.0, 0.0, 0.0f64, 0.0, 0usize);
    let (mut sum_a, mut sum_r) = (0.0f64, 0.0f64);
    let counted = rows.len() * grid.width;
    for j in rows {
        let w = grid.texel_solid_angle(j);
        for i in 0..grid.width {
            let k = j * grid.width + i;
            let (a, r) = (approx[k], reference[k]);
            if a.iter().any(|v| *v < 0.0) {
                neg += 1;
            }
            for c in 0..3 {
                let e = a[c] - r[c];
                se += e * e;
                swe += w * e * e;
                sref += r[c] * r[c];
                sum_a += w * a[c];
                sum_r += w * r[c];
                max_abs = max_abs.max(e.abs());
                let den = a[c].abs() + r[c].abs();
                if den > 0.0 {
                    smape += 2.0 * e.abs() / den;
                }
            }
            sw += 3.0 * w;
        }
    }
    let n = (3 * counted) as f64;
    let rms = (se / n).sqrt();
    let ref_rms = (sref / n).sqrt();
    Metrics {
        rms,
        rms_weighted: (swe / sw).sqrt(),
        rel_rms: if ref_rms > 0.0 { rms / ref_rms } else { 0.0 },
        max_abs,
        smape: smape / n,
        negative_fraction: neg as f64 / grid.texel_count() as f64,
        mean_ratio: if sum_r > 0.0 { sum_a / sum_r } else { f64::NAN },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mean ratio is the approximation's light over the reference's: a uniform scale k
    /// gives k exactly (identity), a zero reference NaN, and one extra unit of radiance counts
    /// by its texel's solid angle — (2π/W)(cos θ₀ − cos θ₁) in closed form — so at the pole
    /// it weighs less than at the equator by the ratio of the bands' solid angles.
    #[test]
    fn mean_ratio_is_the_solid_angle_weighted_light_ratio() {
        let grid = LatLong { width: 8, height: 6 };
        let reference: Vec<[f64; 3]> = (0..48).map(|k| [1.0 + k as f64 * 0.1, 2.0, 0.5 + (k % 5) as f64]).collect();
        let scaled: Vec<[f64; 3]> = reference.iter().map(|r| r.map(|v| 1.25 * v)).collect();
        assert!((compute(grid, &scaled, &reference).mean_ratio - 1.25).abs() < 1e-14);
        assert!(compute(grid, &scaled, &vec![[0.0; 3]; 48]).mean_ratio.is_nan());
        let band = |j: usize| {
            let dt = std::f64::consts::PI / 6.0;
            (2.0 * std::f64::consts::PI / 8.0) * ((j as f64 * dt).cos() - ((j + 1) as f64 * dt).cos())
        };
        let bump = |k: usize| {
            let mut a = reference.clone();
            a[k][1] += 1.0;
            compute(grid, &a, &reference).mean_ratio - 1.0
        };
        let (pole, equator) = (bump(3), bump(2 * 8 + 3));
        assert!(pole > 0.0 && equator > pole);
        assert!((equator / pole - band(2) / band(0)).abs() < 1e-12, "{} vs {}", equator / pole, band(2) / band(0));
    }
}
