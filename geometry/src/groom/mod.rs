//! Authored grooms: strands of any vertex count, as stored in their files.
//!
//! [`load`] reads AMD TressFX 4 `.tfx` binaries (the format of the grooms in
//! `shared/data/grooms`) and Cem Yuksel's cyHair `.hair` files, told apart by
//! content; [`cyhair::write`] exports a groom (a simulated one, say) to
//! `.hair`. Positions are kept exactly as stored (no unit conversion);
//! [`Groom::uniform_points`] scales them for the simulation. Hostile input
//! gets an [`Error`], never a panic, and nothing is allocated from a
//! header's word before the input is known to hold that much data.

pub mod cyhair;
pub mod tfx;

use glam::Vec3;
use std::fmt;

/// Why a groom could not be read.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// The input ends before the data its header announces.
    Truncated {
        /// Bytes the header announces.
        needed: u64,
        /// Bytes the input has.
        available: u64,
    },
    /// A header field is impossible (zero strands, a count that overflows...).
    BadHeader(&'static str),
    /// Neither a TressFX 4 nor a cyHair file.
    UnknownFormat,
    /// The groom cannot be written in the format (e.g. a strand too long
    /// for cyHair's 16-bit segment counts).
    Unwritable(&'static str),
    /// Point `index` has a non-finite coordinate.
    NonFinite {
        /// Index of the point.
        index: usize,
    },
    /// A resampling request that cannot be met (fewer than two points per
    /// strand, a scale that is not finite and positive, a result too large).
    BadResample(&'static str),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Truncated { needed, available } => {
                write!(f, "groom truncated: needs {needed} bytes, has {available}")
            }
            Error::BadHeader(why) => write!(f, "bad groom header: {why}"),
            Error::UnknownFormat => write!(f, "not a TressFX 4 (.tfx) or cyHair (.hair) groom"),
            Error::Unwritable(why) => write!(f, "cannot write the groom: {why}"),
            Error::NonFinite { index } => write!(f, "groom point {index} is not finite"),
            Error::BadResample(why) => write!(f, "cannot resample the groom: {why}"),
        }
    }
}

impl std::error::Error for Error {}

/// Reads a TressFX 4 `.tfx` or cyHair `.hair` groom, told apart by content
/// (cyHair starts with the bytes `HAIR`; TressFX with the f32 version 4.x).
///
/// # Errors
///
/// [`Error`] on any bad input: an unknown format, truncation, lying counts
/// or offsets, non-finite coordinates.
///
/// ```
/// use coif_geometry::groom::{self, cyhair, Groom};
/// use glam::Vec3;
/// // Two strands of different counts, written as a cyHair file and read back.
/// let points = vec![Vec3::ZERO, Vec3::Y, Vec3::X, Vec3::X + Vec3::Y, Vec3::X * 2.0];
/// let bytes = cyhair::write(&Groom::from_strands(points, &[2, 3]).unwrap(), "doc").unwrap();
/// let g = groom::load(&bytes).unwrap();
/// assert_eq!((g.strand_count(), g.vertex_count()), (2, 5));
/// assert_eq!(g.strand(1).len(), 3);
/// assert!(groom::load(b"not a groom").is_err());
/// ```
pub fn load(bytes: &[u8]) -> Result<Groom, Error> {
    if cyhair::sniff(bytes) {
        cyhair::parse(bytes)
    } else if tfx::sniff(bytes) {
        tfx::parse(bytes)
    } else {
        Err(Error::UnknownFormat)
    }
}

/// Strands of any vertex count, root first, positions as stored in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct Groom {
    points: Vec<Vec3>,
    /// `starts[i]..starts[i + 1]` are strand i's points.
    starts: Vec<usize>,
}

impl Groom {
    /// Builds a groom from points and per-strand vertex counts.
    ///
    /// # Errors
    ///
    /// [`Error`] on no strands, a strand with no points, counts that do not
    /// add up to `points.len()`, or a non-finite point.
    pub fn from_strands(points: Vec<Vec3>, counts: &[usize]) -> Result<Groom, Error> {
        if counts.is_empty() {
            return Err(Error::BadHeader("no strands"));
        }
        let mut starts = Vec::with_capacity(counts.len() + 1);
        let mut total = 0usize;
        starts.push(0);
        for &c in counts {
            if c == 0 {
                return Err(Error::BadHeader("a strand with no vertices"));
            }
            total = total
                .checked_add(c)
                .ok_or(Error::BadHeader("vertex count overflows"))?;
            starts.push(total);
        }
        if total != points.len() {
            return Err(Error::BadHeader(
                "vertex counts do not add up to the points",
            ));
        }
        if let Some(index) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFinite { index });
        }
        Ok(Groom { points, starts })
    }

    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.starts.len() - 1
    }

    /// Total number of vertices over all strands.
    pub fn vertex_count(&self) -> usize {
        self.points.len()
    }

    /// Points of strand `i`, root first.
    ///
    /// # Panics
    ///
    /// If `i >= strand_count()`; [`Groom::get_strand`] returns `None`
    /// instead.
    pub fn strand(&self, i: usize) -> &[Vec3] {
        &self.points[self.starts[i]..self.starts[i + 1]]
    }

    /// Points of strand `i`, root first, or `None` if there is no strand
    /// `i` (never panics).
    ///
    /// ```
    /// use coif_geometry::groom::Groom;
    /// let groom = Groom::from_strands(vec![glam::Vec3::ZERO, glam::Vec3::Y], &[2]).unwrap();
    /// assert_eq!(groom.get_strand(0).map(|s| s.len()), Some(2));
    /// assert!(groom.get_strand(5).is_none());
    /// ```
    pub fn get_strand(&self, i: usize) -> Option<&[Vec3]> {
        let (a, b) = (*self.starts.get(i)?, *self.starts.get(i + 1)?);
        self.points.get(a..b)
    }

    /// Every point, strand after strand.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// Every strand resampled to `verts_per_strand` points evenly spaced in
    /// arc length from its root to its tip (both kept exactly), times
    /// `scale` (0.01 takes TressFX's and cyHair's centimetres to metres),
    /// strand after strand: what `coif_kernels::Strands::from_polylines`
    /// takes, whatever vertex counts the file had. A one-point strand
    /// becomes `verts_per_strand` copies of its point. Strands of the same
    /// count and evenly spaced already come back as they are (times
    /// `scale`).
    ///
    /// # Errors
    /// [`Error::BadResample`] for `verts_per_strand < 2`, a scale that is
    /// not finite and positive, more than 2^16 points per strand or more
    /// than 2^24 points in all;
    /// [`Error::NonFinite`] if scaling overflows a point.
    ///
    /// ```
    /// use coif_geometry::groom::Groom;
    /// use glam::Vec3;
    /// // A 3-point strand and a 2-point one, in centimetres.
    /// let points = vec![Vec3::ZERO, Vec3::X * 10.0, Vec3::X * 20.0, Vec3::Y, Vec3::Y * 5.0];
    /// let groom = Groom::from_strands(points, &[3, 2]).unwrap();
    /// let guides = groom.resampled(5, 0.01).unwrap();
    /// assert_eq!(guides.len(), 10);
    /// assert!((guides[1] - Vec3::X * 0.05).length() < 1e-6);
    /// ```
    pub fn resampled(&self, verts_per_strand: usize, scale: f32) -> Result<Vec<Vec3>, Error> {
        self.resample(
            (0..self.strand_count()).map(|i| self.strand(i)),
            verts_per_strand,
            scale,
        )
    }

    /// The guides an engine keeps of a dense groom: the strands `0, stride,
    /// 2 stride, ...` (every strand for `stride` 1) with two or more points,
    /// resampled as [`Groom::resampled`] does. `stride` 0 is taken as 1.
    ///
    /// # Errors
    /// As [`Groom::resampled`]; [`Error::BadResample`] too when no kept
    /// strand has two points.
    ///
    /// ```
    /// use coif_geometry::groom::Groom;
    /// use glam::Vec3;
    /// let points = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::Z * 2.0];
    /// let groom = Groom::from_strands(points, &[2, 1, 2]).unwrap();
    /// // Every strand kept but the one-point one; every other: strands 0 and 2.
    /// assert_eq!(groom.guides(1, 3, 1.0).unwrap().len(), 6);
    /// assert_eq!(groom.guides(2, 3, 1.0).unwrap()[3], Vec3::Z);
    /// ```
    pub fn guides(
        &self,
        stride: usize,
        verts_per_strand: usize,
        scale: f32,
    ) -> Result<Vec<Vec3>, Error> {
        let kept = self.guide_strands(stride);
        let guides = self.resample(kept, verts_per_strand, scale)?;
        if guides.is_empty() {
            return Err(Error::BadResample("no kept strand has two or more points"));
        }
        Ok(guides)
    }

    /// The strands [`Groom::guides`] keeps.
    pub fn guide_strands(&self, stride: usize) -> impl Iterator<Item = &[Vec3]> + Clone + '_ {
        (0..self.strand_count())
            .step_by(stride.max(1))
            .map(|s| self.strand(s))
            .filter(|s| s.len() >= 2)
    }

    /// `strands` scaled and resampled to `verts` points each, strand after
    /// strand (the body of [`Groom::resampled`] and [`Groom::guides`]).
    fn resample<'a>(
        &self,
        strands: impl Iterator<Item = &'a [Vec3]> + Clone,
        verts: usize,
        scale: f32,
    ) -> Result<Vec<Vec3>, Error> {
        if verts < 2 {
            return Err(Error::BadResample("fewer than two points per strand"));
        }
        if verts > 1 << 16 {
            return Err(Error::BadResample("more than 2^16 points per strand"));
        }
        if !(scale.is_finite() && scale > 0.0) {
            return Err(Error::BadResample("the scale must be finite and positive"));
        }
        let total = strands.clone().count().checked_mul(verts);
        let total = total
            .filter(|&n| n <= 1 << 24)
            .ok_or(Error::BadResample("more than 2^24 points (200 MB)"))?;
        let mut out = vec![Vec3::ZERO; total];
        let mut scaled = Vec::new();
        for (strand, dst) in strands.zip(out.chunks_exact_mut(verts)) {
            scaled.clear();
            scaled.extend(strand.iter().map(|p| *p * scale));
            coif_base::polyline::arc_length_samples(&scaled, dst);
        }
        if let Some(index) = out.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFinite { index });
        }
        Ok(out)
    }

    /// If every strand has the same vertex count V: all points times `scale`
    /// (e.g. 0.01 for centimetres to metres), strand after strand, and V.
    pub fn uniform_points(&self, scale: f32) -> Option<(Vec<Vec3>, usize)> {
        let v = self.strand(0).len();
        let uniform = self.starts.windows(2).all(|w| w[1] - w[0] == v);
        uniform.then(|| (self.points.iter().map(|p| *p * scale).collect(), v))
    }
}
