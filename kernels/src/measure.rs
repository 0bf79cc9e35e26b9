//! Measurements of a simulated state: stretch, penetration, distance between
//! two runs. For tests, the time-against-error study and the demo's readout;
//! not per-frame work.

use crate::lanes::LANES;
use crate::{Sphere, Strands};
use glam::Vec3;

/// What a state looks like against its rest lengths and a sphere rig.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measures {
    /// Largest `polyline length / rest length - 1` over strands.
    pub max_stretch: f32,
    /// Largest `|tip - root| / rest arc length - 1` over strands (what the
    /// strain limit `max_stretch` bounds).
    pub max_tip_strain: f32,
    /// Largest `|x_{v+1} - x_v| / rest - 1` over segments with rest > 0.
    pub max_segment_strain: f32,
    /// Deepest point below a sphere's surface (the sphere's own radius, not
    /// counting the pearl radius), over free vertices and segment midpoints,
    /// in metres; 0 when nothing is inside.
    pub max_penetration: f32,
}

/// Measures every strand of `strands` against its rest lengths and `spheres`.
pub fn measure(strands: &Strands, spheres: &[Sphere]) -> Measures {
    let mut m = Measures::default();
    let verts = strands.verts;
    let local: Vec<(Vec3, f32)> = spheres
        .iter()
        .map(|s| ((s.center.as_dvec3() - strands.origin).as_vec3(), s.radius))
        .collect();
    let depth = |p: Vec3| {
        local
            .iter()
            .map(|&(c, r)| r - (p - c).length())
            .fold(0.0f32, f32::max)
    };
    for i in 0..strands.strand_count {
        let (b, l) = (i / LANES, i % LANES);
        let at = |v: usize| strands.pos[b * verts + v].lane(l);
        let rest = |v: usize| strands.rest_len[b * verts + v].as_array()[l];
        let (mut length, mut rest_total) = (0.0f32, 0.0f32);
        for v in 0..verts - 1 {
            let seg = (at(v + 1) - at(v)).length();
            length += seg;
            rest_total += rest(v);
            if rest(v) > 0.0 {
                m.max_segment_strain = m.max_segment_strain.max(seg / rest(v) - 1.0);
            }
            m.max_penetration = m
                .max_penetration
                .max(depth(at(v + 1)))
                .max(depth((at(v) + at(v + 1)) * 0.5));
        }
        if rest_total > 0.0 {
            m.max_stretch = m.max_stretch.max(length / rest_total - 1.0);
            let tip = (at(verts - 1) - at(0)).length();
            m.max_tip_strain = m.max_tip_strain.max(tip / rest_total - 1.0);
        }
    }
    m
}

/// Largest and root-mean-square distance between corresponding vertices of
/// two sets of the same shape (`(INFINITY, INFINITY)` if the shapes differ).
pub fn distances(a: &Strands, b: &Strands) -> (f32, f32) {
    if a.strand_count != b.strand_count || a.verts != b.verts {
        return (f32::INFINITY, f32::INFINITY);
    }
    let shift = (b.origin - a.origin).as_vec3();
    let (mut worst, mut sum2) = (0.0f32, 0.0f64);
    for i in 0..a.strand_count {
        let (blk, l) = (i / LANES, i % LANES);
        for v in 0..a.verts {
            let k = blk * a.verts + v;
            let d = (a.pos[k].lane(l) - (b.pos[k].lane(l) + shift)).length();
            worst = worst.max(d);
            sum2 += (d as f64) * (d as f64);
        }
    }
    (
        worst,
        (sum2 / (a.strand_count * a.verts) as f64).sqrt() as f32,
    )
}

/// Largest distance between corresponding vertices of two sets of the same
/// shape (`f32::INFINITY` if the shapes differ).
pub fn max_distance(a: &Strands, b: &Strands) -> f32 {
    distances(a, b).0
}

/// Largest vertex speed `|x - x_prev| / dt` in m/s, a measure of jitter at rest.
pub fn max_speed(strands: &Strands, dt: f32) -> f32 {
    let mut worst = 0.0f32;
    for i in 0..strands.strand_count {
        let (b, l) = (i / LANES, i % LANES);
        for v in 0..strands.verts {
            let k = b * strands.verts + v;
            worst = worst.max((strands.pos[k].lane(l) - strands.prev[k].lane(l)).length() / dt);
        }
    }
    worst
}
