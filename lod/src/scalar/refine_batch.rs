//! Scalar twin of `src/refine_batch.rs`: the same steps, one lane at a time.

use crate::culling::Visibility;
use crate::refine_batch::{block_needed, combine, RefinedGuides, MIN_LENGTH_SQUARED};
use crate::Error;
use coif_base::{StrandBlocks, LANES};
use glam::Vec3;

/// Scalar twin of [`crate::refine_strands`].
///
/// # Errors
///
/// As [`crate::refine_strands`]: [`Error::CountMismatch`] if `out` was made
/// for a set of another shape.
pub fn refine_strands(
    strands: StrandBlocks<'_>,
    visibility: Option<&Visibility>,
    out: &mut RefinedGuides,
) -> Result<usize, Error> {
    refine_blocks::<true>(strands, visibility, out)
}

/// Scalar twin of [`crate::refine_strands_positions`].
///
/// # Errors
///
/// As [`crate::refine_strands`].
pub fn refine_strands_positions(
    strands: StrandBlocks<'_>,
    visibility: Option<&Visibility>,
    out: &mut RefinedGuides,
) -> Result<usize, Error> {
    refine_blocks::<false>(strands, visibility, out)
}

fn refine_blocks<const TANGENTS: bool>(
    strands: StrandBlocks<'_>,
    visibility: Option<&Visibility>,
    out: &mut RefinedGuides,
) -> Result<usize, Error> {
    out.check_fits(strands)?;
    let (v, r, n) = (out.control_verts, out.verts, out.segments);
    let mut count = 0;
    for b in 0..out.blocks {
        // 1. Skip the blocks not needed.
        let needed = block_needed(visibility, b);
        out.refined[b] = needed;
        if !needed {
            continue;
        }
        count += 1;
        let ctrl = strands.block_positions_local(b);
        for l in 0..LANES {
            let c = |i: usize| ctrl[i].lane(l);
            for j in 0..v - 1 {
                // 2. The span's four control points, phantom ends at the ends.
                let p0 = if j == 0 { c(0) + c(0) - c(1) } else { c(j - 1) };
                let p1 = c(j);
                let p2 = c(j + 1);
                let p3 = if j + 2 < v {
                    c(j + 2)
                } else {
                    c(v - 1) + c(v - 1) - c(v - 2)
                };
                // 3. Positions and tangents of the span's refined vertices.
                let ks = if j == v - 2 { n + 1 } else { n };
                for k in 0..ks {
                    let w = out.weights[k];
                    let i = b * r + j * n + k;
                    let p = combine_vec3(p0, p1, p2, p3, [w[0], w[1], w[2], w[3]]);
                    out.positions[i].set_lane(l, p);
                    if TANGENTS {
                        let d = combine_vec3(p0, p1, p2, p3, [w[4], w[5], w[6], w[7]]);
                        out.tangents[i].set_lane(l, unit_or_y(d));
                    }
                }
            }
            // 4. Pin the end points.
            out.positions[b * r].set_lane(l, c(0));
            out.positions[b * r + r - 1].set_lane(l, c(v - 1));
        }
    }
    Ok(count)
}

/// `p0 w0 + p1 w1 + p2 w2 + p3 w3`: the shared [`combine`] on each coordinate.
#[inline]
fn combine_vec3(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3, w: [f32; 4]) -> Vec3 {
    Vec3::new(
        combine(p0.x, p1.x, p2.x, p3.x, w),
        combine(p0.y, p1.y, p2.y, p3.y, w),
        combine(p0.z, p1.z, p2.z, p3.z, w),
    )
}

/// `d / |d|`, or `+Y` where `|d|^2 <= 1e-30` or not finite (scalar twin of
/// the SIMD `unit_or_y_simd`).
#[inline]
pub(crate) fn unit_or_y(d: Vec3) -> Vec3 {
    let len2 = d.x * d.x + d.y * d.y + d.z * d.z;
    if len2 > MIN_LENGTH_SQUARED && len2 < f32::INFINITY {
        // Exact 1 / sqrt; the SIMD path's rsqrt + Newton step agrees
        // to a few ulp.
        d * (1.0 / len2.sqrt())
    } else {
        Vec3::Y
    }
}
