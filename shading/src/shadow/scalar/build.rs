//! Scalar twin of `shadow/build.rs`: the same steps, one sample at a time,
//! one texel at a time in the prefix sum.

use super::raster::{for_each_sample, for_each_sample_lanes, Splat};
use crate::shadow::light_frame::LightFrame;
use crate::shadow::settings::ShadowMode;
use crate::shadow::strand_lanes::StrandLanes;
use crate::shadow::OpacityShadowMap;
use coif_base::LANES;
use glam::Vec3;

/// The scalar reference of [`OpacityShadowMap::build`]: the same steps,
/// one sample at a time, one texel at a time in the prefix sum. Makes the
/// same map bit for bit.
pub fn build(
    map: &mut OpacityShadowMap,
    light_dir: Vec3,
    points: &[Vec3],
    verts_per_strand: usize,
) {
    let Some(points) = map.prepare(light_dir, points, verts_per_strand, light_bounds) else {
        return;
    };
    let (frame, placement) = (map.frame, map.placement);
    let (n, r) = (map.settings.resolution, map.settings.hair_radius);
    rasterise(map, |deposit| {
        for_each_sample(&frame, &placement, n, r, points, verts_per_strand, deposit)
    });
}

/// The scalar twin of [`OpacityShadowMap::build_lanes`] (one task): the
/// same steps from hair in lane layout, one lane and one sample at a time,
/// in the SIMD order (group of eight lanes, segment, round, lane). Makes the same map bit
/// for bit as the SIMD build with one task.
pub fn build_lanes<H: StrandLanes + ?Sized>(map: &mut OpacityShadowMap, light_dir: Vec3, hair: &H) {
    if !map.prepare_with(light_dir, hair.verts(), |frame| lane_bounds(frame, hair)) {
        return;
    }
    let (frame, placement) = (map.frame, map.placement);
    let (n, r) = (map.settings.resolution, map.settings.hair_radius);
    let groups = 0..hair.groups();
    rasterise(map, |deposit| {
        for_each_sample_lanes(&frame, &placement, n, r, hair, groups.clone(), deposit)
    });
}

/// Steps 2 to 4 of both scalar builds, `samples` calling its argument once
/// per sample (splat and depth), in order.
fn rasterise(map: &mut OpacityShadowMap, samples: impl Fn(&mut dyn FnMut(&Splat, f32))) {
    let (placement, layering) = (map.placement, map.layering);
    let n = map.settings.resolution;
    let nn = n * n;
    // The four texels of a splat, relative to its lower-left one.
    let offsets = [0, 1, n, n + 1];
    match map.settings.mode {
        ShadowMode::Slices => {
            // 3. Deposit every sample into its plane interval.
            let texels = &mut map.texels;
            samples(&mut |sp, z| {
                let (slice, _) = layering.locate(z - placement.near);
                let plane = &mut texels[(slice / 4) * nn..(slice / 4 + 1) * nn];
                for (o, w) in offsets.iter().zip(sp.weights) {
                    plane[sp.t0 + o][slice % 4] += w;
                }
            });
        }
        ShadowMode::Deep => {
            // 2. The depth map z0: the nearest sample per texel.
            let z0 = &mut map.first_depth;
            z0.fill(f32::INFINITY);
            samples(&mut |sp, z| {
                for o in offsets {
                    let d = &mut z0[sp.t0 + o];
                    *d = d.min(z);
                }
            });
            for z in z0.iter_mut().filter(|z| **z == f32::INFINITY) {
                *z = placement.near;
            }
            // 3. Deposit every sample into its plane interval from z0.
            let z0 = &map.first_depth;
            let texels = &mut map.texels;
            samples(&mut |sp, z| {
                for (o, w) in offsets.iter().zip(sp.weights) {
                    let t = sp.t0 + o;
                    let (slice, _) = layering.locate(z - z0[t]);
                    texels[(slice / 4) * nn + t][slice % 4] += w;
                }
            });
        }
    }
    // 4. Prefix sum along depth.
    prefix_sum(&mut map.texels, nn, map.settings.layers);
    map.keep_depth_in_texels();
    map.ready = true;
}

/// Light-space bounding box `(min, max)` of the finite points, or `None`
/// when no point is finite or a finite point's light-space coordinates
/// overflow (then no map is usable). Light space as
/// [`LightFrame::to_light`]: `x = p . x_axis` and so on.
fn light_bounds(frame: &LightFrame, points: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for p in points.iter().filter(|p| p.is_finite()) {
        let l = frame.to_light(*p);
        if !l.is_finite() {
            return None;
        }
        min = min.min(l);
        max = max.max(l);
    }
    // Stays inverted (min > max) when no point is finite.
    (min.x <= max.x).then_some((min, max))
}

/// [`light_bounds`] of hair in lane layout: every lane that is hair,
/// vertex by vertex.
fn lane_bounds<H: StrandLanes + ?Sized>(frame: &LightFrame, hair: &H) -> Option<(Vec3, Vec3)> {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for b in 0..hair.blocks() {
        let (bits, row) = hair.block(b);
        for r in 0..hair.verts() {
            let p = row(r);
            for l in (0..LANES).filter(|l| bits >> l & 1 == 1) {
                let q = p.lane(l);
                if !q.is_finite() {
                    continue;
                }
                let c = frame.to_light(q);
                if !c.is_finite() {
                    return None;
                }
                min = min.min(c);
                max = max.max(c);
            }
        }
    }
    (min.x <= max.x).then_some((min, max))
}

/// The prefix sum along depth, `S[s] = S[s - 1] + deposit[s]` per texel
/// (`S[-1] = 0`), in plane order.
fn prefix_sum(texels: &mut [[f32; 4]], nn: usize, layers: usize) {
    for t in 0..nn {
        let mut sum = 0.0;
        for s in 0..layers {
            let texel = &mut texels[(s / 4) * nn + t][s % 4];
            sum += *texel;
            *texel = sum;
        }
    }
}
