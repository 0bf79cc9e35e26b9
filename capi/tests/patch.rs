//! Cloth patches through C equal `coif_kernels::patch` bit for bit (skin,
//! weights, max distances, steps against a sphere, blended and simulated
//! output), and refused calls change nothing.

use coif_capi::*;
use coif_kernels::patch::quality::flag_scene;
use coif_kernels::{Patch, SimParams, Sphere};
use glam::Vec3;
use std::ptr;

const ROWS: usize = 6;
const COLS: usize = 11; // not a multiple of 8

fn flat(v: &[Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

fn skin_at(frame: usize, grid: &[Vec3]) -> Vec<Vec3> {
    let shift = Vec3::new(0.02 * (frame as f32 * 0.2).sin(), 0.0, 0.001 * frame as f32);
    grid.iter().map(|p| *p + shift).collect()
}

#[test]
fn c_patch_matches_rust_bit_for_bit() {
    let (grid, pinned) = flag_scene(ROWS, COLS);
    let n = ROWS * COLS;
    let weights: Vec<f32> = (0..n)
        .map(|k| (k / COLS) as f32 / (ROWS - 1) as f32)
        .collect();
    let distances: Vec<f32> = (0..n)
        .map(|k| if k % 3 == 0 { 0.05 } else { f32::INFINITY })
        .collect();
    let rig = [Sphere {
        center: Vec3::new(0.1, 0.9, 0.05),
        radius: 0.06,
    }];
    let c_rig = [CoifSphere {
        center: rig[0].center.to_array(),
        radius: rig[0].radius,
    }];
    let params = SimParams {
        bend_stiffness: 0.3,
        ..SimParams::default()
    };
    let c_params = CoifSimParams {
        bend_stiffness: 0.3,
        ..coif_sim_params_default()
    };

    let mut rust = Patch::new(&grid, ROWS, COLS, &pinned).unwrap();
    rust.set_weights(&weights).unwrap();
    rust.set_max_distances(&distances).unwrap();
    rust.set_shear_stiffness(0.2).unwrap();
    let flags: Vec<u8> = pinned.iter().map(|&p| u8::from(p)).collect();
    let mut c: *mut CoifPatch = ptr::null_mut();
    let mut got = vec![0.0f32; 3 * n];
    let mut want = vec![Vec3::ZERO; n];
    // SAFETY: every buffer holds what its count says; `c` is live until freed.
    unsafe {
        let xyz = flat(&grid);
        assert_eq!(
            coif_patch_new(xyz.as_ptr(), ROWS, COLS, flags.as_ptr(), &mut c),
            CoifStatus::COIF_OK
        );
        assert_eq!(coif_patch_particle_count(c), n);
        assert_eq!(
            coif_patch_set_weights(c, weights.as_ptr(), n),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_patch_set_max_distances(c, distances.as_ptr(), n),
            CoifStatus::COIF_OK
        );
        assert_eq!(coif_patch_set_shear_stiffness(c, 0.2), CoifStatus::COIF_OK);
        for frame in 0..90 {
            let skin = skin_at(frame, &grid);
            rust.set_skinned(&skin).unwrap();
            coif_kernels::patch::step(&mut rust, &params, &rig);
            let skin_xyz = flat(&skin);
            assert_eq!(
                coif_patch_set_skinned(c, skin_xyz.as_ptr(), n),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_patch_step(c, &c_params, c_rig.as_ptr(), 1),
                CoifStatus::COIF_OK
            );
        }
        let same_blend = |got: &mut [f32], want: &mut [Vec3], rust: &Patch| {
            // `got` holds `n` points; `c` is live.
            let st = coif_patch_blended(c, got.as_mut_ptr(), n);
            assert_eq!(st, CoifStatus::COIF_OK);
            rust.write_blended(want).unwrap();
            assert_eq!(got, flat(want));
        };
        same_blend(&mut got, &mut want, &rust);
        assert_eq!(
            coif_patch_positions(c, got.as_mut_ptr(), n),
            CoifStatus::COIF_OK
        );
        rust.write_positions(&mut want).unwrap();
        assert_eq!(got, flat(&want));
        // The cloth moved off its rest grid.
        assert!(got != flat(&grid));

        // Refused calls change nothing.
        let before = got.clone();
        let mut bad_weights = weights.clone();
        bad_weights[4] = 1.5;
        let mut nan_skin = flat(&grid);
        nan_skin[7] = f32::NAN;
        let negative = vec![-1.0f32; n];
        let bad_params = CoifSimParams {
            dt: -1.0,
            ..c_params
        };
        let statuses = [
            coif_patch_set_weights(c, bad_weights.as_ptr(), n),
            coif_patch_set_weights(c, weights.as_ptr(), n - 1),
            coif_patch_set_skinned(c, nan_skin.as_ptr(), n),
            coif_patch_set_max_distances(c, negative.as_ptr(), n),
            coif_patch_set_shear_stiffness(c, f32::NAN),
            coif_patch_step(c, &bad_params, ptr::null(), 0),
            coif_patch_step(c, &c_params, ptr::null(), 1),
            coif_patch_set_skinned(ptr::null_mut(), nan_skin.as_ptr(), n),
        ];
        assert_eq!(
            statuses,
            [
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_COUNT_MISMATCH,
                CoifStatus::COIF_ERROR_NON_FINITE,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_NON_FINITE,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_NULL,
                CoifStatus::COIF_ERROR_NULL,
            ]
        );
        let mut short = vec![-1.0f32; 3 * n];
        assert_eq!(
            coif_patch_blended(c, short.as_mut_ptr(), n - 1),
            CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL
        );
        assert!(short.iter().all(|&x| x == -1.0));
        assert_eq!(
            coif_patch_positions(c, got.as_mut_ptr(), n),
            CoifStatus::COIF_OK
        );
        assert_eq!(got, before);
        // One more step on both sides still agrees (the refused weights did
        // not slip in).
        coif_kernels::patch::step(&mut rust, &params, &rig);
        assert_eq!(
            coif_patch_step(c, &c_params, c_rig.as_ptr(), 1),
            CoifStatus::COIF_OK
        );
        same_blend(&mut got, &mut want, &rust);

        assert_eq!(coif_patch_reset_to_skin(c), CoifStatus::COIF_OK);
        assert_eq!(
            coif_patch_positions(c, got.as_mut_ptr(), n),
            CoifStatus::COIF_OK
        );
        rust.reset_to_skin();
        rust.write_positions(&mut want).unwrap();
        assert_eq!(got, flat(&want));

        // Construction: a bad shape leaves *out NULL.
        let mut bad: *mut CoifPatch = ptr::dangling_mut();
        let xyz = flat(&grid);
        assert_eq!(
            coif_patch_new(xyz.as_ptr(), 1, n, flags.as_ptr(), &mut bad),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert!(bad.is_null());
        assert_eq!(
            coif_patch_new(xyz.as_ptr(), ROWS, COLS, ptr::null(), &mut bad),
            CoifStatus::COIF_ERROR_NULL
        );
        assert_eq!(
            coif_patch_new(xyz.as_ptr(), usize::MAX, 2, flags.as_ptr(), &mut bad),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        coif_patch_free(c);
        coif_patch_free(ptr::null_mut());
    }
}
