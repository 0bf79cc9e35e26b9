//! `coif_last_error_message`: after a failed call, what was wrong, naming
//! the bad parameter, index or value; empty after a call that succeeded;
//! the status's message for the interface's own checks.

use coif_capi::world::*;
use coif_capi::*;
use std::ffi::CStr;
use std::ptr;

fn last() -> String {
    // SAFETY: never NULL, NUL-terminated, valid until the next call.
    unsafe { CStr::from_ptr(coif_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

#[test]
fn failed_calls_say_what_was_wrong() {
    // A parameter out of range: its name, value and range.
    let bad = CoifSimParams {
        volume_stiffness: 1.5,
        ..coif_sim_params_default()
    };
    // SAFETY: a pointer to a local.
    let status = unsafe { coif_sim_params_validate(&bad) };
    assert_eq!(status, CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    let m = last();
    assert!(m.contains("volume_stiffness") && m.contains("1.5"), "{m}");

    // A triangle naming a vertex that does not exist: which, and how many there are.
    let xyz = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let tris = [0u32, 1, 7];
    let mut sdf = ptr::null_mut();
    // SAFETY: pointers to locals of the stated lengths.
    let status = unsafe { coif_sdf_new(xyz.as_ptr(), 3, tris.as_ptr(), 1, 0.01, &mut sdf) };
    assert_ne!(status, CoifStatus::COIF_OK);
    let m = last();
    assert!(m.contains('7') && m.contains('3'), "{m}");

    // NULL: the status's own message.
    // SAFETY: NULL is refused.
    let status = unsafe { coif_sim_params_validate(ptr::null()) };
    assert_eq!(status, CoifStatus::COIF_ERROR_NULL);
    assert_eq!(last(), "a required pointer is NULL");

    // Success clears it.
    let good = coif_sim_params_default();
    // SAFETY: a pointer to a local.
    assert_eq!(
        unsafe { coif_sim_params_validate(&good) },
        CoifStatus::COIF_OK
    );
    assert_eq!(last(), "");
}

#[test]
fn the_lane_width_is_the_builds() {
    assert_eq!(coif_lanes(), coif_base::LANES);
    assert!(coif_lanes() == 8 || coif_lanes() == 16);
}
