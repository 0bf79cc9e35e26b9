//! Explicit fibre geometry: capsules (sphere-swept segments, radius `r`)
//! around the segments of polylines, in a bounding-volume hierarchy (binary,
//! median split, flattened; built and traversed without recursion).
//!
//! **Why capsules.** A capsule is the set of points within `r` of a
//! segment, so the capsules of consecutive segments of a polyline share the
//! sphere at their joint and the bent tube has neither gaps nor seams; a
//! capsule is convex, so a line enters it at most once, and the first
//! entry among all capsules is the entry into their union. Strand ends are
//! hemispherical caps.
//!
//! **The offset `h`.** pbrt's hair BSDF is parameterised by the offset of
//! the hit across the fibre (`h = sin gamma_o`). In the local frame that
//! [`crate::pbrt::local_directions`]`(tangent, _, wo)` builds for
//! `wo = -dir` (x = tangent, y = `wo`'s part normal to the tangent,
//! normalised, z = x cross y), the surface normal of a lateral hit is
//! `cos(gamma_o) y - sin(gamma_o) z`, so `h = -(n . z)`. The R lobe checks
//! the sign: reflecting `wo` about that normal gives azimuth
//! `-2 gamma_o`, pbrt's `Phi(0, gamma_o, .)` (tested). Here `h` is
//! computed as `-(q . z) / r` with `q` the hit point's offset from the
//! segment's axis line, which is exactly `-(n . z)` on the lateral surface;
//! on the spherical caps (within `r` of a joint or strand end) it is the
//! value the infinite cylinder would have there, clamped to [-1, 1], an
//! approximation that touches a fraction of about `r / segment length` of
//! the hits.

use super::bvh::Bvh;
use crate::Error;
use glam::Vec3;

/// Rays ignore entries closer than this many radii to their origin.
pub const T_MIN_RADII: f32 = 1e-4;

/// One ray-fibre intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FibreHit {
    /// Distance along the (normalised) ray direction.
    pub t: f32,
    /// The hit point, `origin + t dir`.
    pub point: Vec3,
    /// The segment's unit direction (from its first point to its second).
    pub tangent: Vec3,
    /// Signed offset across the fibre in [-1, 1], pbrt's convention (see
    /// the module documentation).
    pub h: f32,
    /// Index of the segment hit (order of [`FibreScene::segment`]).
    pub segment: usize,
}

/// Capsules of radius `r` around segments, with a BVH.
#[derive(Clone, Debug)]
pub struct FibreScene {
    radius: f32,
    /// First point, unit direction and length of each segment.
    start: Vec<Vec3>,
    axis: Vec<Vec3>,
    length: Vec<f32>,
    bvh: Bvh,
}

fn invalid(name: &'static str, value: f32) -> Error {
    Error::InvalidParameter { name, value }
}

impl FibreScene {
    /// Fibres along polylines: `counts[k]` consecutive points of `points`
    /// form strand `k` (a strand of `c` points has `c - 1` segments; a
    /// strand of 0 or 1 point contributes none). Segments of zero length are
    /// dropped (a joint's sphere still covers them).
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] if the counts do not sum to `points.len()`;
    /// [`Error::InvalidParameter`] for a non-finite point (`"points"`), a
    /// radius that is not finite and positive (`"radius"`), or no segment
    /// at all (`"segments"`, value 0), or a segment whose length overflows
    /// `f32` (`"segment length"`).
    pub fn from_strands(points: &[Vec3], counts: &[usize], radius: f32) -> Result<Self, Error> {
        let total = counts
            .iter()
            .try_fold(0usize, |s, &c| s.checked_add(c))
            .unwrap_or(usize::MAX);
        if total != points.len() {
            return Err(Error::CountMismatch {
                what: "points (the sum of the strand counts)",
                expected: total,
                got: points.len(),
            });
        }
        let mut segments = Vec::with_capacity(points.len());
        let mut first = 0usize;
        for &c in counts {
            let strand = &points[first..first + c];
            segments.extend(strand.windows(2).map(|w| (w[0], w[1])));
            first += c;
        }
        Self::from_segments(&segments, radius)
    }

    /// Fibres around independent segments `(a, b)`. Segments of zero length
    /// are dropped.
    ///
    /// # Errors
    ///
    /// As [`FibreScene::from_strands`] (no count check).
    pub fn from_segments(segments: &[(Vec3, Vec3)], radius: f32) -> Result<Self, Error> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(invalid("radius", radius));
        }
        let (mut start, mut axis, mut length) = (Vec::new(), Vec::new(), Vec::new());
        for &(a, b) in segments {
            for p in [a, b] {
                if !p.is_finite() {
                    let bad = p.to_array().into_iter().find(|c| !c.is_finite());
                    return Err(invalid("points", bad.unwrap_or(f32::NAN)));
                }
            }
            let d = b - a;
            // Scaled so that long segments of huge coordinates do not
            // overflow the squared length.
            let m = d.abs().max_element();
            if m == 0.0 {
                continue;
            }
            let dn = d / m;
            let ln = dn.length();
            let (len, u) = if d.is_finite() {
                (ln * m, dn / ln)
            } else {
                return Err(invalid("segment length", f32::INFINITY));
            };
            if !len.is_finite() {
                return Err(invalid("segment length", len));
            }
            start.push(a);
            axis.push(u);
            length.push(len);
        }
        if start.is_empty() {
            return Err(invalid("segments", 0.0));
        }
        if start.len() >= (1usize << 31) {
            return Err(invalid("segments", start.len() as f32));
        }
        let boxes: Vec<(Vec3, Vec3)> = (0..start.len())
            .map(|i| {
                let (a, b) = (start[i], start[i] + axis[i] * length[i]);
                (
                    a.min(b) - Vec3::splat(radius),
                    a.max(b) + Vec3::splat(radius),
                )
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        Ok(FibreScene {
            radius,
            start,
            axis,
            length,
            bvh,
        })
    }

    /// The fibre radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Number of segments (after dropping zero-length ones).
    pub fn segment_count(&self) -> usize {
        self.start.len()
    }

    /// Segment `i`'s end points, `None` past the end.
    pub fn segment(&self, i: usize) -> Option<(Vec3, Vec3)> {
        let a = *self.start.get(i)?;
        Some((a, a + self.axis[i] * self.length[i]))
    }

    /// The box holding every capsule (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let root = &self.bvh.nodes[0];
        (root.min, root.max)
    }

    /// The entry parameter of the line `origin + t dir` (unit `dir`) into
    /// capsule `i`, or `None` if the line misses it. Negative when the
    /// entry lies behind the origin (also when the origin is inside).
    #[inline]
    fn capsule_entry(&self, i: usize, origin: Vec3, dir: Vec3) -> Option<f32> {
        let (a, u, len, r) = (self.start[i], self.axis[i], self.length[i], self.radius);
        let oa = origin - a;
        let du = dir.dot(u);
        let ou = oa.dot(u);
        let dp = dir - u * du;
        let op = oa - u * ou;
        let aa = dp.dot(dp);
        if aa > 1e-12 {
            // Closest approach of the projected line to the axis, then back
            // off by the half chord: stable however far the origin is.
            let tc = -op.dot(dp) / aa;
            let q = op + dp * tc;
            let disc = r * r - q.dot(q);
            if disc < 0.0 {
                // Misses the infinite tube, which contains both caps.
                return None;
            }
            let t = tc - (disc / aa).sqrt();
            let s = ou + t * du;
            if (0.0..=len).contains(&s) {
                return Some(t);
            }
        }
        // Enters through a cap (or travels along the axis).
        let sphere = |c: Vec3| {
            let oc = origin - c;
            let tc = -oc.dot(dir);
            let q = oc + dir * tc;
            let disc = r * r - q.dot(q);
            (disc >= 0.0).then(|| tc - disc.sqrt())
        };
        match (sphere(a), sphere(a + u * len)) {
            (Some(x), Some(y)) => Some(x.min(y)),
            (x, y) => x.or(y),
        }
    }

    /// Whether `p` lies strictly inside capsule `i` (by 0.1 % of `r`).
    #[inline]
    fn inside(&self, i: usize, p: Vec3) -> bool {
        let q = p - self.start[i];
        let s = q.dot(self.axis[i]).clamp(0.0, self.length[i]);
        let r = self.radius * 0.999;
        (q - self.axis[i] * s).length_squared() < r * r
    }

    /// The hit record for segment `i` at distance `t`.
    fn hit(&self, i: usize, origin: Vec3, dir: Vec3, t: f32) -> FibreHit {
        let point = origin + dir * t;
        let u = self.axis[i];
        let q = point - self.start[i];
        let q_perp = q - u * q.dot(u);
        let wo = -dir;
        let y = (wo - u * wo.dot(u))
            .try_normalize()
            .unwrap_or_else(|| u.any_orthonormal_vector());
        let z = u.cross(y);
        let h = (-q_perp.dot(z) / self.radius).clamp(-1.0, 1.0);
        FibreHit {
            t,
            point,
            tangent: u,
            h,
            segment: i,
        }
    }

    /// The nearest fibre along `origin + t dir`, `t` in
    /// `(T_MIN_RADII r, t_max)` (`dir` need not be unit: it is normalised,
    /// and `t` is a distance). A ray starting inside a fibre does not hit
    /// that fibre. `None` for a miss or for non-finite or zero `origin`/`dir`.
    pub fn intersect(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<FibreHit> {
        self.intersect_excluding(origin, dir, t_max, None)
    }

    /// [`FibreScene::intersect`] ignoring segment `exclude` and any entry
    /// into another capsule at a point strictly inside `exclude`'s capsule
    /// (an internal surface of the union, e.g. the next segment of the
    /// same bent strand): the continuation of a path that scattered at
    /// `exclude` passes through that fibre, whose internal paths pbrt's
    /// BSDF already accounts for.
    pub fn intersect_excluding(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_max: f32,
        exclude: Option<usize>,
    ) -> Option<FibreHit> {
        let dir = unit(origin, dir)?;
        let t_min = T_MIN_RADII * self.radius;
        let mut best: Option<(f32, usize)> = None;
        self.bvh.traverse(origin, dir, t_max, |p| {
            let i = p as usize;
            let limit = best.map_or(t_max, |b| b.0);
            if Some(i) != exclude {
                if let Some(t) = self.capsule_entry(i, origin, dir) {
                    if t > t_min
                        && t < limit
                        && !exclude.is_some_and(|e| self.inside(e, origin + dir * t))
                    {
                        best = Some((t, i));
                        return Some(t);
                    }
                }
            }
            Some(limit)
        });
        best.map(|(t, i)| self.hit(i, origin, dir, t))
    }

    /// Whether any fibre lies along `origin + t dir`, `t` in
    /// `(T_MIN_RADII r, t_max)` (same conventions as [`FibreScene::intersect`]).
    pub fn occluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        self.occluded_excluding(origin, dir, t_max, None)
    }

    /// [`FibreScene::occluded`] with [`FibreScene::intersect_excluding`]'s
    /// exclusion (the shadow ray of a hit on `exclude`).
    pub fn occluded_excluding(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_max: f32,
        exclude: Option<usize>,
    ) -> bool {
        let Some(dir) = unit(origin, dir) else {
            return false;
        };
        let t_min = T_MIN_RADII * self.radius;
        let mut found = false;
        self.bvh.traverse(origin, dir, t_max, |p| {
            let i = p as usize;
            if Some(i) != exclude {
                if let Some(t) = self.capsule_entry(i, origin, dir) {
                    if t > t_min
                        && t < t_max
                        && !exclude.is_some_and(|e| self.inside(e, origin + dir * t))
                    {
                        found = true;
                        return None;
                    }
                }
            }
            Some(t_max)
        });
        found
    }

    /// How many distinct segments' capsules the ray enters for `t` in
    /// `(T_MIN_RADII r, t_max)`: the number of fibres between a point and a
    /// light (a fibre whose capsule holds the origin is not counted; the
    /// overlapping capsules of two segments of one strand count twice when
    /// the ray enters both). 0 for non-finite or zero input.
    pub fn crossings(&self, origin: Vec3, dir: Vec3, t_max: f32) -> usize {
        let Some(dir) = unit(origin, dir) else {
            return 0;
        };
        let t_min = T_MIN_RADII * self.radius;
        let mut n = 0usize;
        self.bvh.traverse(origin, dir, t_max, |p| {
            if let Some(t) = self.capsule_entry(p as usize, origin, dir) {
                if t > t_min && t < t_max {
                    n += 1;
                }
            }
            Some(t_max)
        });
        n
    }

    /// [`FibreScene::crossings`] by testing every segment (no BVH): the
    /// reference the BVH is tested against.
    pub fn crossings_brute_force(&self, origin: Vec3, dir: Vec3, t_max: f32) -> usize {
        let Some(dir) = unit(origin, dir) else {
            return 0;
        };
        let t_min = T_MIN_RADII * self.radius;
        (0..self.segment_count())
            .filter_map(|i| self.capsule_entry(i, origin, dir))
            .filter(|&t| t > t_min && t < t_max)
            .count()
    }
}

/// `dir` normalised, if `origin` and `dir` are finite and `dir` non-zero.
#[inline]
fn unit(origin: Vec3, dir: Vec3) -> Option<Vec3> {
    if !origin.is_finite() {
        return None;
    }
    dir.try_normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::{azimuthal::phi, local_directions};
    use coif_base::rng::SplitMix64;

    #[test]
    fn h_sign_matches_the_r_lobe() {
        // A fibre along a random axis; rays from random directions at
        // random offsets. Reflecting wo about the lateral surface normal
        // lands at azimuth -2 gamma_o (pbrt's Phi(0, gamma_o, .)).
        let mut rng = SplitMix64::new(9);
        for _ in 0..500 {
            let t = rng.unit_vector();
            let scene = FibreScene::from_segments(&[(-50.0 * t, 50.0 * t)], 0.7).unwrap();
            let d = rng.unit_vector();
            if d.dot(t).abs() > 0.95 {
                continue;
            }
            // Offset across the projected width.
            let side = t.cross(d).normalize();
            let off = rng.range(-0.99, 0.99) * 0.7;
            let origin = side * off - d * 10.0 + t * rng.range(-5.0, 5.0);
            let hit = scene.intersect(origin, d, f32::INFINITY).expect("hits");
            let q = hit.point - (hit.point.dot(t)) * t;
            let n = q.normalize();
            assert!((q.length() - 0.7).abs() < 1e-4, "on the surface");
            let wo = -d;
            let wo_p = wo - t * wo.dot(t);
            let refl = 2.0 * n.dot(wo_p) * n - wo_p + t * wo.dot(t);
            let (wo_l, r_l) = local_directions(t, refl, wo);
            assert!(wo_l.z.abs() < 1e-5);
            let azimuth = r_l.z.atan2(r_l.y);
            let expected = phi(0, hit.h.asin(), 0.0);
            let diff = crate::pbrt::azimuthal::wrap(azimuth - expected);
            assert!(diff.abs() < 2e-3, "h {} az {azimuth} exp {expected}", hit.h);
            // |h| is the offset across the projected width.
            assert!((hit.h.abs() - off.abs() / 0.7).abs() < 1e-3);
        }
    }

    #[test]
    fn bvh_agrees_with_brute_force() {
        let mut rng = SplitMix64::new(4);
        let segs: Vec<(Vec3, Vec3)> = (0..3000)
            .map(|_| {
                let a = Vec3::new(
                    rng.range(-20.0, 20.0),
                    rng.range(-20.0, 20.0),
                    rng.range(-5.0, 5.0),
                );
                (a, a + rng.unit_vector() * rng.range(0.5, 6.0))
            })
            .collect();
        let scene = FibreScene::from_segments(&segs, 0.2).unwrap();
        for _ in 0..400 {
            let o = rng.unit_vector() * 40.0;
            let d = (rng.unit_vector() * 8.0 - o).normalize();
            let tmax = if rng.next_f32() < 0.5 {
                f32::INFINITY
            } else {
                rng.range(10.0, 60.0)
            };
            let n = scene.crossings(o, d, tmax);
            assert_eq!(n, scene.crossings_brute_force(o, d, tmax));
            assert_eq!(scene.occluded(o, d, tmax), n > 0);
            // The nearest hit is the smallest entry of all segments.
            let best = (0..scene.segment_count())
                .filter_map(|i| scene.capsule_entry(i, o, d).map(|t| (t, i)))
                .filter(|&(t, _)| t > T_MIN_RADII * 0.2 && t < tmax)
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let hit = scene.intersect(o, d, tmax);
            assert_eq!(best.map(|b| b.1), hit.map(|h| h.segment));
        }
    }

    #[test]
    fn hundred_thousand_segments() {
        // A long strand of 100,000 segments (a random walk) and the BVH
        // built over it without recursion; queries agree with brute force.
        let mut rng = SplitMix64::new(8);
        let mut p = Vec3::ZERO;
        let pts: Vec<Vec3> = (0..100_001)
            .map(|_| {
                p += rng.unit_vector() * 0.5;
                p
            })
            .collect();
        let scene = FibreScene::from_strands(&pts, &[pts.len()], 0.05).unwrap();
        assert_eq!(scene.segment_count(), 100_000);
        for _ in 0..20 {
            let o = rng.unit_vector() * 300.0;
            let d = (rng.unit_vector() * 20.0 - o).normalize();
            let n = scene.crossings(o, d, f32::INFINITY);
            assert_eq!(n, scene.crossings_brute_force(o, d, f32::INFINITY));
        }
    }

    #[test]
    fn caps_and_inside_origin() {
        let scene = FibreScene::from_segments(&[(Vec3::ZERO, Vec3::X * 4.0)], 1.0).unwrap();
        // Along the axis into the cap at the origin end.
        let hit = scene
            .intersect(Vec3::new(-5.0, 0.0, 0.0), Vec3::X, f32::INFINITY)
            .unwrap();
        assert!((hit.t - 4.0).abs() < 1e-5);
        // From inside: no hit.
        assert!(scene
            .intersect(Vec3::new(2.0, 0.0, 0.0), Vec3::Y, 10.0)
            .is_none());
        // Beyond the far cap, heading away: none; heading back: the cap.
        assert!(scene
            .intersect(Vec3::new(6.0, 0.0, 0.0), Vec3::X, 10.0)
            .is_none());
        let back = scene
            .intersect(Vec3::new(6.0, 0.0, 0.0), -Vec3::X, 10.0)
            .unwrap();
        assert!((back.t - 1.0).abs() < 1e-5);
        // Degenerate input.
        assert!(scene.intersect(Vec3::NAN, Vec3::X, 1.0).is_none());
        assert!(scene.intersect(Vec3::ZERO, Vec3::ZERO, 1.0).is_none());
        assert_eq!(
            scene.crossings(Vec3::new(2.0, -5.0, 0.0), Vec3::Y, f32::NAN),
            0
        );
    }

    #[test]
    fn bent_strand_has_no_internal_hit() {
        // Two segments at a right angle; a ray leaving the first capsule's
        // surface near the joint through the fibre does not stop at the
        // second capsule's internal surface.
        let pts = [
            Vec3::new(-5.0, 0.0, 0.0),
            Vec3::ZERO,
            Vec3::new(0.0, 5.0, 0.0),
        ];
        let scene = FibreScene::from_strands(&pts, &[3], 0.5).unwrap();
        let o = Vec3::new(-0.3, -0.5, 0.0); // on segment 0's surface, near the joint
        let d = Vec3::new(0.6, 1.0, 0.0).normalize();
        assert!(scene
            .intersect_excluding(o, d, f32::INFINITY, Some(0))
            .is_none());
        assert!(
            scene.intersect(o, d, f32::INFINITY).is_some(),
            "without the exclusion"
        );
    }
}
