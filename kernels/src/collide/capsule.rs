//! The capsule collider: a bone or a limb.

use glam::Vec3;

/// A capsule: the points within `radius` of the segment `a`-`b` (a bone, a
/// limb), world coordinates, metres. `a == b` is a sphere, and moves hair
/// exactly as a [`crate::Sphere`] of the same centre and radius does (the
/// closest point of the segment is `a + t (b - a)` with `t = 0`: the same
/// arithmetic).
///
/// The distance of a point `p` to the capsule's axis is `|p - (a + t (b -
/// a))|` with `t = clamp(((p - a) . (b - a)) / |b - a|^2, 0, 1)` (Ericson,
/// *Real-Time Collision Detection*, 2005, 5.1.2). A capsule with a
/// non-finite coordinate or a negative or non-finite radius is ignored by
/// the step: it never puts a NaN into the hair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// One end of the axis.
    pub a: Vec3,
    /// The other end of the axis.
    pub b: Vec3,
    /// Radius around the axis, metres (>= 0).
    pub radius: f32,
}

impl Capsule {
    /// True if the step uses it: finite ends, a finite radius >= 0.
    pub fn is_valid(&self) -> bool {
        self.a.is_finite() && self.b.is_finite() && self.radius.is_finite() && self.radius >= 0.0
    }

    /// Distance from `p` to the capsule's surface (negative inside).
    pub fn distance(&self, p: Vec3) -> f32 {
        let ab = self.b - self.a;
        let len2 = ab.length_squared();
        let t = if len2 > 0.0 {
            ((p - self.a).dot(ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - (self.a + ab * t)).length() - self.radius
    }
}
