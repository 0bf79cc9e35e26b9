//! The generalised winding number of a triangle soup, exact and fast.
//!
//! The winding number of a closed, consistently oriented surface at `q` is
//! 1 inside and 0 outside; for an open or broken surface Jacobson, Kavan and
//! Sorkine-Hornung ("Robust inside-outside segmentation using generalized
//! winding numbers", SIGGRAPH 2013) define it as the sum of the signed solid
//! angles of its triangles seen from `q`, over `4 pi`:
//! `w(q) = (1 / 4 pi) sum_t Omega_t(q)`. It is harmonic off the surface,
//! jumps by one across it, and varies smoothly across holes, so
//! `w >= 1/2` is an inside test that tolerates holes.
//!
//! The solid angle of one triangle (Van Oosterom and Strackee, "The solid
//! angle of a plane triangle", IEEE Trans. Biomed. Eng. 1983), with
//! `a, b, c` the corners minus `q` and `|.|` their lengths:
//! `tan(Omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|)`,
//! so `Omega = 2 atan2(num, den)`; positive when `q` sees the triangle's back
//! (the side its counter-clockwise normal points away from).
//!
//! [`WindingTree`] evaluates the sum hierarchically (Barill, Dickson,
//! Schmidt, Levin and Jacobson, "Fast winding numbers for soups and clouds",
//! SIGGRAPH 2018, first-order term): a bounding-volume tree over the
//! triangles; a node whose triangles all lie within `r` of their
//! area-weighted centre `p` and whose centre is farther than `BETA r` from
//! `q` contributes its dipole, `Omega ~= N.(p - q) / |p - q|^3` with
//! `N = sum_t A_t n_t` the sum of its area vectors; other nodes open, and
//! leaves (up to eight triangles) sum their exact solid angles, eight lanes
//! at once. Zero-area triangles subtend no solid angle and are left out.

use glam::Vec3;
// Leaves of eight triangles in one `f32x8` at every lane width: the SDF built
// from this tree has the same bytes in 8- and 16-lane builds.
use wide::f32x8;

/// A node is taken as a dipole when its centre is farther from the query
/// than `BETA` times its radius (Barill et al.'s 2, with the first-order
/// term only: the error of `w` stays near 2e-2 in the unit test below, which
/// the sign test `w >= 1/2` does not feel away from holes).
const BETA: f32 = 2.0;
/// Triangles per leaf: one SIMD block.
const LEAF: usize = 8;

/// The solid angle of triangle `a b c` seen from `q` (Van Oosterom and
/// Strackee 1983), in steradians, positive from the triangle's back.
#[cfg(test)]
pub(crate) fn solid_angle(q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let (a, b, c) = (a - q, b - q, c - q);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}

/// Eight triangles of a leaf, corners in structure-of-arrays form; unused
/// lanes are masked out.
#[derive(Clone, Copy)]
struct LeafBlock {
    corners: [[f32x8; 3]; 3],
    used: f32x8,
}

#[derive(Clone, Copy)]
struct Node {
    /// Area-weighted centre of the node's triangles.
    center: Vec3,
    /// `(BETA r)^2`: farther than this (squared) the dipole stands in.
    far2: f32,
    /// Sum of the area vectors `(b - a) x (c - a) / 2`.
    dipole: Vec3,
    /// Leaf: index of its block; inner node: index of its first child (the
    /// second is the next one built after the first's subtree).
    first: u32,
    /// Inner node: index of the second child; `u32::MAX` for a leaf.
    second: u32,
}

/// Barill et al.'s tree for the winding number of a fixed triangle soup.
pub(crate) struct WindingTree {
    nodes: Vec<Node>,
    leaves: Vec<LeafBlock>,
}

impl WindingTree {
    /// Builds the tree over the triangles of positive area.
    pub fn new(positions: &[Vec3], triangles: &[[u32; 3]]) -> WindingTree {
        let tris: Vec<[Vec3; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| positions[i as usize]))
            .filter(|[a, b, c]| (*b - *a).cross(*c - *a).length_squared() > 0.0)
            .collect();
        let mut order: Vec<u32> = (0..tris.len() as u32).collect();
        let centroids: Vec<Vec3> = tris.iter().map(|[a, b, c]| (*a + *b + *c) / 3.0).collect();
        let mut tree = WindingTree {
            nodes: Vec::with_capacity(2 * tris.len() / LEAF + 2),
            leaves: Vec::with_capacity(tris.len() / LEAF * 2 + 1),
        };
        if !tris.is_empty() {
            tree.build(&tris, &centroids, &mut order);
        }
        tree
    }

    /// Builds the subtree over `order` and returns its node index.
    fn build(&mut self, tris: &[[Vec3; 3]], centroids: &[Vec3], order: &mut [u32]) -> u32 {
        // Area-weighted centre and dipole, then the radius around the centre.
        let mut dipole = Vec3::ZERO;
        let mut weighted = Vec3::ZERO;
        let mut area = 0.0f32;
        for &t in order.iter() {
            let [a, b, c] = tris[t as usize];
            let n = (b - a).cross(c - a) * 0.5;
            let ar = n.length();
            dipole += n;
            weighted += centroids[t as usize] * ar;
            area += ar;
        }
        let center = weighted / area;
        let mut r2 = 0.0f32;
        for &t in order.iter() {
            for v in tris[t as usize] {
                r2 = r2.max((v - center).length_squared());
            }
        }
        let index = self.nodes.len() as u32;
        self.nodes.push(Node {
            center,
            far2: BETA * BETA * r2,
            dipole,
            first: 0,
            second: u32::MAX,
        });
        if order.len() <= LEAF {
            let mut corners = [[[0.0f32; 8]; 3]; 3];
            let mut used = [0.0f32; 8];
            for (l, &t) in order.iter().enumerate() {
                for (k, v) in tris[t as usize].iter().enumerate() {
                    corners[k][0][l] = v.x;
                    corners[k][1][l] = v.y;
                    corners[k][2][l] = v.z;
                }
                used[l] = 1.0;
            }
            self.nodes[index as usize].first = self.leaves.len() as u32;
            self.leaves.push(LeafBlock {
                corners: corners.map(|c| c.map(f32x8::new)),
                used: f32x8::new(used).simd_gt(f32x8::ZERO),
            });
            return index;
        }
        // Median split on the longest axis of the centroids' box.
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for &t in order.iter() {
            lo = lo.min(centroids[t as usize]);
            hi = hi.max(centroids[t as usize]);
        }
        let axis = (hi - lo).max_position();
        let mid = order.len() / 2;
        order.select_nth_unstable_by(mid, |&x, &y| {
            centroids[x as usize][axis].total_cmp(&centroids[y as usize][axis])
        });
        let (left, right) = order.split_at_mut(mid);
        let first = self.build(tris, centroids, left);
        let second = self.build(tris, centroids, right);
        self.nodes[index as usize].first = first;
        self.nodes[index as usize].second = second;
        index
    }

    /// The winding number at `q` (0 for a tree without triangles).
    pub fn winding(&self, q: Vec3) -> f32 {
        if self.nodes.is_empty() {
            return 0.0;
        }
        let mut stack = [0u32; 64];
        let mut top = 1;
        let mut omega = 0.0f32;
        let mut leaf_sum = f32x8::ZERO;
        let qx = [f32x8::splat(q.x), f32x8::splat(q.y), f32x8::splat(q.z)];
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            let d = node.center - q;
            let d2 = d.length_squared();
            if d2 > node.far2 {
                omega += node.dipole.dot(d) / (d2 * d2.sqrt());
            } else if node.second == u32::MAX {
                leaf_sum += leaf_solid_angles(&self.leaves[node.first as usize], qx);
            } else if top + 2 <= stack.len() {
                stack[top] = node.first;
                stack[top + 1] = node.second;
                top += 2;
            }
        }
        (omega + leaf_sum.reduce_add()) / (4.0 * std::f32::consts::PI)
    }
}

/// The solid angles of a leaf's eight triangles from `q` (Van Oosterom and
/// Strackee), zero in unused lanes.
#[inline]
fn leaf_solid_angles(leaf: &LeafBlock, q: [f32x8; 3]) -> f32x8 {
    let [ca, cb, cc] = leaf.corners;
    let a = [ca[0] - q[0], ca[1] - q[1], ca[2] - q[2]];
    let b = [cb[0] - q[0], cb[1] - q[1], cb[2] - q[2]];
    let c = [cc[0] - q[0], cc[1] - q[1], cc[2] - q[2]];
    let dot = |u: [f32x8; 3], v: [f32x8; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let (la, lb, lc) = (dot(a, a).sqrt(), dot(b, b).sqrt(), dot(c, c).sqrt());
    let bxc = [
        b[1] * c[2] - b[2] * c[1],
        b[2] * c[0] - b[0] * c[2],
        b[0] * c[1] - b[1] * c[0],
    ];
    let num = dot(a, bxc);
    let den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    let omega = f32x8::splat(2.0) * num.atan2(den);
    leaf.used.select(omega, f32x8::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere of radius 1 (outward, counter-clockwise), optionally with
    /// its top cap rings removed.
    fn sphere(open: bool) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let (rings, segs) = (12u32, 24u32);
        let mut p = vec![];
        for i in 0..=rings {
            let th = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..segs {
                let ph = std::f32::consts::TAU * j as f32 / segs as f32;
                p.push(Vec3::new(
                    th.sin() * ph.cos(),
                    th.cos(),
                    th.sin() * ph.sin(),
                ));
            }
        }
        let mut t = vec![];
        for i in 0..rings {
            if open && i < 3 {
                continue;
            }
            for j in 0..segs {
                let (a, b) = (i * segs + j, i * segs + (j + 1) % segs);
                let (c, d) = (a + segs, b + segs);
                t.push([a, b, c]);
                t.push([b, d, c]);
            }
        }
        (p, t)
    }

    fn brute(p: &[Vec3], t: &[[u32; 3]], q: Vec3) -> f32 {
        t.iter()
            .map(|t| solid_angle(q, p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]))
            .sum::<f32>()
            / (4.0 * std::f32::consts::PI)
    }

    #[test]
    fn tree_matches_brute_force_closed_and_open() {
        for open in [false, true] {
            let (p, t) = sphere(open);
            let tree = WindingTree::new(&p, &t);
            let inside_sign = brute(&p, &t, Vec3::ZERO);
            assert!(
                (inside_sign.abs() - if open { 0.85 } else { 1.0 }).abs() < 0.15,
                "{inside_sign}"
            );
            let mut worst = 0.0f32;
            for i in 0..400 {
                let f = i as f32;
                let q = Vec3::new((f * 0.37).sin(), (f * 0.53).cos(), (f * 0.71).sin()) * 1.4;
                let e = (tree.winding(q) - brute(&p, &t, q)).abs();
                worst = worst.max(e);
            }
            assert!(worst < 0.03, "open {open}: {worst}");
        }
    }
}
