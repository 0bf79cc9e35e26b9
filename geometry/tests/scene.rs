//! Built-in scenes: the sphere head's strands, the one grower shared by
//! the sphere head and the scalp mesh, and the sphere fit to roots.

use coif_geometry::grow::{grow, Growth};
use coif_geometry::scalp::ScalpMesh;
use coif_geometry::scene::{fibonacci_cap, fit_sphere, grow_on_sphere, GrowOptions};
use glam::Vec3;

#[test]
fn fits_a_sphere_to_points_on_a_cap() {
    let h = grow_on_sphere(&GrowOptions {
        center: Vec3::new(0.3, 1.6, -0.2),
        radius: 0.09,
        ..Default::default()
    });
    let roots: Vec<Vec3> = h.points.iter().step_by(32).copied().collect();
    let s = fit_sphere(&roots).unwrap();
    assert!(
        (s.center - Vec3::new(0.3, 1.6, -0.2)).length() < 1e-4,
        "{:?}",
        s
    );
    assert!((s.radius - 0.09).abs() < 1e-4);
    assert!(fit_sphere(&roots[..3]).is_none());
    let flat: Vec<Vec3> = (0..20)
        .map(|i| Vec3::new(i as f32, (i * i) as f32, 0.0))
        .collect();
    assert!(
        fit_sphere(&flat).is_none(),
        "coplanar points have no unique sphere"
    );
}

#[test]
fn strands_start_on_the_sphere_and_have_the_asked_length() {
    let o = GrowOptions {
        strand_count: 100,
        curl: 0.0,
        ..Default::default()
    };
    let h = grow_on_sphere(&o);
    assert_eq!(h.points.len(), 100 * 32);
    for s in h.points.chunks(32) {
        assert!(((s[0] - o.center).length() - o.radius).abs() < 1e-5);
        let len: f32 = s.windows(2).map(|w| (w[1] - w[0]).length()).sum();
        assert!((len - o.length).abs() < 1e-4, "{len}");
        assert!(s[0].y >= o.lowest_root * o.radius - 1e-5);
    }
}

#[test]
fn the_sphere_head_and_the_scalp_mesh_grow_through_the_same_grower() {
    let o = GrowOptions {
        strand_count: 50,
        curl: 0.3,
        seed: 7,
        ..Default::default()
    };
    let (roots, normals) = fibonacci_cap(o.center, o.radius, o.strand_count, o.lowest_root);
    assert_eq!(
        grow_on_sphere(&o).points,
        grow(&roots, &normals, &o.growth())
    );
    let mesh = ScalpMesh::sphere_cap(Vec3::ZERO, 0.1, 3, 8, 0.0);
    let growth = Growth {
        curl: 0.3,
        seed: 7,
        ..Default::default()
    };
    assert_eq!(
        mesh.grow_guides(&growth).unwrap(),
        grow(mesh.positions(), mesh.normals(), &growth)
    );
    // Curl keeps the root on the scalp and the first segment near the normal.
    for (s, n) in grow_on_sphere(&o).points.chunks(32).zip(&normals) {
        assert!((s[1] - s[0]).normalize().dot(*n) > 0.9);
    }
}
