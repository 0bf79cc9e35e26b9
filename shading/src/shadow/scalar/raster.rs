//! Scalar twin of `shadow/raster.rs`: the same steps, one segment and one
//! sample at a time, in the SIMD path's order (groups of eight consecutive
//! segments of a strand, sampled in rounds; see that file for the
//! rasterisation and its coverage formula).

use crate::shadow::light_frame::{LightFrame, MapPlacement};
use crate::shadow::raster::{Segment, SAMPLES_PER_TEXEL};
use crate::shadow::strand_lanes::StrandLanes;
use coif_base::lanes::{block_of_group, GROUP_LANES};
use glam::Vec3;
use std::ops::Range;

/// One sample's bilinear splat: the four texels `t0`, `t0 + 1`, `t0 + n`,
/// `t0 + n + 1` around it and their weights times the sample's coverage.
#[derive(Clone, Copy, Debug)]
pub struct Splat {
    /// Lower-left texel of the four.
    pub t0: usize,
    /// Weights of `t0`, `t0 + 1`, `t0 + n`, `t0 + n + 1`.
    pub weights: [f32; 4],
}

/// The setup of one finite segment from its light-space ends (step 1):
/// sample count, coverage per sample (with the cap `pi r^2` when the
/// segment starts a piece), start and step in texel coordinates.
#[derive(Clone, Copy)]
struct Setup {
    placement: MapPlacement,
    hair_radius: f32,
    max_samples: usize,
    cap_area: f32,
    inv_h: f32,
    inv_h2: f32,
}

impl Setup {
    fn new(placement: &MapPlacement, resolution: usize, hair_radius: f32) -> Setup {
        let inv_h = placement.inv_texel;
        Setup {
            placement: *placement,
            hair_radius,
            max_samples: 4 * resolution,
            cap_area: std::f32::consts::PI * hair_radius * hair_radius,
            inv_h,
            inv_h2: inv_h * inv_h,
        }
    }

    /// 1. Segment setup.
    fn segment(&self, prev_light: Vec3, next_light: Vec3, first: bool) -> Segment {
        let inv_h = self.inv_h;
        let d = next_light - prev_light;
        let len_xy = (d.x * d.x + d.y * d.y).sqrt();
        let n = ((SAMPLES_PER_TEXEL * len_xy * inv_h + 0.5).floor() as usize)
            .clamp(1, self.max_samples);
        let inv_n = 1.0 / n as f32;
        let cap = if first { self.cap_area } else { 0.0 };
        let (ua, va) = self.placement.texel_coords(prev_light.x, prev_light.y);
        Segment {
            ua,
            va,
            za: prev_light.z,
            du: d.x * inv_h,
            dv: d.y * inv_h,
            dz: d.z,
            samples: n,
            inv_n,
            weight: (2.0 * self.hair_radius * len_xy + cap) * self.inv_h2 * inv_n,
        }
    }
}

/// Calls `visit(strand, k, segment)` for every segment of the hair
/// (`points`, `verts` per strand) whose two ends are finite, strand after
/// strand, root to tip, with `k` its index in the strand.
/// A segment starts a piece (and gets the cap) when it is the strand's
/// first or follows a broken one. The SIMD twin makes the same segments bit
/// for bit.
pub fn for_each_segment(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    points: &[Vec3],
    verts: usize,
    mut visit: impl FnMut(usize, usize, &Segment),
) {
    if verts < 2 || resolution < 2 {
        return;
    }
    let setup = Setup::new(placement, resolution, hair_radius);
    for (index, strand) in points.chunks_exact(verts).enumerate() {
        let mut prev = strand[0];
        let mut prev_light = frame.to_light(prev);
        // The strand's (or, after a broken vertex, the piece's) first segment.
        let mut first = true;
        for (k, &next) in strand[1..].iter().enumerate() {
            let next_light = frame.to_light(next);
            if prev.is_finite() && next.is_finite() {
                visit(index, k, &setup.segment(prev_light, next_light, first));
                first = false;
            } else {
                first = true;
            }
            prev = next;
            prev_light = next_light;
        }
    }
}

/// Steps 2 and 3 for a group of up to eight segments: round `j` takes
/// sample `j` of every segment of the group that has one, in slot order.
///
/// Sample `j` of a segment lies at `t = (j + 1/2) / n` along it; its
/// texel coordinates `(u, v)` split into the lower-left texel
/// `(floor u, floor v)` and bilinear fractions `(fx, fy)`.
/// The placement's margin (hair radius plus a texel on every side) keeps
/// every sample's four texels inside the map; the lower-left texel is still
/// clamped to `[0, n - 2]` so that rounding can never index outside it.
fn sample_group(
    group: &[Option<Segment>; GROUP_LANES],
    resolution: usize,
    deposit: &mut impl FnMut(&Splat, f32),
) {
    let last = resolution.saturating_sub(2) as f32;
    let rounds = group.iter().flatten().map(|s| s.samples).max().unwrap_or(0);
    for j in 0..rounds {
        for seg in group.iter().flatten().filter(|s| j < s.samples) {
            // 2. The sample's splat and depth.
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
            // 3. Deposit, in strand, group, round and segment order.
            deposit(&splat, seg.za + seg.dz * t);
        }
    }
}

/// Calls `deposit(splat, z)` for every sample point of every segment of the
/// hair (`points`, `verts` per strand), with `z` the sample's light-space
/// depth. Segments with a non-finite end are skipped. Deterministic: strand
/// after strand, root to tip, groups of eight consecutive segments of a
/// strand sampled in rounds (see [`sample_group`]). The scalar reference
/// of the SIMD twin.
pub fn for_each_sample(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    points: &[Vec3],
    verts: usize,
    mut deposit: impl FnMut(&Splat, f32),
) {
    // The group of segments k0 .. k0 + 8 of one strand, sampled in rounds
    // when the next segment falls outside it.
    let mut group: [Option<Segment>; GROUP_LANES] = [None; GROUP_LANES];
    let mut key = (usize::MAX, usize::MAX);
    for_each_segment(
        frame,
        placement,
        resolution,
        hair_radius,
        points,
        verts,
        |strand, k, seg| {
            if (strand, k / GROUP_LANES) != key {
                sample_group(&group, resolution, &mut deposit);
                group = [None; GROUP_LANES];
                key = (strand, k / GROUP_LANES);
            }
            group[k % GROUP_LANES] = Some(*seg);
        },
    );
    sample_group(&group, resolution, &mut deposit);
}

/// Scalar twin of the SIMD `for_each_sample_lanes`: the hair of the
/// eight-lane `groups` of `hair` (strands in lanes, see [`StrandLanes`]),
/// per group and per segment `r` the group of the lanes' segments `r`
/// (rows `r`, `r + 1`),
/// one lane at a time, then its rounds ([`sample_group`]). A segment is sampled when its lane is
/// hair and both ends are finite; it starts a piece when it is the strand's
/// first or follows a broken one.
pub fn for_each_sample_lanes<H: StrandLanes + ?Sized>(
    frame: &LightFrame,
    placement: &MapPlacement,
    resolution: usize,
    hair_radius: f32,
    hair: &H,
    groups: Range<usize>,
    mut deposit: impl FnMut(&Splat, f32),
) {
    let verts = hair.verts();
    if verts < 2 || resolution < 2 {
        return;
    }
    let setup = Setup::new(placement, resolution, hair_radius);
    for u in groups {
        // Group by group of eight lanes, as the SIMD twin deposits.
        let (b, k) = block_of_group(u);
        let (bits, row) = hair.block(b);
        // Lane `8 k + i` of the block is slot `i` of the group.
        let in_group = (0..GROUP_LANES).filter(|i| bits >> (k * GROUP_LANES + i) & 1 == 1);
        if bits >> (k * GROUP_LANES) & 0xff == 0 {
            continue;
        }
        let first_row = row(0);
        let mut prev = [Vec3::ZERO; GROUP_LANES];
        let mut prev_light = [Vec3::ZERO; GROUP_LANES];
        for i in in_group.clone() {
            prev[i] = first_row.lane(k * GROUP_LANES + i);
            prev_light[i] = frame.to_light(prev[i]);
        }
        let mut first = [true; GROUP_LANES];
        for r in 1..verts {
            let next_row = row(r);
            let mut group: [Option<Segment>; GROUP_LANES] = [None; GROUP_LANES];
            for i in in_group.clone() {
                // 1. Segment setup, lane by lane.
                let next = next_row.lane(k * GROUP_LANES + i);
                let next_light = frame.to_light(next);
                if prev[i].is_finite() && next.is_finite() {
                    group[i] = Some(setup.segment(prev_light[i], next_light, first[i]));
                    first[i] = false;
                } else {
                    first[i] = true;
                }
                prev[i] = next;
                prev_light[i] = next_light;
            }
            sample_group(&group, resolution, &mut deposit);
        }
    }
}
