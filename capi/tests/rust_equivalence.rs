//! The C interface gives exactly what the Rust API gives: the same strands,
//! roots, rig and parameters stepped through `coif_kernels` directly and
//! through the `extern "C"` functions end bit for bit equal.

use coif_capi::*;
use coif_kernels::{SimParams, Sphere, Strands};
use glam::Vec3;
use std::ptr;

const STRANDS: usize = 21; // not a multiple of 8: a padded last block
const VERTS: usize = 12;

/// Curly strands over a cap: root i on a ring, each vertex turning about y.
fn groom() -> Vec<Vec3> {
    let mut pts = Vec::with_capacity(STRANDS * VERTS);
    for i in 0..STRANDS {
        let a = i as f32 * 0.3;
        let root = Vec3::new(0.09 * a.cos(), 1.7, 0.09 * a.sin());
        for v in 0..VERTS {
            let t = v as f32;
            pts.push(
                root + Vec3::new(
                    0.004 * (t * 0.8).sin(),
                    -0.012 * t,
                    0.004 * (t * 0.8).cos() - 0.004,
                ),
            );
        }
    }
    pts
}

fn roots_at(frame: usize) -> Vec<Vec3> {
    let shift = Vec3::new(
        0.03 * (frame as f32 * 0.1).sin(),
        0.0,
        0.01 * frame as f32 / 60.0,
    );
    groom().iter().step_by(VERTS).map(|r| *r + shift).collect()
}

fn flat(v: &[Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

#[test]
fn c_steps_match_rust_steps_bit_for_bit() {
    let pts = groom();
    let params = SimParams {
        local_shape_stiffness: 0.5,
        bend_stiffness: 0.2,
        ..SimParams::default()
    };
    let rig = [
        Sphere {
            center: Vec3::new(0.0, 1.62, 0.0),
            radius: 0.1,
        },
        Sphere {
            center: Vec3::new(0.05, 1.58, 0.02),
            radius: 0.06,
        },
    ];
    let c_rig: Vec<CoifSphere> = rig
        .iter()
        .map(|s| CoifSphere {
            center: s.center.to_array(),
            radius: s.radius,
        })
        .collect();
    let c_params = CoifSimParams {
        local_shape_stiffness: 0.5,
        bend_stiffness: 0.2,
        ..coif_sim_params_default()
    };

    let mut rust = Strands::from_polylines(&pts, VERTS).unwrap();
    let xyz = flat(&pts);
    let mut c: *mut CoifStrands = ptr::null_mut();
    // SAFETY: `xyz` holds 3 floats per point; `c` is a writable pointer.
    let status = unsafe { coif_strands_new(xyz.as_ptr(), pts.len(), VERTS, &mut c) };
    assert_eq!(status, CoifStatus::COIF_OK);

    let mut out = vec![0.0f32; pts.len() * 3];
    for frame in 0..240 {
        let roots = roots_at(frame);
        rust.set_roots(&roots).unwrap();
        coif_kernels::step(&mut rust, &params, &rig);
        let roots_xyz = flat(&roots);
        // SAFETY: `c` is live; the buffers hold what the counts say.
        unsafe {
            assert_eq!(
                coif_strands_set_roots(c, roots_xyz.as_ptr(), STRANDS),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_step(c, &c_params, c_rig.as_ptr(), c_rig.len()),
                CoifStatus::COIF_OK
            );
        }
        if frame % 60 == 59 {
            // SAFETY: `out` holds pts.len() points.
            let st = unsafe { coif_strands_positions(c, out.as_mut_ptr(), pts.len()) };
            assert_eq!(st, CoifStatus::COIF_OK);
            let want = flat(&rust.positions());
            let same = want
                .iter()
                .zip(&out)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "frame {frame}: C and Rust positions differ");
        }
    }
    // The strands moved (the comparison is not between two idle sets).
    assert!(flat(&rust.positions()) != xyz);
    // SAFETY: `c` came from coif_strands_new and is freed once.
    unsafe { coif_strands_free(c) };
}

#[test]
fn default_params_are_the_rust_defaults() {
    let c = coif_sim_params_default();
    assert_eq!(SimParams::from(&c), SimParams::default());
    // SAFETY: a valid pointer to a local.
    assert_eq!(unsafe { coif_sim_params_validate(&c) }, CoifStatus::COIF_OK);
}

#[test]
fn failed_calls_change_nothing() {
    let pts = groom();
    let xyz = flat(&pts);
    let mut c: *mut CoifStrands = ptr::null_mut();
    let mut before = vec![0.0f32; xyz.len()];
    let mut after = vec![1.0f32; xyz.len()];
    let n = pts.len();
    // SAFETY: every pointer is valid for the count passed (or NULL on purpose).
    unsafe {
        assert_eq!(
            coif_strands_new(xyz.as_ptr(), n, VERTS, &mut c),
            CoifStatus::COIF_OK
        );
        let p = coif_sim_params_default();
        for _ in 0..30 {
            assert_eq!(coif_step(c, &p, ptr::null(), 0), CoifStatus::COIF_OK);
        }
        assert_eq!(
            coif_strands_positions(c, before.as_mut_ptr(), n),
            CoifStatus::COIF_OK
        );

        let mut roots = flat(&roots_at(5));
        roots[4] = f32::INFINITY;
        let bad_params = CoifSimParams {
            max_substep: f32::NAN,
            ..p
        };
        let bad_range = CoifSimParams {
            stiff_mode_damping: 0.5,
            ..p
        };
        let bad_sphere = CoifSphere {
            center: [0.0; 3],
            radius: -1.0,
        };
        let statuses = [
            coif_strands_set_roots(c, roots.as_ptr(), STRANDS),
            coif_strands_set_roots(c, roots.as_ptr(), STRANDS + 1),
            coif_step(c, &bad_params, ptr::null(), 0),
            coif_step(c, &bad_range, ptr::null(), 0),
            coif_step(c, &p, &bad_sphere, 1),
            coif_strands_positions(c, after.as_mut_ptr(), n - 1),
        ];
        assert_eq!(
            statuses,
            [
                CoifStatus::COIF_ERROR_NON_FINITE,
                CoifStatus::COIF_ERROR_COUNT_MISMATCH,
                CoifStatus::COIF_ERROR_NON_FINITE,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
            ]
        );
        assert!(
            after.iter().all(|&x| x == 1.0),
            "a too-small buffer was written"
        );
        assert_eq!(
            coif_strands_positions(c, after.as_mut_ptr(), n),
            CoifStatus::COIF_OK
        );
        assert_eq!(before, after);

        // A misaligned buffer is refused, not read.
        let bytes = vec![0u8; 4 * xyz.len() + 4];
        let misaligned = bytes.as_ptr().add(if bytes.as_ptr().align_offset(4) == 0 {
            1
        } else {
            0
        });
        let mut d: *mut CoifStrands = ptr::null_mut();
        assert_eq!(
            coif_strands_new(misaligned.cast(), n, VERTS, &mut d),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert!(d.is_null());
        // A point count whose size overflows is refused before any read.
        assert_eq!(
            coif_strands_new(xyz.as_ptr(), usize::MAX / 4, VERTS, &mut d),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        coif_strands_free(c);
    }
}

#[test]
fn every_status_has_a_message() {
    use std::ffi::CStr;
    for s in [
        CoifStatus::COIF_OK,
        CoifStatus::COIF_ERROR_NULL,
        CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
        CoifStatus::COIF_ERROR_NON_FINITE,
        CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
        CoifStatus::COIF_ERROR_COUNT_MISMATCH,
        CoifStatus::COIF_ERROR_PANIC,
    ] {
        let p = coif_status_message(s);
        assert!(!p.is_null());
        // SAFETY: the message is a static NUL-terminated string.
        assert!(!unsafe { CStr::from_ptr(p) }.to_bytes().is_empty());
    }
}
