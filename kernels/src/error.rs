//! The error type of coif-kernels' public constructors and setters.

use std::fmt;

/// Why a constructor, setter or parameter check refused its input.
///
/// Hot per-frame paths never return this: they take validated containers and
/// degrade gracefully (a strand that goes non-finite is restored, see
/// [`crate::Strands::restored_strands`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// A strand needs at least two vertices (one segment).
    TooFewVertices {
        /// The vertex count given (for a patch: the smaller of rows and columns).
        verts_per_strand: usize,
    },
    /// The point count is not a whole number of strands.
    NotWholeStrands {
        /// Points given.
        points: usize,
        /// Vertices per strand given.
        verts_per_strand: usize,
    },
    /// There are no strands at all.
    NoStrands,
    /// A coordinate is NaN or infinite; `index` is the offending point.
    NonFinite {
        /// Index of the first offending point (or value).
        index: usize,
    },
    /// A slice has the wrong length.
    CountMismatch {
        /// What was counted (e.g. `"roots (one per strand)"`).
        what: &'static str,
        /// The length needed.
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
    /// A simulation parameter is out of its documented range.
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f32,
        /// The accepted range, in words.
        expected: &'static str,
    },
    /// A mesh has no triangles.
    NoTriangles,
    /// A triangle indexes a vertex that does not exist.
    IndexOutOfRange {
        /// The offending triangle.
        triangle: usize,
        /// The index it holds.
        index: u32,
        /// The vertex count.
        vertices: usize,
    },
    /// A grid would exceed its documented node cap.
    GridTooLarge {
        /// Nodes the grid would need (saturated at `u64::MAX`).
        cells: u64,
        /// The cap.
        max: u64,
    },
    /// A transform is not finite or not rigid (rotation and translation).
    InvalidTransform {
        /// What is wrong, in words.
        reason: &'static str,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::TooFewVertices { verts_per_strand } => write!(
                f,
                "a strand needs at least 2 vertices, got verts_per_strand = {verts_per_strand}"
            ),
            Error::NotWholeStrands {
                points,
                verts_per_strand,
            } => write!(
                f,
                "{points} points are not a whole number of strands of {verts_per_strand} vertices"
            ),
            Error::NoStrands => write!(f, "no strands"),
            Error::NonFinite { index } => write!(f, "point {index} has a non-finite coordinate"),
            Error::CountMismatch {
                what,
                expected,
                got,
            } => write!(f, "expected {expected} {what}, got {got}"),
            Error::BufferTooSmall { needed, got } => write!(
                f,
                "the output buffer holds {got} values but {needed} are needed (nothing written)"
            ),
            Error::InvalidParameter {
                name,
                value,
                expected,
            } => {
                write!(
                    f,
                    "parameter {name} = {value} is invalid: expected {expected}"
                )
            }
            Error::NoTriangles => write!(f, "the mesh has no triangles"),
            Error::IndexOutOfRange {
                triangle,
                index,
                vertices,
            } => write!(
                f,
                "triangle {triangle} indexes vertex {index}, but there are {vertices} vertices"
            ),
            Error::GridTooLarge { cells, max } => write!(
                f,
                "the grid would need {cells} nodes, more than the cap of {max} (cell too small for the mesh)"
            ),
            Error::InvalidTransform { reason } => write!(f, "invalid transform: {reason}"),
        }
    }
}

impl std::error::Error for Error {}
