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

#[test]
fn hostile_inputs_give_errors_or_nothing_never_a_panic() {
    use coif_geometry::grow::MAX_GROWN_VERTS;
    use coif_geometry::mesh::vertex_normals;
    use coif_geometry::scene::scalp_spheres;
    // A triangle naming a missing vertex is skipped.
    let n = vertex_normals(&[Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 7], [0, 1, 2]]);
    assert_eq!(n.len(), 3);
    assert!(n.iter().all(|v| (v.length() - 1.0).abs() < 1e-6));
    // Strands of one point have no first segment: no sphere.
    assert!(scalp_spheres(&[Vec3::ZERO], 1, 1, 0.1).is_empty());
    assert!(scalp_spheres(&[Vec3::ZERO, Vec3::X, Vec3::Y], 1, 3, 0.1).is_empty());
    assert!(scalp_spheres(&[Vec3::ZERO], 0, 1, 0.1).is_empty());
    // One normal per root: the extra roots are not grown; the vertex count
    // is clamped, never allocated as asked.
    let growth = Growth::default();
    assert!(grow(&[Vec3::ZERO, Vec3::X], &[Vec3::Y], &growth).len() == growth.verts_per_strand);
    let huge = Growth {
        verts_per_strand: 1 << 40,
        ..Growth::default()
    };
    assert!(huge.validate().is_err());
    assert_eq!(
        grow(&[Vec3::ZERO], &[Vec3::Y], &huge).len(),
        MAX_GROWN_VERTS
    );
    // The scene's options refuse what would allocate without bound.
    let options = |o: GrowOptions| o.validate();
    assert!(options(GrowOptions::default()).is_ok());
    for bad in [
        GrowOptions {
            strand_count: 1 << 40,
            ..Default::default()
        },
        GrowOptions {
            verts_per_strand: 1 << 40,
            ..Default::default()
        },
        GrowOptions {
            radius: f32::NAN,
            ..Default::default()
        },
        GrowOptions {
            lowest_root: 2.0,
            ..Default::default()
        },
    ] {
        assert!(options(bad).is_err());
    }
}
