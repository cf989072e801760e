//! Errors for parameters outside the physics' domain of validity.

use thiserror::Error;

/// A model input outside the range where the equations hold.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// A scalar parameter is outside its allowed range.
    #[error("{name} = {value} is outside the allowed range: {range}")]
    OutOfRange {
        /// Parameter name as the model knows it (SI).
        name: &'static str,
        /// The offending value.
        value: f64,
        /// Human-readable allowed range.
        range: &'static str,
    },
    /// A laminate that cannot be solved (singular stiffness, no piezo layers, …).
    #[error("laminate: {0}")]
    Laminate(String),
    /// Not enough or degenerate data for a statistical fit.
    #[error("fit: {0}")]
    Fit(String),
    /// A choice (a drive mode, a shape) outside what a model covers.
    #[error("{name} = {value}: {allowed}")]
    NotCovered {
        /// The choice as the model knows it.
        name: &'static str,
        /// Its value, as written.
        value: &'static str,
        /// What the model covers.
        allowed: &'static str,
    },
}

/// Check `lo < value < hi` (open interval) and finiteness.
pub(crate) fn check_open(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    range: &'static str,
) -> Result<f64, ModelError> {
    if value.is_finite() && value > lo && value < hi {
        Ok(value)
    } else {
        Err(ModelError::OutOfRange { name, value, range })
    }
}

/// Check `lo <= value < hi` and finiteness.
pub(crate) fn check_half_open(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    range: &'static str,
) -> Result<f64, ModelError> {
    if value.is_finite() && value >= lo && value < hi {
        Ok(value)
    } else {
        Err(ModelError::OutOfRange { name, value, range })
    }
}
