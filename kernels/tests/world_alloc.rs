//! A step against every kind of collider (spheres, capsules, mesh fields)
//! with wind and gusts allocates nothing once the strands have room for
//! the colliders (`Strands::reserve_colliders`), serial and on a pool of
//! persistent worker threads. One test in this binary, so the counts see
//! only it.

mod common;

use coif_kernels::tasks::{Executor, Serial};
use coif_kernels::{step_colliders_with, Capsule, Colliders, Sdf, SimParams, Sphere, Strands};
use coif_testkit::counting::{allocations, allocations_all_threads};
use coif_testkit::meshes::icosphere;
use common::executors::SpinPool;
use glam::{Affine3A, Vec3};

#[global_allocator]
static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;

#[test]
fn steps_against_every_collider_allocate_nothing() {
    let (pts, rig) = common::curly_strands(300, 12, 5);
    let m = icosphere(2, 0.08);
    let mut fields = vec![Sdf::from_mesh(&m.0, &m.1, 0.005).unwrap(); 2];
    let caps: Vec<Capsule> = (0..5)
        .map(|i| Capsule {
            a: Vec3::new(-0.2, -0.1 + 0.02 * i as f32, 0.0),
            b: Vec3::new(0.2, -0.12, 0.05),
            radius: 0.02,
        })
        .collect();
    let params = SimParams {
        wind: Vec3::new(1.0, 0.0, 0.0),
        drag: 2.0,
        turbulence: 0.5,
        ..Default::default()
    };
    let pool = SpinPool::new(2);
    for exec in [&Serial as &dyn Executor, &pool] {
        let mut s = Strands::from_polylines(&pts, 12).unwrap();
        fn all<'a>(rig: &'a [Sphere], caps: &'a [Capsule], fields: &'a [Sdf]) -> Colliders<'a> {
            Colliders {
                spheres: rig,
                capsules: caps,
                sdfs: fields,
            }
        }
        s.reserve_colliders(&all(&rig, &caps, &fields));
        let (mine, every) = (allocations(), allocations_all_threads());
        for i in 0..30 {
            let t = Affine3A::from_translation(Vec3::new(0.001 * i as f32, -0.15, 0.0));
            fields[0].set_transform(t).unwrap();
            fields[1]
                .set_transform(Affine3A::from_translation(Vec3::new(0.15, -0.1, 0.0)))
                .unwrap();
            step_colliders_with(&mut s, &params, &all(&rig, &caps, &fields), exec);
        }
        assert_eq!(allocations() - mine, 0, "the calling thread allocated");
        assert_eq!(
            allocations_all_threads() - every,
            0,
            "some thread allocated"
        );
    }
}

#[test]
fn new_hair_shares_every_frame_allocate_nothing() {
    // The target density is computed again after new shares: its pose
    // buffer is kept (it was allocated in every step after a change).
    let (pts, rig) = common::curly_strands(64, 12, 5);
    let params = SimParams {
        volume_stiffness: 1.0,
        hair_friction: 1.0,
        ..Default::default()
    };
    let mut s = Strands::from_polylines(&pts, 12).unwrap();
    let mut shares = vec![1.0f32; s.strand_count()];
    coif_kernels::step(&mut s, &params, &rig);
    s.set_hair_shares(&shares).unwrap();
    coif_kernels::step(&mut s, &params, &rig);
    let mine = allocations();
    for i in 0..10 {
        shares[i % 64] = 1.0 + i as f32;
        s.set_hair_shares(&shares).unwrap();
        coif_kernels::step(&mut s, &params, &rig);
    }
    assert_eq!(allocations() - mine, 0, "a step after new shares allocated");
}
