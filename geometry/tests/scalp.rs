//! Scalp meshes: outward area-weighted normals, the cap's area, guides
//! grown along the normals, and bad meshes and options as errors.

use coif_geometry::grow::Growth;
use coif_geometry::scalp::{ScalpError, ScalpMesh};
use glam::Vec3;

#[test]
fn sphere_cap_normals_point_outward_and_area_is_the_caps() {
    let c = Vec3::new(0.0, 1.6, 0.0);
    let mesh = ScalpMesh::sphere_cap(c, 0.1, 12, 24, 0.0);
    for (p, n) in mesh.positions().iter().zip(mesh.normals()) {
        assert!(((*p - c).normalize() - *n).length() < 0.05, "{p} {n}");
    }
    // Triangles wound outward: face normals agree with the vertex normals.
    for t in mesh.triangles() {
        let [a, b, d] = t.map(|i| mesh.positions()[i as usize]);
        assert!((b - a).cross(d - a).dot(a - c) > 0.0);
    }
    // A hemisphere of radius 0.1 has area 2 pi r^2; the mesh's is a bit less.
    let hemisphere = std::f32::consts::TAU * 0.01;
    assert!(
        mesh.area() < hemisphere && mesh.area() > 0.97 * hemisphere,
        "{}",
        mesh.area()
    );
}

#[test]
fn guides_grow_along_normals() {
    let mesh = ScalpMesh::sphere_cap(Vec3::ZERO, 0.1, 4, 12, 0.2);
    let straight = Growth {
        curl: 0.0,
        verts_per_strand: 8,
        ..Default::default()
    };
    let pts = mesh.grow_guides(&straight).unwrap();
    assert_eq!(pts.len(), mesh.positions().len() * 8);
    for (i, s) in pts.chunks(8).enumerate() {
        assert_eq!(s[0], mesh.positions()[i]);
        let dir = (s[7] - s[0]).normalize();
        assert!(dir.dot(mesh.normals()[i]) > 0.999);
    }
}

#[test]
fn bad_meshes_and_options_are_errors() {
    assert_eq!(
        ScalpMesh::new(vec![], vec![[0, 1, 2]]),
        Err(ScalpError::Empty)
    );
    assert_eq!(
        ScalpMesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 3]]),
        Err(ScalpError::IndexOutOfRange { triangle: 0 })
    );
    assert_eq!(
        ScalpMesh::new(vec![Vec3::ZERO, Vec3::NAN, Vec3::ONE], vec![[0, 1, 2]]),
        Err(ScalpError::NonFinite { index: 1 })
    );
    let mesh = ScalpMesh::sphere_cap(Vec3::ZERO, 0.1, 2, 6, 0.0);
    for o in [
        Growth {
            length: 0.0,
            ..Default::default()
        },
        Growth {
            length: f32::NAN,
            ..Default::default()
        },
        Growth {
            verts_per_strand: 1,
            ..Default::default()
        },
        Growth {
            curl: f32::INFINITY,
            ..Default::default()
        },
    ] {
        assert!(matches!(
            mesh.grow_guides(&o),
            Err(ScalpError::InvalidOption(_))
        ));
    }
}

#[test]
fn a_sphere_cap_of_absurd_size_is_clamped_not_allocated() {
    // 2^16 x 2^16 grew to 6 GB and aborted.
    let mesh = ScalpMesh::sphere_cap(Vec3::ZERO, 0.1, 1 << 16, usize::MAX, 0.0);
    assert_eq!(mesh.positions().len(), 1 + 1024 * 4096);
}
