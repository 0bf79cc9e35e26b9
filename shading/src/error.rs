//! The error type of coif-shading's constructors.

use std::fmt;

/// Why a shading constructor or batch call refused its input.
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
    /// Arrays that must agree in length do not; nothing was written.
    CountMismatch {
        /// What was counted (e.g. `"transmittances (one per point)"`).
        what: &'static str,
        /// The length expected.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// An index past the end; nothing was changed.
    IndexOutOfRange {
        /// The index given.
        index: usize,
        /// The length it indexes into.
        len: usize,
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
                write!(
                    f,
                    "invalid table resolution {r} (below 2 or above the table's maximum)"
                )
            }
            Error::InvalidQuadratureOrder(n) => {
                write!(f, "invalid quadrature order {n} (must be 1 to 8192)")
            }
            Error::BufferTooSmall { needed, got } => {
                write!(
                    f,
                    "output buffer too small: needs {needed} entries, has {got}"
                )
            }
            Error::CountMismatch {
                what,
                expected,
                got,
            } => write!(f, "expected {expected} {what}, got {got}"),
            Error::IndexOutOfRange { index, len } => {
                write!(f, "index {index} is out of range for length {len}")
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
