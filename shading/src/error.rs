//! The error type of coif-shading's constructors.

use std::fmt;

/// Why a shading constructor refused its input.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// A material parameter is outside its valid range (name and value).
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f32,
    },
    /// A lookup-table resolution below the minimum (2).
    InvalidResolution(usize),
    /// A quadrature order of zero.
    InvalidQuadratureOrder(usize),
    /// A caller's output buffer is shorter than the input it is for.
    BufferTooSmall {
        /// Entries needed.
        needed: usize,
        /// Entries the buffer has.
        got: usize,
    },
    /// A shadow-map setting outside its range (name, value, what is expected).
    InvalidShadowSetting {
        /// The setting's name.
        name: &'static str,
        /// The value given.
        value: f32,
        /// The accepted range.
        expected: &'static str,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidParameter { name, value } => {
                write!(f, "invalid shading parameter {name} = {value}")
            }
            Error::InvalidResolution(r) => {
                write!(f, "invalid table resolution {r} (must be at least 2)")
            }
            Error::InvalidQuadratureOrder(n) => {
                write!(f, "invalid quadrature order {n} (must be at least 1)")
            }
            Error::BufferTooSmall { needed, got } => {
                write!(
                    f,
                    "output buffer too small: needs {needed} entries, has {got}"
                )
            }
            Error::InvalidShadowSetting {
                name,
                value,
                expected,
            } => write!(
                f,
                "invalid shadow setting {name} = {value} (expected {expected})"
            ),
        }
    }
}

impl std::error::Error for Error {}
