//! The world around the hair: capsules, signed distance fields of meshes
//! and the step against all colliders with wind and drag
//! (`coif_kernels::{Capsule, Sdf, Colliders, step_colliders_with}`).
//!
//! The Rust step borrows its fields as one slice (`Colliders::sdfs:
//! &[Sdf]`), so the C side keeps them in a set that owns them contiguously
//! ([`CoifSdfSet`]): a field is built alone ([`coif_sdf_new`]), may be
//! placed and queried alone, and is then moved into a set
//! ([`coif_sdf_set_add`]); the step borrows the set's fields as they are,
//! so stepping never copies a field nor allocates for one.

use crate::{
    check_points, check_slice, fill_rig, guard, handle, handle_mut, input, new_handle, points,
    rigid_arg, step_inputs, vec3_arg, CoifExecutor, CoifSimParams, CoifSphere, CoifStatus,
    CoifStrands,
};
use coif_kernels::{Capsule, Colliders, Sdf};
use glam::Vec3;

/// A capsule collider (a bone, a limb): the points within `radius` of the
/// segment `a`-`b`, world coordinates in metres. `a == b` is a sphere.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifCapsule {
    /// One end of the axis.
    pub a: [f32; 3],
    /// The other end of the axis.
    pub b: [f32; 3],
    /// Radius around the axis in metres (>= 0).
    pub radius: f32,
}

/// An opaque signed distance field of a closed triangle mesh (created by
/// `coif_sdf_new`, freed by `coif_sdf_free` unless moved into a set by
/// `coif_sdf_set_add`).
pub struct CoifSdf {
    sdf: Sdf,
}

/// An opaque set of fields that one step collides with (created by
/// `coif_sdf_set_new`, freed by `coif_sdf_set_free`): it owns its fields,
/// each at the index `coif_sdf_set_add` gave it.
pub struct CoifSdfSet {
    fields: Vec<Sdf>,
}

/// Builds the signed distance field of a closed triangle mesh:
/// `vertex_count` vertices (`xyz`: 3 floats each, mesh coordinates in
/// metres) and `triangle_count` triangles (`indices`: 3 `uint32_t` vertex
/// indices each, counter-clockwise seen from outside), sampled on a grid of
/// `cell` metres (`coif_kernels::Sdf::from_mesh`). The field starts at the
/// identity transform (mesh coordinates = world coordinates); place it with
/// `coif_sdf_set_transform`. On success `*out` is the new handle (free it
/// with `coif_sdf_free`, or move it into a set with `coif_sdf_set_add`);
/// on error `*out` is NULL. Allocates (once, at load time).
///
/// Errors: `COIF_ERROR_NULL` (`out`, `xyz` or `indices`),
/// `COIF_ERROR_NON_FINITE` (a vertex or `cell`),
/// `COIF_ERROR_INVALID_ARGUMENT` (no vertices or no triangles, an index
/// `>= vertex_count`, `cell <= 0`, a grid over `MAX_SDF_CELLS` cells or a
/// mesh the field refuses, a misaligned pointer, a size that overflows).
///
/// # Safety
/// `xyz` is NULL or points to `3 * vertex_count` readable floats; `indices`
/// is NULL or points to `3 * triangle_count` readable `uint32_t`; `out` is
/// NULL or points to a writable `CoifSdf *`.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_new(
    xyz: *const f32,
    vertex_count: usize,
    indices: *const u32,
    triangle_count: usize,
    cell: f32,
    out: *mut *mut CoifSdf,
) -> CoifStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable (the caller's contract).
        unsafe {
            new_handle(out, || {
                check_points(xyz, vertex_count)?;
                check_slice(indices.cast::<[u32; 3]>(), triangle_count)?;
                if vertex_count == 0 || triangle_count == 0 {
                    return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
                }
                // SAFETY: checked above; the caller guarantees 3 * vertex_count floats.
                let verts = points(xyz, vertex_count);
                // SAFETY: non-NULL, 4-aligned, within isize::MAX bytes
                // (checked); `[u32; 3]` is three packed u32; readable per
                // the caller's contract.
                let tris = std::slice::from_raw_parts(indices.cast::<[u32; 3]>(), triangle_count);
                // `Sdf::from_mesh` checks the rest (a non-finite vertex or
                // cell, an index out of range, a bad cell) and its error
                // names the value (`coif_last_error_message`).
                Ok(CoifSdf {
                    sdf: Sdf::from_mesh(verts, tris, cell)?,
                })
            })
        }
    })
}

/// Frees a field made by `coif_sdf_new`. NULL is fine. (A field moved into
/// a set is freed with the set.)
///
/// # Safety
/// `sdf` is NULL or a handle from `coif_sdf_new` not freed nor moved into a
/// set before; it must not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_free(sdf: *mut CoifSdf) {
    // SAFETY: NULL or a live handle freed once (the caller's contract).
    unsafe { crate::free_handle(sdf) }
}

/// Places a field in the world: `world_from_mesh` is a 3x4 row-major rigid
/// transform, as `coif_strands_teleport` takes (12 floats, `m[0..4]` is the
/// first row: x' = m0 x + m1 y + m2 z + m3; the 3x3 part a rotation,
/// orthonormal within 1e-3 with determinant +1; the translation in metres).
/// In a set (`coif_sdf_set_transform_at`), the step moves the field on the
/// straight line from where it was at the last step to here over its
/// substeps.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE`,
/// `COIF_ERROR_INVALID_ARGUMENT` (not a rotation: scale, shear, mirror).
///
/// # Safety
/// `sdf` is NULL or a live handle; `world_from_mesh` is NULL or points to
/// 12 readable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_set_transform(
    sdf: *mut CoifSdf,
    world_from_mesh: *const f32,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle not aliased during the call.
        let h = unsafe { handle_mut(sdf) }?;
        // SAFETY: NULL or 12 readable floats (the caller's contract).
        let xform = unsafe { rigid_arg(world_from_mesh) }?;
        h.sdf.set_transform(xform)?;
        Ok(())
    })
}

/// Writes into `*out` the signed distance in metres from the world point
/// `p` (3 floats) to the field's surface, negative inside
/// (`Sdf::distance`, at the field's current transform). Does not allocate.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE` (a coordinate of
/// `p`), `COIF_ERROR_INVALID_ARGUMENT` (misaligned `out`).
///
/// # Safety
/// `sdf` is NULL or a live handle; `p` is NULL or points to 3 readable
/// floats; `out` is NULL or points to a writable float.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_distance(
    sdf: *const CoifSdf,
    p: *const f32,
    out: *mut f32,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle (the caller's contract).
        let h = unsafe { handle(sdf) }?;
        // SAFETY: the caller's contract.
        unsafe { write_distance(&h.sdf, p, out) }
    })
}

/// `*out = sdf.distance(p)` after checking `p` and `out`.
///
/// # Safety
/// `p` is NULL or points to 3 readable floats; `out` is NULL or writable.
unsafe fn write_distance(sdf: &Sdf, p: *const f32, out: *mut f32) -> Result<(), CoifStatus> {
    // SAFETY: the caller's contract.
    let p = unsafe { vec3_arg(p) }?;
    check_slice(out.cast_const(), 1)?;
    let d = sdf.distance(p);
    // SAFETY: non-NULL and aligned (checked), writable (the caller's contract).
    unsafe { out.write(d) };
    Ok(())
}

/// Creates an empty set of fields. On success `*out` is the new handle
/// (free it with `coif_sdf_set_free`).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT` (misaligned).
///
/// # Safety
/// `out` is NULL or points to a writable `CoifSdfSet *`.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_set_new(out: *mut *mut CoifSdfSet) -> CoifStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable (the caller's contract).
        unsafe { new_handle(out, || Ok(CoifSdfSet { fields: Vec::new() })) }
    })
}

/// Frees a set and every field in it. NULL is fine.
///
/// # Safety
/// `set` is NULL or a handle from `coif_sdf_set_new` not freed before; it
/// must not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_set_free(set: *mut CoifSdfSet) {
    // SAFETY: NULL or a live handle freed once (the caller's contract).
    unsafe { crate::free_handle(set) }
}

/// Moves the field `*sdf` into `set` at the next index (the set's count
/// before the call), which it keeps for the set's life: the step remembers
/// where each field was by that index. On success the set owns the field
/// and `*sdf` is set to NULL (do not free it); `*out_index` (if
/// `out_index` is not NULL) is its index. On error nothing changes and the
/// caller still owns `*sdf`. Allocates when the set grows (once, at load
/// time); a step that sees the set's count change takes every field as not
/// moving for that step.
///
/// Errors: `COIF_ERROR_NULL` (`set`, `sdf` or `*sdf`),
/// `COIF_ERROR_INVALID_ARGUMENT` (a misaligned pointer, no memory).
///
/// # Safety
/// `set` is NULL or a live set not in use by a step; `sdf` is NULL or
/// points to a `CoifSdf *` that is NULL or a live handle from
/// `coif_sdf_new`; `out_index` is NULL or points to a writable `size_t`.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_set_add(
    set: *mut CoifSdfSet,
    sdf: *mut *mut CoifSdf,
    out_index: *mut usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live set not aliased during the call.
        let h = unsafe { handle_mut(set) }?;
        check_slice(sdf.cast_const(), 1)?;
        if !out_index.is_null() && !out_index.is_aligned() {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        // SAFETY: non-NULL, aligned (checked), readable (the caller's contract).
        let field = unsafe { sdf.read() };
        if field.is_null() {
            return Err(CoifStatus::COIF_ERROR_NULL);
        }
        h.fields
            .try_reserve(1)
            .map_err(|_| CoifStatus::COIF_ERROR_INVALID_ARGUMENT)?;
        // Nothing fails from here on: take the field.
        // SAFETY: `field` came from `coif_sdf_new` (Box::into_raw) and is
        // live (the caller's contract); the caller's pointer to it is
        // cleared below, so it is taken once.
        let field = unsafe { Box::from_raw(field) };
        let index = h.fields.len();
        h.fields.push(field.sdf);
        // SAFETY: non-NULL, aligned, writable (checked / the caller's contract).
        unsafe { sdf.write(std::ptr::null_mut()) };
        if !out_index.is_null() {
            // SAFETY: non-NULL, aligned (checked), writable (the caller's contract).
            unsafe { out_index.write(index) };
        }
        Ok(())
    })
}

/// Number of fields in the set (0 for NULL).
///
/// # Safety
/// `set` is NULL or a live set.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_set_count(set: *const CoifSdfSet) -> usize {
    crate::guard_or(0, || {
        // SAFETY: NULL or a live set (the caller's contract).
        unsafe { set.as_ref() }.map_or(0, |h| h.fields.len())
    })
}

/// `coif_sdf_set_transform` for the field at `index` of `set` (call it
/// every frame for a field that moves, before the step). Does not allocate.
///
/// Errors: as `coif_sdf_set_transform`, and `COIF_ERROR_INVALID_ARGUMENT`
/// for `index >= coif_sdf_set_count(set)`.
///
/// # Safety
/// `set` is NULL or a live set not in use by a step; `world_from_mesh` is
/// NULL or points to 12 readable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_set_transform_at(
    set: *mut CoifSdfSet,
    index: usize,
    world_from_mesh: *const f32,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live set not aliased during the call.
        let h = unsafe { handle_mut(set) }?;
        let field = h
            .fields
            .get_mut(index)
            .ok_or(CoifStatus::COIF_ERROR_INVALID_ARGUMENT)?;
        // SAFETY: NULL or 12 readable floats (the caller's contract).
        let xform = unsafe { rigid_arg(world_from_mesh) }?;
        field.set_transform(xform)?;
        Ok(())
    })
}

/// `coif_sdf_distance` for the field at `index` of `set`.
///
/// Errors: as `coif_sdf_distance`, and `COIF_ERROR_INVALID_ARGUMENT` for
/// `index >= coif_sdf_set_count(set)`.
///
/// # Safety
/// `set` is NULL or a live set; `p` is NULL or points to 3 readable floats;
/// `out` is NULL or points to a writable float.
#[no_mangle]
pub unsafe extern "C" fn coif_sdf_set_distance_at(
    set: *const CoifSdfSet,
    index: usize,
    p: *const f32,
    out: *mut f32,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live set (the caller's contract).
        let h = unsafe { handle(set) }?;
        let field = h
            .fields
            .get(index)
            .ok_or(CoifStatus::COIF_ERROR_INVALID_ARGUMENT)?;
        // SAFETY: the caller's contract.
        unsafe { write_distance(field, p, out) }
    })
}

/// Advances every strand by one fixed step of `params->dt` against every
/// collider: `sphere_count` spheres, `capsule_count` capsules (world
/// coordinates; either array may be NULL when its count is 0) and the
/// fields of `sdfs` (NULL = none), each placed by its transform; with
/// `params`' wind, drag, gusts and Coulomb friction
/// (`coif_kernels::step_colliders`), on the calling thread
/// (`coif_step_colliders_with` with a NULL executor). `coif_step(s, p,
/// spheres, n)` is this call with no capsules and no fields.
///
/// The step remembers where each collider was at the last step by its
/// index (per kind) and moves it on the straight line to where it is now
/// over its substeps: keep each sphere, capsule and field at the same
/// index from frame to frame (a kind whose count changed is taken as not
/// moving for that step). Several strand sets may share one `CoifSdfSet`
/// (it is only read; do not change it during a step).
///
/// Validates the parameters, spheres and capsules first; does not allocate
/// unless there are more spheres, capsules or fields than at any earlier
/// step of `s`.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE` (a NaN or infinite
/// parameter, sphere or capsule), `COIF_ERROR_INVALID_ARGUMENT` (a
/// parameter out of range, a negative radius, a misaligned array).
///
/// # Safety
/// `s` is NULL or a live handle; `params` is NULL or readable; `spheres`
/// and `capsules` are NULL or point to their counts of readable values;
/// `sdfs` is NULL or a live set not written during the call.
#[no_mangle]
pub unsafe extern "C" fn coif_step_colliders(
    s: *mut CoifStrands,
    params: *const CoifSimParams,
    spheres: *const CoifSphere,
    sphere_count: usize,
    capsules: *const CoifCapsule,
    capsule_count: usize,
    sdfs: *const CoifSdfSet,
) -> CoifStatus {
    // SAFETY: the caller's contract; a NULL executor is the calling thread.
    unsafe {
        coif_step_colliders_with(
            s,
            params,
            spheres,
            sphere_count,
            capsules,
            capsule_count,
            sdfs,
            std::ptr::null(),
        )
    }
}

/// `coif_step_colliders` with the strands' blocks handed out as tasks to
/// `executor`, as `coif_step_with` does (`coif_kernels::step_colliders_with`):
/// the same bytes as `coif_step_colliders` with any executor, thread count
/// and task order. NULL `executor` runs the tasks on the calling thread.
/// Every check runs first: an error leaves the strands unchanged and `run`
/// uncalled.
///
/// Errors: as `coif_step_colliders`, and `COIF_ERROR_NULL` for an executor
/// whose `run` is NULL, `COIF_ERROR_INVALID_ARGUMENT` for a misaligned one.
///
/// # Safety
/// As `coif_step_colliders`; `executor` is NULL or points to a readable
/// `CoifExecutor` that keeps its contract during the call.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn coif_step_colliders_with(
    s: *mut CoifStrands,
    params: *const CoifSimParams,
    spheres: *const CoifSphere,
    sphere_count: usize,
    capsules: *const CoifCapsule,
    capsule_count: usize,
    sdfs: *const CoifSdfSet,
    executor: *const CoifExecutor,
) -> CoifStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        with_world(
            s,
            params,
            (spheres, sphere_count),
            (capsules, capsule_count),
            sdfs,
            executor,
            |strands, params, colliders, exec| {
                coif_kernels::step_colliders_with(strands, params, colliders, exec);
                Ok(())
            },
        )
    }
}

/// Makes the strands' current pose their rest state under `params`
/// (`coif_kernels::Strands::solve_sag_free`): the local shape springs'
/// rest vectors are set so that this pose is the step's equilibrium under
/// gravity and the wind's pull (`R t = e - g M l^2 / c^2` per segment), so
/// the groom keeps its style instead of sagging. Call it once after
/// `coif_strands_new` (or `coif_strands_from_groom`) and the first
/// `coif_strands_set_head_pose`, before stepping, with the colliders the
/// step will see (they are checked); a second call changes nothing. No
/// allocation; well under a millisecond for a few hundred guides.
///
/// Errors: as `coif_step_colliders`; an error leaves the strands unchanged.
///
/// # Safety
/// As `coif_step_colliders`.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_solve_sag_free(
    s: *mut CoifStrands,
    params: *const CoifSimParams,
    spheres: *const CoifSphere,
    sphere_count: usize,
    capsules: *const CoifCapsule,
    capsule_count: usize,
    sdfs: *const CoifSdfSet,
) -> CoifStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        with_world(
            s,
            params,
            (spheres, sphere_count),
            (capsules, capsule_count),
            sdfs,
            std::ptr::null(),
            |strands, params, colliders, _| Ok(strands.solve_sag_free(params, colliders)?),
        )
    }
}

/// Every check of a call that takes the world (the handle, the
/// parameters, the spheres, the capsules, the field set and the executor,
/// in that order), then `f` on the strands with the colliders gathered
/// into the handle's own arrays (which allocate only when they grow).
///
/// # Safety
/// As `coif_step_colliders_with`.
unsafe fn with_world(
    s: *mut CoifStrands,
    params: *const CoifSimParams,
    (spheres, sphere_count): (*const CoifSphere, usize),
    (capsules, capsule_count): (*const CoifCapsule, usize),
    sdfs: *const CoifSdfSet,
    executor: *const CoifExecutor,
    f: impl FnOnce(
        &mut coif_kernels::Strands,
        &coif_kernels::SimParams,
        &Colliders<'_>,
        &dyn coif_base::tasks::Executor,
    ) -> Result<(), CoifStatus>,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle not aliased during the call.
        let h = unsafe { handle_mut(s) }?;
        // SAFETY: the caller's contract on the pointers.
        let (params, exec, rig) = unsafe { step_inputs(params, spheres, sphere_count, executor) }?;
        // SAFETY: the caller's contract.
        let caps = unsafe { check_capsules(capsules, capsule_count) }?;
        if !sdfs.is_aligned() {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        // SAFETY: NULL or a live set not written during the call.
        let fields: &[Sdf] = unsafe { sdfs.as_ref() }.map_or(&[], |set| &set.fields);
        fill_rig(rig, &mut h.spheres);
        fill_capsules(caps, &mut h.capsules);
        let colliders = Colliders {
            spheres: &h.spheres,
            capsules: &h.capsules,
            sdfs: fields,
        };
        f(&mut h.strands, &params, &colliders, exec.get())
    })
}

/// Checks `count` capsules at `capsules` (finite, radius >= 0) and returns
/// them, without converting anything.
///
/// # Safety
/// `capsules` is NULL or points to `count` readable capsules not written
/// during `'a`.
pub(crate) unsafe fn check_capsules<'a>(
    capsules: *const CoifCapsule,
    count: usize,
) -> Result<&'a [CoifCapsule], CoifStatus> {
    // SAFETY: the caller's contract.
    let caps = unsafe { input(capsules, count) }?;
    for c in caps {
        let finite = c.a.iter().chain(&c.b).all(|v| v.is_finite()) && c.radius.is_finite();
        if !finite {
            return Err(CoifStatus::COIF_ERROR_NON_FINITE);
        }
        if c.radius < 0.0 {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
    }
    Ok(caps)
}

/// Converts capsules [`check_capsules`] passed into `scratch`, which
/// allocates only when it grows. (`Capsule` is not `#[repr(C)]`, so the
/// caller's array cannot be borrowed as it is.)
pub(crate) fn fill_capsules(caps: &[CoifCapsule], scratch: &mut Vec<Capsule>) {
    scratch.clear();
    scratch.extend(caps.iter().map(|c| Capsule {
        a: Vec3::from_array(c.a),
        b: Vec3::from_array(c.b),
        radius: c.radius,
    }));
}
