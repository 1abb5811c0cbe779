//! Rotation of real SH coefficients, any order: Ivanic–Ruedenberg recurrences.
//!
//! J. Ivanic, K. Ruedenberg, "Rotation Matrices for Real Spherical Harmonics. Direct
//! Determination by Recursion", J. Phys. Chem. 100 (1996) 6342, with the corrections of
//! J. Phys. Chem. A 102 (1998) 9099. Band l's (2l+1)² matrix follows from band l − 1's and
//! band 1's (a permutation of the 3×3 rotation itself):
//!
//! M^l_mn = u·U + v·V + w·W, with, for |n| < l, D = (l + n)(l − n), else D = 2l(2l − 1),
//!
//! - u = √((l + m)(l − m)/D)
//! - v = ½·√((1 + δ_m0)(l + |m| − 1)(l + |m|)/D)·(1 − 2δ_m0)
//! - w = −½·√((l − |m| − 1)(l − |m|)/D)·(1 − δ_m0)
//!
//! and U, V, W sums of the helper P(i, a, b) = R¹_i0·M^{l−1}_ab for |b| < l, with the
//! two edge columns b = ±l mixing R¹_i,±1 and M^{l−1}_a,±(l−1) (see [`ShRotation::new`]).
//! The recurrence is stable in f64 for the orders used in lighting and beyond (each band
//! is orthogonal to ~1e-13 at l = 40; tested).
//!
//! Convention: [`ShRotation::new`]`(order, R)` maps the coefficients of f to those of the
//! rotated function g(v) = f(Rᵀ·v) — the lighting turned by R. To express a world-space
//! probe in an object frame whose axes (as world vectors) are the columns of O, rotate by
//! Oᵀ. The crate's SH convention (no Condon–Shortley phase, band 1 ∝ (y, z, x)) makes
//! band 1's matrix the rotation with rows and columns permuted to (y, z, x). The WGSL
//! twin (`sh_rotation.wgsl`, f32, orders 1, 2, 4) runs the same recurrence.

use super::sh::{sh_count, MAX_SH_ORDER};
use crate::error::{check_len, SbfError};
use glam::DMat3;

/// Largest deviation of RᵀR from the identity (max-abs entry) accepted as a rotation.
/// Loose enough for a matrix assembled in f32 (≈ 1e-7 per entry), tight enough that a
/// scale or shear of 1e-5 is refused rather than silently turned into a wrong rotation.
pub const ROTATION_TOLERANCE: f64 = 1e-5;

/// The block-diagonal SH rotation matrix for bands 0..=order.
#[derive(Debug, Clone)]
pub struct ShRotation {
    order: usize,
    /// Band l's (2l+1)×(2l+1) matrix, row-major, rows and columns m = −l..=l.
    bands: Vec<Vec<f64>>,
}

impl ShRotation {
    /// Rotation matrices for bands 0..=order of the rotation `r` (acting on column
    /// vectors). Errors if `order > MAX_SH_ORDER`, if `r` has a non-finite entry, is not
    /// orthonormal to [`ROTATION_TOLERANCE`], or is a reflection (det < 0).
    pub fn new(order: usize, r: DMat3) -> Result<Self, SbfError> {
        if order > MAX_SH_ORDER {
            return Err(SbfError::OrderTooHigh { order, max: MAX_SH_ORDER, storage: "ShRotation (f64)" });
        }
        check_rotation(r)?;
        let mut bands = vec![vec![1.0]];
        if order == 0 {
            return Ok(ShRotation { order, bands });
        }
        // Band 1: R with rows and columns in the order (y, z, x) of m = −1, 0, 1.
        const AXIS: [usize; 3] = [1, 2, 0];
        let r1: Vec<f64> = (0..9).map(|k| r.col(AXIS[k % 3])[AXIS[k / 3]]).collect();
        bands.push(r1);
        for l in 2..=order {
            let next = next_band(l, &bands[1], &bands[l - 1]);
            bands.push(next);
        }
        Ok(ShRotation { order, bands })
    }

    /// Highest band.
    pub fn order(&self) -> usize {
        self.order
    }

    /// Band l's matrix, row-major (2l+1)², rows and columns m = −l..=l. Panics if l > order.
    pub fn band(&self, l: usize) -> &[f64] {
        &self.bands[l]
    }

    /// Rotates one channel of coefficients (length (order+1)²) into `out`.
    pub fn apply_into(&self, coeffs: &[f64], out: &mut [f64]) -> Result<(), SbfError> {
        let n = sh_count(self.order);
        check_len("SH coefficients to rotate", n, coeffs.len())?;
        check_len("rotated SH coefficients", n, out.len())?;
        for (l, m) in self.bands.iter().enumerate() {
            let w = 2 * l + 1;
            let base = l * l;
            let src = &coeffs[base..base + w];
            for (row, o) in m.chunks_exact(w).zip(&mut out[base..base + w]) {
                *o = row.iter().zip(src).map(|(a, b)| a * b).sum();
            }
        }
        Ok(())
    }

    /// Rotates one channel of coefficients (length (order+1)²).
    pub fn apply(&self, coeffs: &[f64]) -> Result<Vec<f64>, SbfError> {
        let mut out = vec![0.0; coeffs.len()];
        self.apply_into(coeffs, &mut out)?;
        Ok(out)
    }
}

/// Refuses a matrix that is not a proper rotation (the check [`ShRotation::new`] makes).
pub fn check_rotation(r: DMat3) -> Result<(), SbfError> {
    if !r.is_finite() {
        return Err(SbfError::InvalidParameter { name: "rotation", value: f64::NAN, reason: "has a non-finite entry" });
    }
    let g = r.transpose() * r - DMat3::IDENTITY;
    let dev = g.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if dev > ROTATION_TOLERANCE {
        return Err(SbfError::InvalidParameter {
            name: "rotation",
            value: dev,
            reason: "is not orthonormal (value: max |RᵀR − I|; tolerance sbf::basis::sh_rotation::ROTATION_TOLERANCE)",
        });
    }
    let det = r.determinant();
    if det < 0.0 {
        return Err(SbfError::InvalidParameter {
            name: "rotation",
            value: det,
            reason: "is a reflection (value: determinant); SH rotation needs det = +1",
        });
    }
    Ok(())
}

/// Band l from band 1 (`r1`, 3×3) and band l − 1 (`prev`, (2l−1)²), Ivanic–Ruedenberg.
fn next_band(l: usize, r1: &[f64], prev: &[f64]) -> Vec<f64> {
    let li = l as i64;
    let w = 2 * l + 1;
    let wp = 2 * l - 1;
    let r1_at = |i: i64, j: i64| r1[((i + 1) * 3 + (j + 1)) as usize];
    let prev_at = |a: i64, b: i64| prev[((a + li - 1) * wp as i64 + (b + li - 1)) as usize];
    // P(i, a, b) of the paper (band l, row a of band l − 1, column b of band l).
    let p = |i: i64, a: i64, b: i64| {
        if b == li {
            r1_at(i, 1) * prev_at(a, li - 1) - r1_at(i, -1) * prev_at(a, -li + 1)
        } else if b == -li {
            r1_at(i, 1) * prev_at(a, -li + 1) + r1_at(i, -1) * prev_at(a, li - 1)
        } else {
            r1_at(i, 0) * prev_at(a, b)
        }
    };
    let mut out = vec![0.0; w * w];
    for m in -li..=li {
        for n in -li..=li {
            let d0 = (m == 0) as i64 as f64;
            let denom = if n.abs() < li { ((li + n) * (li - n)) as f64 } else { (2 * li * (2 * li - 1)) as f64 };
            let am = m.abs();
            let u = (((li + m) * (li - m)) as f64 / denom).sqrt();
            let v = 0.5 * ((1.0 + d0) * ((li + am - 1) * (li + am)) as f64 / denom).sqrt() * (1.0 - 2.0 * d0);
            let wc = -0.5 * (((li - am - 1) * (li - am)) as f64 / denom).sqrt() * (1.0 - d0);
            let mut x = 0.0;
            if u != 0.0 {
                x += u * p(0, m, n);
            }
            if v != 0.0 {
                let vv = if m == 0 {
                    p(1, 1, n) + p(-1, -1, n)
                } else if m > 0 {
                    let d1 = (m == 1) as i64 as f64;
                    p(1, m - 1, n) * (1.0 + d1).sqrt() - p(-1, -m + 1, n) * (1.0 - d1)
                } else {
                    let d1 = (m == -1) as i64 as f64;
                    p(1, m + 1, n) * (1.0 - d1) + p(-1, -m - 1, n) * (1.0 + d1).sqrt()
                };
                x += v * vv;
            }
            if wc != 0.0 {
                let ww = if m > 0 { p(1, m + 1, n) + p(-1, -m - 1, n) } else { p(1, m - 1, n) - p(-1, -m + 1, n) };
                x += wc * ww;
            }
            out[((m + li) as usize) * w + (n + li) as usize] = x;
        }
    }
    out
}
