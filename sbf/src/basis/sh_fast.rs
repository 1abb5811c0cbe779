//! f32 fast paths for real SH up to band 4 (25 coefficients), on glam `Vec3`.
//!
//! Cartesian polynomials of the same convention as [`super::sh`] (no
//! Condon–Shortley phase, index l(l+1)+m). Constants are K_lm·(polynomial
//! normalisation) from the closed forms, e.g. Sloan, "Stupid Spherical Harmonics
//! Tricks" (2008), Appendix A2, with the CS sign dropped; the test suite checks
//! every value against the f64 recurrence to 1e-6.

use crate::error::SbfError;
use glam::Vec3;

/// Highest band the fast path supports.
pub const MAX_FAST_ORDER: usize = 4;

const K00: f32 = 0.282_094_79; // 1/(2√π)
const K1: f32 = 0.488_602_51; // √(3/4π)
const K2A: f32 = 1.092_548_4; // ½√(15/π)
const K20: f32 = 0.315_391_57; // ¼√(5/π)
const K22: f32 = 0.546_274_2; // ¼√(15/π)
const K33: f32 = 0.590_043_6; // ¼√(35/2π)
const K32A: f32 = 2.890_611_4; // ½√(105/π)
const K31: f32 = 0.457_045_8; // ¼√(21/2π)
const K30: f32 = 0.373_176_33; // ¼√(7/π)
const K32B: f32 = 1.445_305_7; // ¼√(105/π)
const K44: f32 = 2.503_343; // ¾√(35/π)
const K43: f32 = 1.770_130_8; // ¾√(35/2π)
const K42: f32 = 0.946_174_7; // ¾√(5/π)
const K41: f32 = 0.669_046_5; // ¾√(5/2π)
const K40: f32 = 0.105_785_55; // (3/16)√(1/π)
const K42B: f32 = 0.473_087_35; // (3/8)√(5/π)
const K44B: f32 = 0.625_835_7; // (3/16)√(35/π)

/// Evaluates SH bands 0..=order (order ≤ 4) for unit `d` into `out[..(order+1)²]`.
///
/// Errors: `OrderTooHigh` for order > 4 (use [`super::ShBasis`] in f64),
/// `LengthMismatch` if `out` is shorter than (order+1)².
pub fn eval_sh_f32(order: usize, d: Vec3, out: &mut [f32]) -> Result<(), SbfError> {
    if order > MAX_FAST_ORDER {
        return Err(SbfError::OrderTooHigh { order, max: MAX_FAST_ORDER, storage: "f32 SH fast path" });
    }
    let n = (order + 1) * (order + 1);
    if out.len() < n {
        return Err(SbfError::LengthMismatch { what: "SH f32 output", expected: n, got: out.len() });
    }
    match order {
        0 => out[0] = K00,
        1 => out[..4].copy_from_slice(&eval_sh_l1(d)),
        2 => out[..9].copy_from_slice(&eval_sh_l2(d)),
        3 => out[..16].copy_from_slice(&eval_sh_l3(d)),
        _ => out[..25].copy_from_slice(&eval_sh_l4(d)),
    }
    Ok(())
}

/// SH L1 (4 coefficients) in f32. Precondition: `d` unit length (debug-asserted).
#[inline]
pub fn eval_sh_l1(d: Vec3) -> [f32; 4] {
    debug_assert!((d.length_squared() - 1.0).abs() < 1e-4, "direction must be unit length: {d:?}");
    [K00, K1 * d.y, K1 * d.z, K1 * d.x]
}

/// SH L2 (9 coefficients) in f32. Precondition: `d` unit length.
#[inline]
pub fn eval_sh_l2(d: Vec3) -> [f32; 9] {
    let [c0, c1, c2, c3] = eval_sh_l1(d);
    let (x, y, z) = (d.x, d.y, d.z);
    [c0, c1, c2, c3, K2A * x * y, K2A * y * z, K20 * (3.0 * z * z - 1.0), K2A * x * z, K22 * (x * x - y * y)]
}

/// SH L3 (16 coefficients) in f32. Precondition: `d` unit length.
#[inline]
pub fn eval_sh_l3(d: Vec3) -> [f32; 16] {
    let mut o = [0.0; 16];
    o[..9].copy_from_slice(&eval_sh_l2(d));
    let (x, y, z) = (d.x, d.y, d.z);
    let (x2, y2, z2) = (x * x, y * y, z * z);
    o[9] = K33 * y * (3.0 * x2 - y2);
    o[10] = K32A * x * y * z;
    o[11] = K31 * y * (5.0 * z2 - 1.0);
    o[12] = K30 * z * (5.0 * z2 - 3.0);
    o[13] = K31 * x * (5.0 * z2 - 1.0);
    o[14] = K32B * z * (x2 - y2);
    o[15] = K33 * x * (x2 - 3.0 * y2);
    o
}

/// SH L4 (25 coefficients) in f32. Precondition: `d` unit length.
#[inline]
pub fn eval_sh_l4(d: Vec3) -> [f32; 25] {
    let mut o = [0.0; 25];
    o[..16].copy_from_slice(&eval_sh_l3(d));
    let (x, y, z) = (d.x, d.y, d.z);
    let (x2, y2, z2) = (x * x, y * y, z * z);
    o[16] = K44 * x * y * (x2 - y2);
    o[17] = K43 * y * z * (3.0 * x2 - y2);
    o[18] = K42 * x * y * (7.0 * z2 - 1.0);
    o[19] = K41 * y * z * (7.0 * z2 - 3.0);
    o[20] = K40 * (35.0 * z2 * z2 - 30.0 * z2 + 3.0);
    o[21] = K41 * x * z * (7.0 * z2 - 3.0);
    o[22] = K42B * (x2 - y2) * (7.0 * z2 - 1.0);
    o[23] = K43 * x * z * (x2 - 3.0 * y2);
    o[24] = K44B * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2));
    o
}
