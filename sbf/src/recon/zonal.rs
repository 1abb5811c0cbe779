//! Zonal (rotation-invariant) kernels shared by every basis family: the clamped-cosine
//! band factors A_l (Ramamoorthi & Hanrahan 2001) that SH irradiance, the exact SG
//! convolution and the map references all use.

use std::f64::consts::PI;

/// Clamped-cosine band factor A_l: A_0 = π, A_1 = 2π/3, odd l > 1 vanish, and for even l
/// A_l = 2π·(−1)^(l/2+1)/((l + 2)(l − 1))·(l − 1)!!/l!! (Ramamoorthi & Hanrahan 2001, eq. 8).
pub fn lambert_band_factor(l: usize) -> f64 {
    match l {
        0 => PI,
        1 => 2.0 * PI / 3.0,
        l if l % 2 == 1 => 0.0,
        l => {
            let m = l / 2;
            let binom: f64 = (1..=m).map(|k| (2 * k - 1) as f64 / (2 * k) as f64).product();
            let sign = if (m + 1) % 2 == 0 { 1.0 } else { -1.0 };
            2.0 * PI * sign / ((l + 2) as f64 * (l - 1) as f64) * binom
        }
    }
}
