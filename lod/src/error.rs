//! The error type of coif-lod's public constructors and fits.

use std::fmt;

/// Why a fit, a constructor, a parameter check or a batch pass refused its
/// input.
///
/// Per-frame batch paths ([`crate::refine_strands`], [`crate::interpolate`],
/// [`crate::cull`], [`crate::write_render_vertices`]) return
/// [`Error::CountMismatch`] when their containers were made for another set
/// and [`Error::BufferTooSmall`] when a caller's buffer cannot take the
/// whole result; they then write nothing. Bad numbers (NaN, infinities) in
/// otherwise consistent data are not errors there: they degrade gracefully.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// A fit needs at least two control points.
    TooFewControlPoints {
        /// The control points asked for.
        n_control: usize,
    },
    /// A fit cannot have more control points than samples.
    MoreControlsThanPoints {
        /// The control points asked for.
        n_control: usize,
        /// The samples given.
        points: usize,
    },
    /// A coordinate is NaN or infinite; `index` is the offending point.
    NonFinite {
        /// Index of the first non-finite point.
        index: usize,
    },
    /// A parameter is out of its documented range.
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The documented range.
        expected: &'static str,
    },
    /// A slice or container has the wrong length or shape.
    CountMismatch {
        /// What was counted (e.g. `"guide strands"`).
        what: &'static str,
        /// The length expected.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A caller's output buffer is shorter than the result; nothing was written.
    BufferTooSmall {
        /// The length needed.
        needed: usize,
        /// The length given.
        got: usize,
    },
    /// A scalp triangle names a guide strand that does not exist.
    GuideOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The guide it names.
        guide: u32,
    },
    /// The fit's normal matrix `B^T B + lambda D2^T D2` is not positive
    /// definite (faer's Cholesky met a non-positive pivot).
    SingularFit {
        /// The pivot where the factorisation failed.
        pivot: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::TooFewControlPoints { n_control } => {
                write!(f, "a fit needs at least 2 control points, got {n_control}")
            }
            Error::MoreControlsThanPoints { n_control, points } => write!(
                f,
                "cannot fit {n_control} control points to only {points} points"
            ),
            Error::NonFinite { index } => write!(f, "point {index} has a non-finite coordinate"),
            Error::InvalidParameter {
                name,
                value,
                expected,
            } => write!(
                f,
                "parameter {name} = {value} is invalid: expected {expected}"
            ),
            Error::CountMismatch {
                what,
                expected,
                got,
            } => write!(f, "expected {expected} {what}, got {got}"),
            Error::BufferTooSmall { needed, got } => write!(
                f,
                "the output buffer holds {got} values but {needed} are needed (nothing written)"
            ),
            Error::GuideOutOfRange { triangle, guide } => write!(
                f,
                "scalp triangle {triangle} names guide {guide}, which does not exist"
            ),
            Error::SingularFit { pivot } => write!(
                f,
                "the fit's normal matrix is not positive definite (pivot {pivot})"
            ),
        }
    }
}

impl std::error::Error for Error {}
