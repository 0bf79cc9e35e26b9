//! Structs the caller passes by pointer (`CoifSimParams`, `CoifSphere`,
//! counts) are refused when NULL or misaligned, never read or written
//! there, and a refused call writes nothing: found by a review of every
//! exported function.

use coif_capi::scalp::{coif_fit_head_sphere, coif_scalp_triangles};
use coif_capi::*;
use glam::Vec3;
use std::ptr;

/// 16 strands of 4 vertices with their roots on a 10 cm ball's upper half.
fn strands_on_a_ball() -> *mut CoifStrands {
    let mut xyz = Vec::new();
    for i in 0..16 {
        let a = i as f32 * 2.399_963; // the golden angle
        let up = 0.2 + 0.75 * (i as f32 + 0.5) / 16.0;
        let side = (1.0 - up * up).sqrt();
        let root = Vec3::new(side * a.cos(), up, side * a.sin()) * 0.1;
        for v in 0..4 {
            xyz.extend_from_slice(&(root * (1.0 + 0.1 * v as f32)).to_array());
        }
    }
    let mut s: *mut CoifStrands = ptr::null_mut();
    // SAFETY: 64 points of 3 floats; `s` is writable.
    let status = unsafe { coif_strands_new(xyz.as_ptr(), 64, 4, &mut s) };
    assert_eq!(status, CoifStatus::COIF_OK);
    s
}

/// A pointer one byte past an aligned one inside `bytes`: misaligned for
/// any type of alignment 2 or more.
fn misaligned(bytes: &mut [u8]) -> *mut u8 {
    let at = bytes.as_ptr().align_offset(8);
    bytes[at + 1..].as_mut_ptr()
}

#[test]
fn iterations_have_a_bound() {
    let mut p = coif_sim_params_default();
    p.iterations = coif_kernels::MAX_ITERATIONS;
    // SAFETY: a readable struct.
    assert_eq!(unsafe { coif_sim_params_validate(&p) }, CoifStatus::COIF_OK);
    p.iterations = u32::MAX;
    // SAFETY: a readable struct.
    assert_eq!(
        unsafe { coif_sim_params_validate(&p) },
        CoifStatus::COIF_ERROR_INVALID_ARGUMENT
    );
}

#[test]
fn misaligned_parameters_are_refused() {
    let s = strands_on_a_ball();
    let mut bytes = vec![0u8; 2 * std::mem::size_of::<CoifSimParams>() + 16];
    let p = misaligned(&mut bytes).cast::<CoifSimParams>();
    // SAFETY: misaligned pointers are refused before any read; `s` is live.
    unsafe {
        assert_eq!(
            coif_sim_params_validate(p),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            coif_step(s, p, ptr::null(), 0),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        coif_strands_free(s);
    }
}

#[test]
fn the_head_fit_and_the_scalp_write_nothing_when_refused() {
    let s = strands_on_a_ball();
    let mut bytes = vec![0u8; 64];
    // SAFETY: `s` is live; every other pointer is NULL, misaligned (both
    // refused before any write) or a local.
    unsafe {
        let out = misaligned(&mut bytes).cast::<CoifSphere>();
        assert_eq!(
            coif_fit_head_sphere(s, out),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert!(bytes.iter().all(|&b| b == 0), "a refused fit wrote");
        let mut head = CoifSphere {
            center: [0.0; 3],
            radius: 0.0,
        };
        assert_eq!(coif_fit_head_sphere(s, &mut head), CoifStatus::COIF_OK);
        assert!((head.radius - 0.1).abs() < 1e-3, "{}", head.radius);

        // Sized first (capacity 0 with NULL indices is the sizing call).
        let mut count = 0usize;
        assert_eq!(
            coif_scalp_triangles(s, head.center.as_ptr(), ptr::null_mut(), 0, &mut count),
            CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL
        );
        assert!(count > 0);
        // NULL indices with room claimed: refused, the count untouched.
        let mut untouched = 999_999usize;
        assert_eq!(
            coif_scalp_triangles(
                s,
                head.center.as_ptr(),
                ptr::null_mut(),
                1000,
                &mut untouched
            ),
            CoifStatus::COIF_ERROR_NULL
        );
        assert_eq!(untouched, 999_999);
        // Misaligned indices or count: refused, nothing written.
        let mut big = vec![0u8; 16 * 1000 + 16];
        let indices = misaligned(&mut big).cast::<u32>();
        assert_eq!(
            coif_scalp_triangles(s, head.center.as_ptr(), indices, 1000, &mut untouched),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(untouched, 999_999);
        assert!(big.iter().all(|&b| b == 0), "refused indices were written");
        let mut small = vec![0u8; 32];
        let at = misaligned(&mut small).cast::<usize>();
        let mut tri = vec![0u32; 3 * count];
        assert_eq!(
            coif_scalp_triangles(s, head.center.as_ptr(), tri.as_mut_ptr(), count, at),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert!(small.iter().all(|&b| b == 0), "a refused count was written");
        assert!(
            tri.iter().all(|&i| i == 0),
            "refused triangles were written"
        );
        // And the good call.
        let mut got = 0usize;
        assert_eq!(
            coif_scalp_triangles(s, head.center.as_ptr(), tri.as_mut_ptr(), count, &mut got),
            CoifStatus::COIF_OK
        );
        assert_eq!(got, count);
        assert!(tri.iter().all(|&i| i < 16));
        coif_strands_free(s);
    }
}
