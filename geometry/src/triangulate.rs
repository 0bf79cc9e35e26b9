//! Scalp triangles for interpolation from guide roots lying (roughly) on a
//! sphere.
//!
//! The roots' directions from the sphere's centre are mapped to a plane by
//! the stereographic projection from the point opposite the roots' mean
//! direction `a` (with `e1, e2` completing the frame):
//! `u -> (u . e1, u . e2) / (1 + u . a)`. Stereographic projection maps
//! circles on the sphere to circles in the plane, so the planar Delaunay
//! triangulation of the projected points (Bowyer 1981, Watson 1981:
//! insert points one by one, remove the triangles whose circumcircle holds
//! the new point, fan the cavity) is the spherical Delaunay triangulation
//! of the directions, i.e. their convex hull. Roots within 10 degrees of
//! the projection pole are left out (they would map far away).
//! Triangles with an edge longer than `max_edge` (metres, between the
//! actual roots) are dropped: they bridge a gap (a parting, the edge of a
//! mohawk) where no hair grows.

use glam::{DVec2, DVec3, Vec3};

/// Edges longer than this many median edges are gaps between hair patches
/// ([`scalp_triangles`]).
pub const MAX_EDGE_IN_MEDIANS: f32 = 3.0;

/// The scalp of a groom's roots for interpolation: the Delaunay triangles
/// of the root directions around `center` (the centre of the head: the
/// centre of `crate::scene::fit_sphere` of the roots serves), without the
/// triangles that have an edge longer than [`MAX_EDGE_IN_MEDIANS`] median
/// edges (they bridge partings). Indices into `roots`; empty when fewer
/// than three roots lie around `center`.
///
/// ```
/// use coif_geometry::scene::fit_sphere;
/// use coif_geometry::triangulate::scalp_triangles;
/// use glam::Vec3;
/// // Roots on the cap of a 10 cm head.
/// let roots: Vec<Vec3> = (0..200)
///     .map(|i| {
///         let (y, a) = (1.0 - 0.5 * (i as f32 + 0.5) / 200.0, i as f32 * 2.39996);
///         let r = (1.0 - y * y).sqrt();
///         Vec3::new(r * a.cos(), y, r * a.sin()) * 0.1
///     })
///     .collect();
/// let head = fit_sphere(&roots).unwrap();
/// let triangles = scalp_triangles(&roots, head.center);
/// assert!(triangles.len() > 300);
/// ```
pub fn scalp_triangles(roots: &[Vec3], center: Vec3) -> Vec<[u32; 3]> {
    let all = triangulate_roots(roots, center, f32::INFINITY);
    let max_edge = MAX_EDGE_IN_MEDIANS * median_edge(roots, &all);
    triangulate_roots(roots, center, max_edge)
}

/// Delaunay triangles of the root directions around `center`, keeping
/// those whose three root-to-root edges are at most `max_edge` long.
/// Indices into `roots`. Runs in O(n^2) time once per groom.
pub fn triangulate_roots(roots: &[Vec3], center: Vec3, max_edge: f32) -> Vec<[u32; 3]> {
    let dirs: Vec<DVec3> = roots
        .iter()
        .map(|r| (*r - center).as_dvec3().normalize_or_zero())
        .collect();
    let mean = dirs.iter().copied().sum::<DVec3>();
    let axis = mean.try_normalize().unwrap_or(DVec3::Y);
    let (e1, e2) = axis.any_orthonormal_pair();
    let mut points: Vec<(DVec2, u32)> = dirs
        .iter()
        .enumerate()
        .filter(|(_, u)| u.length_squared() > 0.5 && u.dot(axis) > -0.985)
        .map(|(i, u)| {
            (
                DVec2::new(u.dot(e1), u.dot(e2)) / (1.0 + u.dot(axis)),
                i as u32,
            )
        })
        .collect();
    // Exact duplicates would make degenerate triangles: keep the first.
    points.sort_by(|a, b| a.0.x.total_cmp(&b.0.x).then(a.0.y.total_cmp(&b.0.y)));
    points.dedup_by(|a, b| a.0 == b.0);
    let triangles = delaunay(&points.iter().map(|p| p.0).collect::<Vec<_>>());
    let max2 = max_edge * max_edge;
    triangles
        .into_iter()
        .map(|t| t.map(|k| points[k].1))
        .filter(|t| {
            let [a, b, c] = t.map(|i| roots[i as usize]);
            a.distance_squared(b) <= max2
                && b.distance_squared(c) <= max2
                && c.distance_squared(a) <= max2
        })
        .collect()
}

/// A triangle with its circumcircle (centre, squared radius).
#[derive(Clone, Copy)]
struct Triangle {
    v: [usize; 3],
    center: DVec2,
    radius2: f64,
}

fn circumcircle(p: &[DVec2], v: [usize; 3]) -> Option<Triangle> {
    let (a, b, c) = (p[v[0]], p[v[1]], p[v[2]]);
    let (ab, ac) = (b - a, c - a);
    let d = 2.0 * ab.perp_dot(ac);
    if d.abs() < 1e-300 {
        return None;
    }
    let (l1, l2) = (ab.length_squared(), ac.length_squared());
    let off = DVec2::new(ac.y * l1 - ab.y * l2, ab.x * l2 - ac.x * l1) / d;
    Some(Triangle {
        v,
        center: a + off,
        radius2: off.length_squared(),
    })
}

/// Bowyer-Watson Delaunay triangulation of `points` (indices into it).
pub fn delaunay(points: &[DVec2]) -> Vec<[usize; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in points {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let span = (hi - lo).max_element().max(1e-9);
    let mid = 0.5 * (lo + hi);
    // A super-triangle far around everything; its corners are n, n+1, n+2.
    let mut p = points.to_vec();
    p.push(mid + DVec2::new(-40.0 * span, -30.0 * span));
    p.push(mid + DVec2::new(40.0 * span, -30.0 * span));
    p.push(mid + DVec2::new(0.0, 40.0 * span));
    let mut tris: Vec<Triangle> = circumcircle(&p, [n, n + 1, n + 2]).into_iter().collect();
    let mut edges: Vec<[usize; 2]> = Vec::new();
    for i in 0..n {
        let q = p[i];
        edges.clear();
        let mut k = 0;
        while k < tris.len() {
            let t = tris[k];
            if q.distance_squared(t.center) < t.radius2 {
                for e in [[t.v[0], t.v[1]], [t.v[1], t.v[2]], [t.v[2], t.v[0]]] {
                    // An edge shared by two removed triangles is interior.
                    if let Some(j) = edges
                        .iter()
                        .position(|f| (f[0] == e[1] && f[1] == e[0]) || *f == e)
                    {
                        edges.swap_remove(j);
                    } else {
                        edges.push(e);
                    }
                }
                tris.swap_remove(k);
            } else {
                k += 1;
            }
        }
        for e in &edges {
            if let Some(t) = circumcircle(&p, [e[0], e[1], i]) {
                tris.push(t);
            }
        }
    }
    let mut out: Vec<[usize; 3]> = tris
        .into_iter()
        .filter(|t| t.v.iter().all(|&v| v < n))
        .map(|t| t.v)
        .collect();
    out.sort_unstable();
    out
}

/// Median length of the edges of `triangles` over `roots` (0 if none).
pub fn median_edge(roots: &[Vec3], triangles: &[[u32; 3]]) -> f32 {
    let mut lengths: Vec<f32> = triangles
        .iter()
        .flat_map(|t| {
            let [a, b, c] = t.map(|i| roots[i as usize]);
            [a.distance(b), b.distance(c), c.distance(a)]
        })
        .collect();
    if lengths.is_empty() {
        return 0.0;
    }
    let mid = lengths.len() / 2;
    *lengths.select_nth_unstable_by(mid, f32::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_gets_two_triangles_per_cell_and_circumcircles_are_empty() {
        let mut pts = Vec::new();
        for j in 0..6 {
            for i in 0..7 {
                // Interior points jittered so that no four points are
                // cocircular; the boundary stays a rectangle.
                let inside = i > 0 && i < 6 && j > 0 && j < 5;
                let jit = if inside {
                    ((i * 7 + j * 13) % 5) as f64 * 1e-2 + 1e-3
                } else {
                    0.0
                };
                pts.push(DVec2::new(i as f64 + jit, j as f64 - jit));
            }
        }
        let t = delaunay(&pts);
        assert_eq!(
            t.len(),
            2 * 6 * 5,
            "a convex 7 x 6 grid: 2 (n - 1)(m - 1) triangles"
        );
        for tri in &t {
            let c = circumcircle(&pts, *tri).unwrap();
            for (k, q) in pts.iter().enumerate() {
                if !tri.contains(&k) {
                    assert!(
                        q.distance_squared(c.center) >= c.radius2 * (1.0 - 1e-9),
                        "{tri:?} holds {k}"
                    );
                }
            }
        }
    }

    #[test]
    fn roots_on_a_cap_are_covered_and_long_edges_dropped() {
        let head = crate::scene::grow_on_sphere(&crate::scene::GrowOptions {
            strand_count: 400,
            verts_per_strand: 2,
            ..Default::default()
        });
        let roots: Vec<Vec3> = head.points.iter().step_by(2).copied().collect();
        let all = triangulate_roots(&roots, head.head.center, 1.0);
        // Area of the triangles vs the cap's area 2 pi r^2 (1 - lowest).
        let area: f32 = all
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| roots[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        let cap = 2.0 * std::f32::consts::PI * 0.01 * 1.25;
        assert!(area > 0.9 * cap && area < cap, "area {area} vs cap {cap}");
        let med = median_edge(&roots, &all);
        let short = triangulate_roots(&roots, head.head.center, 0.5 * med);
        assert!(short.len() < all.len() / 2);
    }
}
