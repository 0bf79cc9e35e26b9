//! Rasterising hair segments into a light-space map: points along each
//! segment at texel spacing, each splatted bilinearly into the four
//! texels around it. This is the SIMD path; `shadow/scalar/raster.rs` is its
//! scalar twin.
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
//!
//! Steps, in both twins: the setup of eight segments of a strand at a time,
//! then the samples of each segment eight at a time in `f32x8` lanes, the
//! same arithmetic in the same order as the scalar (no fused multiply-adds
//! in either), so every lane's splat is bit for bit the scalar one:
//!
//! 1. Segment setup: light-space ends, length across the light, sample
//!    count `n = ceil(|d_xy| / h)` clamped to `[1, 4 res]`, `1 / n`,
//!    coverage per sample (with the cap on a piece's first segment).
//! 2. Per sample: `t = (j + 1/2) / n`, texel coordinates, lower-left texel
//!    (clamped to `[0, n - 2]`) and bilinear weights times the coverage,
//!    depth `za + t dz`.
//! 3. Deposit, in strand and sample order (the SIMD caller deposits the
//!    lanes in lane order, which is the scalar sample order).

use super::light_frame::{LightFrame, MapPlacement};
use coif_base::{Vec3x8, LANES};
use glam::Vec3;
use wide::{f32x8, i32x8};

/// Samples per texel of projected segment length.
pub(crate) const SAMPLES_PER_TEXEL: f32 = 1.0;

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

/// Lane `l` holds `l`: sample `base + l` of a segment.
const LANE_INDEX: f32x8 = f32x8::new([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);

/// Up to eight consecutive samples of one segment: per lane the lower-left
/// texel `t0` of the splat, the four bilinear weights times the coverage
/// (texels `t0`, `t0 + 1`, `t0 + n`, `t0 + n + 1`) and the depth `z`.
/// Lanes `count..8` are past the segment's end and must not be deposited
/// (their `t0` is still clamped into the map, so they may be read from).
#[derive(Clone, Copy, Debug)]
pub struct SplatX8 {
    /// Lower-left texel per lane.
    pub t0: [usize; LANES],
    /// Weights of `t0`, `t0 + 1`, `t0 + n`, `t0 + n + 1` per lane.
    pub weights: [f32x8; 4],
    /// Light-space depth per lane.
    pub z: f32x8,
    /// Lanes that hold samples (the rest are past the segment's end).
    pub count: usize,
}

/// SIMD twin of [`super::scalar::raster::for_each_segment`]: the setup of eight
/// consecutive segments of a strand per step (light-space ends, length
/// across the light, sample count `n = ceil(|d_xy| / h)` clamped to
/// `[1, 4 res]`, `1 / n`, coverage per sample, start and step in texel
/// coordinates), with the same operations in the same order, so each
/// [`Segment`] equals the scalar one bit for bit. `visit` is called for the
/// segments whose two ends are finite, in strand order. A segment starts a
/// piece (and gets the cap `pi r^2`) when it is the strand's first or the
/// vertex before it is not finite, as in the scalar.
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
    let axes = [frame.x_axis, frame.y_axis, frame.z_axis].map(Vec3x8::splat);
    let to_light = |p: Vec3x8| Vec3x8 {
        x: p.dot(axes[0]),
        y: p.dot(axes[1]),
        z: p.dot(axes[2]),
    };
    let max_samples = f32x8::splat((4 * resolution) as f32);
    let cap_area = std::f32::consts::PI * hair_radius * hair_radius;
    let inv_h = placement.inv_texel;
    let inv_h_x8 = f32x8::splat(inv_h);
    let inv_h2 = f32x8::splat(inv_h * inv_h);
    let diameter = f32x8::splat(2.0 * hair_radius);
    let (x0, y0) = (f32x8::splat(placement.x0), f32x8::splat(placement.y0));
    let (one, half) = (f32x8::ONE, f32x8::splat(0.5));
    for strand in points.chunks_exact(verts) {
        let segments = verts - 1;
        let mut k0 = 0;
        while k0 < segments {
            // 1. Segment setup, eight segments at a time.
            let count = (segments - k0).min(LANES);
            // Vertices k0 - 1 ..= k0 + count: `finite[i]` is vertex
            // k0 - 1 + i (false before the root); lane l's segment runs
            // from vertex k0 + l to k0 + l + 1.
            let mut finite = [false; LANES + 2];
            let (mut a, mut b) = (Vec3x8::ZERO, Vec3x8::ZERO);
            finite[0] = k0 > 0 && strand[k0 - 1].is_finite();
            finite[1] = strand[k0].is_finite();
            for l in 0..count {
                let (p, q) = (strand[k0 + l], strand[k0 + l + 1]);
                finite[l + 2] = q.is_finite();
                a.set_lane(l, p);
                b.set_lane(l, q);
            }
            let (la, lb) = (to_light(a), to_light(b));
            let d = lb - la;
            let len_xy = (d.x * d.x + d.y * d.y).sqrt();
            // The scalar's `ceil as usize` clamped to [1, 4 res]: equal for
            // the finite, non-negative lengths of finite segments.
            let n = (one * len_xy * inv_h_x8).ceil().max(one).min(max_samples);
            let inv_n = one / n;
            let cap = f32x8::new(std::array::from_fn(
                |l| {
                    if finite[l] {
                        0.0
                    } else {
                        cap_area
                    }
                },
            ));
            let weight = (diameter * len_xy + cap) * inv_h2 * inv_n;
            let ua = (la.x - x0) * inv_h_x8 - half;
            let va = (la.y - y0) * inv_h_x8 - half;
            let (du, dv) = (d.x * inv_h_x8, d.y * inv_h_x8);
            let n = n.fast_trunc_int().to_array();
            let [ua, va, za, du, dv, dz, inv_n, weight] =
                [ua, va, la.z, du, dv, d.z, inv_n, weight].map(|v| v.to_array());
            for l in 0..count {
                if finite[l + 1] && finite[l + 2] {
                    visit(&Segment {
                        ua: ua[l],
                        va: va[l],
                        za: za[l],
                        du: du[l],
                        dv: dv[l],
                        dz: dz[l],
                        samples: n[l] as usize,
                        inv_n: inv_n[l],
                        weight: weight[l],
                    });
                }
            }
            k0 += LANES;
        }
    }
}

/// SIMD twin of [`super::scalar::raster::for_each_sample`]: calls `deposit` once per
/// eight samples (fewer at the end of a segment: [`SplatX8::count`]), in
/// the scalar order. Per lane: `t = (j + 1/2) / n`, `(u, v) = (ua, va) +
/// t (du, dv)`, `floor` and fraction, weights `(1 - fx)(1 - fy) w`, ...,
/// lower-left texel clamped to `[0, n - 2]`, depth `za + t dz`.
pub fn for_each_sample(
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
    let row = i32x8::splat(resolution as i32);
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
            // 2. Eight samples' splats and depths.
            let j = f32x8::splat(base as f32) + LANE_INDEX;
            let t = (j + half) * inv_n;
            let (u, v) = (ua + du * t, va + dv * t);
            let (fu, fv) = (u.floor(), v.floor());
            let (fx, fy) = (u - fu, v - fv);
            let (gx, gy) = (one - fx, one - fy);
            // In range and never NaN (finite segment, usable placement), so
            // max/min equal the scalar clamp and the truncation is exact.
            let i0 = fu.max(zero).min(last).fast_trunc_int();
            let j0 = fv.max(zero).min(last).fast_trunc_int();
            // Below n^2 <= 8192^2 < 2^31: no overflow in i32.
            let t0 = (j0 * row + i0).to_array();
            // 3. Deposit (the caller goes through the lanes in order).
            deposit(&SplatX8 {
                t0: t0.map(|t| t as usize),
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
