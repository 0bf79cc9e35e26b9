//! Scalar twin of `src/interpolation.rs`: the same steps, one hair at a time.

use super::refine_batch::unit_or_y;
use crate::culling::Visibility;
use crate::interpolation::{blend, group_drawn, Interpolation, RenderHairs};
use crate::refine_batch::RefinedGuides;
use crate::Error;
use coif_base::LANES;
use glam::Vec3;

/// Scalar twin of [`crate::interpolate`]: same algorithm, same order, one
/// hair at a time.
///
/// # Errors
///
/// As [`crate::interpolate`]: [`Error::CountMismatch`] or
/// [`Error::BufferTooSmall`], and nothing written.
pub fn interpolate(
    interpolation: &Interpolation,
    guides: &RefinedGuides,
    visibility: Option<&Visibility>,
    groups_drawn: usize,
    out: &mut RenderHairs,
) -> Result<usize, Error> {
    interpolate_groups(interpolation, guides, visibility, groups_drawn, out, true)
}

/// Scalar twin of [`crate::interpolate_positions`].
///
/// # Errors
///
/// As [`crate::interpolate`].
pub fn interpolate_positions(
    interpolation: &Interpolation,
    guides: &RefinedGuides,
    visibility: Option<&Visibility>,
    groups_drawn: usize,
    out: &mut RenderHairs,
) -> Result<usize, Error> {
    interpolate_groups(interpolation, guides, visibility, groups_drawn, out, false)
}

fn interpolate_groups(
    interpolation: &Interpolation,
    guides: &RefinedGuides,
    visibility: Option<&Visibility>,
    groups_drawn: usize,
    out: &mut RenderHairs,
    with_tangents: bool,
) -> Result<usize, Error> {
    out.begin(interpolation, guides, with_tangents)?;
    let r_len = out.verts;
    let mut count = 0;
    for (g, group) in interpolation.groups.iter().enumerate() {
        // 1. Skip the groups not drawn.
        if !group_drawn(g, group, groups_drawn, visibility, guides) {
            continue;
        }
        out.written[g] = true;
        count += 1;
        let [a, b, c] = group.guides.map(|s| s as usize);
        for l in 0..LANES {
            let w = interpolation.weights(g, l);
            for r in 0..r_len {
                let i = g * r_len + r;
                // 2. Positions.
                let p = blend_vec3(
                    w,
                    guides.position(a, r),
                    guides.position(b, r),
                    guides.position(c, r),
                );
                out.positions[i].set_lane(l, p);
                // 3. Tangents.
                if with_tangents {
                    let t = blend_vec3(
                        w,
                        guides.tangent(a, r),
                        guides.tangent(b, r),
                        guides.tangent(c, r),
                    );
                    out.tangents[i].set_lane(l, unit_or_y(t));
                }
            }
        }
    }
    Ok(count)
}

/// `wa a + wb b + wc c`: the shared [`blend`] on each coordinate.
#[inline]
fn blend_vec3(w: [f32; 3], a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    Vec3::new(
        blend(w, a.x, b.x, c.x),
        blend(w, a.y, b.y, c.y),
        blend(w, a.z, b.z, c.z),
    )
}
