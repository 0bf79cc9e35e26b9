//! The SIMD patch step computes what its scalar twin computes, bit
//! for bit (compared with `==`; see `patch/step.rs`), over many steps with
//! every constraint kind, collisions, max distances and a moving skin.

use coif_kernels::patch::{self, ribbon_on_sphere};
use coif_kernels::{SimParams, Sphere};
use glam::Vec3;

struct Case {
    rows: usize,
    cols: usize,
    shear: f32,
    bend: f32,
    pearls: u32,
    iterations: u32,
}

/// Ribbon on a head that turns and bobs; two spheres (head, a shoulder).
fn run_both(c: &Case, steps: usize) {
    let head = Sphere {
        center: Vec3::new(0.0, 1.6, 0.0),
        radius: 0.1,
    };
    let ribbon = ribbon_on_sphere(&head, Vec3::new(0.3, 0.2, -1.0), 0.06, 0.3, c.rows, c.cols);
    let mut simd = ribbon.patch().unwrap();
    simd.set_shear_stiffness(c.shear).unwrap();
    // Some particles limited to 5 cm from their skin, the rest free.
    let max: Vec<f32> = (0..c.rows * c.cols)
        .map(|k| if k % 3 == 0 { 0.05 } else { f32::INFINITY })
        .collect();
    simd.set_max_distances(&max).unwrap();
    let mut scalar = simd.clone();
    let params = SimParams {
        iterations: c.iterations,
        bend_stiffness: c.bend,
        pearls_per_segment: c.pearls,
        ..Default::default()
    };
    params.validate().unwrap();
    let mut skin = ribbon.points.clone();
    let mut compared = 0;
    for s in 0..steps {
        let a = s as f32 * 0.15;
        let off = Vec3::new(0.08 * a.sin(), 0.03 * (2.0 * a).sin(), 0.05 * a.cos());
        let rot = glam::Quat::from_rotation_y(0.6 * a.sin());
        for (k, p) in skin.iter_mut().enumerate() {
            *p = head.center + rot * (ribbon.points[k] - head.center) + off;
        }
        let rig = [
            Sphere {
                center: head.center + off,
                radius: head.radius,
            },
            Sphere {
                center: head.center + off + Vec3::new(0.12, -0.25, -0.05),
                radius: 0.08,
            },
        ];
        simd.set_skinned(&skin).unwrap();
        scalar.set_skinned(&skin).unwrap();
        patch::step(&mut simd, &params, &rig);
        patch::scalar::step(&mut scalar, &params, &rig);
        let (a, b) = (simd.positions_local(), scalar.positions_local());
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(x == y, "step {s} particle {k}: simd {x} scalar {y}");
            compared += 1;
        }
    }
    assert_eq!(compared, steps * c.rows * c.cols);
    assert_eq!(simd.restored_count(), 0);
    // The ribbon really moved and met the rig (the comparison is not trivial).
    let moved = simd
        .positions()
        .iter()
        .zip(&skin)
        .map(|(p, s)| p.distance(*s))
        .fold(0.0f32, f32::max);
    assert!(moved > 0.01, "simulation stayed on the skin ({moved} m)");
}

#[test]
fn simd_matches_scalar_for_every_constraint_kind() {
    let cases = [
        // One block, partial: padding lanes.
        Case {
            rows: 6,
            cols: 3,
            shear: 0.0,
            bend: 0.0,
            pearls: 0,
            iterations: 4,
        },
        // Exactly one block, everything on.
        Case {
            rows: 12,
            cols: 8,
            shear: 1.0,
            bend: 0.5,
            pearls: 1,
            iterations: 4,
        },
        // Three blocks, the last partial: cross-block colour passes.
        Case {
            rows: 10,
            cols: 19,
            shear: 0.7,
            bend: 0.3,
            pearls: 2,
            iterations: 3,
        },
        // Wide, few rows, many iterations.
        Case {
            rows: 3,
            cols: 24,
            shear: 1.0,
            bend: 1.0,
            pearls: 1,
            iterations: 12,
        },
    ];
    for c in &cases {
        run_both(c, 90);
    }
}
