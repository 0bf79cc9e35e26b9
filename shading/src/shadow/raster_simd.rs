//! The SIMD rasteriser: the samples of each segment eight at a time in
//! `f32x8` lanes, the same arithmetic in the same order as the scalar
//! [`super::raster::for_each_sample`] (no fused multiply-adds in either), so
//! every lane's splat is bit for bit the scalar one. The caller then
//! deposits the lanes in lane order, which is the scalar sample order.

use super::light_frame::{LightFrame, MapPlacement};
use super::raster::{for_each_segment, Segment};
use coif_kernels::LANES;
use glam::Vec3;
use wide::f32x8;

/// Lane `l` holds `l`: sample `base + l` of a segment.
const LANE_INDEX: f32x8 = f32x8::new([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);

/// Up to eight consecutive samples of one segment: per lane the lower-left
/// texel `t0` of the splat, the four bilinear weights times the coverage
/// (texels `t0`, `t0 + 1`, `t0 + n`, `t0 + n + 1`) and the depth `z`.
/// Lanes `count..8` are past the segment's end and must be ignored.
#[derive(Clone, Copy, Debug)]
pub struct SplatX8 {
    pub t0: [usize; LANES],
    pub weights: [f32x8; 4],
    pub z: f32x8,
    pub count: usize,
}

/// SIMD twin of [`super::raster::for_each_sample`]: calls `deposit` once per
/// eight samples (fewer at the end of a segment: [`SplatX8::count`]), in
/// the scalar order. Per lane: `t = (j + 1/2) / n`, `(u, v) = (ua, va) +
/// t (du, dv)`, `floor` and fraction, weights `(1 - fx)(1 - fy) w`, ...,
/// lower-left texel clamped to `[0, n - 2]`, depth `za + t dz`.
pub fn for_each_sample_x8(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    points: &[Vec3],
    verts: usize,
    mut deposit: impl FnMut(&SplatX8),
) {
    let last = f32x8::splat(resolution.saturating_sub(2) as f32);
    let (zero, one, half) = (f32x8::ZERO, f32x8::ONE, f32x8::splat(0.5));
    let each = |seg: &Segment| {
        let (ua, va, za) = (
            f32x8::splat(seg.ua),
            f32x8::splat(seg.va),
            f32x8::splat(seg.za),
        );
        let (du, dv, dz) = (
            f32x8::splat(seg.du),
            f32x8::splat(seg.dv),
            f32x8::splat(seg.dz),
        );
        let (inv_n, w) = (f32x8::splat(seg.inv_n), f32x8::splat(seg.weight));
        let mut base = 0;
        while base < seg.samples {
            let j = f32x8::splat(base as f32) + LANE_INDEX;
            let t = (j + half) * inv_n;
            let (u, v) = (ua + du * t, va + dv * t);
            let (fu, fv) = (u.floor(), v.floor());
            let (fx, fy) = (u - fu, v - fv);
            let (gx, gy) = (one - fx, one - fy);
            // In range and never NaN (finite segment, usable placement), so
            // max/min equal the scalar clamp and the truncation is exact.
            let i0 = fu.max(zero).min(last).fast_trunc_int().to_array();
            let j0 = fv.max(zero).min(last).fast_trunc_int().to_array();
            let mut t0 = [0usize; LANES];
            for l in 0..LANES {
                t0[l] = j0[l] as usize * resolution + i0[l] as usize;
            }
            deposit(&SplatX8 {
                t0,
                weights: [gx * gy * w, fx * gy * w, gx * fy * w, fx * fy * w],
                z: za + dz * t,
                count: (seg.samples - base).min(LANES),
            });
            base += LANES;
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
