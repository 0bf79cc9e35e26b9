//! The task API: `coif_step_with`, `coif_patch_step_all` and the
//! `coif_shade_*_with` calls give the bytes of the serial calls whatever C
//! parallel-for runs their tasks (indices backwards on the calling thread,
//! or spread over three std threads), with sleeping on; the C step equals
//! the Rust step with sleeping (positions and awake counts); bad executors
//! and bad handle lists are refused before anything changes or runs.

use coif_capi::*;
use coif_kernels::patch::quality::flag_scene;
use coif_kernels::{SimParams, Sphere, Strands};
use glam::Vec3;
use std::ffi::c_void;
use std::ptr;
use std::sync::atomic::{AtomicUsize, Ordering};

const STRANDS: usize = 70; // 9 blocks of 8, the last padded
const VERTS: usize = 10;

/// Counts the `run` calls and the task calls of one executor.
#[derive(Default)]
struct Calls {
    runs: AtomicUsize,
    tasks: AtomicUsize,
}

/// A parallel-for that runs the indices backwards on the calling thread.
unsafe extern "C" fn backwards(
    ctx: *mut c_void,
    count: usize,
    task: CoifTaskFn,
    tctx: *mut c_void,
) {
    // SAFETY (test): ctx is a live `Calls`.
    let calls = unsafe { &*(ctx as *const Calls) };
    calls.runs.fetch_add(1, Ordering::Relaxed);
    for i in (0..count).rev() {
        calls.tasks.fetch_add(1, Ordering::Relaxed);
        // SAFETY: each index once, before returning.
        unsafe { task(tctx, i) };
    }
}

/// A parallel-for over three std threads taking indices from a shared
/// counter (the calling thread only waits), as a job system's workers do.
unsafe extern "C" fn three_threads(
    ctx: *mut c_void,
    count: usize,
    task: CoifTaskFn,
    tctx: *mut c_void,
) {
    // SAFETY (test): ctx is a live `Calls`.
    let calls = unsafe { &*(ctx as *const Calls) };
    calls.runs.fetch_add(1, Ordering::Relaxed);
    let next = AtomicUsize::new(0);
    let tctx = tctx as usize;
    std::thread::scope(|s| {
        for _ in 0..3 {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= count {
                    break;
                }
                calls.tasks.fetch_add(1, Ordering::Relaxed);
                // SAFETY: each index once (the counter), before returning.
                unsafe { task(tctx as *mut c_void, i) };
            });
        }
    });
}

fn executor_of(calls: &Calls, threads: usize, run: CoifRunFn) -> CoifExecutor {
    CoifExecutor {
        ctx: calls as *const Calls as *mut c_void,
        threads,
        run: Some(run),
    }
}

fn groom() -> Vec<Vec3> {
    let mut pts = Vec::with_capacity(STRANDS * VERTS);
    for i in 0..STRANDS {
        let a = i as f32 * 0.09;
        let root = Vec3::new(0.1 * a.cos(), 1.7, 0.1 * a.sin());
        for v in 0..VERTS {
            let t = v as f32;
            pts.push(root + Vec3::new(0.003 * (t * 0.7).sin(), -0.015 * t, 0.0));
        }
    }
    pts
}

const FRAMES: usize = 300;
const WAKE: usize = 200;

/// Roots that swing for the first half second and then stay still (so blocks
/// fall asleep), and a sphere that sweeps through part of the hair late on
/// (so some wake again).
fn frame_input(frame: usize, pts: &[Vec3]) -> (Vec<f32>, [CoifSphere; 1]) {
    let t = frame.min(30) as f32 / 30.0;
    let shift = Vec3::new(0.01 * (t * 3.0).sin(), 0.0, 0.0);
    let roots = pts
        .iter()
        .step_by(VERTS)
        .flat_map(|r| (*r + shift).to_array())
        .collect();
    let x = if frame < WAKE {
        1.0
    } else {
        0.5 - 0.01 * (frame - WAKE) as f32
    };
    let sphere = CoifSphere {
        center: [x, 1.6, 0.0],
        radius: 0.05,
    };
    (roots, [sphere])
}

fn new_strands(pts: &[Vec3]) -> *mut CoifStrands {
    let xyz: Vec<f32> = pts.iter().flat_map(|p| p.to_array()).collect();
    let mut s = ptr::null_mut();
    // SAFETY: `xyz` holds 3 floats per point.
    let st = unsafe { coif_strands_new(xyz.as_ptr(), pts.len(), VERTS, &mut s) };
    assert_eq!(st, CoifStatus::COIF_OK);
    s
}

fn positions(s: *const CoifStrands) -> Vec<u32> {
    let mut out = vec![0.0f32; STRANDS * VERTS * 3];
    // SAFETY: `s` is live; `out` holds every point.
    let st = unsafe { coif_strands_positions(s, out.as_mut_ptr(), STRANDS * VERTS) };
    assert_eq!(st, CoifStatus::COIF_OK);
    out.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn step_with_any_executor_is_the_serial_step_and_the_rust_step() {
    let pts = groom();
    let params = coif_sim_params_default();
    assert!(params.sleep_speed > 0.0, "sleeping is on by default");
    let (back, threads) = (Calls::default(), Calls::default());
    let executors = [
        executor_of(&back, 1, backwards),
        executor_of(&threads, 3, three_threads),
    ];
    let serial = new_strands(&pts);
    let tasked = [new_strands(&pts), new_strands(&pts)];
    let mut rust = Strands::from_polylines(&pts, VERTS).unwrap();
    let rust_params = SimParams::default();
    let (mut slept, mut woke) = (false, false);
    for frame in 0..FRAMES {
        let (roots, rig) = frame_input(frame, &pts);
        let rust_rig = [Sphere {
            center: Vec3::from_array(rig[0].center),
            radius: rig[0].radius,
        }];
        let rust_roots: Vec<Vec3> = roots
            .chunks(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        rust.set_roots(&rust_roots).unwrap();
        coif_kernels::step(&mut rust, &rust_params, &rust_rig);
        // SAFETY: live handles; buffers as their counts say.
        unsafe {
            assert_eq!(
                coif_strands_set_roots(serial, roots.as_ptr(), STRANDS),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_step(serial, &params, rig.as_ptr(), 1),
                CoifStatus::COIF_OK
            );
            for (s, e) in tasked.iter().zip(&executors) {
                assert_eq!(
                    coif_strands_set_roots(*s, roots.as_ptr(), STRANDS),
                    CoifStatus::COIF_OK
                );
                assert_eq!(
                    coif_step_with(*s, &params, rig.as_ptr(), 1, e),
                    CoifStatus::COIF_OK
                );
            }
        }
        // SAFETY: live handles.
        let awake = unsafe { coif_strands_awake_strands(serial) };
        assert_eq!(
            awake,
            rust.awake_strands(),
            "frame {frame}: C and Rust awake"
        );
        for s in &tasked {
            // SAFETY: live handle.
            assert_eq!(unsafe { coif_strands_awake_strands(*s) }, awake);
            assert_eq!(
                unsafe { coif_strands_sleeping_strands(*s) },
                rust.sleeping_strands()
            );
        }
        slept |= awake < STRANDS;
        woke |= slept && frame > WAKE && awake > 0 && awake < STRANDS;
        if frame % 20 == 19 {
            let want: Vec<u32> = rust
                .positions()
                .iter()
                .flat_map(|p| p.to_array())
                .map(f32::to_bits)
                .collect();
            assert_eq!(positions(serial), want, "frame {frame}: C and Rust");
            for s in &tasked {
                assert_eq!(positions(*s), want, "frame {frame}: executor and serial");
            }
        }
    }
    assert!(slept, "some blocks slept: sleeping was exercised");
    assert!(woke, "the sphere woke some blocks and not others");
    for calls in [&back, &threads] {
        assert_eq!(
            calls.runs.load(Ordering::Relaxed),
            FRAMES,
            "one run per step"
        );
        assert!(calls.tasks.load(Ordering::Relaxed) >= FRAMES, "tasks ran");
    }
    // SAFETY: handles from coif_strands_new, freed once.
    unsafe {
        coif_strands_free(serial);
        tasked.iter().for_each(|s| coif_strands_free(*s));
    }
}

#[test]
fn sleep_speed_zero_never_sleeps_and_the_field_is_validated() {
    let pts = groom();
    let s = new_strands(&pts);
    let never = CoifSimParams {
        sleep_speed: 0.0,
        ..coif_sim_params_default()
    };
    for _ in 0..90 {
        // SAFETY: live handle, no spheres.
        assert_eq!(
            unsafe { coif_step(s, &never, ptr::null(), 0) },
            CoifStatus::COIF_OK
        );
        // SAFETY: live handle.
        assert_eq!(unsafe { coif_strands_awake_strands(s) }, STRANDS);
    }
    let before = positions(s);
    for (bad, want) in [
        (-0.1, CoifStatus::COIF_ERROR_INVALID_ARGUMENT),
        (f32::NAN, CoifStatus::COIF_ERROR_NON_FINITE),
    ] {
        let p = CoifSimParams {
            sleep_speed: bad,
            ..coif_sim_params_default()
        };
        // SAFETY: live handle / readable params.
        unsafe {
            assert_eq!(coif_sim_params_validate(&p), want);
            assert_eq!(coif_step(s, &p, ptr::null(), 0), want);
        }
    }
    assert_eq!(positions(s), before, "a refused step changed nothing");
    // SAFETY: NULL is 0; `s` freed once.
    unsafe {
        assert_eq!(coif_strands_awake_strands(ptr::null()), 0);
        assert_eq!(coif_strands_sleeping_strands(ptr::null()), 0);
        coif_strands_free(s);
    }
}

#[test]
fn bad_calls_with_an_executor_change_nothing_and_run_nothing() {
    let pts = groom();
    let s = new_strands(&pts);
    let calls = Calls::default();
    let good = executor_of(&calls, 2, three_threads);
    let no_run = CoifExecutor { run: None, ..good };
    let params = coif_sim_params_default();
    let nan_params = CoifSimParams {
        dt: f32::NAN,
        ..params
    };
    let nan_rig = [CoifSphere {
        center: [f32::NAN, 0.0, 0.0],
        radius: 0.1,
    }];
    let before = positions(s);
    // SAFETY: live handle; every pointer readable or NULL.
    unsafe {
        let cases = [
            (
                coif_step_with(s, &params, ptr::null(), 0, &no_run),
                CoifStatus::COIF_ERROR_NULL,
            ),
            (
                coif_step_with(s, ptr::null(), ptr::null(), 0, &good),
                CoifStatus::COIF_ERROR_NULL,
            ),
            (
                coif_step_with(s, &nan_params, ptr::null(), 0, &good),
                CoifStatus::COIF_ERROR_NON_FINITE,
            ),
            (
                coif_step_with(s, &params, nan_rig.as_ptr(), 1, &good),
                CoifStatus::COIF_ERROR_NON_FINITE,
            ),
            (
                coif_step_with(s, &params, ptr::null(), 1, &good),
                CoifStatus::COIF_ERROR_NULL,
            ),
            (
                coif_step_with(ptr::null_mut(), &params, ptr::null(), 0, &good),
                CoifStatus::COIF_ERROR_NULL,
            ),
        ];
        for (i, (got, want)) in cases.into_iter().enumerate() {
            assert_eq!(got, want, "case {i}");
        }
    }
    assert_eq!(positions(s), before, "refused steps changed nothing");
    assert_eq!(calls.runs.load(Ordering::Relaxed), 0, "and ran nothing");
    // SAFETY: freed once.
    unsafe { coif_strands_free(s) };
}

fn new_patch(shift: f32) -> *mut CoifPatch {
    let (rows, cols) = (5, 11);
    let (grid, pinned) = flag_scene(rows, cols);
    let xyz: Vec<f32> = grid
        .iter()
        .flat_map(|p| (*p + Vec3::new(shift, 0.0, 0.0)).to_array())
        .collect();
    let flags: Vec<u8> = pinned.iter().map(|&p| u8::from(p)).collect();
    let mut p = ptr::null_mut();
    // SAFETY: buffers of rows * cols points and flags.
    let st = unsafe { coif_patch_new(xyz.as_ptr(), rows, cols, flags.as_ptr(), &mut p) };
    assert_eq!(st, CoifStatus::COIF_OK);
    p
}

fn patch_positions(p: *const CoifPatch) -> Vec<u32> {
    // SAFETY: live handle; the buffer holds every particle.
    unsafe {
        let n = coif_patch_particle_count(p);
        let mut out = vec![0.0f32; 3 * n];
        assert_eq!(
            coif_patch_positions(p, out.as_mut_ptr(), n),
            CoifStatus::COIF_OK
        );
        out.iter().map(|x| x.to_bits()).collect()
    }
}

#[test]
fn patch_step_all_is_each_patch_stepped_alone() {
    const PATCHES: usize = 7;
    let rig = [CoifSphere {
        center: [0.1, 0.9, 0.05],
        radius: 0.06,
    }];
    let params = CoifSimParams {
        bend_stiffness: 0.3,
        ..coif_sim_params_default()
    };
    let make =
        || -> Vec<*mut CoifPatch> { (0..PATCHES).map(|i| new_patch(0.03 * i as f32)).collect() };
    let (alone, backs, threes) = (make(), make(), make());
    let (back, threads) = (Calls::default(), Calls::default());
    let e_back = executor_of(&back, 1, backwards);
    let e_threads = executor_of(&threads, 3, three_threads);
    for _ in 0..40 {
        // SAFETY: live, distinct handles; the rig and params readable.
        unsafe {
            for p in &alone {
                assert_eq!(
                    coif_patch_step(*p, &params, rig.as_ptr(), 1),
                    CoifStatus::COIF_OK
                );
            }
            let st =
                coif_patch_step_all(backs.as_ptr(), PATCHES, &params, rig.as_ptr(), 1, &e_back);
            assert_eq!(st, CoifStatus::COIF_OK);
            let st = coif_patch_step_all(
                threes.as_ptr(),
                PATCHES,
                &params,
                rig.as_ptr(),
                1,
                &e_threads,
            );
            assert_eq!(st, CoifStatus::COIF_OK);
        }
    }
    let first = patch_positions(alone[0]);
    assert_ne!(first, patch_positions(alone[1]), "the patches differ");
    for i in 0..PATCHES {
        let want = patch_positions(alone[i]);
        assert_eq!(patch_positions(backs[i]), want, "patch {i}, backwards");
        assert_eq!(patch_positions(threes[i]), want, "patch {i}, three threads");
    }
    assert!(
        threads.tasks.load(Ordering::Relaxed) > 40,
        "more than one task per step"
    );

    // Refused lists: a handle twice, a NULL handle, NULL with a count; the
    // patches stay as they were and nothing runs.
    let runs = threads.runs.load(Ordering::Relaxed);
    let twice = [threes[0], threes[1], threes[0]];
    let with_null = [threes[0], ptr::null_mut()];
    // SAFETY: the lists hold live handles or NULL.
    unsafe {
        let st = coif_patch_step_all(twice.as_ptr(), 3, &params, rig.as_ptr(), 1, &e_threads);
        assert_eq!(st, CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        let st = coif_patch_step_all(with_null.as_ptr(), 2, &params, rig.as_ptr(), 1, &e_threads);
        assert_eq!(st, CoifStatus::COIF_ERROR_NULL);
        let st = coif_patch_step_all(ptr::null(), 2, &params, rig.as_ptr(), 1, &e_threads);
        assert_eq!(st, CoifStatus::COIF_ERROR_NULL);
        let st = coif_patch_step_all(ptr::null(), 0, &params, rig.as_ptr(), 1, &e_threads);
        assert_eq!(st, CoifStatus::COIF_OK, "no patches is nothing to do");
    }
    assert_eq!(threads.runs.load(Ordering::Relaxed), runs, "nothing ran");
    for i in 0..PATCHES {
        assert_eq!(
            patch_positions(threes[i]),
            patch_positions(alone[i]),
            "patch {i} unchanged"
        );
    }
    // SAFETY: every handle freed once.
    unsafe {
        for p in alone.iter().chain(&backs).chain(&threes) {
            coif_patch_free(*p);
        }
    }
}

#[test]
fn shading_with_any_executor_is_the_serial_shading() {
    const N: usize = 1003; // not a multiple of 8
    let verts: Vec<CoifRenderVertex> = (0..N)
        .map(|i| {
            let a = i as f32 * 0.037;
            let t = Vec3::new(a.cos(), 0.3 * a.sin(), a.sin()).normalize();
            CoifRenderVertex {
                position: [0.01 * a.sin(), -0.0005 * i as f32, 0.02 * a.cos()],
                width: 6e-5,
                tangent: t.to_array(),
                strand_parameter: (i % 17) as f32 / 16.0,
            }
        })
        .collect();
    let (light, eye) = ([0.3f32, 1.0, 0.5], [0.0f32, 0.1, 1.5]);
    let kk = coif_kajiya_kay_default();
    let mp = coif_marschner_params_default();
    let mut lut = ptr::null_mut();
    // SAFETY: readable params, writable out.
    assert_eq!(
        unsafe { coif_marschner_lut_new(&mp, 32, &mut lut) },
        CoifStatus::COIF_OK
    );
    let (back, threads) = (Calls::default(), Calls::default());
    let execs = [
        executor_of(&back, 1, backwards),
        executor_of(&threads, 3, three_threads),
    ];
    // SAFETY: every buffer holds N vertices / N colours; `lut` live.
    unsafe {
        let mut want_kk = vec![0.0f32; 3 * N];
        let mut want_m = vec![0.0f32; 3 * N];
        let (v, l, e) = (verts.as_ptr(), light.as_ptr(), eye.as_ptr());
        assert_eq!(
            coif_shade_kajiya_kay(&kk, v, N, l, e, want_kk.as_mut_ptr(), N),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_shade_marschner_lut(lut, v, N, l, e, want_m.as_mut_ptr(), N),
            CoifStatus::COIF_OK
        );
        assert!(want_kk.iter().any(|c| *c > 0.0) && want_m.iter().any(|c| *c > 0.0));
        for ex in &execs {
            let mut got = vec![f32::NAN; 3 * N];
            let st = coif_shade_kajiya_kay_with(&kk, v, N, l, e, got.as_mut_ptr(), N, ex);
            assert_eq!(st, CoifStatus::COIF_OK);
            let bits = |x: &[f32]| x.iter().map(|c| c.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&got), bits(&want_kk), "Kajiya-Kay");
            let mut got = vec![f32::NAN; 3 * N];
            let st = coif_shade_marschner_lut_with(lut, v, N, l, e, got.as_mut_ptr(), N, ex);
            assert_eq!(st, CoifStatus::COIF_OK);
            assert_eq!(bits(&got), bits(&want_m), "Marschner");
            // A buffer too small: refused, untouched, nothing run.
            let runs = threads.runs.load(Ordering::Relaxed) + back.runs.load(Ordering::Relaxed);
            let mut small = vec![7.0f32; 3 * N];
            let st = coif_shade_kajiya_kay_with(&kk, v, N, l, e, small.as_mut_ptr(), N - 1, ex);
            assert_eq!(st, CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL);
            assert!(small.iter().all(|c| *c == 7.0));
            let after = threads.runs.load(Ordering::Relaxed) + back.runs.load(Ordering::Relaxed);
            assert_eq!(after, runs);
        }
        coif_marschner_lut_free(lut);
    }
    assert!(
        threads.tasks.load(Ordering::Relaxed) > 2,
        "split into tasks"
    );
}
