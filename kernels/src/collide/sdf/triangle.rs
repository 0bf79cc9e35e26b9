//! The closest point of a triangle to a point, and its squared distance.
//!
//! Ericson, *Real-Time Collision Detection* (2005), section 5.1.5: the
//! point's Voronoi region of the triangle (three vertex regions, three edge
//! regions, the face) is found from the six dot products
//! `d1 = ab.ap, d2 = ac.ap, d3 = ab.bp, d4 = ac.bp, d5 = ab.cp, d6 = ac.cp`
//! and the three barycentric numerators
//! `vc = d1 d4 - d3 d2, vb = d5 d2 - d1 d6, va = d3 d6 - d5 d4`;
//! in the face region the closest point is `a + ab vb/(va+vb+vc) + ac vc/(va+vb+vc)`.
//!
//! Degenerate (zero-area) triangles are tolerated: where the formula's
//! denominators vanish the distance falls back to the nearest of the three
//! edges as segments.

use glam::Vec3;

/// A triangle's three corners, ready for distance queries.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tri {
    pub a: Vec3,
    pub b: Vec3,
    pub c: Vec3,
}

impl Tri {
    /// Squared distance from `p` to the closest point of the triangle.
    #[inline]
    pub fn distance2(&self, p: Vec3) -> f32 {
        let q = closest_point(p, self.a, self.b, self.c);
        let d2 = (p - q).length_squared();
        if d2.is_finite() {
            d2
        } else {
            self.edges_distance2(p)
        }
    }

    /// The squared distance to the nearest edge taken as a segment (the
    /// fallback for degenerate triangles).
    fn edges_distance2(&self, p: Vec3) -> f32 {
        segment_distance2(p, self.a, self.b)
            .min(segment_distance2(p, self.b, self.c))
            .min(segment_distance2(p, self.c, self.a))
    }
}

/// Squared distance from `p` to the segment `a b` (a point when `a = b`).
#[inline]
fn segment_distance2(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length_squared()
}

/// Ericson's closest point on triangle `a b c` to `p` (section 5.1.5). May
/// return a non-finite point for a degenerate triangle; [`Tri::distance2`]
/// then falls back to the edges.
#[inline]
pub(crate) fn closest_point(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a; // vertex region a
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b; // vertex region b
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3)); // edge region ab
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c; // vertex region c
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6)); // edge region ac
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + (c - b) * w; // edge region bc
    }
    let inv = 1.0 / (va + vb + vc);
    a + ab * (vb * inv) + ac * (vc * inv) // face region
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against a dense sampling of the triangle: never below the sampled
    /// minimum, and within the sampling's resolution of it.
    #[test]
    fn matches_dense_sampling() {
        let t = Tri {
            a: Vec3::new(0.0, 0.0, 0.0),
            b: Vec3::new(1.0, 0.2, 0.0),
            c: Vec3::new(0.3, 0.9, 0.4),
        };
        let n = 200;
        let mut rng = 12345u32;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 17;
            rng ^= rng << 5;
            rng as f32 / u32::MAX as f32 * 4.0 - 2.0
        };
        for _ in 0..200 {
            let p = Vec3::new(next(), next(), next());
            let mut best = f32::INFINITY;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                    let q = t.a + (t.b - t.a) * u + (t.c - t.a) * v;
                    best = best.min((p - q).length_squared());
                }
            }
            let d = t.distance2(p).sqrt();
            assert!(d <= best.sqrt() + 1e-5, "{p}: {d} > {}", best.sqrt());
            assert!(d >= best.sqrt() - 0.01, "{p}: {d} << {}", best.sqrt());
        }
    }

    #[test]
    fn degenerate_triangles_give_the_segment_distance() {
        let p = Vec3::new(0.5, 1.0, 0.0);
        // Collinear, and all three corners equal.
        let line = Tri {
            a: Vec3::ZERO,
            b: Vec3::X,
            c: Vec3::X * 2.0,
        };
        assert!((line.distance2(p) - 1.0).abs() < 1e-6);
        let point = Tri {
            a: Vec3::ONE,
            b: Vec3::ONE,
            c: Vec3::ONE,
        };
        assert!((point.distance2(Vec3::ZERO) - 3.0).abs() < 1e-6);
    }
}
