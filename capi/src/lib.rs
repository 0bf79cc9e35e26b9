//! coif-capi: the C interface of the coif hair simulation.
//!
//! A C or C++ program creates a set of equal-length strands from its points
//! ([`coif_strands_new`]), moves their roots every frame
//! ([`coif_strands_set_roots`]), advances them by one fixed step against a
//! rig of spheres ([`coif_step`]) and reads the positions back into a buffer
//! it owns ([`coif_strands_positions`]); [`coif_step_colliders`] steps
//! against capsules and mesh fields too, with wind and drag
//! ([`world`]). An engine that makes the render hairs on the GPU with
//! coif-gpu's shaders packs the guides and render hairs into its buffers
//! and fills the view uniform ([`gpu`]). The header `include/coif.h` is
//! generated from this file by cbindgen (`cbindgen.toml`); a test fails when
//! the committed header differs from what cbindgen generates now.
//!
//! Rules at the boundary (every function follows them):
//! - handles are opaque ([`CoifStrands`]); the caller owns every buffer and
//!   passes its size, which is checked;
//! - bad input (NULL, NaN or infinity, wrong counts, a buffer too small,
//!   parameters out of range) returns an error [`CoifStatus`] and changes
//!   nothing: every check runs before anything is written;
//! - no panic crosses the boundary: each body runs under
//!   [`std::panic::catch_unwind`] and a panic returns
//!   [`CoifStatus::COIF_ERROR_PANIC`];
//! - [`coif_step`], [`coif_strands_set_roots`] and [`coif_strands_positions`]
//!   do not allocate once the rig is as large as it will get (the sphere
//!   scratch lives in the handle and only grows).

#![warn(missing_docs)]
// The C names are the Rust names: `COIF_OK`, not `Ok`.
#![allow(non_camel_case_types)]

pub mod groom;
pub mod lod;
pub mod patch;
pub mod scalp;
pub mod shading;
pub mod tasks;
pub mod world;
// After the modules it builds on, so the header declares it after them.
pub mod dual_scattering;
pub mod gpu;

pub use dual_scattering::*;
pub use gpu::*;
pub use groom::*;
pub use lod::*;
pub use patch::*;
pub use shading::*;
pub use tasks::*;
pub use world::*;

use coif_kernels::{SimParams, Sphere, Strands};
use glam::{Affine3A, Mat3, Vec3};
use std::ffi::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Result of every fallible call: `COIF_OK` (0) or the reason it refused its
/// input. A call that returns an error changed nothing.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoifStatus {
    /// Success.
    COIF_OK = 0,
    /// A required pointer was NULL.
    COIF_ERROR_NULL = 1,
    /// An argument is out of its range (fewer than 2 vertices per strand, no
    /// points, a parameter out of range, a non-rigid transform, a misaligned
    /// pointer, a size that overflows).
    COIF_ERROR_INVALID_ARGUMENT = 2,
    /// A coordinate or parameter is NaN or infinite.
    COIF_ERROR_NON_FINITE = 3,
    /// The output buffer holds fewer points than the set has.
    COIF_ERROR_BUFFER_TOO_SMALL = 4,
    /// A count does not match: roots other than one per strand, or a point
    /// count that is not a whole number of strands.
    COIF_ERROR_COUNT_MISMATCH = 5,
    /// The library panicked (a bug in coif); the handle may be in a partial
    /// state and should be freed.
    COIF_ERROR_PANIC = 6,
    /// Input data is malformed: a groom file that is truncated, whose header
    /// lies about its counts or offsets, or that is neither TressFX 4 nor
    /// cyHair.
    COIF_ERROR_BAD_DATA = 7,
}

/// Parameters of one fixed step (`coif_step`, `coif_step_colliders`); start from
/// `coif_sim_params_default()` and change the fields you need. The meaning
/// and range of every field is that of `coif_kernels::SimParams`. The
/// fields from `static_friction` on were added after `sleep_speed` (a
/// layout change: rebuild against this header).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifSimParams {
    /// Fixed step in seconds (> 0; default 1/60).
    pub dt: f32,
    /// Velocity kept per step in [0, 1] (default 0.97; 1 = no damping).
    pub damping: f32,
    /// Acceleration in m/s^2 (default 0, -9.81, 0).
    pub gravity: [f32; 3],
    /// Projections of the length constraints per substep (0..=256, default 1).
    pub iterations: u32,
    /// Collision points per segment besides its end vertices (0..=64, default 1).
    pub pearls_per_segment: u32,
    /// Collision radius of vertices and pearls in metres (>= 0, default 0.002).
    pub pearl_radius: f32,
    /// Two-sided strain limit per segment (>= 0, default 0.01).
    pub max_stretch: f32,
    /// Local shape constraints (TressFX 4, AMD 2017) in [0, 1]; 0 (default) = off.
    pub local_shape_stiffness: f32,
    /// Longest substep in seconds (> 0, default 1/240).
    pub max_substep: f32,
    /// Blend of the constraint directions in [0, 0.25] (default 0.05).
    pub stiff_mode_damping: f32,
    /// Bending constraints (Yip 2011) in [0, 1]; 0 (default) = off.
    pub bend_stiffness: f32,
    /// Pull toward the rest shape at the root in [0, 1]; 0 (default) = off.
    pub shape_stiffness: f32,
    /// Contact friction, Coulomb's law: the kinetic coefficient (>= 0, no
    /// upper bound; default 0.3). A vertex a collider pushes out by `d`
    /// slides against `friction d` per substep once it slides at all (see
    /// `static_friction`). 0 and 0 = frictionless.
    pub friction: f32,
    /// Sleeping in m/s (>= 0): a block of 8 strands whose vertices all moved
    /// slower than this for half a second of steps, with still roots and no
    /// moving sphere near, is skipped until something moves it (its roots,
    /// a sphere sweeping into its box, a teleport, a reset, other
    /// parameters). 0 = never sleep. Default 0.02 (`SimParams::sleep_speed`).
    pub sleep_speed: f32,
    /// Contact friction, Coulomb's law: the static coefficient (>= 0;
    /// default 0.5). A pushed-out vertex does not slide while its motion
    /// along the surface, relative to the collider, is within
    /// `static_friction d` per substep: hair rests on a slope of angle
    /// theta exactly when `static_friction > tan(theta)`.
    pub static_friction: f32,
    /// Air velocity in m/s, world frame (finite; default 0, 0, 0: still
    /// air). Acts only through `drag`.
    pub wind: [f32; 3],
    /// Linear aerodynamic drag in 1/s (>= 0; default 0 = none): air moving
    /// at `wind` pulls a vertex moving at `v` with `drag (wind - v)`. A
    /// strand in a steady wind hangs along `gravity + drag wind`; swings
    /// decay as `exp(-drag t / 2)`. About 1 to 10 /s for hair in a clump.
    pub drag: f32,
    /// Gusts: RMS speed in m/s of a deterministic turbulent field added to
    /// `wind` (>= 0; default 0 = none). Acts through `drag`; hair in gusts
    /// does not fall asleep.
    pub turbulence: f32,
    /// Gusts: size of their features in metres (> 0; default 0.2).
    pub turbulence_scale: f32,
    /// Gusts: how long a gust lasts in seconds (> 0; default 1).
    pub turbulence_period: f32,
    /// The roots rule (>= 0; default 0.25): a strand whose root lies
    /// `depth` inside a collider's skin may have vertex `v` up to
    /// `max(0, depth - root_exit * arc(v))` inside it (`arc(v)` its rest
    /// arc from the root), so roots on a scalp keep their groom.
    pub root_exit: f32,
    /// Hair-hair volume in [0, 1] (default 0 = off): hair packed denser
    /// than its groomed pose's densest is pushed apart, through a grid of
    /// the hair rebuilt every step.
    pub volume_stiffness: f32,
    /// Hair-hair friction in [0, 1] (default 0 = off): the share of each
    /// vertex's velocity relative to the hair around it removed per step.
    pub hair_friction: f32,
    /// Cell of the hair grid in metres (1e-4 to 1; default 0.015).
    pub hair_grid_cell: f32,
}

/// A collision sphere of the rig, world coordinates (metres).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifSphere {
    /// Centre.
    pub center: [f32; 3],
    /// Radius (>= 0).
    pub radius: f32,
}

/// An opaque set of equal-length strands (created by `coif_strands_new`,
/// freed by `coif_strands_free`).
pub struct CoifStrands {
    pub(crate) strands: Strands,
    /// The rig converted for `coif_kernels::step`; grows only when the rig does.
    pub(crate) spheres: Vec<Sphere>,
    /// The capsules converted for `coif_kernels::step_colliders`; grows
    /// only when their count does.
    pub(crate) capsules: Vec<coif_kernels::Capsule>,
    /// Refinement scratch of `coif_refine`, made at its first call and
    /// remade only for a finer level than any before.
    pub(crate) refined: Option<coif_lod::RefinedGuides>,
}

impl CoifStrands {
    pub(crate) fn new(strands: Strands) -> CoifStrands {
        CoifStrands {
            strands,
            spheres: Vec::new(),
            capsules: Vec::new(),
            refined: None,
        }
    }
}

// The casts of caller buffers (`*const f32`, three per point) to `&[Vec3]`
// rely on glam's `Vec3` being `#[repr(C)] { x, y, z: f32 }`.
const _: () = assert!(std::mem::size_of::<Vec3>() == 12 && std::mem::align_of::<Vec3>() == 4);

impl From<&CoifSimParams> for SimParams {
    #[allow(clippy::needless_update)]
    fn from(p: &CoifSimParams) -> SimParams {
        SimParams {
            dt: p.dt,
            damping: p.damping,
            gravity: Vec3::from_array(p.gravity),
            iterations: p.iterations,
            pearls_per_segment: p.pearls_per_segment,
            pearl_radius: p.pearl_radius,
            max_stretch: p.max_stretch,
            bend_stiffness: p.bend_stiffness,
            shape_stiffness: p.shape_stiffness,
            friction: p.friction,
            local_shape_stiffness: p.local_shape_stiffness,
            max_substep: p.max_substep,
            stiff_mode_damping: p.stiff_mode_damping,
            sleep_speed: p.sleep_speed,
            static_friction: p.static_friction,
            wind: Vec3::from_array(p.wind),
            drag: p.drag,
            turbulence: p.turbulence,
            turbulence_scale: p.turbulence_scale,
            turbulence_period: p.turbulence_period,
            root_exit: p.root_exit,
            volume_stiffness: p.volume_stiffness,
            hair_friction: p.hair_friction,
            hair_grid_cell: p.hair_grid_cell,
            // Fields SimParams gains before CoifSimParams carries them keep
            // their Rust defaults (the C layout changes only deliberately).
            ..SimParams::default()
        }
    }
}

impl From<&SimParams> for CoifSimParams {
    fn from(p: &SimParams) -> CoifSimParams {
        CoifSimParams {
            dt: p.dt,
            damping: p.damping,
            gravity: p.gravity.to_array(),
            iterations: p.iterations,
            pearls_per_segment: p.pearls_per_segment,
            pearl_radius: p.pearl_radius,
            max_stretch: p.max_stretch,
            local_shape_stiffness: p.local_shape_stiffness,
            max_substep: p.max_substep,
            stiff_mode_damping: p.stiff_mode_damping,
            bend_stiffness: p.bend_stiffness,
            shape_stiffness: p.shape_stiffness,
            friction: p.friction,
            sleep_speed: p.sleep_speed,
            static_friction: p.static_friction,
            wind: p.wind.to_array(),
            drag: p.drag,
            turbulence: p.turbulence,
            turbulence_scale: p.turbulence_scale,
            turbulence_period: p.turbulence_period,
            root_exit: p.root_exit,
            volume_stiffness: p.volume_stiffness,
            hair_friction: p.hair_friction,
            hair_grid_cell: p.hair_grid_cell,
        }
    }
}

impl From<coif_kernels::Error> for CoifStatus {
    fn from(e: coif_kernels::Error) -> CoifStatus {
        set_last_error(&e);
        use coif_kernels::Error as E;
        match e {
            E::NonFinite { .. } => CoifStatus::COIF_ERROR_NON_FINITE,
            E::CountMismatch { .. } | E::NotWholeStrands { .. } => {
                CoifStatus::COIF_ERROR_COUNT_MISMATCH
            }
            E::BufferTooSmall { .. } => CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
            E::InvalidParameter { value, .. } if !value.is_finite() => {
                CoifStatus::COIF_ERROR_NON_FINITE
            }
            _ => CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
        }
    }
}

thread_local! {
    /// What the last failed coif call on this thread said of its error
    /// (`coif_last_error_message`), NUL-terminated; empty (no bytes at
    /// all) when there is none, so clearing it allocates nothing.
    static LAST_ERROR: std::cell::RefCell<Vec<u8>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Records `message` as this thread's last error detail (a NUL inside it
/// ends it early). Allocates only on a failure, and only to grow.
pub(crate) fn set_last_error(message: &dyn std::fmt::Display) {
    use std::io::Write as _;
    // A thread being torn down has no slot: the detail is dropped.
    let _ = LAST_ERROR.try_with(|e| {
        let mut e = e.borrow_mut();
        e.clear();
        let _ = write!(e, "{message}");
        let end = e.iter().position(|&b| b == 0).unwrap_or(e.len());
        e.truncate(end);
        e.push(0);
    });
}

/// Clears this thread's last error detail (no allocation).
fn clear_last_error() {
    let _ = LAST_ERROR.try_with(|e| e.borrow_mut().clear());
}

fn last_error_is_empty() -> bool {
    LAST_ERROR
        .try_with(|e| e.borrow().len() <= 1)
        .unwrap_or(true)
}

/// Runs `body`, turning a panic into `COIF_ERROR_PANIC`. The thread's
/// last error detail is cleared first; a failure that left none (a check of
/// the interface's own: NULL, a short buffer) gets its status's message.
pub(crate) fn guard(body: impl FnOnce() -> Result<(), CoifStatus>) -> CoifStatus {
    clear_last_error();
    let status = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => CoifStatus::COIF_OK,
        Ok(Err(status)) => status,
        Err(_) => CoifStatus::COIF_ERROR_PANIC,
    };
    if status != CoifStatus::COIF_OK && last_error_is_empty() {
        let message = coif_status_message(status);
        // SAFETY: `coif_status_message` returns a static NUL-terminated string.
        let text = unsafe { std::ffi::CStr::from_ptr(message) };
        set_last_error(&text.to_string_lossy());
    }
    status
}

/// What the last coif call on this thread that failed said of its error,
/// naming the bad value where the library knows it ("mesh vertex 12 is not
/// finite", "triangle 3 names vertex 900, but the mesh has 800 vertices",
/// "invalid parameter volume_stiffness = 1.5 (expected 0 <= volume_stiffness
/// <= 1)"); the empty string after a call that succeeded. Owned by coif and
/// valid until the next coif call on this thread; never NULL.
#[no_mangle]
pub extern "C" fn coif_last_error_message() -> *const c_char {
    LAST_ERROR
        .try_with(|e| {
            let e = e.borrow();
            if e.is_empty() {
                c"".as_ptr()
            } else {
                e.as_ptr().cast::<c_char>()
            }
        })
        .unwrap_or(c"".as_ptr())
}

/// Runs `body`, returning `fallback` on a panic (for calls without a status).
pub(crate) fn guard_or<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or(fallback)
}

/// Checks that `ptr` can back a slice of `count` values of `T`: not NULL,
/// aligned for `T`, and not so long that its size in bytes overflows `isize`.
pub(crate) fn check_slice<T>(ptr: *const T, count: usize) -> Result<(), CoifStatus> {
    if ptr.is_null() {
        return Err(CoifStatus::COIF_ERROR_NULL);
    }
    if !ptr.is_aligned() {
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    match count.checked_mul(std::mem::size_of::<T>()) {
        Some(bytes) if bytes <= isize::MAX as usize => Ok(()),
        _ => Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT),
    }
}

/// Boxes what `make` returns into `*out`: `*out` is NULL first and stays
/// NULL when `make` fails.
///
/// # Safety
/// `out` is NULL or points to a writable `*mut T`.
pub(crate) unsafe fn new_handle<T>(
    out: *mut *mut T,
    make: impl FnOnce() -> Result<T, CoifStatus>,
) -> Result<(), CoifStatus> {
    if out.is_null() {
        return Err(CoifStatus::COIF_ERROR_NULL);
    }
    if !out.is_aligned() {
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    // SAFETY: `out` is not NULL, aligned (checked) and writable (the caller's contract).
    unsafe { out.write(std::ptr::null_mut()) };
    let value = make()?;
    // SAFETY: as above.
    unsafe { out.write(Box::into_raw(Box::new(value))) };
    Ok(())
}

/// Drops a handle made by [`new_handle`]; NULL is fine.
///
/// # Safety
/// `p` is NULL or came from [`new_handle`] and is freed once.
pub(crate) unsafe fn free_handle<T>(p: *mut T) {
    guard_or((), || {
        if !p.is_null() {
            // SAFETY: `p` came from `Box::into_raw` and is freed once.
            drop(unsafe { Box::from_raw(p) });
        }
    })
}

/// The handle or caller's struct behind `p`, or `COIF_ERROR_NULL` (NULL)
/// or `COIF_ERROR_INVALID_ARGUMENT` (misaligned: a struct the caller
/// placed at an odd address is refused, not read).
///
/// # Safety
/// `p` is NULL, misaligned, or a live handle (a readable struct) not
/// written during `'a`.
pub(crate) unsafe fn handle<'a, T>(p: *const T) -> Result<&'a T, CoifStatus> {
    check_slice(p, 1)?;
    // SAFETY: non-NULL and aligned (checked); live per the caller's contract.
    Ok(unsafe { &*p })
}

/// [`handle`] for writing.
///
/// # Safety
/// `p` is NULL, misaligned, or a live handle (a writable struct) not
/// aliased during `'a`.
pub(crate) unsafe fn handle_mut<'a, T>(p: *mut T) -> Result<&'a mut T, CoifStatus> {
    check_slice(p.cast_const(), 1)?;
    // SAFETY: non-NULL and aligned (checked); live and unaliased per the
    // caller's contract.
    Ok(unsafe { &mut *p })
}

/// `count` readable values at `ptr` (NULL is fine when `count` is 0).
///
/// # Safety
/// `ptr` is NULL or points to `count` readable values not written during `'a`.
pub(crate) unsafe fn input<'a, T>(ptr: *const T, count: usize) -> Result<&'a [T], CoifStatus> {
    if count == 0 {
        return Ok(&[]);
    }
    check_slice(ptr, count)?;
    // SAFETY: non-NULL, aligned, within isize::MAX bytes (checked); readable
    // per the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(ptr, count) })
}

/// The first `needed` of `capacity` writable values at `ptr`:
/// `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT` (misaligned, overflowing)
/// or `COIF_ERROR_BUFFER_TOO_SMALL` when `capacity < needed`.
///
/// # Safety
/// `ptr` is NULL or points to `capacity` writable values not aliased during `'a`.
pub(crate) unsafe fn output<'a, T>(
    ptr: *mut T,
    needed: usize,
    capacity: usize,
) -> Result<&'a mut [T], CoifStatus> {
    check_slice(ptr.cast_const(), needed)?;
    if capacity < needed {
        return Err(CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL);
    }
    // SAFETY: non-NULL, aligned, `needed <= capacity` values within
    // isize::MAX bytes (checked); writable and unaliased per the caller.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, needed) })
}

/// `[f32; 3]` as a finite `Vec3`, or `COIF_ERROR_NULL` / `COIF_ERROR_NON_FINITE`.
///
/// # Safety
/// `v` is NULL or points to 3 readable floats.
pub(crate) unsafe fn vec3_arg(v: *const f32) -> Result<Vec3, CoifStatus> {
    check_points(v, 1)?;
    // SAFETY: checked; 3 readable floats per the caller's contract.
    let p = unsafe { points(v, 1) }[0];
    if !p.is_finite() {
        return Err(CoifStatus::COIF_ERROR_NON_FINITE);
    }
    Ok(p)
}

/// [`check_slice`] for `count` points of 3 floats at `xyz`.
pub(crate) fn check_points(xyz: *const f32, count: usize) -> Result<(), CoifStatus> {
    check_slice(xyz.cast::<Vec3>(), count)
}

/// The points at `xyz` as a slice of `Vec3`.
///
/// # Safety
/// `check_points(xyz, count)` passed and `xyz` points to `3 * count` readable
/// floats that nothing writes while the slice lives.
pub(crate) unsafe fn points<'a>(xyz: *const f32, count: usize) -> &'a [Vec3] {
    // SAFETY: non-NULL, 4-aligned and at most isize::MAX bytes (checked by
    // `check_points`); `Vec3` is three packed f32 (asserted above); the
    // caller guarantees the floats are readable and not mutated meanwhile.
    unsafe { std::slice::from_raw_parts(xyz.cast::<Vec3>(), count) }
}

/// The default parameters (those of `coif_kernels::SimParams::default()`):
/// one step of 1/60 s in 4 substeps, damping 0.97, gravity -9.81 along y.
#[no_mangle]
pub extern "C" fn coif_sim_params_default() -> CoifSimParams {
    CoifSimParams::from(&SimParams::default())
}

/// Checks every field of `*params` against its range: `COIF_OK`,
/// `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE` (a NaN or infinite field) or
/// `COIF_ERROR_INVALID_ARGUMENT` (a field out of range).
///
/// # Safety
/// `params` is NULL or points to a readable `CoifSimParams`.
#[no_mangle]
pub unsafe extern "C" fn coif_sim_params_validate(params: *const CoifSimParams) -> CoifStatus {
    guard(|| {
        // SAFETY: the caller passes NULL or a valid pointer; NULL and a
        // misaligned pointer are refused.
        let p = unsafe { handle(params) }?;
        validate_params(p).map(|_| ())
    })
}

pub(crate) fn validate_params(p: &CoifSimParams) -> Result<SimParams, CoifStatus> {
    let params = SimParams::from(p);
    params.validate()?;
    Ok(params)
}

/// Creates a set of strands from `point_count` points (`xyz`: 3 floats per
/// point, world coordinates in metres), `verts_per_strand` per strand, strand
/// after strand, root first. Roots are pinned; rest lengths and the rest
/// shape come from these points. On success `*out` is the new handle (free
/// it with `coif_strands_free`); on error `*out` is NULL (when `out` is not).
///
/// Errors: `COIF_ERROR_NULL` (`xyz` or `out`), `COIF_ERROR_INVALID_ARGUMENT`
/// (`verts_per_strand < 2`, no points), `COIF_ERROR_COUNT_MISMATCH`
/// (`point_count` not a multiple of `verts_per_strand`),
/// `COIF_ERROR_NON_FINITE` (a NaN or infinite coordinate).
///
/// # Safety
/// `xyz` is NULL or points to `3 * point_count` readable floats; `out` is
/// NULL or points to a writable `CoifStrands *`.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_new(
    xyz: *const f32,
    point_count: usize,
    verts_per_strand: usize,
    out: *mut *mut CoifStrands,
) -> CoifStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable (the caller's contract).
        unsafe {
            new_handle(out, || {
                check_points(xyz, point_count)?;
                // SAFETY: checked above; the caller guarantees 3 * point_count floats.
                let pts = points(xyz, point_count);
                Ok(CoifStrands::new(Strands::from_polylines(
                    pts,
                    verts_per_strand,
                )?))
            })
        }
    })
}

/// Frees a set made by `coif_strands_new`. NULL is fine.
///
/// # Safety
/// `s` is NULL or a handle from `coif_strands_new` not freed before; it must
/// not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_free(s: *mut CoifStrands) {
    // SAFETY: NULL or a handle from coif_strands_new freed once (the caller's contract).
    unsafe { free_handle(s) }
}

/// Number of strands in the set (0 for NULL).
///
/// # Safety
/// `s` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_strand_count(s: *const CoifStrands) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle (the caller's contract).
        unsafe { s.as_ref() }.map_or(0, |h| h.strands.strand_count())
    })
}

/// Vertices per strand, root included (0 for NULL).
///
/// # Safety
/// `s` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_verts_per_strand(s: *const CoifStrands) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle (the caller's contract).
        unsafe { s.as_ref() }.map_or(0, |h| h.strands.verts_per_strand())
    })
}

/// Number of points `coif_strands_positions` writes: strands times vertices
/// per strand (0 for NULL). Size the buffer with it (3 floats per point).
///
/// # Safety
/// `s` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_point_count(s: *const CoifStrands) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle (the caller's contract).
        unsafe { s.as_ref() }.map_or(0, |h| {
            h.strands.strand_count() * h.strands.verts_per_strand()
        })
    })
}

/// Moves the pinned roots: `root_count` points (`xyz`, 3 floats each, world
/// space), one per strand. The next step carries each root there over its
/// substeps. Does not allocate.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_COUNT_MISMATCH` (not one root per
/// strand), `COIF_ERROR_NON_FINITE`.
///
/// # Safety
/// `s` is NULL or a live handle; `xyz` is NULL or points to `3 * root_count`
/// readable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_set_roots(
    s: *mut CoifStrands,
    xyz: *const f32,
    root_count: usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle not aliased during the call.
        let h = unsafe { s.as_mut() }.ok_or(CoifStatus::COIF_ERROR_NULL)?;
        check_points(xyz, root_count)?;
        // SAFETY: checked above; the caller guarantees 3 * root_count floats.
        let roots = unsafe { points(xyz, root_count) };
        // `set_roots` checks the count and every coordinate before writing.
        h.strands.set_roots(roots)?;
        Ok(())
    })
}

/// Advances every strand by one fixed step of `params->dt` against
/// `sphere_count` spheres (`spheres` may be NULL when `sphere_count` is 0),
/// on the calling thread (`coif_step_with` with a NULL executor).
/// Validates the parameters and spheres first; does not allocate unless the
/// rig has more spheres than at any earlier call. Blocks of 8 strands that
/// sleep (`CoifSimParams::sleep_speed`) are skipped.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE` (a NaN or infinite
/// parameter or sphere), `COIF_ERROR_INVALID_ARGUMENT` (a parameter out of
/// range, a negative radius).
///
/// # Safety
/// `s` is NULL or a live handle; `params` is NULL or readable; `spheres` is
/// NULL or points to `sphere_count` readable spheres.
#[no_mangle]
pub unsafe extern "C" fn coif_step(
    s: *mut CoifStrands,
    params: *const CoifSimParams,
    spheres: *const CoifSphere,
    sphere_count: usize,
) -> CoifStatus {
    // SAFETY: the caller's contract; a NULL executor is the calling thread.
    unsafe { coif_step_with(s, params, spheres, sphere_count, std::ptr::null()) }
}

/// `coif_step` with the strands' blocks handed out as tasks to `executor`
/// (`coif_kernels::step_with`): at most 64 tasks of whole blocks of 8
/// strands, each writing only its own blocks. The result is the same bytes
/// as `coif_step` with any executor, thread count and task order. NULL
/// `executor` runs the tasks on the calling thread. Nothing is checked
/// inside the tasks: every check runs first, and an error leaves the
/// strands unchanged and `run` uncalled. Allocates nothing more than
/// `coif_step` (nothing at all from coif's side of `run`).
///
/// Errors: as `coif_step`, and `COIF_ERROR_NULL` for an executor whose
/// `run` is NULL, `COIF_ERROR_INVALID_ARGUMENT` for a misaligned one.
///
/// # Safety
/// As `coif_step`; `executor` is NULL or points to a readable
/// `CoifExecutor` that keeps its contract during the call.
#[no_mangle]
pub unsafe extern "C" fn coif_step_with(
    s: *mut CoifStrands,
    params: *const CoifSimParams,
    spheres: *const CoifSphere,
    sphere_count: usize,
    executor: *const CoifExecutor,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle not aliased during the call.
        let h = unsafe { s.as_mut() }.ok_or(CoifStatus::COIF_ERROR_NULL)?;
        // SAFETY: the caller's contract on the pointers.
        let (params, exec, rig) = unsafe { step_inputs(params, spheres, sphere_count, executor) }?;
        fill_rig(rig, &mut h.spheres);
        coif_kernels::step_with(&mut h.strands, &params, &h.spheres, exec.get());
        Ok(())
    })
}

/// Strands the last step advanced (awake); all of them before the first
/// step, 0 for NULL. Strands skipped because their block sleeps are not
/// counted (`Strands::awake_strands`).
///
/// # Safety
/// `s` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_awake_strands(s: *const CoifStrands) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle (the caller's contract).
        unsafe { s.as_ref() }.map_or(0, |h| h.strands.awake_strands())
    })
}

/// Strands in blocks that sleep now, which the next step skips unless
/// something wakes them (`Strands::sleeping_strands`); 0 for NULL.
///
/// # Safety
/// `s` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_sleeping_strands(s: *const CoifStrands) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle (the caller's contract).
        unsafe { s.as_ref() }.map_or(0, |h| h.strands.sleeping_strands())
    })
}

/// The checked inputs of a step, in this order: the parameters
/// (`validate_params`), the executor and the rig (`check_rig`).
///
/// # Safety
/// `params` is NULL or readable; `spheres` as `check_rig` says; `executor`
/// as `tasks::executor` says.
pub(crate) unsafe fn step_inputs<'a>(
    params: *const CoifSimParams,
    spheres: *const CoifSphere,
    sphere_count: usize,
    executor: *const CoifExecutor,
) -> Result<(SimParams, tasks::Exec, &'a [CoifSphere]), CoifStatus> {
    // SAFETY: the caller's contract (NULL and misaligned refused).
    let p = unsafe { handle(params) }?;
    let params = validate_params(p)?;
    // SAFETY: the caller's contract.
    let exec = unsafe { tasks::executor(executor) }?;
    // SAFETY: the caller's contract.
    let rig = unsafe { check_rig(spheres, sphere_count) }?;
    Ok((params, exec, rig))
}

/// Checks `count` spheres at `spheres` (finite, radius >= 0) and returns
/// them, without converting anything.
///
/// # Safety
/// `spheres` is NULL or points to `count` readable spheres not written
/// during `'a`.
pub(crate) unsafe fn check_rig<'a>(
    spheres: *const CoifSphere,
    count: usize,
) -> Result<&'a [CoifSphere], CoifStatus> {
    // SAFETY: the caller's contract.
    let rig = unsafe { input(spheres, count) }?;
    for sphere in rig {
        if !(sphere.center.iter().all(|c| c.is_finite()) && sphere.radius.is_finite()) {
            return Err(CoifStatus::COIF_ERROR_NON_FINITE);
        }
        if sphere.radius < 0.0 {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
    }
    Ok(rig)
}

/// Converts a rig [`check_rig`] passed into `scratch`, which allocates only
/// when it grows.
pub(crate) fn fill_rig(rig: &[CoifSphere], scratch: &mut Vec<Sphere>) {
    scratch.clear();
    scratch.extend(rig.iter().map(|c| Sphere {
        center: Vec3::from_array(c.center),
        radius: c.radius,
    }));
}

/// Writes every point (strand after strand, root first; 3 floats each,
/// world space) into `out_xyz` when it holds `capacity_points` points and
/// that is at least `coif_strands_point_count(s)`. Does not allocate.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_BUFFER_TOO_SMALL` (nothing written).
///
/// # Safety
/// `s` is NULL or a live handle; `out_xyz` is NULL or points to
/// `3 * capacity_points` writable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_positions(
    s: *const CoifStrands,
    out_xyz: *mut f32,
    capacity_points: usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle (the caller's contract).
        let h = unsafe { s.as_ref() }.ok_or(CoifStatus::COIF_ERROR_NULL)?;
        let n = h.strands.strand_count() * h.strands.verts_per_strand();
        check_points(out_xyz.cast_const(), n)?;
        if capacity_points < n {
            return Err(CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL);
        }
        // SAFETY: non-NULL and 4-aligned (checked), `n <= capacity_points`
        // points of 12 bytes within isize::MAX (checked), writable and not
        // aliased per the caller's contract; `Vec3` is three packed f32.
        let out = unsafe { std::slice::from_raw_parts_mut(out_xyz.cast::<Vec3>(), n) };
        h.strands.write_positions(out)?;
        Ok(())
    })
}

/// Moves the whole set rigidly by a 3x4 row-major affine transform
/// (`m[0..4]` is the first row: x' = m0 x + m1 y + m2 z + m3), positions and
/// previous positions alike, so no velocity is injected (a teleport, a cut).
/// The 3x3 part must be a rotation (orthonormal within 1e-3, determinant +1).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE`,
/// `COIF_ERROR_INVALID_ARGUMENT` (not a rotation).
///
/// # Safety
/// `s` is NULL or a live handle; `m` is NULL or points to 12 readable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_teleport(s: *mut CoifStrands, m: *const f32) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle not aliased during the call.
        let h = unsafe { s.as_mut() }.ok_or(CoifStatus::COIF_ERROR_NULL)?;
        // SAFETY: NULL or 12 readable floats (the caller's contract).
        let xform = unsafe { rigid_arg(m) }?;
        h.strands.teleport(xform)?;
        Ok(())
    })
}

/// A 3x4 row-major rigid transform (`m[0..4]` is the first row: x' = m0 x +
/// m1 y + m2 z + m3) as an `Affine3A`: `COIF_ERROR_NULL`,
/// `COIF_ERROR_INVALID_ARGUMENT` (misaligned; the 3x3 part not a rotation:
/// orthonormal within 1e-3, determinant +1) or `COIF_ERROR_NON_FINITE`.
///
/// # Safety
/// `m` is NULL or points to 12 readable floats.
pub(crate) unsafe fn rigid_arg(m: *const f32) -> Result<Affine3A, CoifStatus> {
    if m.is_null() {
        return Err(CoifStatus::COIF_ERROR_NULL);
    }
    if !m.is_aligned() {
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    // SAFETY: non-NULL and aligned (checked); 12 readable floats per the
    // caller's contract.
    let m = unsafe { &*m.cast::<[f32; 12]>() };
    if let Some(i) = m.iter().position(|v| !v.is_finite()) {
        set_last_error(&format_args!(
            "transform entry {i} is {} (not finite)",
            m[i]
        ));
        return Err(CoifStatus::COIF_ERROR_NON_FINITE);
    }
    let rot = Mat3::from_cols_array(&[m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]]);
    let gram = rot.transpose() * rot;
    let orthonormal = gram.abs_diff_eq(Mat3::IDENTITY, 1e-3);
    if !orthonormal || rot.determinant() < 0.0 {
        set_last_error(&format_args!(
            "the transform's 3 x 3 part is not a rotation (determinant {}; a scale, shear or mirror)",
            rot.determinant()
        ));
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    Ok(Affine3A::from_mat3_translation(
        rot,
        Vec3::new(m[3], m[7], m[11]),
    ))
}

/// Puts every strand in its rest shape at its current root, at rest.
///
/// Errors: `COIF_ERROR_NULL`.
///
/// # Safety
/// `s` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_reset_to_rest(s: *mut CoifStrands) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle not aliased during the call.
        let h = unsafe { s.as_mut() }.ok_or(CoifStatus::COIF_ERROR_NULL)?;
        h.strands.reset_to_rest();
        Ok(())
    })
}

/// Strands per SIMD block in this build of coif: 8 (an AVX2 build) or 16
/// (a build for AVX-512, or with the `lanes16` feature). Results are the
/// same bytes at both widths and no call's arguments depend on it: it says
/// which build a program loaded.
#[no_mangle]
pub extern "C" fn coif_lanes() -> usize {
    coif_base::LANES
}

/// A static, NUL-terminated English description of `status` (never NULL).
/// Pass a value of `CoifStatus` (one a coif call returned).
#[no_mangle]
pub extern "C" fn coif_status_message(status: CoifStatus) -> *const c_char {
    let msg = match status {
        CoifStatus::COIF_OK => c"success",
        CoifStatus::COIF_ERROR_NULL => c"a required pointer is NULL",
        CoifStatus::COIF_ERROR_INVALID_ARGUMENT => c"an argument is out of its range",
        CoifStatus::COIF_ERROR_NON_FINITE => c"a coordinate or parameter is NaN or infinite",
        CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL => c"the output buffer is too small",
        CoifStatus::COIF_ERROR_COUNT_MISMATCH => c"a count does not match the strands",
        CoifStatus::COIF_ERROR_PANIC => c"internal error (panic caught in coif)",
        CoifStatus::COIF_ERROR_BAD_DATA => {
            c"malformed data (truncated, lying counts or unknown format)"
        }
    };
    msg.as_ptr()
}

/// `coif_status_message` for any integer: the message of the status with
/// that value, or "unknown status" for a value no `CoifStatus` has (a C
/// `enum` may hold any `int`, which `coif_status_message` must not be given).
#[no_mangle]
pub extern "C" fn coif_status_message_code(code: i32) -> *const c_char {
    match status_from_code(code) {
        Some(status) => coif_status_message(status),
        None => c"unknown status".as_ptr(),
    }
}

/// The status whose value is `code`, if there is one.
fn status_from_code(code: i32) -> Option<CoifStatus> {
    use CoifStatus as S;
    [
        S::COIF_OK,
        S::COIF_ERROR_NULL,
        S::COIF_ERROR_INVALID_ARGUMENT,
        S::COIF_ERROR_NON_FINITE,
        S::COIF_ERROR_BUFFER_TOO_SMALL,
        S::COIF_ERROR_COUNT_MISMATCH,
        S::COIF_ERROR_PANIC,
        S::COIF_ERROR_BAD_DATA,
    ]
    .into_iter()
    .find(|s| *s as i32 == code)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_a_status() {
        let status = guard(|| panic!("a bug inside coif"));
        assert_eq!(status, CoifStatus::COIF_ERROR_PANIC);
        assert_eq!(guard_or(7usize, || panic!("a bug")), 7);
    }
}
