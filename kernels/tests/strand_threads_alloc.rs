//! Stepping on threads allocates nothing in coif: after a warm-up step,
//! strands (`step_with`) and patches (`patch::step_all`) on `Serial`, on
//! a pool of persistent worker threads (an engine's job system, which
//! itself allocates nothing per run) and on coif's `Workers` make no
//! allocation on any thread.
//! One test in this binary, so the count of every thread sees only it.
//! Rayon's own allocations are measured and printed, not asserted (they
//! are rayon's; see kernels/README.md).

mod common;

use coif_geometry::scene::{grow_on_sphere, GrowOptions};
use coif_kernels::patch::{self, ribbon_on_sphere, Patch};
use coif_kernels::tasks::{Executor, Serial};
use coif_kernels::{step_with, SimParams, Sphere, Strands};
use coif_testkit::counting::{allocations, allocations_all_threads};
use common::executors::SpinPool;
use glam::Vec3;

#[global_allocator]
static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;

struct Scene {
    strands: Strands,
    roots: Vec<Vec<Vec3>>,
    patches: Vec<Patch>,
    rig: Vec<Sphere>,
}

fn scene() -> Scene {
    let s = grow_on_sphere(&GrowOptions {
        strand_count: 1001,
        verts_per_strand: 12,
        curl: 0.4,
        ..Default::default()
    });
    let count = 1001;
    let roots = (0..8)
        .map(|f| {
            (0..count)
                .map(|i| s.points[i * 12] + Vec3::new(0.01 * f as f32, 0.0, 0.0))
                .collect()
        })
        .collect();
    let patches = (0..6)
        .map(|i| {
            let a = i as f32;
            ribbon_on_sphere(&s.head, Vec3::new(a.cos(), 0.2, a.sin()), 0.04, 0.2, 12, 10)
                .patch()
                .unwrap()
        })
        .collect();
    let rig = vec![
        s.head.clone(),
        Sphere {
            center: Vec3::new(0.0, -0.14, 0.0),
            radius: 0.06,
        },
    ];
    Scene {
        strands: Strands::from_polylines(&s.points, 12).unwrap(),
        roots,
        patches,
        rig,
    }
}

/// Allocations (this thread, every thread) over `frames` frames after a
/// warm-up.
fn count(exec: &dyn Executor, frames: usize) -> (usize, usize) {
    let mut sc = scene();
    let params = SimParams {
        local_shape_stiffness: 1.0,
        pearls_per_segment: 1,
        ..Default::default()
    };
    step_with(&mut sc.strands, &params, &sc.rig, exec);
    patch::step_all(&mut sc.patches, &params, &sc.rig, exec);
    let (here, all) = (allocations(), allocations_all_threads());
    for roots in sc.roots.iter().cycle().take(frames) {
        sc.strands.set_roots(roots).unwrap();
        step_with(&mut sc.strands, &params, &sc.rig, exec);
        patch::step_all(&mut sc.patches, &params, &sc.rig, exec);
    }
    (allocations() - here, allocations_all_threads() - all)
}

#[test]
fn stepping_on_threads_allocates_nothing() {
    // Serially coif runs on this thread only: its count is the one that
    // is coif's. (Another thread of the test process allocated 4 times
    // during this run once, under a heavily loaded machine: not coif's, as
    // coif starts no thread; it is printed, not asserted.)
    let (here, all) = count(&Serial, 8);
    println!("serial: {here} allocations here, {all} on all threads");
    assert_eq!(here, 0, "serial");
    let pool = SpinPool::new(2);
    assert_eq!(count(&pool, 8), (0, 0), "persistent workers");
    drop(pool);
    // coif's own workers, asleep between some runs and spinning between
    // others: nothing on any thread.
    for threads in [2, 3] {
        let workers = coif_kernels::tasks::Workers::new(threads).unwrap();
        count(&workers, 2);
        assert_eq!(count(&workers, 40), (0, 0), "Workers({threads})");
    }
    #[cfg(feature = "rayon")]
    for threads in [1, 2, 4] {
        let rayon = coif_kernels::tasks::Rayon::new(threads).unwrap();
        std::thread::sleep(std::time::Duration::from_millis(200));
        let (here, all) = count(&rayon, 200);
        println!(
            "rayon {threads}: {here} allocations on the caller, {all} on all threads over 200 frames (400 runs)"
        );
    }
}
