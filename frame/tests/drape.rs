//! Draping: grown guides fall under gravity onto the head and stay out of
//! it; the draped sphere head is what the grower and the simulation make.

use coif_frame::drape::{drape, draped_on_scalp, draped_on_sphere};
use coif_geometry::grow::Growth;
use coif_geometry::scalp::ScalpMesh;
use coif_geometry::scene::{grow_on_sphere, GrowOptions};
use coif_kernels::Sphere;
use glam::Vec3;

#[test]
fn scalp_guides_relax_onto_the_head() {
    let head = Sphere {
        center: Vec3::ZERO,
        radius: 0.1,
    };
    let mesh = ScalpMesh::sphere_cap(head.center, head.radius, 4, 12, 0.2);
    let growth = Growth {
        verts_per_strand: 8,
        curl: 0.3,
        ..Default::default()
    };
    let grown = mesh
        .grow_guides(&Growth {
            curl: 0.0,
            ..growth.clone()
        })
        .unwrap();
    let relaxed = draped_on_scalp(&mesh, &growth, std::slice::from_ref(&head), 90).unwrap();
    assert_eq!(relaxed.len(), grown.len());
    // Relaxed hair has fallen: tips lower on average, none inside the head.
    let tip_y = |p: &[Vec3]| p.chunks(8).map(|s| s[7].y).sum::<f32>();
    assert!(tip_y(&relaxed) < tip_y(&grown) - 0.05);
    assert!(relaxed.iter().all(|p| p.length() > head.radius - 1e-3));
    assert!(draped_on_scalp(
        &mesh,
        &Growth {
            length: 0.0,
            ..growth
        },
        &[],
        1
    )
    .is_err());
}

#[test]
fn the_draped_sphere_head_is_the_grown_head_simulated() {
    let (points, verts) = draped_on_sphere(64, 12, 20);
    let grown = grow_on_sphere(&GrowOptions {
        strand_count: 64,
        verts_per_strand: 12,
        curl: 0.3,
        ..Default::default()
    });
    assert_eq!(verts, 12);
    let by_hand = drape(&grown.points, 12, std::slice::from_ref(&grown.head), 20).unwrap();
    assert_eq!(points, by_hand);
    // Roots stay pinned where they grew (to the rounding of the
    // simulation's origin-relative storage).
    for (a, b) in points.chunks(12).zip(grown.points.chunks(12)) {
        assert!(a[0].distance(b[0]) < 1e-6, "{} {}", a[0], b[0]);
    }
}
