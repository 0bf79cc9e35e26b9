//! Scalar twins of the constraint helpers in `constraints.rs` that the
//! cloth patches share: `1/|d|`, dot products in the SIMD order, sphere
//! push-out.

use crate::constraints::MIN_LENGTH;
use crate::lanes::inv_sqrt;
use glam::Vec3;

/// `1 / max(|delta|, MIN_LENGTH)`, the twin of `step::inv_len`.
pub(crate) fn inv_len(delta: Vec3) -> f32 {
    inv_sqrt(dot(delta, delta).max(MIN_LENGTH * MIN_LENGTH))
}

/// `a.b` summed x, y, z in that order (the SIMD paths' order).
pub(crate) fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// Outward unit normal and distance; +y and 0 where the point sits on the centre.
pub(crate) fn outward(d: Vec3, d2: f32) -> (Vec3, f32) {
    let inv = inv_sqrt(d2.max(1e-30));
    if d2 > 1e-30 {
        (d * inv, d2 * inv)
    } else {
        (Vec3::Y, 0.0)
    }
}

/// A free point `x` (inverse mass `w`) pushed out of the sphere to distance
/// `R + r`: the new position and the outward normal, or None if it is outside
/// (or pinned). The scalar twin of `step::collide_vertex`, shared by strands
/// and patches.
pub(crate) fn push_out(
    x: Vec3,
    w: f32,
    sphere: [f32; 4],
    pearl_radius: f32,
) -> Option<(Vec3, Vec3)> {
    let centre = Vec3::new(sphere[0], sphere[1], sphere[2]);
    let reach = sphere[3] + pearl_radius;
    let d = x - centre;
    let d2 = dot(d, d);
    if d2 < reach * reach && w > 0.0 {
        let (n, dist) = outward(d, d2);
        Some((x + n * (reach - dist), n))
    } else {
        None
    }
}
