//! Dev-only fixtures of the coif-shading tests.
#![allow(dead_code)]

use coif_base::{SplitMix64, Vec3Lanes};
use coif_shading::shadow::OpacityShadowMap;
use glam::Vec3;

/// A unit direction at longitudinal angle `theta` from the normal plane of
/// the fibre axis `X` (`sin theta = w . X`) and azimuth `phi` around `X`.
pub fn fibre_direction(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(
        theta.sin(),
        theta.cos() * phi.cos(),
        theta.cos() * phi.sin(),
    )
}

/// `strands` random curly strands of `verts` vertices, 1 cm segments,
/// roots within 10 cm of the origin: each segment is the strand's
/// direction plus `wander` times a random unit vector, renormalised.
pub fn curly_hair(strands: usize, verts: usize, seed: u64, wander: f32) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    let mut pts = Vec::with_capacity(strands * verts);
    for _ in 0..strands {
        let mut p = rng.unit_vector() * 0.1;
        let d = rng.unit_vector();
        for _ in 0..verts {
            pts.push(p);
            p += (d + rng.unit_vector() * wander).normalize() * 0.01;
        }
    }
    pts
}

/// Every stored texel of `map` as bits (row by row, layer innermost), for
/// bit-for-bit comparisons.
pub fn stored_bits(map: &OpacityShadowMap) -> Vec<u32> {
    let s = map.settings();
    let n = s.resolution;
    let mut v = Vec::with_capacity(n * n * s.layers);
    for y in 0..n {
        for x in 0..n {
            for l in 0..s.layers {
                v.push(map.stored_opacity(x, y, l).to_bits());
            }
        }
    }
    v
}

/// The whole strands of `points` (`verts` each) in lane layout for
/// `build_lanes` (`shadow::to_lane_rows`); lanes past the last strand hold
/// `1e30` (finite, far away: a build that read them would place its map
/// elsewhere). Returns the rows and the strand count.
pub fn lane_rows(points: &[Vec3], verts: usize) -> (Vec<Vec3Lanes>, usize) {
    let mut rows = Vec::new();
    let strands = coif_shading::shadow::to_lane_rows(points, verts, Vec3::splat(1.0e30), &mut rows);
    (rows, strands)
}
