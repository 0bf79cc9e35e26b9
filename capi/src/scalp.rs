//! From guides to a scalp and a posed head, for C: the head proxy fitted
//! to the roots (`coif_geometry::scene::fit_sphere`), the scalp triangles
//! that render hairs are interpolated over
//! (`coif_geometry::triangulate::scalp_triangles`: a groom file has none),
//! and the head pose in one call (`Strands::set_head_pose`).

use crate::{guard, handle, handle_mut, rigid_arg, CoifSphere, CoifStatus, CoifStrands};
use coif_geometry::scene::fit_sphere;
use coif_geometry::triangulate::scalp_triangles;
use glam::Vec3;

/// The guides' current roots.
fn current_roots(h: &CoifStrands) -> Vec<Vec3> {
    let verts = h.strands.verts_per_strand();
    h.strands.positions().into_iter().step_by(verts).collect()
}

/// Poses the head in one call: every root of `s` moves to `world_from_rest`
/// applied to where it was when the strands were made, and the rest frame
/// (what `local_shape_stiffness` keeps the groom in) turns with the pose,
/// so a turned head keeps its groom. `world_from_rest` is 12 floats, row
/// after row of a 3 x 4 rigid transform as `coif_strands_teleport` takes
/// (`m[0..4]` the first row: x' = m0 x + m1 y + m2 z + m3; the 3 x 3 part a
/// rotation, orthonormal within 1e-3, determinant +1; metres). Call it
/// once per frame (or per fixed step) before `coif_step`; a skinned scalp
/// uses `coif_strands_set_roots` instead.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE`,
/// `COIF_ERROR_INVALID_ARGUMENT` (not a rotation: scale, shear, mirror);
/// nothing changes then.
///
/// # Safety
/// `s` is NULL or a live handle; `world_from_rest` is NULL or points to 12
/// readable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_set_head_pose(
    s: *mut CoifStrands,
    world_from_rest: *const f32,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle not aliased during the call.
        let h = unsafe { handle_mut(s) }?;
        // SAFETY: NULL or 12 readable floats (the caller's contract).
        let pose = unsafe { rigid_arg(world_from_rest) }?;
        h.strands.set_head_pose(pose)?;
        Ok(())
    })
}

/// The head proxy of a groom without a mesh: the least-squares sphere
/// through the guides' current roots, written to `*out`.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT` (fewer than
/// four roots, or roots on a plane or a line: no sphere).
///
/// # Safety
/// `guides` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn coif_fit_head_sphere(
    guides: *const CoifStrands,
    out: *mut CoifSphere,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle (the caller's contract).
        let h = unsafe { handle(guides) }?;
        // SAFETY: NULL, misaligned (both refused) or writable (the
        // caller's contract).
        let out = unsafe { crate::handle_mut(out) }?;
        let s = fit_sphere(&current_roots(h)).ok_or(CoifStatus::COIF_ERROR_INVALID_ARGUMENT)?;
        *out = CoifSphere {
            center: s.center.to_array(),
            radius: s.radius,
        };
        Ok(())
    })
}

/// The scalp triangles of the guides' current roots, for `coif_hairs_new`:
/// the Delaunay triangles of the roots' directions seen from `center` (the
/// head's centre: `coif_fit_head_sphere`'s, or the caller's), without those
/// with an edge longer than three median edges (they bridge partings).
/// Writes `3 * count` indices (guide numbers) to `out_indices` and `count`
/// to `*out_count` when `capacity` triangles fit; otherwise writes only
/// `*out_count` (the count needed) and returns
/// `COIF_ERROR_BUFFER_TOO_SMALL`, so a first call with `capacity` 0 sizes
/// the buffer.
///
/// Errors (nothing written, but the count with `COIF_ERROR_BUFFER_TOO_SMALL`):
/// `COIF_ERROR_NULL` (`guides`, `center` or `out_count`; or `out_indices`
/// with a nonzero capacity), `COIF_ERROR_NON_FINITE` (a NaN or infinite
/// centre), `COIF_ERROR_INVALID_ARGUMENT` (no triangle: fewer than three
/// roots around the centre; a misaligned `out_count` or `out_indices`; a
/// capacity whose `3 * capacity` overflows), `COIF_ERROR_BUFFER_TOO_SMALL`.
///
/// # Safety
/// `guides` is NULL or a live handle; `center` is NULL or 3 readable
/// floats; `out_indices` is NULL or `3 * capacity` writable `uint32_t`;
/// `out_count` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn coif_scalp_triangles(
    guides: *const CoifStrands,
    center: *const f32,
    out_indices: *mut u32,
    capacity: usize,
    out_count: *mut usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle (the caller's contract).
        let h = unsafe { handle(guides) }?;
        // SAFETY: NULL, misaligned (both refused) or writable (the
        // caller's contract).
        let count = unsafe { crate::handle_mut(out_count) }?;
        // SAFETY: NULL or 3 readable floats (the caller's contract).
        let c = unsafe { crate::vec3_arg(center) }?;
        // Every argument is checked before anything is written: an error
        // changes nothing (BUFFER_TOO_SMALL writes only the count).
        let indices = capacity
            .checked_mul(3)
            .ok_or(CoifStatus::COIF_ERROR_INVALID_ARGUMENT)?;
        if capacity > 0 {
            crate::check_slice(out_indices.cast_const(), indices)?;
        }
        let triangles = scalp_triangles(&current_roots(h), c);
        if triangles.is_empty() {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        *count = triangles.len();
        if capacity < triangles.len() {
            return Err(CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL);
        }
        // SAFETY: non-NULL and aligned (checked, `capacity >= len > 0`),
        // `3 * capacity >= 3 * len` writable (the caller's contract).
        let out = unsafe { std::slice::from_raw_parts_mut(out_indices, 3 * triangles.len()) };
        for (dst, t) in out.chunks_exact_mut(3).zip(&triangles) {
            dst.copy_from_slice(t);
        }
        Ok(())
    })
}
