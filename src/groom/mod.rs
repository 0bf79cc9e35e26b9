//! Authored grooms: strands of any vertex count, as stored in their files.
//!
//! [`tfx::parse`] reads AMD TressFX 4 `.tfx` binaries (the format of the grooms
//! in `shared/data/grooms`). Positions are kept exactly as stored (no unit
//! conversion); [`Groom::uniform_points`] scales them for the simulation.

pub mod tfx;

use glam::Vec3;
use std::fmt;

/// Why a groom could not be read.
#[derive(Clone, Debug, PartialEq)]
pub enum GroomError {
    /// The input ends before the data its header announces.
    Truncated { needed: u64, available: u64 },
    /// A header field is impossible (zero strands, a count that overflows...).
    BadHeader(&'static str),
    /// Point `index` has a non-finite coordinate.
    NonFinite { index: usize },
}

impl fmt::Display for GroomError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GroomError::Truncated { needed, available } => {
                write!(f, "groom truncated: needs {needed} bytes, has {available}")
            }
            GroomError::BadHeader(why) => write!(f, "bad groom header: {why}"),
            GroomError::NonFinite { index } => write!(f, "groom point {index} is not finite"),
        }
    }
}

impl std::error::Error for GroomError {}

/// Strands of any vertex count, root first, positions as stored in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct Groom {
    points: Vec<Vec3>,
    /// `starts[i]..starts[i + 1]` are strand i's points.
    starts: Vec<usize>,
}

impl Groom {
    /// Builds a groom from points and per-strand vertex counts.
    pub fn from_strands(points: Vec<Vec3>, counts: &[usize]) -> Result<Groom, GroomError> {
        if counts.is_empty() {
            return Err(GroomError::BadHeader("no strands"));
        }
        let mut starts = Vec::with_capacity(counts.len() + 1);
        let mut total = 0usize;
        starts.push(0);
        for &c in counts {
            if c == 0 {
                return Err(GroomError::BadHeader("a strand with no vertices"));
            }
            total = total
                .checked_add(c)
                .ok_or(GroomError::BadHeader("vertex count overflows"))?;
            starts.push(total);
        }
        if total != points.len() {
            return Err(GroomError::BadHeader(
                "vertex counts do not add up to the points",
            ));
        }
        if let Some(index) = points.iter().position(|p| !p.is_finite()) {
            return Err(GroomError::NonFinite { index });
        }
        Ok(Groom { points, starts })
    }

    pub fn strand_count(&self) -> usize {
        self.starts.len() - 1
    }

    /// Total number of vertices over all strands.
    pub fn vertex_count(&self) -> usize {
        self.points.len()
    }

    /// Points of strand `i`, root first.
    pub fn strand(&self, i: usize) -> &[Vec3] {
        &self.points[self.starts[i]..self.starts[i + 1]]
    }

    /// If every strand has the same vertex count V: all points times `scale`
    /// (e.g. 0.01 for centimetres to metres), strand after strand, and V.
    pub fn uniform_points(&self, scale: f32) -> Option<(Vec<Vec3>, usize)> {
        let v = self.strand(0).len();
        let uniform = self.starts.windows(2).all(|w| w[1] - w[0] == v);
        uniform.then(|| (self.points.iter().map(|p| *p * scale).collect(), v))
    }
}
