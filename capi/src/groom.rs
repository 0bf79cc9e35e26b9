//! Grooms read from memory (`coif_geometry::groom::load`: TressFX 4 `.tfx`
//! and cyHair `.hair`, told apart by content) and strands made from them.

use crate::{guard, guard_or, handle, input, new_handle, output, CoifStatus, CoifStrands};
use coif_geometry::groom::{self, Groom};
use coif_kernels::Strands;
use glam::Vec3;

/// An opaque authored groom: strands of any vertex count, positions as
/// stored in the file (created by `coif_groom_load`, freed by
/// `coif_groom_free`).
pub struct CoifGroom {
    groom: Groom,
}

impl From<groom::Error> for CoifStatus {
    fn from(e: groom::Error) -> CoifStatus {
        crate::set_last_error(&e);
        match e {
            groom::Error::NonFinite { .. } => CoifStatus::COIF_ERROR_NON_FINITE,
            groom::Error::BadResample(_) => CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
            _ => CoifStatus::COIF_ERROR_BAD_DATA,
        }
    }
}

/// Reads a groom from the `len` bytes at `bytes`: a TressFX 4 `.tfx` or a
/// cyHair `.hair` file, told apart by content. The bytes are only read
/// during the call (the groom keeps its own copy of the points). On success
/// `*out` is the new handle (free it with `coif_groom_free`); on error
/// `*out` is NULL (when `out` is not).
///
/// Errors: `COIF_ERROR_NULL` (`bytes` or `out`), `COIF_ERROR_BAD_DATA`
/// (truncated, a header whose counts or offsets do not fit the bytes, an
/// unknown format), `COIF_ERROR_NON_FINITE` (a NaN or infinite coordinate).
///
/// # Safety
/// `bytes` is NULL or points to `len` readable bytes; `out` is NULL or points
/// to a writable `CoifGroom *`.
#[no_mangle]
pub unsafe extern "C" fn coif_groom_load(
    bytes: *const u8,
    len: usize,
    out: *mut *mut CoifGroom,
) -> CoifStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable (the caller's contract).
        unsafe {
            new_handle(out, || {
                if bytes.is_null() {
                    return Err(CoifStatus::COIF_ERROR_NULL);
                }
                // SAFETY: `len` readable bytes at a non-NULL `bytes`.
                let data = input(bytes, len)?;
                Ok(CoifGroom {
                    groom: groom::load(data)?,
                })
            })
        }
    })
}

/// Frees a groom made by `coif_groom_load`. NULL is fine. Strands made from
/// it with `coif_strands_from_groom` stay valid.
///
/// # Safety
/// `g` is NULL or a handle from `coif_groom_load` not freed before.
#[no_mangle]
pub unsafe extern "C" fn coif_groom_free(g: *mut CoifGroom) {
    // SAFETY: the caller's contract.
    unsafe { crate::free_handle(g) }
}

/// Number of strands in the groom (0 for NULL).
///
/// # Safety
/// `g` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_groom_strand_count(g: *const CoifGroom) -> usize {
    // SAFETY: NULL or a live handle.
    guard_or(0, || {
        unsafe { g.as_ref() }.map_or(0, |h| h.groom.strand_count())
    })
}

/// Number of vertices over all strands (0 for NULL).
///
/// # Safety
/// `g` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_groom_vertex_count(g: *const CoifGroom) -> usize {
    // SAFETY: NULL or a live handle.
    guard_or(0, || {
        unsafe { g.as_ref() }.map_or(0, |h| h.groom.vertex_count())
    })
}

/// Number of vertices of strand `strand` (0 for NULL or a strand out of
/// range): the bound of `coif_groom_strand_points`.
///
/// # Safety
/// `g` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_groom_strand_vertex_count(
    g: *const CoifGroom,
    strand: usize,
) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle.
        unsafe { g.as_ref() }.map_or(0, |h| {
            if strand < h.groom.strand_count() {
                h.groom.strand(strand).len()
            } else {
                0
            }
        })
    })
}

/// Writes strand `strand`'s points (root first, 3 floats each, as stored in
/// the file: no unit conversion) into `out_xyz`, which holds
/// `capacity_points` points, at least `coif_groom_strand_vertex_count`.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT` (no such
/// strand), `COIF_ERROR_BUFFER_TOO_SMALL` (nothing written).
///
/// # Safety
/// `g` is NULL or a live handle; `out_xyz` is NULL or points to
/// `3 * capacity_points` writable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_groom_strand_points(
    g: *const CoifGroom,
    strand: usize,
    out_xyz: *mut f32,
    capacity_points: usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle.
        let h = unsafe { handle(g) }?;
        if strand >= h.groom.strand_count() {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        let pts = h.groom.strand(strand);
        // SAFETY: the caller's contract on `out_xyz`; `Vec3` is three packed f32.
        let out = unsafe { output(out_xyz.cast::<Vec3>(), pts.len(), capacity_points) }?;
        out.copy_from_slice(pts);
        Ok(())
    })
}

/// Number of strands `coif_strands_from_groom(g, stride, ...)` makes: the
/// strands `0, stride, 2 stride, ...` of the groom that have at least two
/// points (0 for NULL or `stride == 0`).
///
/// # Safety
/// `g` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_groom_guide_count(g: *const CoifGroom, stride: usize) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle.
        unsafe { g.as_ref() }.map_or(0, |h| {
            if stride == 0 {
                0
            } else {
                h.groom.guide_strands(stride).count()
            }
        })
    })
}

/// Creates simulation strands from a groom: the strands `0, stride,
/// 2 stride, ...` (every strand for `stride` 1) that have at least two
/// points, each scaled by `scale` (0.01 turns TressFX's and cyHair's usual
/// centimetres into metres) and resampled to `verts_per_strand` points
/// evenly spaced in arc length (authored strands differ in vertex count;
/// `coif_geometry::groom::Groom::guides`). Roots are pinned; the groom's pose is
/// the rest shape. Move the result into place with `coif_strands_teleport`.
/// `coif_groom_guide_count(g, stride)` tells how many strands it has.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT`
/// (`verts_per_strand < 2`, `stride == 0`, `scale <= 0`, no strand of two
/// points), `COIF_ERROR_NON_FINITE` (`scale` or a scaled point not finite).
///
/// # Safety
/// `g` is NULL or a live handle; `out` is NULL or points to a writable
/// `CoifStrands *`.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_from_groom(
    g: *const CoifGroom,
    stride: usize,
    verts_per_strand: usize,
    scale: f32,
    out: *mut *mut CoifStrands,
) -> CoifStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable; `g` NULL or live (the caller's contract).
        unsafe {
            new_handle(out, || {
                let h = handle(g)?;
                if !scale.is_finite() {
                    return Err(CoifStatus::COIF_ERROR_NON_FINITE);
                }
                if verts_per_strand < 2 || stride == 0 || scale <= 0.0 {
                    return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
                }
                let guides = h.groom.guides(stride, verts_per_strand, scale)?;
                Ok(CoifStrands::new(Strands::from_polylines(
                    &guides,
                    verts_per_strand,
                )?))
            })
        }
    })
}
