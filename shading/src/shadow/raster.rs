//! Rasterising hair segments into a light-space map: points along each
//! segment at texel spacing, each splatted bilinearly into the four
//! texels around it.
//!
//! A segment `a b` of a hair of radius `r` seen from the light covers the
//! projected area `A = 2 r |(b - a)_xy|`, plus `pi r^2` for the round cap
//! that starts a strand (a strand's shadow is the union of its capsules;
//! neighbouring caps overlap, and the exact reference counts a ray through a
//! joint once). Spread over the `n` samples
//! (`n = ceil(|(b - a)_xy| / h)`, at least 1, a texel apart: the
//! bilinear splats of points a texel apart along a line sum to a smooth
//! band; half a texel apart measured the same error and built 1.6 times
//! slower), each
//! deposits `A / (n h^2)`: the map then holds, per texel, the texel-averaged
//! number of segments a ray through it crosses, which is what the exact
//! reference counts at a point.

use super::light_frame::{LightFrame, MapPlacement};
use glam::Vec3;

/// Samples per texel of projected segment length.
const SAMPLES_PER_TEXEL: f32 = 1.0;

/// One bilinear splat target: texel index `y * n + x` and weight.
pub type Corner = (usize, f32);

/// Calls `deposit(corners, z)` for every sample point of every segment of
/// the hair (`points`, `verts` per strand), where `corners` are the in-map
/// texels around the sample with their splat weight times the sample's
/// coverage, and `z` the sample's light-space depth. Segments with a
/// non-finite end are skipped. Deterministic: strand after strand, root to
/// tip.
pub fn for_each_sample(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    points: &[Vec3],
    verts: usize,
    mut deposit: impl FnMut(&[Corner; 4], usize, f32),
) {
    if verts < 2 {
        return;
    }
    let max_samples = 4 * resolution;
    let cap_area = std::f32::consts::PI * hair_radius * hair_radius;
    let inv_h2 = placement.inv_texel * placement.inv_texel;
    for strand in points.chunks_exact(verts) {
        let mut prev = strand[0];
        let mut prev_light = frame.to_light(prev);
        // The strand's (or, after a broken vertex, the piece's) first segment.
        let mut first = true;
        for &next in &strand[1..] {
            let next_light = frame.to_light(next);
            if prev.is_finite() && next.is_finite() {
                let d = next_light - prev_light;
                let len_xy = (d.x * d.x + d.y * d.y).sqrt();
                let n = ((SAMPLES_PER_TEXEL * len_xy * placement.inv_texel).ceil() as usize)
                    .clamp(1, max_samples);
                let inv_n = 1.0 / n as f32;
                let cap = if first { cap_area } else { 0.0 };
                let weight = (2.0 * hair_radius * len_xy + cap) * inv_h2 * inv_n;
                first = false;
                for j in 0..n {
                    let t = (j as f32 + 0.5) * inv_n;
                    let q = prev_light + d * t;
                    let mut corners = [(0usize, 0.0f32); 4];
                    let count =
                        splat_corners(placement, resolution, q.x, q.y, weight, &mut corners);
                    deposit(&corners, count, q.z);
                }
            } else {
                first = true;
            }
            prev = next;
            prev_light = next_light;
        }
    }
}

/// The in-map texels around light-space `(x, y)` with bilinear weights times
/// `weight` (zero weights dropped); returns how many of `out` are filled.
#[inline(always)]
fn splat_corners(
    placement: &MapPlacement,
    n: usize,
    x: f32,
    y: f32,
    weight: f32,
    out: &mut [Corner; 4],
) -> usize {
    let (u, v) = placement.texel_coords(x, y);
    let (fu, fv) = (u.floor(), v.floor());
    let (fx, fy) = (u - fu, v - fv);
    let (i0, j0) = (fu as isize, fv as isize);
    let weights = [
        (1.0 - fx) * (1.0 - fy),
        fx * (1.0 - fy),
        (1.0 - fx) * fy,
        fx * fy,
    ];
    let mut count = 0;
    for (c, w) in weights.into_iter().enumerate() {
        let (i, j) = (i0 + (c & 1) as isize, j0 + (c >> 1) as isize);
        if w > 0.0 && i >= 0 && j >= 0 && (i as usize) < n && (j as usize) < n {
            out[count] = (j as usize * n + i as usize, w * weight);
            count += 1;
        }
    }
    count
}
