//! Filling the buffers from coif's CPU data: the guides every frame, the
//! render hairs once. Destination first, nothing allocated, the count
//! written returned (meshoptimizer's convention); a buffer too small is an
//! error and nothing is written.

use crate::layout::{GuideVertex, RenderHair};
use crate::Error;
use coif_base::{StrandBlocks, LANES};
use coif_lod::Interpolation;

/// Writes every guide vertex of `strands` (positions relative to its
/// origin) into `out`, guide after guide, root first: vertex `v` of guide
/// `g` at `g V + v`. Reads the SoA blocks straight (lane `l` of block `b`
/// is guide `8 b + l`); padding lanes are skipped. Returns the number of
/// entries written, `strand_count * verts_per_strand`. Non-finite
/// positions are copied as they are: on the GPU they reach only the render
/// hairs that use that guide, as on the CPU.
///
/// # Errors
///
/// [`Error::BufferTooSmall`] if `out` is shorter than the count.
pub fn pack_guides(strands: StrandBlocks<'_>, out: &mut [GuideVertex]) -> Result<usize, Error> {
    let v = strands.verts_per_strand();
    let n = strands.strand_count();
    let needed = n.saturating_mul(v);
    if out.len() < needed {
        return Err(Error::BufferTooSmall {
            needed,
            got: out.len(),
        });
    }
    for b in 0..strands.block_count() {
        let block = strands.block_positions_local(b);
        for (l, guide) in out[b * LANES * v..needed]
            .chunks_exact_mut(v)
            .take(strands.lanes_in_block(b))
            .enumerate()
        {
            for (dst, src) in guide.iter_mut().zip(block) {
                *dst = GuideVertex {
                    position: src.lane(l).to_array(),
                    w: 0.0,
                };
            }
        }
    }
    Ok(needed)
}

/// Writes every render hair of `interpolation` into `out` in the order
/// `lod::write_render_vertices` writes their vertices: group after group
/// (coif's shuffled order, so a prefix is an even thinning of the scalp),
/// the group's real hairs in lane order. Returns the number of hairs,
/// `interpolation.hair_count()`. Built once per groom.
///
/// # Errors
///
/// [`Error::BufferTooSmall`] if `out` is shorter than the count.
pub fn pack_hairs(interpolation: &Interpolation, out: &mut [RenderHair]) -> Result<usize, Error> {
    let needed = interpolation.hair_count();
    if out.len() < needed {
        return Err(Error::BufferTooSmall {
            needed,
            got: out.len(),
        });
    }
    let mut written = 0;
    for (g, group) in interpolation.groups().iter().enumerate() {
        for l in 0..(group.hairs as usize).min(LANES) {
            out[written] = RenderHair {
                guides: group.guides,
                reserved: 0,
                weights: interpolation.weights(g, l),
                reserved_weight: 0.0,
            };
            written += 1;
        }
    }
    Ok(written)
}

/// Render hairs drawn when the first `groups_drawn` groups are (the
/// distance-LOD prefix): the `hairs` field of [`crate::HairView`].
pub fn render_hair_count(interpolation: &Interpolation, groups_drawn: usize) -> usize {
    interpolation.hairs_in_prefix(groups_drawn)
}

#[cfg(test)]
mod tests {
    use super::*;
    use coif_base::Vec3Lanes;
    use glam::{DVec3, Vec3};

    #[test]
    fn guides_come_out_guide_major_without_padding_lanes() {
        // 11 strands of 3 points: two blocks, the second with 3 real lanes.
        let (n, v) = (11, 3);
        let mut blocks = vec![Vec3Lanes::ZERO; 2 * v];
        for s in 0..16 {
            for k in 0..v {
                let p = Vec3::new(s as f32, k as f32, if s < n { 1.0 } else { -1.0 });
                blocks[(s / LANES) * v + k].set_lane(s % LANES, p);
            }
        }
        let strands = StrandBlocks::new(&blocks, n, v, DVec3::ZERO).unwrap();
        let mut out = vec![
            GuideVertex {
                position: [9.0; 3],
                w: 9.0
            };
            n * v + 1
        ];
        assert_eq!(pack_guides(strands, &mut out), Ok(n * v));
        for s in 0..n {
            for k in 0..v {
                assert_eq!(out[s * v + k].position, [s as f32, k as f32, 1.0]);
                assert_eq!(out[s * v + k].w, 0.0);
            }
        }
        assert_eq!(out[n * v].position, [9.0; 3], "past the count: untouched");
        let mut short = vec![GuideVertex::default(); n * v - 1];
        assert!(matches!(
            pack_guides(strands, &mut short),
            Err(Error::BufferTooSmall { .. })
        ));
        assert!(short.iter().all(|g| *g == GuideVertex::default()));
    }
}
