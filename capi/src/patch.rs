//! Cloth patches (`coif_kernels::patch`): a grid of particles following a
//! skin, stepped against the rig, blended with the skin per particle.

use crate::tasks::per_task;
use crate::{
    check_points, fill_rig, guard, guard_or, handle, handle_mut, input, new_handle, output, points,
    step_inputs, CoifExecutor, CoifSimParams, CoifSphere, CoifStatus,
};
use coif_kernels::{Patch, Sphere};
use glam::Vec3;

/// An opaque cloth patch (created by `coif_patch_new`, freed by
/// `coif_patch_free`).
pub struct CoifPatch {
    patch: Patch,
    /// The rig converted for `patch::step`; grows only when the rig does.
    spheres: Vec<Sphere>,
}

/// Creates a patch from its rest grid: `rows * cols` points (`grid_xyz`, 3
/// floats each, world metres, row-major) and a flag per particle
/// (`pinned`, nonzero = follows the skin exactly). Needs at least 2 rows
/// and 2 columns, at most 256 columns. The skin starts at the grid, blend
/// weights at 1 (fully simulated), max distances at infinity, shear
/// stiffness at 0. On error `*out` is NULL (when `out` is not).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT` (a grid shape
/// out of range, a size that overflows), `COIF_ERROR_NON_FINITE`.
///
/// # Safety
/// `grid_xyz` is NULL or points to `3 * rows * cols` readable floats,
/// `pinned` to `rows * cols` readable bytes; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_new(
    grid_xyz: *const f32,
    rows: usize,
    cols: usize,
    pinned: *const u8,
    out: *mut *mut CoifPatch,
) -> CoifStatus {
    guard(|| {
        // SAFETY: every pointer NULL or valid for the counts (the caller's contract).
        unsafe {
            new_handle(out, || {
                let n = rows
                    .checked_mul(cols)
                    .ok_or(CoifStatus::COIF_ERROR_INVALID_ARGUMENT)?;
                check_points(grid_xyz, n)?;
                if pinned.is_null() {
                    return Err(CoifStatus::COIF_ERROR_NULL);
                }
                let grid = points(grid_xyz, n);
                let pinned: Vec<bool> = input(pinned, n)?.iter().map(|&p| p != 0).collect();
                Ok(CoifPatch {
                    patch: Patch::new(grid, rows, cols, &pinned)?,
                    spheres: Vec::new(),
                })
            })
        }
    })
}

/// Frees a patch made by `coif_patch_new`. NULL is fine.
///
/// # Safety
/// `p` is NULL or a handle from `coif_patch_new` not freed before.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_free(p: *mut CoifPatch) {
    // SAFETY: the caller's contract.
    unsafe { crate::free_handle(p) }
}

/// Number of particles, `rows * cols` (0 for NULL): the count of every
/// per-particle array and the bound of the output calls.
///
/// # Safety
/// `p` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_particle_count(p: *const CoifPatch) -> usize {
    // SAFETY: NULL or a live handle.
    guard_or(0, || {
        unsafe { p.as_ref() }.map_or(0, |h| h.patch.particle_count())
    })
}

/// Gives this frame's skinned positions (`count` points, 3 floats each,
/// world metres, row-major, one per particle): pinned particles move there
/// at the next step, the others are held by max distance and blended.
/// Does not allocate.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_COUNT_MISMATCH`, `COIF_ERROR_NON_FINITE`.
///
/// # Safety
/// `p` is NULL or a live handle; `xyz` is NULL or points to `3 * count` readable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_set_skinned(
    p: *mut CoifPatch,
    xyz: *const f32,
    count: usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle; `xyz` as the caller's contract says.
        let h = unsafe { handle_mut(p) }?;
        check_points(xyz, count)?;
        h.patch.set_skinned(unsafe { points(xyz, count) })?;
        Ok(())
    })
}

/// Sets the blend weight of every particle (`count` floats in [0, 1],
/// row-major): 0 = the blended output is the skin, 1 = fully simulated.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_COUNT_MISMATCH`,
/// `COIF_ERROR_NON_FINITE`, `COIF_ERROR_INVALID_ARGUMENT` (outside [0, 1]).
///
/// # Safety
/// `p` is NULL or a live handle; `weights` is NULL or points to `count` readable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_set_weights(
    p: *mut CoifPatch,
    weights: *const f32,
    count: usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle; `weights` as the caller's contract says.
        let h = unsafe { handle_mut(p) }?;
        h.patch.set_weights(unsafe { input(weights, count) }?)?;
        Ok(())
    })
}

/// Sets how far (metres, `>= 0`, `INFINITY` = no limit) each simulated
/// particle may move from its skinned position (`count` floats, row-major).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_COUNT_MISMATCH`,
/// `COIF_ERROR_INVALID_ARGUMENT` (negative), `COIF_ERROR_NON_FINITE` (NaN).
///
/// # Safety
/// `p` is NULL or a live handle; `distances` is NULL or points to `count` readable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_set_max_distances(
    p: *mut CoifPatch,
    distances: *const f32,
    count: usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle; `distances` as the caller's contract says.
        let h = unsafe { handle_mut(p) }?;
        h.patch
            .set_max_distances(unsafe { input(distances, count) }?)?;
        Ok(())
    })
}

/// Sets the stiffness in [0, 1] of the shear (diagonal) edges (0 = off, the default).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT`, `COIF_ERROR_NON_FINITE`.
///
/// # Safety
/// `p` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_set_shear_stiffness(
    p: *mut CoifPatch,
    stiffness: f32,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle.
        let h = unsafe { handle_mut(p) }?;
        h.patch.set_shear_stiffness(stiffness)?;
        Ok(())
    })
}

/// Advances the patch by one fixed step of `params->dt` toward the last
/// skin, against `sphere_count` spheres (`coif_kernels::patch::step`, SIMD;
/// the parameters mean what they mean for strands). Validates the
/// parameters and spheres first; does not allocate unless the rig has more
/// spheres than at any earlier call.
///
/// Errors: as `coif_step`.
///
/// # Safety
/// `p` is NULL or a live handle; `params` is NULL or readable; `spheres` is
/// NULL or points to `sphere_count` readable spheres.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_step(
    p: *mut CoifPatch,
    params: *const CoifSimParams,
    spheres: *const CoifSphere,
    sphere_count: usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or live/readable (the caller's contract).
        let h = unsafe { handle_mut(p) }?;
        let (params, _, rig) =
            unsafe { step_inputs(params, spheres, sphere_count, std::ptr::null()) }?;
        fill_rig(rig, &mut h.spheres);
        coif_kernels::patch::step(&mut h.patch, &params, &h.spheres);
        Ok(())
    })
}

/// The patch handles of one `coif_patch_step_all` call, shared by its tasks.
struct PatchList<'a>(&'a [*mut CoifPatch]);
// SAFETY: the handles are distinct (checked) and each is reached by the one
// task whose run of indices holds it.
unsafe impl Sync for PatchList<'_> {}

/// Steps `patch_count` patches (`patches`: that many distinct handles)
/// against the same rig, as `coif_patch_step` on each, with runs of
/// consecutive patches handed out as tasks to `executor` (about four per
/// thread, at most 64; a patch is never split). Patches share nothing, so
/// every patch ends in the same bytes as `coif_patch_step` gives it, with
/// any executor and any task order (`coif_kernels::patch::step_all`'s rule).
/// NULL `executor` runs the tasks on the calling thread. Every check runs
/// before any patch moves: the handles (none NULL, none twice, a check of
/// `patch_count^2 / 2` pointer comparisons), the parameters, the executor
/// and the rig. Does not allocate unless the rig has more spheres than at
/// any earlier step of a patch.
///
/// Errors: as `coif_step_with`, and `COIF_ERROR_NULL` for a NULL handle in
/// the list, `COIF_ERROR_INVALID_ARGUMENT` for a handle listed twice.
///
/// # Safety
/// `patches` is NULL or points to `patch_count` readable pointers, each
/// NULL or a live handle not used elsewhere during the call; `params`,
/// `spheres` and `executor` as `coif_step_with` says.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_step_all(
    patches: *const *mut CoifPatch,
    patch_count: usize,
    params: *const CoifSimParams,
    spheres: *const CoifSphere,
    sphere_count: usize,
    executor: *const CoifExecutor,
) -> CoifStatus {
    guard(|| {
        if patches.is_null() && patch_count > 0 {
            return Err(CoifStatus::COIF_ERROR_NULL);
        }
        // SAFETY: the caller's contract on `patches`.
        let list = unsafe { input(patches, patch_count) }?;
        if list.iter().any(|p| p.is_null()) {
            return Err(CoifStatus::COIF_ERROR_NULL);
        }
        let distinct = (1..list.len()).all(|i| !list[..i].contains(&list[i]));
        if !distinct || !list.iter().all(|p| p.is_aligned()) {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        // SAFETY: the caller's contract on the pointers.
        let (params, exec, rig) = unsafe { step_inputs(params, spheres, sphere_count, executor) }?;
        let exec = exec.get();
        let per = per_task(list.len(), exec, 1);
        let shared = PatchList(list);
        exec.run(list.len().div_ceil(per), &|t| {
            let shared = &shared;
            for &p in shared.0.iter().skip(t * per).take(per) {
                // SAFETY: a live handle (the caller's contract), listed once
                // (checked), so only this task reaches it during the call.
                let h = unsafe { &mut *p };
                fill_rig(rig, &mut h.spheres);
                coif_kernels::patch::step(&mut h.patch, &params, &h.spheres);
            }
        });
        Ok(())
    })
}

/// Writes the blended positions, `skinned (1 - weight) + simulated weight`
/// per particle (world metres, row-major, 3 floats each) into `out_xyz`,
/// which holds `capacity_points` points, at least `coif_patch_particle_count`.
/// Does not allocate.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_BUFFER_TOO_SMALL` (nothing written).
///
/// # Safety
/// `p` is NULL or a live handle; `out_xyz` is NULL or points to
/// `3 * capacity_points` writable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_blended(
    p: *const CoifPatch,
    out_xyz: *mut f32,
    capacity_points: usize,
) -> CoifStatus {
    // SAFETY: the caller's contract.
    unsafe {
        write_particles(p, out_xyz, capacity_points, |patch, out| {
            patch.write_blended(out).map_err(CoifStatus::from)
        })
    }
}

/// Writes the simulated positions (before the blend; world metres,
/// row-major) into `out_xyz`, as `coif_patch_blended` does.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_BUFFER_TOO_SMALL` (nothing written).
///
/// # Safety
/// As `coif_patch_blended`.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_positions(
    p: *const CoifPatch,
    out_xyz: *mut f32,
    capacity_points: usize,
) -> CoifStatus {
    // SAFETY: the caller's contract.
    unsafe {
        write_particles(p, out_xyz, capacity_points, |patch, out| {
            patch.write_positions(out)?;
            Ok(())
        })
    }
}

/// One point per particle into the caller's buffer, by `write`.
///
/// # Safety
/// As `coif_patch_blended`.
unsafe fn write_particles(
    p: *const CoifPatch,
    out_xyz: *mut f32,
    capacity_points: usize,
    write: impl FnOnce(&Patch, &mut [Vec3]) -> Result<(), CoifStatus>,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle; the buffer as the caller's contract says.
        let h = unsafe { handle(p) }?;
        let n = h.patch.particle_count();
        let out = unsafe { output(out_xyz.cast::<Vec3>(), n, capacity_points) }?;
        write(&h.patch, out)
    })
}

/// Moves every particle onto the skin, at rest (a teleport or a reset).
///
/// Errors: `COIF_ERROR_NULL`.
///
/// # Safety
/// `p` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_patch_reset_to_skin(p: *mut CoifPatch) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle.
        let h = unsafe { handle_mut(p) }?;
        h.patch.reset_to_skin();
        Ok(())
    })
}
