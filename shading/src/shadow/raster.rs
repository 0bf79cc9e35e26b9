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

/// One sample's bilinear splat: the four texels `t0`, `t0 + 1`, `t0 + n`,
/// `t0 + n + 1` around it and their weights times the sample's coverage.
#[derive(Clone, Copy, Debug)]
pub struct Splat {
    pub t0: usize,
    pub weights: [f32; 4],
}

/// One finite segment ready to sample: its start in texel coordinates
/// `(ua, va)` and light-space depth `za`, its extent `(du, dv, dz)` (texels,
/// texels, depth), the number of samples `n`, `1 / n`, and the coverage each
/// sample deposits, `A / (n h^2)`.
#[derive(Clone, Copy, Debug)]
pub struct Segment {
    pub ua: f32,
    pub va: f32,
    pub za: f32,
    pub du: f32,
    pub dv: f32,
    pub dz: f32,
    pub samples: usize,
    pub inv_n: f32,
    pub weight: f32,
}

/// Calls `visit(segment)` for every segment of the hair (`points`, `verts`
/// per strand) whose two ends are finite, strand after strand, root to tip.
/// A segment starts a piece (and gets the cap) when it is the strand's
/// first or follows a broken one. The scalar setup; the SIMD twin,
/// [`super::raster_simd::for_each_segment_x8`], makes the same segments bit
/// for bit.
pub fn for_each_segment(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    points: &[Vec3],
    verts: usize,
    mut visit: impl FnMut(&Segment),
) {
    if verts < 2 || resolution < 2 {
        return;
    }
    let max_samples = 4 * resolution;
    let cap_area = std::f32::consts::PI * hair_radius * hair_radius;
    let inv_h = placement.inv_texel;
    let inv_h2 = inv_h * inv_h;
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
                let n =
                    ((SAMPLES_PER_TEXEL * len_xy * inv_h).ceil() as usize).clamp(1, max_samples);
                let inv_n = 1.0 / n as f32;
                let cap = if first { cap_area } else { 0.0 };
                first = false;
                let (ua, va) = placement.texel_coords(prev_light.x, prev_light.y);
                visit(&Segment {
                    ua,
                    va,
                    za: prev_light.z,
                    du: d.x * inv_h,
                    dv: d.y * inv_h,
                    dz: d.z,
                    samples: n,
                    inv_n,
                    weight: (2.0 * hair_radius * len_xy + cap) * inv_h2 * inv_n,
                });
            } else {
                first = true;
            }
            prev = next;
            prev_light = next_light;
        }
    }
}

/// Calls `deposit(splat, z)` for every sample point of every segment of the
/// hair (`points`, `verts` per strand), with `z` the sample's light-space
/// depth. Segments with a non-finite end are skipped. Deterministic: strand
/// after strand, root to tip. The scalar reference; the SIMD twin is
/// [`super::raster_simd::for_each_sample_x8`].
///
/// Sample `j` of a segment lies at `t = (j + 1/2) / n` along it; its
/// texel coordinates `(u, v)` split into the lower-left texel
/// `(floor u, floor v)` and bilinear fractions `(fx, fy)`.
/// The placement's margin (hair radius plus a texel on every side) keeps
/// every sample's four texels inside the map; the lower-left texel is still
/// clamped to `[0, n - 2]` so that rounding can never index outside it.
pub fn for_each_sample(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    points: &[Vec3],
    verts: usize,
    mut deposit: impl FnMut(&Splat, f32),
) {
    let last = resolution.saturating_sub(2) as f32;
    let each = |seg: &Segment| {
        for j in 0..seg.samples {
            let t = (j as f32 + 0.5) * seg.inv_n;
            let (u, v) = (seg.ua + seg.du * t, seg.va + seg.dv * t);
            let (fu, fv) = (u.floor(), v.floor());
            let (fx, fy) = (u - fu, v - fv);
            let (gx, gy) = (1.0 - fx, 1.0 - fy);
            let i0 = fu.clamp(0.0, last) as usize;
            let j0 = fv.clamp(0.0, last) as usize;
            let w = seg.weight;
            let splat = Splat {
                t0: j0 * resolution + i0,
                weights: [gx * gy * w, fx * gy * w, gx * fy * w, fx * fy * w],
            };
            deposit(&splat, seg.za + seg.dz * t);
        }
    };
    for_each_segment(
        frame,
        placement,
        resolution,
        hair_radius,
        points,
        verts,
        each,
    );
}
