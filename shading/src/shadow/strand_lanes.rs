//! Hair in lane layout for a shadow-map build: blocks of up to eight
//! strands of one length in the lanes of `F32Lanes`, as an interpolation pass
//! makes them (a group of hairs of one scalp triangle), so that a build can
//! take them without a frame-sized buffer of points and without moving
//! them out of their lanes (see `OpacityShadowMap::build_lanes`).

use coif_base::lanes::GROUP_LANES;
use coif_base::{Vec3Lanes, LANES};
use glam::Vec3;

/// Strands in blocks of [`LANES`] lanes, every strand with
/// [`StrandLanes::verts`] vertices: the lanes of block `b` set in its bits
/// are strands, and its row `r` holds vertex `r` of each (the other lanes
/// are not hair and are never read as such). Rows are asked for in order
/// `0, 1, ...` once per block (or per group of eight lanes) and pass, so a
/// source may compute them on the fly (an interpolation) instead of
/// storing them.
///
/// A block is [`GROUPS_PER_BLOCK`](coif_base::lanes::GROUPS_PER_BLOCK)
/// groups of eight lanes ([`GROUP_LANES`]); group `u` of the hair is group
/// `u % GROUPS_PER_BLOCK` of block `u / GROUPS_PER_BLOCK`. The builds
/// deposit group by group and split tasks at group boundaries, so the same
/// strands in the same groups give the same bytes at 8 and 16 lanes.
pub trait StrandLanes: Sync {
    /// Vertices per strand (the rows of a block).
    fn verts(&self) -> usize;

    /// Number of blocks.
    fn blocks(&self) -> usize;

    /// Number of groups of eight lanes holding hair or before one that
    /// does (at most `blocks() * GROUPS_PER_BLOCK`; the last block's empty
    /// trailing groups are not counted, so the count does not depend on
    /// the width).
    fn groups(&self) -> usize;

    /// Block `b`: which of its lanes are strands, as bits (bit `l` for lane
    /// `l`; 0 for a block that is out of range or empty), and its rows.
    fn block(&self, b: usize) -> (u32, impl Fn(usize) -> Vec3Lanes + '_);
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

    fn groups(&self) -> usize {
        self.strands
            .div_ceil(GROUP_LANES)
            .min(self.blocks() * (LANES / GROUP_LANES))
    }

    fn block(&self, b: usize) -> (u32, impl Fn(usize) -> Vec3Lanes + '_) {
        let lanes = if b < self.blocks() {
            (self.strands - b * LANES).min(LANES)
        } else {
            0
        };
        let bits = ((1u64 << lanes) - 1) as u32;
        let rows = if lanes > 0 {
            &self.rows[b * self.verts..(b + 1) * self.verts]
        } else {
            &[]
        };
        (bits, move |r: usize| {
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
