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
//! (`n = round(|(b - a)_xy| / h)`, at least 1, so samples lie between
//! 2/3 of a texel and 1.5 texels apart: the bilinear splats of points
//! about a texel apart along a line sum to a smooth band, which the
//! bilinear lookup smooths again; half a texel apart measured the same
//! error and built 1.6 times slower; rounding instead of `ceil`, which put
//! every segment's samples at most a texel apart, takes 30 % fewer samples
//! on the default frame for 0.7 % more error against the exact reference
//! there, 0.9 % less on the report's scene: `shading/SHADOWS.md`), each
//! deposits `A / (n h^2)`: the map then holds, per texel, the texel-averaged
//! number of segments a ray through it crosses, which is what the exact
//! reference counts at a point.
//!
//! Steps, in both twins: the setup of a group of up to eight consecutive
//! segments of a strand (`k0 .. k0 + 8`), then the group's samples in
//! rounds, round `j` taking sample `j` of every segment of the group that
//! has one (eight segments in the `F32Lanes` lanes: the lanes stay full however
//! few samples a segment has, where one segment's samples per register left
//! most lanes idle on short segments), the same arithmetic in the same
//! order in both twins (no fused multiply-adds in either), so every lane's
//! splat is bit for bit the scalar one:
//!
//! 1. Segment setup: light-space ends, length across the light, sample
//!    count `n = round(|d_xy| / h)` (as `floor(x + 1/2)`) clamped to
//!    `[1, 4 res]`, `1 / n`,
//!    coverage per sample (with the cap on a piece's first segment).
//! 2. Per round `j` and segment: `t = (j + 1/2) / n`, texel coordinates,
//!    lower-left texel (clamped to `[0, n - 2]`) and bilinear weights times
//!    the coverage, depth `za + t dz`.
//! 3. Deposit, in strand, group, round and segment order (the SIMD caller
//!    deposits the active lanes in lane order, which is the scalar order).

use super::light_frame::{LightFrame, MapPlacement};
use super::strand_lanes::StrandLanes;
use coif_base::lanes::lanes_of_bits;
use coif_base::lanes::{block_of_group, F32Lanes, I32Lanes, GROUP_LANES};
use coif_base::{Vec3Lanes, LANES};
use glam::Vec3;

/// Samples per texel of projected segment length.
pub(crate) const SAMPLES_PER_TEXEL: f32 = 1.0;

/// One finite segment ready to sample (the scalar twin's setup): its start
/// in texel coordinates `(ua, va)` and light-space depth `za`, its extent
/// `(du, dv, dz)` (texels, texels, depth), the number of samples `n`,
/// `1 / n`, and the coverage each sample deposits, `A / (n h^2)`.
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

/// One round of a group of segments: per lane (segment `k0 + l` of the
/// strand) the lower-left texel `t0` of its sample's splat, the four
/// bilinear weights times the coverage (texels `t0`, `t0 + 1`, `t0 + n`,
/// `t0 + n + 1`) and the depth `z`. Only the lanes set in `active` hold a
/// sample (the others' segment has fewer samples, is not finite or is past
/// the strand's end); every lane's `t0` is clamped into the map, so it may
/// be read from.
#[derive(Clone, Copy, Debug)]
pub struct SplatX8 {
    /// Lower-left texel per lane.
    pub t0: [usize; LANES],
    /// The same as `i32` lanes.
    pub t0_simd: I32Lanes,
    /// Weights of `t0`, `t0 + 1`, `t0 + n`, `t0 + n + 1` per lane.
    pub weights: [F32Lanes; 4],
    /// Light-space depth per lane.
    pub z: F32Lanes,
    /// Bit `l` set: lane `l` holds a sample to deposit.
    pub active: u32,
}

impl SplatX8 {
    /// The active lanes in lane order.
    #[inline(always)]
    pub fn lanes(&self) -> impl Iterator<Item = usize> {
        let mut m = self.active;
        std::iter::from_fn(move || {
            (m != 0).then(|| {
                let l = m.trailing_zeros() as usize;
                m &= m - 1;
                l
            })
        })
    }
}

/// What the rasterising of one pass shares: the light frame's axes, the
/// placement in texel units, the map's size and the hair radius, splatted
/// into lanes once.
#[derive(Clone, Copy)]
struct Raster {
    axes: [Vec3Lanes; 3],
    max_samples: F32Lanes,
    cap_area: F32Lanes,
    inv_h: F32Lanes,
    inv_h2: F32Lanes,
    diameter: F32Lanes,
    x0: F32Lanes,
    y0: F32Lanes,
    last: F32Lanes,
    row: I32Lanes,
    top: I32Lanes,
}

impl Raster {
    /// `None` for maps under two texels a side (nothing to splat into).
    fn new(
        frame: &LightFrame,
        placement: &MapPlacement,
        resolution: usize,
        hair_radius: f32,
    ) -> Option<Raster> {
        if resolution < 2 {
            return None;
        }
        let inv_h = placement.inv_texel;
        Some(Raster {
            axes: [frame.x_axis, frame.y_axis, frame.z_axis].map(Vec3Lanes::splat),
            max_samples: F32Lanes::splat((4 * resolution) as f32),
            cap_area: F32Lanes::splat(std::f32::consts::PI * hair_radius * hair_radius),
            inv_h: F32Lanes::splat(inv_h),
            inv_h2: F32Lanes::splat(inv_h * inv_h),
            diameter: F32Lanes::splat(2.0 * hair_radius),
            x0: F32Lanes::splat(placement.x0),
            y0: F32Lanes::splat(placement.y0),
            last: F32Lanes::splat(resolution.saturating_sub(2) as f32),
            row: I32Lanes::splat(resolution as i32),
            // The largest lower-left texel, (n - 2) n + n - 2.
            top: I32Lanes::splat((resolution * resolution - resolution - 2) as i32),
        })
    }

    /// Light-space coordinates of eight points (the scalar's unfused dot
    /// products).
    #[inline(always)]
    fn light_space(&self, p: Vec3Lanes) -> Vec3Lanes {
        Vec3Lanes {
            x: p.dot(self.axes[0]),
            y: p.dot(self.axes[1]),
            z: p.dot(self.axes[2]),
        }
    }

    /// Steps 1 (from the light-space ends `la`, `lb` on) to 3 for eight
    /// segments, one per lane: the lanes set in `sampled` are sampled,
    /// with the coverage `cap` (`pi r^2` or 0) added to each one's first
    /// sample weight sum.
    #[inline(always)]
    fn segments(
        &self,
        la: Vec3Lanes,
        lb: Vec3Lanes,
        sampled: u32,
        cap: F32Lanes,
        deposit: &mut impl FnMut(&SplatX8),
    ) {
        let (zero, one, half) = (F32Lanes::ZERO, F32Lanes::ONE, F32Lanes::splat(0.5));
        let d = lb - la;
        let len_xy = (d.x * d.x + d.y * d.y).sqrt();
        // The scalar's `floor(x + 1/2) as usize` clamped to [1, 4 res]: equal for
        // the finite, non-negative lengths of finite segments (lanes
        // not sampled may hold anything; they are never deposited).
        let n = (one * len_xy * self.inv_h + half)
            .floor()
            .max(one)
            .min(self.max_samples);
        let inv_n = one / n;
        let w = (self.diameter * len_xy + cap) * self.inv_h2 * inv_n;
        let ua = (la.x - self.x0) * self.inv_h - half;
        let va = (la.y - self.y0) * self.inv_h - half;
        let (du, dv, za, dz) = (d.x * self.inv_h, d.y * self.inv_h, la.z, d.z);
        // Per group of eight lanes, all the rounds of one group before the
        // next: the deposits come in the same order at 8 and 16 lanes
        // (sums into a texel depend on their order).
        for k in 0..LANES / GROUP_LANES {
            let group = sampled & (((1u32 << GROUP_LANES) - 1) << (k * GROUP_LANES));
            if group == 0 {
                continue;
            }
            // The most samples of a sampled lane (n >= 1 there, an exact
            // integer): the rounds.
            let sampled_lanes = I32Lanes::new(std::array::from_fn(|l| -((group >> l) as i32 & 1)));
            let rounds = (n.fast_trunc_int() & sampled_lanes).reduce_max();
            for j in 0..rounds {
                // 2. Sample j of every segment of the group.
                let jf = F32Lanes::splat(j as f32); // j < 2^24: exact
                let t = (jf + half) * inv_n;
                let (u, v) = (ua + du * t, va + dv * t);
                let (fu, fv) = (u.floor(), v.floor());
                let (fx, fy) = (u - fu, v - fv);
                let (gx, gy) = (one - fx, one - fy);
                // max/min equal the scalar clamp on the sampled lanes
                // (finite); NaN lanes (not sampled) land on 0 or `last`
                // (`max`/`min` return the other operand), in the map.
                let i0 = fu.max(zero).min(self.last).fast_trunc_int();
                let j0 = fv.max(zero).min(self.last).fast_trunc_int();
                // Below n^2 <= 8192^2 < 2^31: no overflow in i32.
                // Lanes not sampled may be garbage: clamped into the map.
                let t0_simd = (j0 * self.row + i0).max(I32Lanes::ZERO).min(self.top);
                let t0 = t0_simd.to_array();
                // j < n, both exact small integers in f32.
                let active = jf.simd_lt(n).to_bitmask() & group;
                // 3. Deposit (the caller goes through the lanes in order).
                deposit(&SplatX8 {
                    t0: t0.map(|t| t as usize),
                    t0_simd,
                    weights: [gx * gy * w, fx * gy * w, gx * fy * w, fx * fy * w],
                    z: za + dz * t,
                    active,
                });
            }
        }
    }
}

/// SIMD twin of [`super::scalar::raster::for_each_sample`]: per group of
/// eight consecutive segments of a strand, the setup in `F32Lanes` lanes
/// (light-space ends, length across the light, sample count `n =
/// round(|d_xy| / h)` clamped to `[1, 4 res]`, `1 / n`, coverage per
/// sample, start and step in texel coordinates: the scalar operations in
/// the scalar order), then `deposit` once per round `j < max n` with lane
/// `l` holding sample `j` of segment `k0 + l` (`t = (j + 1/2) / n`, `(u,
/// v) = (ua, va) + t (du, dv)`, `floor` and fraction, weights `(1 - fx)(1 -
/// fy) w`, ..., lower-left texel clamped to `[0, n - 2]`, depth `za + t
/// dz`). A segment is sampled when both its ends are finite; it starts a
/// piece (and gets the cap `pi r^2`) when it is the strand's first or the
/// vertex before it is not finite, as in the scalar.
pub fn for_each_sample(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    points: &[Vec3],
    verts: usize,
    mut deposit: impl FnMut(&SplatX8),
) {
    if verts < 2 {
        return;
    }
    let Some(raster) = Raster::new(frame, placement, resolution, hair_radius) else {
        return;
    };
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
            let (mut a, mut b) = (Vec3Lanes::ZERO, Vec3Lanes::ZERO);
            finite[0] = k0 > 0 && strand[k0 - 1].is_finite();
            finite[1] = strand[k0].is_finite();
            for l in 0..count {
                let (p, q) = (strand[k0 + l], strand[k0 + l + 1]);
                finite[l + 2] = q.is_finite();
                a.set_lane(l, p);
                b.set_lane(l, q);
            }
            let mut sampled = 0u32;
            for l in 0..count {
                if finite[l + 1] && finite[l + 2] {
                    sampled |= 1 << l;
                }
            }
            k0 += LANES;
            if sampled == 0 {
                continue;
            }
            let cap = F32Lanes::new(std::array::from_fn(|l| if finite[l] { 0.0 } else { 1.0 }));
            let cap = cap
                .simd_gt(F32Lanes::ZERO)
                .select(raster.cap_area, F32Lanes::ZERO);
            let (la, lb) = (raster.light_space(a), raster.light_space(b));
            raster.segments(la, lb, sampled, cap, &mut deposit);
        }
    }
}

/// The lane-layout twin of [`for_each_sample`] (scalar twin
/// [`super::scalar::raster::for_each_sample_lanes`]): the hair of the
/// eight-lane `groups` of `hair` (see [`StrandLanes`]), segment `r` of a
/// group's eight strands (rows `r` and `r + 1`) in its lanes, so no
/// lane shuffling: per group, per segment, the group's rounds, the same
/// per-lane arithmetic as [`for_each_sample`] (each row is taken to light
/// space once). A segment is sampled when its lane is hair and both its
/// ends are finite; it starts a piece (the cap) when it is the strand's
/// first or the vertex before it is not finite.
pub fn for_each_sample_lanes<H: StrandLanes + ?Sized>(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    hair: &H,
    groups: std::ops::Range<usize>,
    mut deposit: impl FnMut(&SplatX8),
) {
    let verts = hair.verts();
    if verts < 2 {
        return;
    }
    let Some(raster) = Raster::new(frame, placement, resolution, hair_radius) else {
        return;
    };
    for u in groups {
        // Group by group of eight lanes (the same deposit order at 8 and
        // 16 lanes): a block's rows are read once per group holding hair.
        let (b, k) = block_of_group(u);
        let (bits, row) = hair.block(b);
        let in_group = bits & (0xff << (k * GROUP_LANES));
        if in_group == 0 {
            continue;
        }
        let hair_lanes = lanes_of_bits(in_group);
        // 1. Segment setup per row pair; `before`: the vertex before the
        // segment is finite (none before the root).
        let p = row(0);
        let mut before = F32Lanes::ZERO;
        let mut fin_a = p.finite() & hair_lanes;
        let mut la = raster.light_space(p);
        for r in 1..verts {
            let q = row(r);
            let fin_b = q.finite() & hair_lanes;
            let lb = raster.light_space(q);
            let sampled = (fin_a & fin_b).to_bitmask();
            if sampled != 0 {
                let cap = before.select(F32Lanes::ZERO, raster.cap_area);
                raster.segments(la, lb, sampled, cap, &mut deposit);
            }
            (before, fin_a, la) = (fin_a, fin_b, lb);
        }
    }
}
