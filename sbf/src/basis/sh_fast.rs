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
    debug_assert!((d.length_squared() - 1.0).abs() < 1e-4, "direction must be unit length: {d:?}");
    let (x, y, z) = (d.x, d.y, d.z);
    out[0] = K00;
    if order == 0 {
        return Ok(());
    }
    out[1] = K1 * y;
    out[2] = K1 * z;
    out[3] = K1 * x;
    if order == 1 {
        return Ok(());
    }
    let (x2, y2, z2) = (x * x, y * y, z * z);
    out[4] = K2A * x * y;
    out[5] = K2A * y * z;
    out[6] = K20 * (3.0 * z2 - 1.0);
    out[7] = K2A * x * z;
    out[8] = K22 * (x2 - y2);
    if order == 2 {
        return Ok(());
    }
    out[9] = K33 * y * (3.0 * x2 - y2);
    out[10] = K32A * x * y * z;
    out[11] = K31 * y * (5.0 * z2 - 1.0);
    out[12] = K30 * z * (5.0 * z2 - 3.0);
    out[13] = K31 * x * (5.0 * z2 - 1.0);
    out[14] = K32B * z * (x2 - y2);
    out[15] = K33 * x * (x2 - 3.0 * y2);
    if order == 3 {
        return Ok(());
    }
    out[16] = K44 * x * y * (x2 - y2);
    out[17] = K43 * y * z * (3.0 * x2 - y2);
    out[18] = K42 * x * y * (7.0 * z2 - 1.0);
    out[19] = K41 * y * z * (7.0 * z2 - 3.0);
    out[20] = K40 * (35.0 * z2 * z2 - 30.0 * z2 + 3.0);
    out[21] = K41 * x * z * (7.0 * z2 - 3.0);
    out[22] = K42B * (x2 - y2) * (7.0 * z2 - 1.0);
    out[23] = K43 * x * z * (x2 - 3.0 * y2);
    out[24] = K44B * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2));
    Ok(())
}

/// SH L1 (4 coefficients) in f32.
pub fn eval_sh_l1(d: Vec3) -> [f32; 4] {
    let mut o = [0.0; 4];
    eval_sh_f32(1, d, &mut o).expect("fixed order and size");
    o
}

/// SH L2 (9 coefficients) in f32.
pub fn eval_sh_l2(d: Vec3) -> [f32; 9] {
    let mut o = [0.0; 9];
    eval_sh_f32(2, d, &mut o).expect("fixed order and size");
    o
}

/// SH L3 (16 coefficients) in f32.
pub fn eval_sh_l3(d: Vec3) -> [f32; 16] {
    let mut o = [0.0; 16];
    eval_sh_f32(3, d, &mut o).expect("fixed order and size");
    o
}

/// SH L4 (25 coefficients) in f32.
pub fn eval_sh_l4(d: Vec3) -> [f32; 25] {
    let mut o = [0.0; 25];
    eval_sh_f32(4, d, &mut o).expect("fixed order and size");
    o
}
