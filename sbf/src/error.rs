//! The crate's error type. Every variant names the offending value.

use std::fmt;

/// Errors returned by the public API of `sbf` on bad input.
#[derive(Debug, Clone, PartialEq)]
pub enum SbfError {
    /// A direction was zero-length, not finite, or otherwise unusable.
    InvalidDirection {
        /// Its components, as given.
        x: f64,
        /// See `x`.
        y: f64,
        /// See `x`.
        z: f64,
    },
    /// A requested SH order (or other degree) exceeds what the chosen storage supports.
    OrderTooHigh {
        /// The order asked for.
        order: usize,
        /// The largest the storage supports.
        max: usize,
        /// The storage (e.g. a fixed-size array or table).
        storage: &'static str,
    },
    /// An output or input slice has the wrong length.
    LengthMismatch {
        /// What the slice holds.
        what: &'static str,
        /// The length needed.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A scalar parameter is outside its valid range.
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The range or condition it violates.
        reason: &'static str,
    },
    /// A matrix that must be symmetric positive definite is not (numerically).
    NotPositiveDefinite {
        /// Which matrix.
        what: &'static str,
    },
    /// Coefficients that do not hold the quantity asked for (an irradiance basis asked for
    /// radiance or specular).
    NotEncoded {
        /// The basis.
        basis: &'static str,
        /// What was asked for.
        what: &'static str,
    },
}

impl fmt::Display for SbfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SbfError::InvalidDirection { x, y, z } => write!(f, "invalid direction ({x}, {y}, {z}): must be finite and of non-zero length"),
            SbfError::OrderTooHigh { order, max, storage } => {
                write!(f, "order {order} too high for {storage} (maximum {max})")
            }
            SbfError::LengthMismatch { what, expected, got } => {
                write!(f, "{what}: expected length {expected}, got {got}")
            }
            SbfError::InvalidParameter { name, value, reason } => {
                write!(f, "invalid {name} = {value}: {reason}")
            }
            SbfError::NotPositiveDefinite { what } => {
                write!(f, "{what} is not numerically positive definite")
            }
            SbfError::NotEncoded { basis, what } => {
                write!(f, "{basis} coefficients hold irradiance (E/π) only: no {what}")
            }
        }
    }
}

impl std::error::Error for SbfError {}

/// Validates and normalises a direction: finite, length > 1e-300.
///
/// This is the checked entry used by `try_*` functions; hot paths take unit
/// vectors as a documented precondition instead.
pub fn normalize_direction(d: glam::DVec3) -> Result<glam::DVec3, SbfError> {
    let len2 = d.length_squared();
    if !d.is_finite() || !len2.is_finite() || len2 <= 1e-300 {
        return Err(SbfError::InvalidDirection { x: d.x, y: d.y, z: d.z });
    }
    Ok(d / len2.sqrt())
}

/// Checks that a slice has the expected length.
pub fn check_len(what: &'static str, expected: usize, got: usize) -> Result<(), SbfError> {
    if expected != got {
        return Err(SbfError::LengthMismatch { what, expected, got });
    }
    Ok(())
}

/// Checks a strictly positive, finite parameter.
pub fn check_positive(name: &'static str, value: f64) -> Result<(), SbfError> {
    if !(value.is_finite() && value > 0.0) {
        return Err(SbfError::InvalidParameter { name, value, reason: "must be finite and > 0" });
    }
    Ok(())
}
