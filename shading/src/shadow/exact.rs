//! The exact reference: count the hair segments the ray toward the light
//! passes through.

use super::light_frame::LightFrame;
use super::settings::ShadowSettings;
use glam::Vec3;

/// The exact reference transmittance `exp(-k n)`, where `n` counts the hair
/// segments, as capsules of radius `settings.hair_radius`, that the ray from
/// `p` toward the light (along `-light_dir`) passes through. Segments within
/// `2 hair_radius` of `p` (the one `p` lies on and its neighbours) are not
/// counted. Segments with a non-finite end are skipped; a non-finite `p` or
/// light direction gives 1. Brute force over every segment: a reference,
/// not a kernel.
///
/// In light space the ray is the half-line `{p - t z, t >= 0}`; the squared
/// distance from a segment point `q(s) = a + s (b - a)` to it is
/// `|q_xy - p_xy|^2 + max(0, q_z - p_z)^2`, convex in `s`, so its minimum
/// over `[0, 1]` is at one of: the minimiser of the first (2D) term, of the
/// full 3D distance, or the point where `q_z = p_z` (each clamped to
/// `[0, 1]`). The ray hits the capsule when that minimum is `<= r^2`.
pub fn exact_transmittance(
    settings: &ShadowSettings,
    light_dir: Vec3,
    points: &[Vec3],
    verts_per_strand: usize,
    p: Vec3,
) -> f32 {
    let Some(frame) = LightFrame::new(light_dir) else {
        return 1.0;
    };
    if !p.is_finite() || verts_per_strand < 2 {
        return 1.0;
    }
    let n = count_crossings(&frame, settings.hair_radius, points, verts_per_strand, p, p);
    (-settings.density * n as f32).exp()
}

/// The number of segment capsules of radius `r` the ray from `p` toward the
/// light crosses, excluding segments within `2 r` of `own` (the point whose
/// shadow is wanted; `p` may be offset from it across the light).
pub(crate) fn count_crossings(
    frame: &LightFrame,
    r: f32,
    points: &[Vec3],
    verts: usize,
    p: Vec3,
    own: Vec3,
) -> usize {
    let pl = frame.to_light(p);
    let (r2, exclude2) = (r * r, 4.0 * r * r);
    let mut n = 0;
    for strand in points.chunks_exact(verts) {
        for (i, pair) in strand.windows(2).enumerate() {
            let (a, b) = (pair[0], pair[1]);
            if !(a.is_finite() && b.is_finite()) {
                continue;
            }
            if point_segment_distance_squared(own, a, b) < exclude2 {
                continue;
            }
            let (al, bl) = (frame.to_light(a), frame.to_light(b));
            let (d2, s) = ray_segment_distance_squared(pl, al, bl);
            let next_continues = strand.get(i + 2).is_some_and(|c| c.is_finite());
            if d2 <= r2 && !(s >= 1.0 && next_continues) {
                n += 1;
            }
        }
    }
    n
}

/// Squared distance from `p` to the segment `a b`.
fn point_segment_distance_squared(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let e = b - a;
    let len2 = e.length_squared();
    let s = if len2 > 0.0 {
        ((p - a).dot(e) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + e * s - p).length_squared()
}

/// Squared distance between the light-space half-line from `p` toward the
/// light (`-z`) and the segment `a b` (see [`exact_transmittance`]), and the
/// segment parameter of the nearest point.
fn ray_segment_distance_squared(p: Vec3, a: Vec3, b: Vec3) -> (f32, f32) {
    let e = b - a;
    let w = a - p;
    let dist2 = |s: f32| {
        let q = w + e * s;
        let behind = q.z.max(0.0);
        q.x * q.x + q.y * q.y + behind * behind
    };
    let minimiser = |quad: f32, lin: f32| {
        if quad > 0.0 {
            (-lin / quad).clamp(0.0, 1.0)
        } else {
            0.0
        }
    };
    let exy = e.x * e.x + e.y * e.y;
    let s_xy = minimiser(exy, w.x * e.x + w.y * e.y);
    let s_3d = minimiser(exy + e.z * e.z, w.dot(e));
    let s_cross = if e.z != 0.0 {
        (-w.z / e.z).clamp(0.0, 1.0)
    } else {
        0.0
    };
    [s_xy, s_3d, s_cross]
        .into_iter()
        .map(|s| (dist2(s), s))
        .fold(
            (f32::INFINITY, 0.0),
            |best, c| if c.0 < best.0 { c } else { best },
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_segment_distance_cases() {
        // Ray from the origin along -z.
        let p = Vec3::ZERO;
        // A segment crossing the ray's line in front (z < 0) at distance 0.
        let d =
            ray_segment_distance_squared(p, Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, -1.0))
                .0;
        assert!(d.abs() < 1e-12);
        // The same segment behind p (z > 0): nearest point is p, distance 1.
        let d =
            ray_segment_distance_squared(p, Vec3::new(-1.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0)).0;
        assert!((d - 1.0).abs() < 1e-6);
        // Offset sideways by 0.5 in y, in front: 0.25.
        let d =
            ray_segment_distance_squared(p, Vec3::new(-1.0, 0.5, -2.0), Vec3::new(1.0, 0.5, -2.0))
                .0;
        assert!((d - 0.25).abs() < 1e-6);
        // A segment running from behind to in front, offset 0.3 in x.
        let d =
            ray_segment_distance_squared(p, Vec3::new(0.3, 0.0, 2.0), Vec3::new(0.3, 0.0, -2.0)).0;
        assert!((d - 0.09).abs() < 1e-6);
    }
}
