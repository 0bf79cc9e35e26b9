//! The `Strands` container: layout round trips, input validation, the local
//! origin (far from the world origin, rebasing) and rigid teleports.

use coif_kernels::measure::max_speed;
use coif_kernels::{Error, Strands, LANES};
use glam::{Affine3A, DVec3, Vec3};

fn line(n_strands: usize, verts: usize, offset: Vec3) -> Vec<Vec3> {
    (0..n_strands)
        .flat_map(|s| {
            (0..verts).map(move |v| offset + Vec3::new(s as f32 * 0.01, -(v as f32) * 0.02, 0.0))
        })
        .collect()
}

#[test]
fn round_trips_positions_in_input_order() {
    for n in [1, 7, 8, 9, 17] {
        let pts = line(n, 5, Vec3::new(1.0, 2.0, 3.0));
        let s = Strands::from_polylines(&pts, 5).unwrap();
        assert_eq!(s.strand_count(), n);
        assert_eq!(s.verts_per_strand(), 5);
        assert_eq!(s.block_count(), n.div_ceil(LANES));
        let back = s.positions();
        for (a, b) in pts.iter().zip(&back) {
            assert!((*a - *b).length() < 1e-6, "{a} vs {b}");
        }
        assert!((s.rest_length(0, 0).unwrap() - 0.02).abs() < 1e-6);
        assert!((s.rest_strand_length(n - 1).unwrap() - 0.08).abs() < 1e-6);
    }
}

#[test]
fn rejects_bad_input() {
    let pts = line(2, 4, Vec3::ZERO);
    assert_eq!(
        Strands::from_polylines(&pts, 1).unwrap_err(),
        Error::TooFewVertices {
            verts_per_strand: 1
        }
    );
    assert!(matches!(
        Strands::from_polylines(&pts, 3),
        Err(Error::NotWholeStrands { .. })
    ));
    assert_eq!(
        Strands::from_polylines(&[], 4).unwrap_err(),
        Error::NoStrands
    );
    let mut nan = pts.clone();
    nan[5].y = f32::NAN;
    assert_eq!(
        Strands::from_polylines(&nan, 4).unwrap_err(),
        Error::NonFinite { index: 5 }
    );
    let mut s = Strands::from_polylines(&pts, 4).unwrap();
    assert!(matches!(
        s.set_roots(&[Vec3::ZERO]),
        Err(Error::CountMismatch {
            expected: 2,
            got: 1,
            ..
        })
    ));
    assert!(matches!(
        s.set_roots(&[Vec3::ZERO, Vec3::NAN]),
        Err(Error::NonFinite { index: 1 })
    ));
    assert!(s
        .teleport(Affine3A::from_translation(Vec3::new(
            f32::INFINITY,
            0.0,
            0.0
        )))
        .is_err());
}

#[test]
fn far_origin_keeps_precision() {
    let far = Vec3::new(10_000.0, 0.0, -10_000.0);
    let s = Strands::from_polylines(&line(3, 4, far), 4).unwrap();
    let local = s.positions_local();
    // Local coordinates are small, so millimetre detail survives.
    assert!(local.iter().all(|p| p.length() < 1.0));
    assert!((s.origin().x - 10_000.0).abs() < 1.0);
}

#[test]
fn teleport_moves_rigidly_and_keeps_velocity_zero() {
    let pts = line(9, 4, Vec3::ZERO);
    let mut s = Strands::from_polylines(&pts, 4).unwrap();
    let xf = Affine3A::from_rotation_translation(
        glam::Quat::from_rotation_y(0.7),
        Vec3::new(10.0, 0.0, 0.0),
    );
    s.teleport(xf).unwrap();
    for (a, b) in pts.iter().zip(s.positions()) {
        assert!((xf.transform_point3(*a) - b).length() < 1e-4);
    }
    assert_eq!(max_speed(&s, 1.0), 0.0, "no velocity injected");
    // Resetting after the teleport keeps the rotated rest shape.
    s.reset_to_rest();
    for (a, b) in pts.iter().zip(s.positions()) {
        assert!((xf.transform_point3(*a) - b).length() < 1e-4);
    }
}

#[test]
fn rebase_is_invisible_in_world_space() {
    let mut s = Strands::from_polylines(&line(3, 4, Vec3::ZERO), 4).unwrap();
    let before = s.positions();
    s.rebase(DVec3::new(100.0, -3.0, 0.5));
    for (a, b) in before.iter().zip(s.positions()) {
        assert!((*a - b).length() < 1e-5);
    }
    let roots: Vec<Vec3> = (0..3)
        .map(|i| Vec3::new(500.0 + i as f32, 0.0, 0.0))
        .collect();
    s.set_roots(&roots).unwrap();
    assert!(
        (s.origin().x - 501.0).abs() < 2.0,
        "rebased near the roots: {}",
        s.origin()
    );
    assert!((s.vertex(2, 0).unwrap() - roots[2]).length() < 1e-4);
}
