//! The same bytes at any thread count: strands (SIMD and scalar) and cloth
//! patches stepped on `Serial`, on rayon pools of 1, 2, 3 and 8 threads,
//! and on engine-style executors (reverse order, scoped threads taking
//! indices from a counter, persistent spinning workers, a C callback)
//! give bit-identical positions, previous positions and restored counts,
//! with sleeping blocks too.

mod common;

use coif_geometry::scene::{grow_on_sphere, GrowOptions};
use coif_kernels::patch::{self, ribbon_on_sphere, Patch};
use coif_kernels::tasks::{Executor, Serial};
use coif_kernels::{scalar, step, step_with, SimParams, Sphere, Strands};
use common::executors::{c_callback, Backwards, Scoped, SpinPool};
use glam::Vec3;

/// Executors under test, with a name for messages.
fn executors() -> Vec<(String, Box<dyn Executor>)> {
    #[cfg_attr(not(feature = "rayon"), allow(unused_mut))]
    let mut v: Vec<(String, Box<dyn Executor>)> = vec![
        ("serial".into(), Box::new(Serial)),
        ("reverse".into(), Box::new(Backwards(1))),
        ("scoped 3".into(), Box::new(Scoped(3))),
        ("spin pool 2+1".into(), Box::new(SpinPool::new(2))),
        ("C callback".into(), Box::new(c_callback())),
    ];
    #[cfg(feature = "rayon")]
    for threads in [1, 2, 3, 8] {
        v.push((
            format!("rayon {threads}"),
            Box::new(coif_kernels::tasks::Rayon::new(threads).unwrap()),
        ));
    }
    v
}

/// 1,001 strands of 12 vertices (126 blocks, the last padded: 16 tasks, the
/// last short) on a head, with a neck sphere.
fn scene() -> (Vec<Vec3>, usize, Vec<Sphere>) {
    let s = grow_on_sphere(&GrowOptions {
        strand_count: 1001,
        verts_per_strand: 12,
        length: 0.2,
        curl: 0.4,
        ..Default::default()
    });
    let rig = vec![
        s.head.clone(),
        Sphere {
            center: Vec3::new(0.0, -0.14, 0.02),
            radius: 0.06,
        },
    ];
    (s.points, s.verts_per_strand, rig)
}

/// The positions as bits, and the restored count. (Previous positions
/// feed every next step, so 12 steps compare them too.)
fn state(s: &Strands) -> (Vec<[u32; 3]>, u64) {
    let bits = s
        .positions_local()
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    (bits, s.restored_strands())
}

/// Steps the scene 12 times with `stepper`: the roots move 2 cm per step
/// (the hair swings into the neck sphere), local shape on, one pearl. (A
/// lane restored inside a task is step.rs's unit test.)
fn run(stepper: &dyn Fn(&mut Strands, &SimParams, &[Sphere])) -> (Vec<[u32; 3]>, u64) {
    let (points, verts, rig) = scene();
    let mut strands = Strands::from_polylines(&points, verts).unwrap();
    let params = SimParams {
        local_shape_stiffness: 1.0,
        pearls_per_segment: 1,
        ..Default::default()
    };
    let count = points.len() / verts;
    for frame in 0..12 {
        let t = frame as f32 * 0.02;
        let roots: Vec<Vec3> = (0..count)
            .map(|i| points[i * verts] + Vec3::new(t, -0.5 * t, 0.0))
            .collect();
        strands.set_roots(&roots).unwrap();
        stepper(&mut strands, &params, &rig);
    }
    state(&strands)
}

#[test]
fn strands_give_the_same_bytes_on_every_executor() {
    let reference = run(&|s, p, r| step(s, p, r));
    let (points, _, _) = scene();
    let first: Vec<[u32; 3]> = points
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    assert!(reference.0 != first, "the hair moved");
    for (name, exec) in executors() {
        let got = run(&|s, p, r| step_with(s, p, r, exec.as_ref()));
        assert_eq!(got.1, reference.1, "{name}: restored count");
        assert!(got.0 == reference.0, "{name}: positions differ from serial");
    }
}

#[test]
fn scalar_strands_give_the_same_bytes_on_every_executor() {
    let reference = run(&|s, p, r| scalar::step(s, p, r));
    assert!(reference == run(&|s, p, r| step(s, p, r)), "scalar = SIMD");
    for (name, exec) in executors().into_iter().skip(1).step_by(2) {
        let got = run(&|s, p, r| scalar::step_with(s, p, r, exec.as_ref()));
        assert!(
            got == reference,
            "{name}: scalar positions differ from serial"
        );
    }
}

/// Steps a slice of patches.
type PatchStepper<'a> = dyn Fn(&mut [Patch], &SimParams, &[Sphere]) + 'a;

/// Nine ribbons of different sizes round a head (one to three column
/// blocks each), skinned to a head that turns, stepped 20 times.
fn patches_run(stepper: &PatchStepper<'_>) -> Vec<Vec<[u32; 3]>> {
    let head = Sphere {
        center: Vec3::ZERO,
        radius: 0.1,
    };
    let ribbons: Vec<_> = (0..9)
        .map(|i| {
            let a = i as f32 * 0.7;
            let attach = Vec3::new(a.cos(), 0.3, a.sin());
            ribbon_on_sphere(
                &head,
                attach,
                0.03 + 0.01 * i as f32,
                0.2,
                10 + i,
                4 + 2 * i,
            )
        })
        .collect();
    let mut patches: Vec<Patch> = ribbons.iter().map(|r| r.patch().unwrap()).collect();
    let params = SimParams {
        pearls_per_segment: 1,
        ..Default::default()
    };
    let rig = [head];
    for frame in 0..20 {
        let turn = glam::Quat::from_rotation_y(0.05 * frame as f32);
        for (p, r) in patches.iter_mut().zip(&ribbons) {
            let skin: Vec<Vec3> = r.points.iter().map(|x| turn * *x).collect();
            p.set_skinned(&skin).unwrap();
        }
        stepper(&mut patches, &params, &rig);
    }
    patches
        .iter()
        .map(|p| {
            p.positions_local()
                .iter()
                .map(|x| x.to_array().map(f32::to_bits))
                .collect()
        })
        .collect()
}

#[test]
fn patches_give_the_same_bytes_on_every_executor() {
    let one_by_one = patches_run(&|ps, p, r| ps.iter_mut().for_each(|x| patch::step(x, p, r)));
    let scalar = patches_run(&|ps, p, r| ps.iter_mut().for_each(|x| patch::scalar::step(x, p, r)));
    for (name, exec) in executors() {
        let got = patches_run(&|ps, p, r| patch::step_all(ps, p, r, exec.as_ref()));
        assert!(got == one_by_one, "{name}: patch positions differ");
        let got = patches_run(&|ps, p, r| patch::scalar::step_all(ps, p, r, exec.as_ref()));
        // The scalar twin agrees with SIMD up to the sign of zero (see
        // patch/step.rs): compare it with itself, bit for bit.
        assert!(got == scalar, "{name}: scalar patch positions differ");
    }
}

/// Sleeping with tasks: 256 hanging strands (32 blocks, 2 tasks) settle for
/// 1.5 s until most blocks sleep, then a sphere sweeps through the side of
/// the hair and the roots of one corner move: positions and awake counts
/// after every step are identical on every executor.
#[test]
fn sleeping_gives_the_same_bytes_on_every_executor() {
    let (verts, side) = (16, 16);
    let points = common::hanging_grid(side, 0.03, verts, 0.02);
    let params = SimParams {
        sleep_speed: 0.02,
        ..Default::default()
    };
    let run = |exec: &dyn Executor| {
        let mut strands = Strands::from_polylines(&points, verts).unwrap();
        let mut awake = Vec::new();
        for frame in 0..150 {
            let mut rig = Vec::new();
            if frame >= 100 {
                let x = -0.1 + 0.004 * (frame - 100) as f32;
                rig.push(Sphere {
                    center: Vec3::new(x, -0.15, 0.0),
                    radius: 0.05,
                });
            }
            if frame == 130 {
                let roots: Vec<Vec3> = (0..side * side)
                    .map(|i| points[i * verts] + Vec3::new(0.0, 0.0, 0.01 * (i < 8) as u8 as f32))
                    .collect();
                strands.set_roots(&roots).unwrap();
            }
            step_with(&mut strands, &params, &rig, exec);
            awake.push(strands.awake_strands());
        }
        (state(&strands), awake)
    };
    let reference = run(&Serial);
    assert!(
        reference.1[99] < 64,
        "most hair asleep before the sphere: {} awake",
        reference.1[99]
    );
    assert!(
        reference.1.iter().skip(100).any(|&a| a > reference.1[99]),
        "the sphere wakes some hair"
    );
    for (name, exec) in executors() {
        let got = run(exec.as_ref());
        assert!(got.1 == reference.1, "{name}: awake counts differ");
        assert!(got.0 == reference.0, "{name}: positions differ from serial");
    }
}
