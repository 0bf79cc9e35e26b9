//! A read-only view of strands stored in SIMD lanes, the layout every coif
//! crate shares.
//!
//! Strands are grouped in blocks of [`LANES`]; vertex `v` of block `b` is
//! element `b * V + v` of the position slice, and its lane `l` is strand
//! `b * LANES + l`. The simulation owns such a set (`coif_kernels::Strands`
//! hands out this view); LOD reads it without knowing how it was simulated.

use crate::lanes::{Vec3Lanes, LANES};
use glam::DVec3;

/// Borrowed positions of a set of equal-length strands in lane layout,
/// relative to a local origin.
#[derive(Clone, Copy, Debug)]
pub struct StrandBlocks<'a> {
    positions: &'a [Vec3Lanes],
    strand_count: usize,
    verts_per_strand: usize,
    origin: DVec3,
}

impl<'a> StrandBlocks<'a> {
    /// A view of `strand_count` strands of `verts_per_strand` vertices whose
    /// block-major positions are `positions` (relative to `origin`). Returns
    /// `None` unless `positions.len()` is `ceil(strand_count / LANES) *
    /// verts_per_strand`.
    pub fn new(
        positions: &'a [Vec3Lanes],
        strand_count: usize,
        verts_per_strand: usize,
        origin: DVec3,
    ) -> Option<StrandBlocks<'a>> {
        let blocks = strand_count.div_ceil(LANES);
        (blocks.checked_mul(verts_per_strand) == Some(positions.len())).then_some(StrandBlocks {
            positions,
            strand_count,
            verts_per_strand,
            origin,
        })
    }

    /// Number of strands (real lanes).
    pub fn strand_count(&self) -> usize {
        self.strand_count
    }

    /// Vertices per strand, `V`.
    pub fn verts_per_strand(&self) -> usize {
        self.verts_per_strand
    }

    /// Number of SIMD blocks, `ceil(strand_count / LANES)`.
    pub fn block_count(&self) -> usize {
        self.strand_count.div_ceil(LANES)
    }

    /// Real strands in block `b` (the rest of its lanes are inert padding).
    pub fn lanes_in_block(&self, b: usize) -> usize {
        self.strand_count.saturating_sub(b * LANES).min(LANES)
    }

    /// World position of the local origin the positions are relative to.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Block `b`'s positions relative to [`StrandBlocks::origin`]: `V`
    /// entries, root first. Panics if `b >= block_count()`.
    pub fn block_positions_local(&self, b: usize) -> &'a [Vec3Lanes] {
        let v = self.verts_per_strand;
        &self.positions[b * v..(b + 1) * v]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_checks_its_length_and_counts_padding_lanes() {
        let pos = vec![Vec3Lanes::ZERO; 2 * 4];
        assert!(StrandBlocks::new(&pos, 9, 4, DVec3::ZERO).is_some());
        assert!(StrandBlocks::new(&pos, 17, 4, DVec3::ZERO).is_none());
        assert!(StrandBlocks::new(&pos, 9, 3, DVec3::ZERO).is_none());
        let view = StrandBlocks::new(&pos, 9, 4, DVec3::X).unwrap();
        assert_eq!(view.block_count(), 2);
        assert_eq!(view.lanes_in_block(0), 8);
        assert_eq!(view.lanes_in_block(1), 1);
        assert_eq!(view.block_positions_local(1).len(), 4);
        assert_eq!(view.origin(), DVec3::X);
    }
}
