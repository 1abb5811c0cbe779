//! Errors of a rendered image against the path-traced reference, over the pixels where a
//! lightmapped surface is visible: RMSE and relative RMSE (RMSE over the reference's RMS)
//! of diffuse, specular and their sum. The reference's own noise is subtracted: for an
//! image x and a reference r = y + e with independent zero-mean noise e of variance σ²
//! (known per pixel), E[(x − r)²] = (x − y)² + σ², so the squared error of the true image
//! is estimated by mean((x − r)²) − mean(σ²) (floored at 0; the noise is reported too).
//! The mean ratio Σx / Σr (channels summed) says whether an image is brighter or darker on
//! average: the reference's noise averages out of it.

use sbf::glam::DVec3;

/// One quantity's errors.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Errors {
    /// RMSE with the reference's noise subtracted (per channel averaged).
    pub rmse: f64,
    /// `rmse` over the reference's RMS.
    pub relative_rmse: f64,
    /// RMSE as measured (noise included).
    pub rmse_measured: f64,
    /// The reference's noise: √mean(σ²).
    pub reference_noise: f64,
    /// Σ image / Σ reference over the pixels and channels (1: as bright on average).
    pub mean_ratio: f64,
}

/// Errors of `image` against `reference` with per-pixel variance-of-mean `var`, over the
/// pixels where `mask` holds.
pub fn errors(image: &[DVec3], reference: &[DVec3], var: &[DVec3], mask: &[bool]) -> Errors {
    let (mut se, mut noise, mut sig, mut n) = (0.0, 0.0, 0.0, 0usize);
    let (mut sum_x, mut sum_r) = (0.0, 0.0);
    for k in 0..image.len() {
        if !mask[k] {
            continue;
        }
        let d = image[k] - reference[k];
        se += d.length_squared() / 3.0;
        noise += var[k].element_sum() / 3.0;
        sig += reference[k].length_squared() / 3.0;
        sum_x += image[k].element_sum();
        sum_r += reference[k].element_sum();
        n += 1;
    }
    if n == 0 {
        return Errors { rmse: 0.0, relative_rmse: 0.0, rmse_measured: 0.0, reference_noise: 0.0, mean_ratio: f64::NAN };
    }
    let nf = n as f64;
    let rmse = ((se - noise) / nf).max(0.0).sqrt();
    let rms = (sig / nf).sqrt();
    Errors {
        rmse,
        relative_rmse: if rms > 0.0 { rmse / rms } else { 0.0 },
        rmse_measured: (se / nf).sqrt(),
        reference_noise: (noise / nf).sqrt(),
        mean_ratio: if sum_r != 0.0 { sum_x / sum_r } else { f64::NAN },
    }
}
