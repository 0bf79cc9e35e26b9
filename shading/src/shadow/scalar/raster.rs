//! Scalar twin of `shadow/raster.rs`: the same steps, one segment and one
//! sample at a time, in the SIMD path's order (groups of eight consecutive
//! segments of a strand, sampled in rounds; see that file for the
//! rasterisation and its coverage formula).

use crate::shadow::light_frame::{LightFrame, MapPlacement};
use crate::shadow::raster::{Segment, SAMPLES_PER_TEXEL};
use coif_base::LANES;
use glam::Vec3;

/// One sample's bilinear splat: the four texels `t0`, `t0 + 1`, `t0 + n`,
/// `t0 + n + 1` around it and their weights times the sample's coverage.
#[derive(Clone, Copy, Debug)]
pub struct Splat {
    /// Lower-left texel of the four.
    pub t0: usize,
    /// Weights of `t0`, `t0 + 1`, `t0 + n`, `t0 + n + 1`.
    pub weights: [f32; 4],
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
    let max_samples = 4 * resolution;
    let cap_area = std::f32::consts::PI * hair_radius * hair_radius;
    let inv_h = placement.inv_texel;
    let inv_h2 = inv_h * inv_h;
    for (index, strand) in points.chunks_exact(verts).enumerate() {
        let mut prev = strand[0];
        let mut prev_light = frame.to_light(prev);
        // The strand's (or, after a broken vertex, the piece's) first segment.
        let mut first = true;
        for (k, &next) in strand[1..].iter().enumerate() {
            let next_light = frame.to_light(next);
            if prev.is_finite() && next.is_finite() {
                // 1. Segment setup.
                let d = next_light - prev_light;
                let len_xy = (d.x * d.x + d.y * d.y).sqrt();
                let n =
                    ((SAMPLES_PER_TEXEL * len_xy * inv_h).ceil() as usize).clamp(1, max_samples);
                let inv_n = 1.0 / n as f32;
                let cap = if first { cap_area } else { 0.0 };
                first = false;
                let (ua, va) = placement.texel_coords(prev_light.x, prev_light.y);
                visit(
                    index,
                    k,
                    &Segment {
                        ua,
                        va,
                        za: prev_light.z,
                        du: d.x * inv_h,
                        dv: d.y * inv_h,
                        dz: d.z,
                        samples: n,
                        inv_n,
                        weight: (2.0 * hair_radius * len_xy + cap) * inv_h2 * inv_n,
                    },
                );
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
/// after strand, root to tip. The scalar reference of the SIMD twin.
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
    let sample = |seg: &Segment, j: usize, deposit: &mut dyn FnMut(&Splat, f32)| {
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
    };
    // The group of segments k0 .. k0 + 8 of one strand, sampled in rounds
    // when the next segment falls outside it.
    let mut group: [Option<Segment>; LANES] = [None; LANES];
    let mut key = (usize::MAX, usize::MAX);
    let mut flush = |group: &mut [Option<Segment>; LANES]| {
        let rounds = group.iter().flatten().map(|s| s.samples).max().unwrap_or(0);
        for j in 0..rounds {
            for seg in group.iter().flatten().filter(|s| j < s.samples) {
                sample(seg, j, &mut deposit);
            }
        }
        *group = [None; LANES];
    };
    for_each_segment(
        frame,
        placement,
        resolution,
        hair_radius,
        points,
        verts,
        |strand, k, seg| {
            if (strand, k / LANES) != key {
                flush(&mut group);
                key = (strand, k / LANES);
            }
            group[k % LANES] = Some(*seg);
        },
    );
    flush(&mut group);
}
