//! Spherical Gaussians: G(v) = μ·exp(λ(v·p − 1)) (Wang et al. 2009; [Roughton19 eq. 8.2]).
//!
//! Closed forms (see `../shared/docs/math.md`), written to stay finite for
//! λ ∈ [0, 1e4] in f32 and f64:
//! - integral over the sphere 2πμ(1 − e^(−2λ))/λ, computed with `expm1`, limit 4πμ at λ = 0;
//! - inner product 2π·μa·μb·e^(d − λa − λb)·(1 − e^(−2d))/d, d = |λa·pa + λb·pb|.
//!   The exponent d − λa − λb is evaluated without cancellation as
//!   −λa·λb·|pa − pb|² / (λa + λb + d) (from (λa+λb)² − d² = λa·λb·|pa − pb|² for unit
//!   axes). The sinh form overflows in f32 from λ ≈ 44 and is not used.
//! - product: axis (λa·pa + λb·pb)/d, sharpness d, amplitude μa·μb·e^(d − λa − λb).
//!
//! Evaluation uses v·p − 1 = −½|v − p|², exact in relative terms near the axis.

use super::Basis;
use crate::error::{check_positive, normalize_direction, SbfError};
use crate::quadrature::Domain;
use glam::{DVec3, Vec3};
use std::f64::consts::PI;

/// One spherical Gaussian lobe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sg {
    /// Unit lobe axis p.
    pub axis: DVec3,
    /// Sharpness λ ≥ 0.
    pub sharpness: f64,
    /// Amplitude μ.
    pub amplitude: f64,
}

impl Sg {
    /// Checked constructor: normalises the axis, requires λ ≥ 0 and finite μ.
    pub fn new(axis: DVec3, sharpness: f64, amplitude: f64) -> Result<Self, SbfError> {
        let axis = normalize_direction(axis)?;
        if !(sharpness.is_finite() && sharpness >= 0.0) {
            return Err(SbfError::InvalidParameter { name: "SG sharpness", value: sharpness, reason: "must be finite and >= 0" });
        }
        if !amplitude.is_finite() {
            return Err(SbfError::InvalidParameter { name: "SG amplitude", value: amplitude, reason: "must be finite" });
        }
        Ok(Sg { axis, sharpness, amplitude })
    }

    /// G(v) for a unit direction v.
    #[inline]
    pub fn eval(&self, v: DVec3) -> f64 {
        self.amplitude * (-0.5 * self.sharpness * (v - self.axis).length_squared()).exp()
    }

    /// ∫_S² G = 2πμ(1 − e^(−2λ))/λ.
    pub fn integral(&self) -> f64 {
        self.amplitude * sg_unit_integral(self.sharpness)
    }

    /// ∫_S² Ga·Gb.
    pub fn inner_product(&self, other: &Sg) -> f64 {
        self.amplitude * other.amplitude * sg_unit_inner_product(self.axis, self.sharpness, other.axis, other.sharpness)
    }

    /// Ga·Gb as a single SG (exact).
    pub fn product(&self, other: &Sg) -> Sg {
        let pm = self.sharpness * self.axis + other.sharpness * other.axis;
        let d = pm.length();
        let e = stable_exponent(self.axis, self.sharpness, other.axis, other.sharpness, d);
        let axis = if d > 0.0 { pm / d } else { self.axis };
        Sg { axis, sharpness: d, amplitude: self.amplitude * other.amplitude * e.exp() }
    }
}

/// (1 − e^(−2λ))/λ · 2π: the integral of a unit-amplitude SG; 4π at λ = 0.
pub fn sg_unit_integral(lambda: f64) -> f64 {
    2.0 * PI * one_minus_exp_m2x_over_x(lambda)
}

/// (1 − e^(−2x))/x with its limit 2 at x = 0; accurate for all x ≥ 0.
fn one_minus_exp_m2x_over_x(x: f64) -> f64 {
    if x < 1e-300 {
        2.0
    } else {
        -(-2.0 * x).exp_m1() / x
    }
}

/// d − λa − λb, computed as −λa·λb·|pa − pb|²/(λa + λb + d) (no cancellation).
fn stable_exponent(pa: DVec3, la: f64, pb: DVec3, lb: f64, d: f64) -> f64 {
    let s = la + lb + d;
    if s <= 0.0 {
        0.0
    } else {
        -la * lb * (pa - pb).length_squared() / s
    }
}

/// ∫_S² exp(λa(v·pa − 1))·exp(λb(v·pb − 1)) dv for unit axes.
pub fn sg_unit_inner_product(pa: DVec3, la: f64, pb: DVec3, lb: f64) -> f64 {
    let d = (la * pa + lb * pb).length();
    2.0 * PI * stable_exponent(pa, la, pb, lb, d).exp() * one_minus_exp_m2x_over_x(d)
}

/// f32 twin of [`sg_unit_integral`] (runtime use; finite for λ ∈ [0, 1e4] and beyond).
pub fn sg_unit_integral_f32(lambda: f32) -> f32 {
    let r = if lambda < 1e-30 { 2.0 } else { -(-2.0 * lambda).exp_m1() / lambda };
    2.0 * std::f32::consts::PI * r
}

/// f32 twin of [`sg_unit_inner_product`].
pub fn sg_unit_inner_product_f32(pa: Vec3, la: f32, pb: Vec3, lb: f32) -> f32 {
    let d = (la * pa + lb * pb).length();
    let s = la + lb + d;
    let e = if s <= 0.0 { 0.0 } else { -la * lb * (pa - pb).length_squared() / s };
    let r = if d < 1e-30 { 2.0 } else { -(-2.0 * d).exp_m1() / d };
    2.0 * std::f32::consts::PI * e.exp() * r
}

/// A fixed set of SG lobes used as a linear basis, B_i(v) = exp(λ_i(v·p_i − 1)),
/// optionally followed by a constant "ambient" function B = 1.
#[derive(Debug, Clone, PartialEq)]
pub struct SgBasis {
    axes: Vec<DVec3>,
    sharpness: Vec<f64>,
    ambient: bool,
}

impl SgBasis {
    /// All lobes share one sharpness λ > 0.
    pub fn new(axes: &[DVec3], sharpness: f64, ambient: bool) -> Result<Self, SbfError> {
        Self::with_sharpness(axes, &vec![sharpness; axes.len()], ambient)
    }

    /// Per-lobe sharpness. Axes are normalised; each λ must be finite and > 0.
    pub fn with_sharpness(axes: &[DVec3], sharpness: &[f64], ambient: bool) -> Result<Self, SbfError> {
        crate::error::check_len("SG sharpness list", axes.len(), sharpness.len())?;
        if axes.is_empty() && !ambient {
            return Err(SbfError::InvalidParameter { name: "SG lobe count", value: 0.0, reason: "need at least one lobe" });
        }
        let axes = axes.iter().map(|a| normalize_direction(*a)).collect::<Result<Vec<_>, _>>()?;
        for &l in sharpness {
            check_positive("SG sharpness", l)?;
        }
        Ok(SgBasis { axes, sharpness: sharpness.to_vec(), ambient })
    }

    /// Lobe axes.
    pub fn axes(&self) -> &[DVec3] {
        &self.axes
    }
    /// Lobe sharpness values.
    pub fn sharpness(&self) -> &[f64] {
        &self.sharpness
    }
    /// Whether a constant function is appended after the lobes.
    pub fn has_ambient(&self) -> bool {
        self.ambient
    }
    /// Number of SG lobes (excluding the ambient function).
    pub fn lobe_count(&self) -> usize {
        self.axes.len()
    }
    /// Lobe i as an [`Sg`] of amplitude 1.
    pub fn lobe(&self, i: usize) -> Sg {
        Sg { axis: self.axes[i], sharpness: self.sharpness[i], amplitude: 1.0 }
    }
}

impl Basis for SgBasis {
    fn name(&self) -> String {
        let l0 = self.sharpness.first().copied().unwrap_or(0.0);
        let same = self.sharpness.iter().all(|&l| l == l0);
        let lam = if same { format!("λ={l0}") } else { "λ varies".to_string() };
        let amb = if self.ambient { " + ambient" } else { "" };
        format!("SG {} {lam}{amb}", self.axes.len())
    }
    fn len(&self) -> usize {
        self.axes.len() + usize::from(self.ambient)
    }
    fn domain(&self) -> Domain {
        Domain::Sphere
    }
    /// Sphere only: lobe pairs by the SG inner product, lobe × ambient by the SG
    /// integral, ambient × ambient = 4π.
    fn closed_form_gram(&self, domain: Domain) -> Option<nalgebra::DMatrix<f64>> {
        if domain != Domain::Sphere {
            return None;
        }
        let n = self.len();
        let k = self.lobe_count();
        Some(nalgebra::DMatrix::from_fn(n, n, |i, j| match (i < k, j < k) {
            (true, true) => self.lobe(i).inner_product(&self.lobe(j)),
            (true, false) => self.lobe(i).integral(),
            (false, true) => self.lobe(j).integral(),
            (false, false) => domain.solid_angle(),
        }))
    }
    fn eval_into(&self, dir: DVec3, out: &mut [f64]) {
        debug_assert!(super::is_unit(dir), "direction must be unit length: {dir:?}");
        debug_assert_eq!(out.len(), self.len());
        for (i, (p, l)) in self.axes.iter().zip(&self.sharpness).enumerate() {
            out[i] = (-0.5 * l * (dir - *p).length_squared()).exp();
        }
        if self.ambient {
            out[self.axes.len()] = 1.0;
        }
    }
}
