//! Hair in lane layout for a shadow-map build: blocks of up to eight
//! strands of one length in the lanes of `F32Lanes`, as an interpolation pass
//! makes them (a group of hairs of one scalp triangle), so that a build can
//! take them without a frame-sized buffer of points and without moving
//! them out of their lanes (see `OpacityShadowMap::build_lanes`).

use coif_base::{Vec3Lanes, LANES};
use glam::Vec3;

/// Strands in blocks of up to [`LANES`], every strand with
/// [`StrandLanes::verts`] vertices: block `b` has `lanes` strands in its
/// first lanes, and its row `r` holds vertex `r` of each (the other lanes
/// are not hair and are never read as such). Rows are asked for in order
/// `0, 1, ...` once per block and pass, so a source may compute them on
/// the fly (an interpolation) instead of storing them.
pub trait StrandLanes: Sync {
    /// Vertices per strand (the rows of a block).
    fn verts(&self) -> usize;

    /// Number of blocks.
    fn blocks(&self) -> usize;

    /// Block `b`: how many of its lanes are strands (0 to [`LANES`]; 0 for
    /// a block that is out of range or empty), and its rows.
    fn block(&self, b: usize) -> (usize, impl Fn(usize) -> Vec3Lanes + '_);
}

/// Stored rows: `rows[b * verts + r]` is row `r` of block `b`, `strands`
/// strands in all (the last block may be partial).
#[derive(Clone, Copy, Debug)]
pub struct LaneRows<'a> {
    /// The rows, block after block.
    pub rows: &'a [Vec3Lanes],
    /// Vertices per strand.
    pub verts: usize,
    /// Strands in all (at most `LANES` per block).
    pub strands: usize,
}

impl StrandLanes for LaneRows<'_> {
    fn verts(&self) -> usize {
        self.verts
    }

    fn blocks(&self) -> usize {
        if self.verts == 0 {
            return 0;
        }
        self.strands
            .div_ceil(LANES)
            .min(self.rows.len() / self.verts)
    }

    fn block(&self, b: usize) -> (usize, impl Fn(usize) -> Vec3Lanes + '_) {
        let lanes = if b < self.blocks() {
            (self.strands - b * LANES).min(LANES)
        } else {
            0
        };
        let rows = if lanes > 0 {
            &self.rows[b * self.verts..(b + 1) * self.verts]
        } else {
            &[]
        };
        (lanes, move |r: usize| {
            rows.get(r).copied().unwrap_or(Vec3Lanes::ZERO)
        })
    }
}

/// The whole strands of `points` (`verts` each, strand after strand) in
/// lane layout for [`LaneRows`]: strand `s` in lane `s % 8` of block
/// `s / 8`, row `r` its vertex `r`; lanes past the last strand hold
/// `fill`. Replaces the contents of `rows` (allocates when it grows: for
/// tests, benchmarks and callers that convert once). Returns the number of
/// strands.
pub fn to_lane_rows(points: &[Vec3], verts: usize, fill: Vec3, rows: &mut Vec<Vec3Lanes>) -> usize {
    rows.clear();
    if verts == 0 {
        return 0;
    }
    let strands = points.len() / verts;
    rows.resize(strands.div_ceil(LANES) * verts, Vec3Lanes::splat(fill));
    for (s, strand) in points.chunks_exact(verts).enumerate() {
        for (r, p) in strand.iter().enumerate() {
            rows[(s / LANES) * verts + r].set_lane(s % LANES, *p);
        }
    }
    strands
}
