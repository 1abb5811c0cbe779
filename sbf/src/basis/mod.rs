//! Spherical basis functions behind one small trait, [`Basis`].
//!
//! | type | functions | domain | module |
//! |---|---|---|---|
//! | [`ShBasis`] | (L+1)² real orthonormal SH, any order (f64); f32 fast paths to L4 | sphere | [`sh`], [`sh_fast`] |
//! | [`ShRotation`] | the (L+1)² block-diagonal rotation of SH coefficients, any order (Ivanic–Ruedenberg) | — | [`sh_rotation`] |
//! | [`SgBasis`] | N spherical Gaussians, any axes/sharpness, optional constant lobe | sphere | [`sg`] |
//! | [`Asg`] | anisotropic SG (Xu et al. 2013), evaluation | sphere | [`asg`] |
//! | [`AmbientDiceSrbf`] | Ambient Dice cosine-lobe SRBF: 12 (icosahedron) or 9 ([Roughton19 §8.3.1] hemisphere set) | sphere | [`ambient_dice`] |
//! | [`AmbientDiceLinear`] | piecewise-linear (gnomonic barycentric) on the icosahedron, 12 | sphere | [`ambient_dice`] |
//! | [`AmbientDiceBezier`] | hybrid cubic Bézier, value + 2 derivatives per vertex, 36 | sphere | [`ambient_dice_bezier`] |
//! | [`AmbientDiceYCoCg`] | Y by Bézier (36) + Co, Cg linear (12 each), colour only | sphere | [`ambient_dice_bezier`] |
//! | [`HBasis`] | H-basis 4 or 6 (Habel & Wimmer 2010) | upper hemisphere | [`hbasis`] |
//! | [`AmbientCube`] | 6 clamped squared-cosine lobes along ±X, ±Y, ±Z | sphere | [`ambient_cube`] |

#[cfg(feature = "ambient-cube")]
pub mod ambient_cube;
#[cfg(feature = "ambient-dice")]
pub mod ambient_dice;
#[cfg(feature = "ambient-dice")]
pub mod ambient_dice_bezier;
#[cfg(feature = "sg")]
pub mod asg;
#[cfg(feature = "h-basis")]
pub mod hbasis;
pub mod icosahedron;
#[cfg(feature = "sg")]
pub mod sg;
#[cfg(feature = "sh")]
pub mod sh;
#[cfg(feature = "sh")]
pub mod sh_fast;
#[cfg(feature = "sh")]
pub mod sh_rotation;

#[cfg(feature = "ambient-cube")]
pub use ambient_cube::AmbientCube;
#[cfg(feature = "ambient-dice")]
pub use ambient_dice::{AmbientDiceLinear, AmbientDiceSrbf};
#[cfg(feature = "ambient-dice")]
pub use ambient_dice_bezier::{AmbientDiceBezier, AmbientDiceYCoCg};
#[cfg(feature = "sg")]
pub use asg::Asg;
#[cfg(feature = "h-basis")]
pub use hbasis::HBasis;
pub use icosahedron::Icosahedron;
#[cfg(feature = "sg")]
pub use sg::{Sg, SgBasis};
#[cfg(feature = "sh")]
pub use sh::ShBasis;
#[cfg(feature = "sh")]
pub use sh_rotation::ShRotation;

use crate::error::{check_len, normalize_direction, SbfError};
use crate::quadrature::Domain;
use glam::DVec3;

/// A fixed set of real functions B_i on the sphere (or hemisphere).
///
/// Evaluation is allocation-free: [`Basis::eval_into`] writes `len()` values.
/// Its preconditions (unit-length finite direction, `out.len() == len()`) are
/// debug-asserted; [`Basis::try_eval_into`] checks them and normalises the direction.
pub trait Basis {
    /// Human-readable name used in reports ("SH L2", "SG 12 λ=6", …).
    fn name(&self) -> String;
    /// Number of basis functions (coefficients per colour channel).
    fn len(&self) -> usize;
    /// Domain on which the basis is defined and fitted.
    fn domain(&self) -> Domain;
    /// Writes B_i(dir) for all i. `dir` must be unit length; `out.len() == len()`.
    fn eval_into(&self, dir: DVec3, out: &mut [f64]);

    /// Whether the basis has no functions (never true for the provided bases).
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Checked evaluation: normalises `dir`, errors on zero/non-finite directions
    /// and on a wrong output length.
    fn try_eval_into(&self, dir: DVec3, out: &mut [f64]) -> Result<(), SbfError> {
        let d = normalize_direction(dir)?;
        check_len("basis output", self.len(), out.len())?;
        self.eval_into(d, out);
        Ok(())
    }
    /// Allocating convenience form of [`Basis::eval_into`].
    fn eval(&self, dir: DVec3) -> Vec<f64> {
        let mut out = vec![0.0; self.len()];
        self.eval_into(dir, &mut out);
        out
    }
    /// The exact Gram matrix on `domain` when a closed form exists (SH and SG on
    /// the sphere); `None` means "use quadrature" (see [`crate::gram`]).
    fn closed_form_gram(&self, _domain: Domain) -> Option<nalgebra::DMatrix<f64>> {
        None
    }
    /// Reconstructs Σ c_i B_i(dir) for one channel of coefficients.
    fn reconstruct(&self, coeffs: &[f64], dir: DVec3, scratch: &mut [f64]) -> f64 {
        debug_assert_eq!(coeffs.len(), self.len());
        self.eval_into(dir, scratch);
        coeffs.iter().zip(scratch.iter()).map(|(c, b)| c * b).sum()
    }
}

impl<B: Basis + ?Sized> Basis for Box<B> {
    fn name(&self) -> String {
        (**self).name()
    }
    fn len(&self) -> usize {
        (**self).len()
    }
    fn domain(&self) -> Domain {
        (**self).domain()
    }
    fn eval_into(&self, dir: DVec3, out: &mut [f64]) {
        (**self).eval_into(dir, out)
    }
    fn closed_form_gram(&self, domain: Domain) -> Option<nalgebra::DMatrix<f64>> {
        (**self).closed_form_gram(domain)
    }
}

/// Unit-length check used by debug assertions (tolerance 1e-6 on |d|²).
#[cfg_attr(
    not(any(feature = "sh", feature = "sg", feature = "ambient-dice", feature = "h-basis", feature = "ambient-cube")),
    allow(dead_code)
)]
pub(crate) fn is_unit(d: DVec3) -> bool {
    d.is_finite() && (d.length_squared() - 1.0).abs() < 1e-6
}
