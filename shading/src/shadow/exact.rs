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
/// light direction gives 1. Every segment is visited (a reference, not a
/// kernel; a box test skips the distance computation for segments the ray
/// cannot reach, see `count_crossings_many`).
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
    let mut n = [0];
    count_crossings_many(frame, r, points, verts, own, &[frame.to_light(p)], &mut n);
    n[0]
}

/// [`count_crossings`] for several parallel rays at once: `counts[j]`
/// (zeroed here) becomes the number of capsules the ray from the
/// light-space origin `origins[j]` crosses, excluding segments within
/// `2 r` of `own`. One pass over the segments for all the rays: each
/// segment is taken to light space once, and skipped when its light-space
/// `x y` box, grown by `r` and a rounding margin, misses the box of the
/// origins (a ray whose origin lies outside the grown box is farther than
/// `r` from the segment across the light, so no count changes); the
/// exclusion is tested once per segment. Every ray gets the count the
/// one-ray brute force gives (tested against it below, count for count).
pub(crate) fn count_crossings_many(
    frame: &LightFrame,
    r: f32,
    points: &[Vec3],
    verts: usize,
    own: Vec3,
    origins: &[Vec3],
    counts: &mut [usize],
) {
    counts.fill(0);
    let Some(first) = origins.first() else {
        return;
    };
    let (r2, exclude2) = (r * r, 4.0 * r * r);
    let (mut lo, mut hi) = (*first, *first);
    for o in origins {
        (lo, hi) = (lo.min(*o), hi.max(*o));
    }
    // The margin is far above the rounding of the distance test (about
    // 1e-7 of the coordinates' size and of r).
    let size = lo.abs().max(hi.abs());
    let reach = r * 1.001 + 1e-5 * size.x.max(size.y);
    let (lo, hi) = (lo - Vec3::splat(reach), hi + Vec3::splat(reach));
    for strand in points.chunks_exact(verts.max(1)) {
        for (i, pair) in strand.windows(2).enumerate() {
            let (a, b) = (pair[0], pair[1]);
            if !(a.is_finite() && b.is_finite()) {
                continue;
            }
            let (al, bl) = (frame.to_light(a), frame.to_light(b));
            let (smin, smax) = (al.min(bl), al.max(bl));
            if smax.x < lo.x || smin.x > hi.x || smax.y < lo.y || smin.y > hi.y {
                continue;
            }
            if point_segment_distance_squared(own, a, b) < exclude2 {
                continue;
            }
            let next_continues = strand.get(i + 2).is_some_and(|c| c.is_finite());
            for (o, n) in origins.iter().zip(counts.iter_mut()) {
                let (d2, s) = ray_segment_distance_squared(*o, al, bl);
                if d2 <= r2 && !(s >= 1.0 && next_continues) {
                    *n += 1;
                }
            }
        }
    }
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
    use coif_base::SplitMix64;

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

    /// The one-ray brute force the reference was before the box test: every
    /// segment's exclusion and ray distance, for one origin.
    fn brute_force(
        frame: &LightFrame,
        r: f32,
        points: &[Vec3],
        verts: usize,
        origin: Vec3,
        own: Vec3,
    ) -> usize {
        let mut n = 0;
        for strand in points.chunks_exact(verts) {
            for (i, pair) in strand.windows(2).enumerate() {
                let (a, b) = (pair[0], pair[1]);
                if !(a.is_finite() && b.is_finite())
                    || point_segment_distance_squared(own, a, b) < 4.0 * r * r
                {
                    continue;
                }
                let (d2, s) =
                    ray_segment_distance_squared(origin, frame.to_light(a), frame.to_light(b));
                let next_continues = strand.get(i + 2).is_some_and(|c| c.is_finite());
                if d2 <= r * r && !(s >= 1.0 && next_continues) {
                    n += 1;
                }
            }
        }
        n
    }

    #[test]
    fn many_rays_count_what_one_ray_at_a_time_counts() {
        let mut rng = SplitMix64::new(11);
        let verts = 12;
        let r = 4e-3;
        // A dense tuft of random walks, a few vertices not finite.
        let mut points = Vec::new();
        for _ in 0..150 {
            let mut p = Vec3::new(
                rng.range(-0.05, 0.05),
                rng.range(-0.05, 0.05),
                rng.range(-0.05, 0.05),
            );
            for _ in 0..verts {
                points.push(p);
                p += rng.unit_vector() * 0.01;
            }
        }
        points[5] = Vec3::NAN;
        points[verts * 7 + 11] = Vec3::new(f32::INFINITY, 0.0, 0.0);
        for (offset, light) in [
            (Vec3::ZERO, Vec3::new(0.3, -1.0, 0.2)),
            (Vec3::splat(1000.0), Vec3::Z),
        ] {
            let shifted: Vec<Vec3> = points.iter().map(|p| *p + offset).collect();
            let frame = LightFrame::new(light).unwrap();
            let (mut crossed, mut compared) = (0, 0);
            for k in (0..shifted.len()).step_by(7) {
                let own = shifted[k];
                if !own.is_finite() {
                    continue;
                }
                // Rays over a disc of 1 cm across the light (2.5 r).
                let origins: Vec<Vec3> = (0..16)
                    .map(|j| {
                        let a = j as f32 * 2.4;
                        let rho = 0.01 * ((j as f32 + 0.5) / 16.0).sqrt();
                        frame
                            .to_light(own + (frame.x_axis * a.cos() + frame.y_axis * a.sin()) * rho)
                    })
                    .collect();
                let mut counts = vec![usize::MAX; origins.len()];
                count_crossings_many(&frame, r, &shifted, verts, own, &origins, &mut counts);
                for (o, n) in origins.iter().zip(&counts) {
                    assert_eq!(*n, brute_force(&frame, r, &shifted, verts, *o, own));
                    crossed += n;
                    compared += 1;
                }
            }
            // The rays do cross hair (the comparison is not all zeros).
            assert!(
                compared > 3000 && crossed > compared,
                "{crossed} crossings over {compared} rays"
            );
        }
    }
}
