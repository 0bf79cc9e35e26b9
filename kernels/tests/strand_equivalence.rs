//! The SIMD step against its scalar reference.
//!
//! Both paths run the same operations in the same order with no fused
//! multiply-adds, so they agree bit for bit on this build; the tolerances
//! below are what we promise on any build (a compiler is free to contract
//! nothing here, but a future path may use FMA): 1e-6 m after one step and
//! 1e-4 m after 120 steps of chaotic, colliding motion.

mod common;

use coif_kernels::{self as kernels, measure::max_distance, scalar, SimParams, Strands};
use glam::Vec3;

fn run_both(
    points: &[Vec3],
    verts: usize,
    params: &SimParams,
    rig: &[kernels::Sphere],
    steps: usize,
) -> f32 {
    let mut simd = Strands::from_polylines(points, verts).unwrap();
    let mut reference = simd.clone();
    let mut worst = 0.0f32;
    for i in 0..steps {
        // Move the roots too, so the comparison covers whipping roots.
        let offset = Vec3::new(
            (i as f32 * 0.2).sin() * 0.03,
            0.0,
            (i as f32 * 0.13).cos() * 0.02,
        );
        let roots = common::shifted_roots(points, verts, offset);
        simd.set_roots(&roots).unwrap();
        reference.set_roots(&roots).unwrap();
        kernels::step(&mut simd, params, rig);
        scalar::step(&mut reference, params, rig);
        worst = worst.max(max_distance(&simd, &reference));
    }
    assert_eq!(simd.restored_strands(), reference.restored_strands());
    worst
}

#[test]
fn simd_matches_scalar_after_one_step() {
    // 37 strands: four full blocks and a partial one with padding lanes.
    let (pts, rig) = common::curly_strands(37, 24, 11);
    for pearls in [0, 1, 3] {
        let params = SimParams {
            pearls_per_segment: pearls,
            ..Default::default()
        };
        let d = run_both(&pts, 24, &params, &rig, 1);
        assert!(
            d <= 1e-6,
            "pearls {pearls}: SIMD and scalar differ by {d} m after 1 step"
        );
    }
}

#[test]
fn simd_matches_scalar_after_120_steps() {
    let (pts, rig) = common::curly_strands(45, 20, 12);
    let cases = [
        SimParams::default(),
        SimParams {
            iterations: 1,
            pearls_per_segment: 2,
            ..Default::default()
        },
        SimParams {
            iterations: 8,
            bend_stiffness: 0.5,
            shape_stiffness: 0.2,
            ..Default::default()
        },
        SimParams {
            dt: 1.0 / 15.0,
            gravity: Vec3::new(3.0, -98.1, 0.0),
            ..Default::default()
        },
    ];
    for params in cases {
        let d = run_both(&pts, 20, &params, &rig, 120);
        assert!(
            d <= 1e-4,
            "{params:?}: SIMD and scalar differ by {d} m after 120 steps"
        );
    }
}

#[test]
fn simd_and_scalar_both_collide() {
    // Guard against a comparison that passes because neither path collides:
    // strands start inside the head and both paths must push them out.
    let (pts, rig) = common::curly_strands(16, 12, 13);
    let sunk: Vec<Vec3> = pts
        .iter()
        .enumerate()
        .map(|(i, p)| if i % 12 == 0 { *p } else { *p * 0.8 })
        .collect();
    let params = SimParams::default();
    for stepper in [
        kernels::step as fn(&mut Strands, &SimParams, &[kernels::Sphere]),
        scalar::step,
    ] {
        let mut s = Strands::from_polylines(&sunk, 12).unwrap();
        let before = kernels::measure(&s, &rig[..1]).max_penetration;
        stepper(&mut s, &params, &rig[..1]);
        let after = kernels::measure(&s, &rig[..1]).max_penetration;
        assert!(
            before > 0.005 && after < 0.002,
            "penetration {before} -> {after}"
        );
    }
}
