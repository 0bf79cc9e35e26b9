//! A render vertex for engines: plain old data, so a `&[RenderVertex]`
//! uploads to a GPU buffer as bytes without copying (`bytemuck::cast_slice`).

use crate::interpolation::{Interpolation, RenderHairs};
use crate::Error;
use bytemuck::{Pod, Zeroable};
use coif_base::LANES;

/// One hair vertex, 32 bytes, `#[repr(C)]`:
/// `position` (metres, relative to the guides' `Strands::origin`), `width`
/// (metres, distance-LOD width factor included, so coverage is kept),
/// unit `tangent` root to tip, and `strand_parameter` `s` in `[0, 1]`
/// (0 at the root, 1 at the tip; for tapering, colour ramps, alpha).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RenderVertex {
    /// Position relative to the strands' origin, metres.
    pub position: [f32; 3],
    /// Hair width at this vertex, metres.
    pub width: f32,
    /// Unit tangent, root to tip.
    pub tangent: [f32; 3],
    /// Parameter along the strand, 0 at the root, 1 at the tip.
    pub strand_parameter: f32,
}

/// Hair width along the strand: `lerp(root, tip, s)` metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairWidth {
    /// Width at the root, metres.
    pub root: f32,
    /// Width at the tip, metres.
    pub tip: f32,
}

impl Default for HairWidth {
    /// 80 micrometres at the root tapering to 40 at the tip (human scalp
    /// hair is roughly 17-180 um thick).
    fn default() -> HairWidth {
        HairWidth {
            root: 80e-6,
            tip: 40e-6,
        }
    }
}

/// Number of vertices [`write_render_vertices`] writes at most, and so the
/// length its `out` needs: real hairs in the first `groups_drawn` groups
/// times vertices per hair of the last interpolation pass.
pub fn render_vertex_len(
    interpolation: &Interpolation,
    hairs: &RenderHairs,
    groups_drawn: usize,
) -> usize {
    interpolation
        .hairs_in_prefix(groups_drawn)
        .saturating_mul(hairs.verts_per_hair())
}

/// Writes the real hairs of every group that the last [`crate::interpolate`]
/// wrote (within the first `groups_drawn`), hair after hair, root first, into
/// `out`; widths are `width` times `width_factor` (from [`crate::distance_lod`]).
/// Tangents come from the last pass if it was [`crate::interpolate`], or
/// from central differences of the positions after
/// [`crate::interpolate_positions`]. Returns the number of vertices
/// written (fewer than `out.len()` when groups were culled; 0 before the
/// first interpolation pass).
///
/// # Errors
///
/// Nothing is written on:
/// - [`Error::CountMismatch`]: `hairs` was made for an interpolation with
///   another group count;
/// - [`Error::BufferTooSmall`]: `out` is shorter than
///   [`render_vertex_len`]`(interpolation, hairs, groups_drawn)`, the most
///   the call can write (whether or not groups were culled this frame).
pub fn write_render_vertices(
    interpolation: &Interpolation,
    hairs: &RenderHairs,
    groups_drawn: usize,
    width: HairWidth,
    width_factor: f32,
    out: &mut [RenderVertex],
) -> Result<usize, Error> {
    if interpolation.group_count() != hairs.group_count() {
        return Err(Error::CountMismatch {
            what: "hair groups (RenderHairs made for another Interpolation)",
            expected: interpolation.group_count(),
            got: hairs.group_count(),
        });
    }
    let needed = render_vertex_len(interpolation, hairs, groups_drawn);
    if out.len() < needed {
        return Err(Error::BufferTooSmall {
            needed,
            got: out.len(),
        });
    }
    let r_len = hairs.verts_per_hair();
    if r_len == 0 {
        return Ok(0);
    }
    let inv = if r_len > 1 {
        1.0 / (r_len - 1) as f32
    } else {
        0.0
    };
    let mut written = 0;
    for (g, group) in interpolation.groups().iter().enumerate().take(groups_drawn) {
        if !hairs.is_group_written(g) {
            continue;
        }
        let pos = hairs.group_positions(g);
        let tan = hairs.group_tangents(g);
        for l in 0..(group.hairs as usize).min(LANES) {
            for r in 0..r_len {
                let s = r as f32 * inv;
                let tangent = if hairs.has_tangents() {
                    tan[r].lane(l)
                } else {
                    // Central difference (one-sided at the ends).
                    let (a, b) = (r.saturating_sub(1), (r + 1).min(r_len - 1));
                    (pos[b].lane(l) - pos[a].lane(l))
                        .try_normalize()
                        .unwrap_or(glam::Vec3::Y)
                };
                out[written] = RenderVertex {
                    position: pos[r].lane(l).to_array(),
                    width: (width.root + (width.tip - width.root) * s) * width_factor,
                    tangent: tangent.to_array(),
                    strand_parameter: s,
                };
                written += 1;
            }
        }
    }
    Ok(written)
}

/// The vertices as bytes for a GPU upload, without copying.
pub fn vertex_bytes(vertices: &[RenderVertex]) -> &[u8] {
    bytemuck::cast_slice(vertices)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_is_32_tightly_packed_bytes() {
        assert_eq!(std::mem::size_of::<RenderVertex>(), 32);
        assert_eq!(std::mem::align_of::<RenderVertex>(), 4);
        let v = [RenderVertex {
            position: [1.0, 2.0, 3.0],
            width: 4.0,
            tangent: [5.0, 6.0, 7.0],
            strand_parameter: 8.0,
        }];
        let bytes = vertex_bytes(&v);
        assert_eq!(bytes.len(), 32);
        let floats: &[f32] = bytemuck::cast_slice(bytes);
        assert_eq!(floats, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
    }
}
