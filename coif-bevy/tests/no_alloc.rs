//! No allocation per fixed step after warm-up: the plugin's step system
//! (pose, colliders gathered, coif's step, positions written) with coif's
//! serial executor allocates nothing; on Bevy's compute pool only Bevy's
//! scope does (a few allocations a step, whatever the hair's size).
//! One test in this binary, so the all-threads count is this test's.
mod common;

use bevy::ecs::schedule::SingleThreadedExecutor;
use bevy::prelude::*;
use coif_bevy::*;
use coif_testkit::counting::{allocations_all_threads, Counting};
use common::*;

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_per_step(executor: HairExecutor) -> (f64, u64) {
    let mut app = app(executor);
    app.edit_schedule(FixedUpdate, |s| {
        s.set_executor(SingleThreadedExecutor::new());
    });
    let groom = add_groom(&mut app, sintel_groom());
    let mut hair = Hair::new(groom);
    hair.params.sleep_speed = 0.0; // every block stepped every time
    let (bone, hair) = spawn_hair(&mut app, hair);
    app.world_mut().spawn((
        SphereCollider { radius: 0.05 },
        Transform::from_xyz(0.05, 0.35, 0.12),
    ));
    app.world_mut().spawn((
        CapsuleCollider {
            half_length: 0.1,
            radius: 0.04,
        },
        Transform::from_xyz(0.0, 0.25, -0.08),
        ChildOf(bone),
    ));
    let mesh = app
        .world_mut()
        .resource_mut::<Assets<BodyMeshAsset>>()
        .add(sintel_bust());
    app.world_mut().spawn((
        MeshCollider { mesh, cell: 0.004 },
        Transform::IDENTITY,
        ChildOf(bone),
    ));
    // Warm-up: built, stepped, the colliders' records sized.
    for f in 0..30 {
        *app.world_mut().get_mut::<Transform>(bone).unwrap() =
            Transform::from_rotation(Quat::from_rotation_y(0.01 * f as f32));
        app.update();
    }
    let before_steps = app.world().get::<HairState>(hair).unwrap().stats().steps;
    let n = 20;
    let before = allocations_all_threads();
    for _ in 0..n {
        // FixedUpdate alone: what the plugin does per fixed step.
        app.world_mut().run_schedule(FixedUpdate);
    }
    let allocated = allocations_all_threads() - before;
    let steps = app.world().get::<HairState>(hair).unwrap().stats().steps - before_steps;
    (allocated as f64 / n as f64, steps)
}

#[test]
fn no_allocation_per_fixed_step_after_warm_up() {
    let (serial, steps) = allocations_per_step(HairExecutor::Serial);
    assert!(steps >= 20, "{steps} steps");
    let (pool, _) = allocations_per_step(HairExecutor::TaskPool);
    println!("allocations per fixed step: serial executor {serial}, Bevy's compute pool {pool}");
    assert_eq!(serial, 0.0, "the serial step allocated");
    // Bevy's scope: boxed task futures and its result list, per stage.
    assert!(pool <= 64.0, "{pool} allocations per step on the pool");
}
