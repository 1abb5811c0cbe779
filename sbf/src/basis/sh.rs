//! Real, orthonormal spherical harmonics of any order.
//!
//! Convention (see the crate root): index i = l(l+1) + m, **no Condon–Shortley
//! phase**, so band 1 is (Y₁₋₁, Y₁₀, Y₁₁) = √(3/4π)·(y, z, x) with positive signs.
//!
//! Evaluation uses the fully normalised associated-Legendre recurrence
//! (e.g. Holmes & Featherstone 2002, "unnormalised" factor sinᵐθ handled by the
//! Cartesian recurrence C_m + i·S_m = (x + iy)ᵐ), which is stable in f64 for
//! orders in the hundreds:
//!
//! - P̄₀⁰ = 1/√(4π),  P̄ₘᵐ = √((2m+1)/(2m))·P̄ₘ₋₁ᵐ⁻¹,  P̄ₘ₊₁ᵐ = √(2m+3)·z·P̄ₘᵐ
//! - P̄ₗᵐ = a·(z·P̄ₗ₋₁ᵐ − b·P̄ₗ₋₂ᵐ), a = √((4l²−1)/(l²−m²)), b = √(((l−1)²−m²)/(4(l−1)²−1))
//! - Y_l0 = P̄ₗ⁰, Y_lm = √2·P̄ₗᵐ·C_m, Y_l,−m = √2·P̄ₗᵐ·S_m (m > 0).
//!
//! The f32 fast paths for l ≤ 4 live in [`super::sh_fast`] and are tested against this.

use super::Basis;
use crate::error::SbfError;
use crate::quadrature::Domain;
use glam::DVec3;
use std::f64::consts::PI;

/// Highest order accepted by [`ShBasis::new`]. (l+1)² = 66 049 coefficients: far
/// beyond any lighting use, small enough that a typo does not allocate gigabytes.
pub const MAX_SH_ORDER: usize = 256;

/// Number of coefficients of SH up to and including band `order`: (order + 1)².
pub const fn sh_count(order: usize) -> usize {
    (order + 1) * (order + 1)
}

/// Index of (l, m) in the flat coefficient array: l(l+1) + m.
pub const fn sh_index(l: usize, m: i64) -> usize {
    ((l * (l + 1)) as i64 + m) as usize
}

/// Real SH basis of bands 0..=order.
#[derive(Debug, Clone)]
pub struct ShBasis {
    order: usize,
    // Recurrence factors a_lm, b_lm, flattened per (l, m) with m ≤ l.
    a: Vec<f64>,
    b: Vec<f64>,
    // Diagonal factors √((2m+1)/(2m)).
    diag: Vec<f64>,
}

impl ShBasis {
    /// SH bands 0..=order. Errors if `order > MAX_SH_ORDER`.
    pub fn new(order: usize) -> Result<Self, SbfError> {
        if order > MAX_SH_ORDER {
            return Err(SbfError::OrderTooHigh { order, max: MAX_SH_ORDER, storage: "ShBasis (f64)" });
        }
        let n = sh_count(order);
        let mut a = vec![0.0; n];
        let mut b = vec![0.0; n];
        for l in 2..=order {
            for m in 0..l.saturating_sub(1) {
                let (lf, mf) = (l as f64, m as f64);
                let k = sh_index(l, m as i64);
                a[k] = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
                let l1 = lf - 1.0;
                b[k] = ((l1 * l1 - mf * mf) / (4.0 * l1 * l1 - 1.0)).sqrt();
            }
        }
        let diag = (0..=order).map(|m| if m == 0 { 0.0 } else { ((2 * m + 1) as f64 / (2 * m) as f64).sqrt() }).collect();
        Ok(ShBasis { order, a, b, diag })
    }

    /// Highest band.
    pub fn order(&self) -> usize {
        self.order
    }
}

impl Basis for ShBasis {
    fn name(&self) -> String {
        format!("SH L{}", self.order)
    }
    fn len(&self) -> usize {
        sh_count(self.order)
    }
    fn domain(&self) -> Domain {
        Domain::Sphere
    }
    fn closed_form_gram(&self, domain: Domain) -> Option<nalgebra::DMatrix<f64>> {
        // Orthonormal on the sphere (by construction of K_lm).
        (domain == Domain::Sphere).then(|| nalgebra::DMatrix::identity(self.len(), self.len()))
    }
    fn eval_into(&self, dir: DVec3, out: &mut [f64]) {
        debug_assert!(crate::basis::is_unit(dir), "direction must be unit length: {dir:?}");
        debug_assert_eq!(out.len(), self.len());
        let (x, y, z) = (dir.x, dir.y, dir.z);
        let order = self.order;
        // P̄ₘᵐ (without the sinᵐθ factor, carried by C_m/S_m).
        let mut pmm = 0.5 / PI.sqrt();
        // C_m + i S_m = (x + i y)^m
        let (mut cm, mut sm) = (1.0f64, 0.0f64);
        for m in 0..=order {
            if m > 0 {
                pmm *= self.diag[m];
                let c_next = x * cm - y * sm;
                sm = x * sm + y * cm;
                cm = c_next;
            }
            let (cw, sw) = if m == 0 { (1.0, 0.0) } else { (std::f64::consts::SQRT_2 * cm, std::f64::consts::SQRT_2 * sm) };
            // l = m
            let mut p_lm2 = 0.0; // P̄_{l-2}^m
            let mut p_lm1 = pmm; // P̄_{l-1}^m (starts as P̄_m^m at l = m)
            store(out, m, m, p_lm1, cw, sw);
            if m < order {
                let p = (2.0 * m as f64 + 3.0).sqrt() * z * pmm;
                p_lm2 = p_lm1;
                p_lm1 = p;
                store(out, m + 1, m, p_lm1, cw, sw);
            }
            for l in (m + 2)..=order {
                let k = sh_index(l, m as i64);
                let p = self.a[k] * (z * p_lm1 - self.b[k] * p_lm2);
                p_lm2 = p_lm1;
                p_lm1 = p;
                store(out, l, m, p, cw, sw);
            }
        }
    }
}

#[inline]
fn store(out: &mut [f64], l: usize, m: usize, p: f64, cw: f64, sw: f64) {
    if m == 0 {
        out[sh_index(l, 0)] = p;
    } else {
        out[sh_index(l, m as i64)] = p * cw;
        out[sh_index(l, -(m as i64))] = p * sw;
    }
}

/// SH projection coefficient of the constant function 1: c₀₀ = ∫Y₀₀ = 2√π.
pub const SH_CONSTANT_C00: f64 = 3.544_907_701_811_032; // 2·√π
