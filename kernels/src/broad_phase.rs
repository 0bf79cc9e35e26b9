//! Broad phase: which rig spheres can touch a block of eight strands.
//!
//! Users of TressFX and Unity's hair ask for rigs of hundreds of spheres.
//! Each block's bounding box, grown by the pearl
//! radius plus a slack of one rest segment (how far a constraint sweep can
//! reasonably carry a vertex after the box was taken), is tested against
//! every sphere once per step; only the spheres that can touch it enter the
//! block's narrow phase. A non-finite sphere never passes the test.

use crate::lanes::Vec3x8;
use crate::Sphere;
use glam::{DVec3, Vec3};
use wide::f32x8;

/// An axis-aligned box in local coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub(crate) fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
}

/// Converts the rig to local coordinates (centre relative to `origin`, radius).
pub(crate) fn spheres_to_local(spheres: &[Sphere], origin: DVec3, out: &mut Vec<[f32; 4]>) {
    out.clear();
    out.extend(spheres.iter().map(|s| {
        let c = (s.center.as_dvec3() - origin).as_vec3();
        [c.x, c.y, c.z, s.radius]
    }));
}

/// Bounding box of the active lanes of one block (SIMD: lane-wise min/max over
/// the vertices, then across lanes). Inactive lanes are masked to +-inf.
pub(crate) fn block_aabb(pos: &[Vec3x8], active: f32x8) -> Aabb {
    let (mut lo, mut hi) = (
        Vec3x8::splat(Vec3::INFINITY),
        Vec3x8::splat(Vec3::NEG_INFINITY),
    );
    for p in pos {
        grow_box(&mut lo, &mut hi, *p, active);
    }
    fold_box(lo, hi)
}

/// Grows the lane-wise box `lo..hi` by `q` in the active lanes.
/// `candidate.fast_min(running)` keeps `running` where the candidate is NaN
/// (minps returns its second operand), as f32::min does.
#[inline(always)]
fn grow_box(lo: &mut Vec3x8, hi: &mut Vec3x8, q: Vec3x8, active: f32x8) {
    let inf = f32x8::splat(f32::INFINITY);
    *lo = Vec3x8::new(
        active.select(q.x, inf).fast_min(lo.x),
        active.select(q.y, inf).fast_min(lo.y),
        active.select(q.z, inf).fast_min(lo.z),
    );
    *hi = Vec3x8::new(
        active.select(q.x, -inf).fast_max(hi.x),
        active.select(q.y, -inf).fast_max(hi.y),
        active.select(q.z, -inf).fast_max(hi.z),
    );
}

/// The box of the active lanes of one strand block swept over the step:
/// every vertex `x` and its extrapolation `x + (x - x_prev) + g dt^2 + m`,
/// with `m` the root's move (`pos[0] - prev[0]`: the roots' target minus
/// where they were). Inactive lanes are masked to +-inf, NaNs are skipped.
pub(crate) fn block_sweep_aabb(
    pos: &[Vec3x8],
    prev: &[Vec3x8],
    g_dt2: Vec3,
    active: f32x8,
) -> Aabb {
    let g = Vec3x8::splat(g_dt2);
    let root_move = pos[0] - prev[0];
    let (mut lo, mut hi) = (
        Vec3x8::splat(Vec3::INFINITY),
        Vec3x8::splat(Vec3::NEG_INFINITY),
    );
    for (x, p) in pos.iter().zip(prev) {
        let ahead = *x + (*x - *p) + g + root_move;
        grow_box(&mut lo, &mut hi, *x, active);
        grow_box(&mut lo, &mut hi, ahead, active);
    }
    fold_box(lo, hi)
}

/// The box that the strain limit keeps the active lanes of a block in
/// over the step: every vertex within `stretch_factor` times its strand's
/// rest arc length of its root's target (`roots`, the step's `pos[0]`), so
/// the roots' box grown by `stretch_factor` times the longest rest arc
/// (`rest_len`: the block's rest segment lengths). The swept box of
/// [`block_sweep_aabb`] extrapolates the last step's velocity and misses
/// hair that a whipping root turns around within one step (measured: a
/// strand left 3.4 cm inside a sphere whipped at 4 m/s with dt 1/15 s);
/// the broad phase tests the union of the two.
pub(crate) fn block_reach_aabb(
    roots: Vec3x8,
    rest_len: &[f32x8],
    stretch_factor: f32,
    active: f32x8,
) -> Aabb {
    let arc = rest_len.iter().fold(f32x8::ZERO, |a, l| a + *l);
    let longest = active
        .select(arc, f32x8::ZERO)
        .to_array()
        .into_iter()
        .fold(0.0, f32::max);
    let reach = longest * stretch_factor;
    let (mut lo, mut hi) = (
        Vec3x8::splat(Vec3::INFINITY),
        Vec3x8::splat(Vec3::NEG_INFINITY),
    );
    grow_box(&mut lo, &mut hi, roots, active);
    let b = fold_box(lo, hi);
    Aabb {
        min: b.min - Vec3::splat(reach),
        max: b.max + Vec3::splat(reach),
    }
}

fn fold_box(lo: Vec3x8, hi: Vec3x8) -> Aabb {
    let fold = |v: f32x8, f: fn(f32, f32) -> f32, init: f32| v.to_array().into_iter().fold(init, f);
    Aabb {
        min: Vec3::new(
            fold(lo.x, f32::min, f32::INFINITY),
            fold(lo.y, f32::min, f32::INFINITY),
            fold(lo.z, f32::min, f32::INFINITY),
        ),
        max: Vec3::new(
            fold(hi.x, f32::max, f32::NEG_INFINITY),
            fold(hi.y, f32::max, f32::NEG_INFINITY),
            fold(hi.z, f32::max, f32::NEG_INFINITY),
        ),
    }
}

/// A rig sphere (local centre, radius) that may touch a group of blocks,
/// with bit `b` set in `blocks` for each block `b` of the group it may touch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Candidate {
    pub sphere: [f32; 4],
    pub blocks: u32,
}

impl Candidate {
    #[inline(always)]
    pub(crate) fn touches(&self, block: usize) -> bool {
        self.blocks & (1 << block) != 0
    }
}

/// True if the sphere's distance to `aabb` is at most its radius plus `margin`.
/// Written so that a non-finite sphere never passes.
fn near(aabb: &Aabb, s: &[f32; 4], margin: f32) -> bool {
    let c = Vec3::new(s[0], s[1], s[2]);
    let gap = (aabb.min - c).max(Vec3::ZERO) + (c - aabb.max).max(Vec3::ZERO);
    let reach = s[3] + margin;
    c.is_finite() && s[3].is_finite() && s[3] >= 0.0 && gap.length_squared() <= reach * reach
}

/// Writes into `out` the spheres near the union of `boxes` (one box per
/// block of a group), each with the blocks whose own box it is near.
pub(crate) fn select_candidates(
    boxes: &[Aabb],
    margin: f32,
    spheres: &[[f32; 4]],
    out: &mut Vec<Candidate>,
) {
    out.clear();
    let Some(union) = boxes.iter().copied().reduce(Aabb::union) else {
        return;
    };
    for s in spheres {
        if !near(&union, s, margin) {
            continue;
        }
        let blocks = boxes
            .iter()
            .enumerate()
            .filter(|(_, b)| near(b, s, margin))
            .fold(0u32, |m, (k, _)| m | 1 << k);
        if blocks != 0 {
            out.push(Candidate { sphere: *s, blocks });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::LANES;

    #[test]
    fn candidates_are_the_spheres_near_the_box() {
        let aabb = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        };
        let spheres = [
            [0.5, 0.5, 0.5, 0.1],  // inside
            [2.0, 0.5, 0.5, 0.5],  // 1.0 away, radius 0.5: out
            [2.0, 0.5, 0.5, 0.95], // 1.0 away, radius 0.95 + margin 0.1: in
            [2.0, 2.0, 2.0, 1.0],  // corner distance sqrt(3) > 1.1: out
            [f32::NAN, 0.0, 0.0, 1.0],
            [0.5, 0.5, 0.5, f32::NAN],
        ];
        let mut out = Vec::new();
        select_candidates(&[aabb], 0.1, &spheres, &mut out);
        let picked: Vec<[f32; 4]> = out.iter().map(|c| c.sphere).collect();
        assert_eq!(picked, vec![spheres[0], spheres[2]]);
        // Per block: a second box far away is touched by none of them.
        let far = Aabb {
            min: Vec3::splat(10.0),
            max: Vec3::splat(11.0),
        };
        select_candidates(&[aabb, far], 0.1, &spheres, &mut out);
        assert!(out.iter().all(|c| c.blocks == 0b01));
        select_candidates(&[far, aabb], 0.1, &spheres, &mut out);
        assert!(out
            .iter()
            .all(|c| c.blocks == 0b10 && c.touches(1) && !c.touches(0)));
    }

    #[test]
    fn simd_and_scalar_boxes_agree_and_ignore_padding() {
        let mut pos = vec![Vec3x8::ZERO; 3];
        for (v, p) in pos.iter_mut().enumerate() {
            for l in 0..LANES {
                let far = if l >= 5 { 1000.0 } else { 0.0 };
                p.set_lane(l, Vec3::new(l as f32 + far, -(v as f32), 0.5 * l as f32));
            }
        }
        let active = f32x8::new(std::array::from_fn(|l| {
            if l < 5 {
                f32::from_bits(!0)
            } else {
                0.0
            }
        }));
        let a = block_aabb(&pos, active);
        assert_eq!(a, crate::scalar::broad_phase::block_aabb(&pos, 5));
        // A NaN in one lane does not poison the box of the others.
        let mut poisoned = pos.clone();
        poisoned[1].set_lane(2, Vec3::NAN);
        let b = block_aabb(&poisoned, active);
        assert_eq!(b, crate::scalar::broad_phase::block_aabb(&poisoned, 5));
        assert!(b.min.is_finite() && b.max.is_finite());
        assert_eq!(a.min, Vec3::new(0.0, -2.0, 0.0));
        assert_eq!(a.max, Vec3::new(4.0, 0.0, 2.0));
    }
}
