//! Small meshes and brute-force references for the tests of mesh fields
//! and collisions: an icosphere, the same sphere with a cap cut off, and
//! the exact distance and winding number by brute force in f64 (independent
//! of the library: the plane distance where the projection falls inside
//! the triangle, the nearest edge otherwise; Van Oosterom and Strackee's
//! solid angles summed over all triangles).

use glam::{DVec3, Vec3};

pub use crate::Mesh;

/// Distance from `p` to the segment `a`-`b`.
pub fn seg_dist(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length()
}

/// Distance from `p` to one triangle, the plane-or-edges way.
/// Distance from `p` to the triangle `a b c`.
pub fn tri_dist(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let n = (b - a).cross(c - a);
    let edges = seg_dist(p, a, b)
        .min(seg_dist(p, b, c))
        .min(seg_dist(p, c, a));
    let n2 = n.length_squared();
    if n2 == 0.0 {
        return edges;
    }
    let q = p - n * ((p - a).dot(n) / n2);
    let inside = (b - a).cross(q - a).dot(n) >= 0.0
        && (c - b).cross(q - b).dot(n) >= 0.0
        && (a - c).cross(q - c).dot(n) >= 0.0;
    if inside {
        (p - q).length()
    } else {
        edges
    }
}

/// The corners of triangle `t` of `m`, in f64.
pub fn corners(m: &Mesh, t: &[u32; 3]) -> [DVec3; 3] {
    t.map(|i| m.0[i as usize].as_dvec3())
}

/// Exact unsigned distance and winding number by brute force.
pub fn brute(m: &Mesh, p: Vec3) -> (f64, f64) {
    let p = p.as_dvec3();
    let mut d = f64::INFINITY;
    let mut w = 0.0;
    for t in &m.1 {
        let [a, b, c] = corners(m, t);
        d = d.min(tri_dist(p, a, b, c));
        let (a, b, c) = (a - p, b - p, c - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c));
        let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        w += 2.0 * num.atan2(den);
    }
    (d, w / (4.0 * std::f64::consts::PI))
}

/// An icosphere of radius `r`: the icosahedron subdivided `n` times,
/// counter-clockwise seen from outside.
pub fn icosphere(n: u32, r: f32) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut p: Vec<Vec3> = [
        (-1., t, 0.),
        (1., t, 0.),
        (-1., -t, 0.),
        (1., -t, 0.),
        (0., -1., t),
        (0., 1., t),
        (0., -1., -t),
        (0., 1., -t),
        (t, 0., -1.),
        (t, 0., 1.),
        (-t, 0., -1.),
        (-t, 0., 1.),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..n {
        let mut mid = std::collections::HashMap::new();
        let mut g = vec![];
        for [a, b, c] in f {
            let mut m = |i: u32, j: u32| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    p.push(((p[i as usize] + p[j as usize]) * 0.5).normalize());
                    p.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            g.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = g;
    }
    (p.into_iter().map(|v| v * r).collect(), f)
}

/// The icosphere with every triangle above `y > cut r` removed: a bowl.
pub fn open_sphere(n: u32, r: f32, cut: f32) -> Mesh {
    let (p, f) = icosphere(n, r);
    let f = f
        .into_iter()
        .filter(|t| t.iter().all(|&i| p[i as usize].y <= cut * r))
        .collect();
    (p, f)
}
