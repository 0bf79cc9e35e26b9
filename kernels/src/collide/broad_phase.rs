//! Broad phase: which colliders can touch a block of eight strands (and,
//! for cloth patches, which rig spheres a column block).
//!
//! Users of TressFX and Unity's hair ask for rigs of hundreds of colliders
//! (Unity caps them at 8). Once per step each block is tested against every
//! collider, with a slack of
//! the pearl radius plus one rest segment: first its swept box (the last
//! step's motion extrapolated), then, if that misses, the reach the strain
//! limit leaves it (vertex `v` within `(1 + max_stretch) arc(v)` of its
//! root's target), which also gives the first vertex that may touch the
//! collider. Only those colliders enter the block's narrow phase, from that
//! vertex on. A still sphere is tested as a sphere against the box; a
//! moving sphere, a capsule and a field by the box they sweep over the step
//! (`rig.rs`), grown by the slack. A non-finite sphere never passes the
//! test (invalid capsules never reach it).

use super::rig::LocalRig;
use crate::lanes::Vec3Lanes;
use crate::Sphere;
use coif_base::lanes::F32Lanes;
use glam::{DVec3, Vec3};

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
pub(crate) fn block_aabb(pos: &[Vec3Lanes], active: F32Lanes) -> Aabb {
    let (mut lo, mut hi) = (
        Vec3Lanes::splat(Vec3::INFINITY),
        Vec3Lanes::splat(Vec3::NEG_INFINITY),
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
fn grow_box(lo: &mut Vec3Lanes, hi: &mut Vec3Lanes, q: Vec3Lanes, active: F32Lanes) {
    let inf = F32Lanes::splat(f32::INFINITY);
    *lo = Vec3Lanes::new(
        active.select(q.x, inf).fast_min(lo.x),
        active.select(q.y, inf).fast_min(lo.y),
        active.select(q.z, inf).fast_min(lo.z),
    );
    *hi = Vec3Lanes::new(
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
    pos: &[Vec3Lanes],
    prev: &[Vec3Lanes],
    g_dt2: Vec3,
    active: F32Lanes,
) -> Aabb {
    let g = Vec3Lanes::splat(g_dt2);
    let root_move = pos[0] - prev[0];
    let (mut lo, mut hi) = (
        Vec3Lanes::splat(Vec3::INFINITY),
        Vec3Lanes::splat(Vec3::NEG_INFINITY),
    );
    // Every lane, then the inactive ones masked out once (the same box:
    // a lane's min and max do not depend on the others).
    let all = active | !active;
    for (x, p) in pos.iter().zip(prev) {
        let ahead = *x + (*x - *p) + g + root_move;
        grow_box(&mut lo, &mut hi, *x, all);
        grow_box(&mut lo, &mut hi, ahead, all);
    }
    let inf = Vec3Lanes::splat(Vec3::INFINITY);
    fold_box(
        Vec3Lanes::select(active, lo, inf),
        Vec3Lanes::select(active, hi, -inf),
    )
}

/// The box of the active lanes' roots over the step: where they were
/// (`from`, a block's `prev[0]` on entry to the step) and their targets
/// (`to`, its `pos[0]`: where `set_roots` put them); the substeps move them
/// on the straight line between.
pub(crate) fn roots_aabb(from: Vec3Lanes, to: Vec3Lanes, active: F32Lanes) -> Aabb {
    let (mut lo, mut hi) = (
        Vec3Lanes::splat(Vec3::INFINITY),
        Vec3Lanes::splat(Vec3::NEG_INFINITY),
    );
    grow_box(&mut lo, &mut hi, from, active);
    grow_box(&mut lo, &mut hi, to, active);
    fold_box(lo, hi)
}

/// What the broad phase knows of one block: its swept box
/// ([`block_sweep_aabb`]) and the reach the strain limit leaves it, the
/// roots' box over the step (`roots`, [`roots_aabb`]) and the rest arc
/// length from the root to each vertex, longest over the lanes (`arc`,
/// `Strands::reach_arc`), with the limit's `stretch_factor`: vertex `v`
/// stays within `stretch_factor arc(v)` of its root. The swept box extrapolates the last step's velocity and misses
/// hair that a whipping root turns round within one step (measured: a
/// strand left 3.4 cm inside a sphere whipped at 4 m/s with dt 1/15 s); the
/// reach does not, and tells the narrow phase from which vertex on a sphere
/// can be touched.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BlockBounds<'a> {
    pub swept: Aabb,
    pub roots: Aabb,
    pub arc: &'a [f32],
    pub stretch_factor: f32,
}

impl BlockBounds<'_> {
    /// The roots' box grown by the reach of vertex `v` (the tip's: the
    /// block's whole reach).
    fn reach(&self, v: usize) -> Aabb {
        let r = Vec3::splat(self.arc[v] * self.stretch_factor);
        Aabb {
            min: self.roots.min - r,
            max: self.roots.max + r,
        }
    }

    /// The first vertex that may touch a collider this step (`near` tells
    /// whether a box, grown by the slack, may touch it): 0 if the swept box
    /// is near it, else the first whose reach is, None if none.
    fn first_vertex(&self, near: impl Fn(&Aabb) -> bool) -> Option<usize> {
        if near(&self.swept) {
            return Some(0);
        }
        let tip = self.arc.len().checked_sub(1)?;
        if !near(&self.reach(tip)) {
            return None;
        }
        // The reach grows with v: the first vertex that reaches, by bisection.
        let (mut lo, mut hi) = (0, tip);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if near(&self.reach(mid)) {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        Some(lo)
    }
}

fn fold_box(lo: Vec3Lanes, hi: Vec3Lanes) -> Aabb {
    let fold =
        |v: F32Lanes, f: fn(f32, f32) -> f32, init: f32| v.to_array().into_iter().fold(init, f);
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
/// with bit `b` set in `blocks` for each block `b` of the group it may touch
/// and `first[b]` the first vertex of block `b` that may touch it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Candidate {
    pub sphere: [f32; 4],
    pub blocks: u32,
    pub first: [u32; crate::drive::GROUP],
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
/// block of a group, at most 32: a patch's column blocks), each with the
/// blocks whose own box it is near (every vertex of those may touch it).
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
            out.push(Candidate {
                sphere: *s,
                blocks,
                first: [0; crate::drive::GROUP],
            });
        }
    }
}

/// True if the boxes are at most `margin` apart; false for a non-finite box.
pub(crate) fn boxes_near(a: &Aabb, b: &Aabb, margin: f32) -> bool {
    let gap = (a.min - b.max).max(b.min - a.max).max(Vec3::ZERO);
    a.min.is_finite()
        && a.max.is_finite()
        && b.min.is_finite()
        && b.max.is_finite()
        && gap.length_squared() <= margin * margin
}

/// Which kind of collider a strand candidate is (its index is in the
/// step's [`LocalRig`] list of that kind).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Sphere,
    Capsule,
    Field,
}

/// A collider that may touch a group of blocks: bit `b` of `blocks` for
/// each block of the group it may touch, `first[b]` the first vertex of
/// block `b` that may touch it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ShapeCandidate {
    pub kind: Kind,
    pub index: u32,
    pub blocks: u32,
    pub first: [u32; crate::drive::GROUP],
}

impl ShapeCandidate {
    #[inline(always)]
    pub(crate) fn touches(&self, block: usize) -> bool {
        self.blocks & (1 << block) != 0
    }
}

/// The strands' broad phase: writes into `out` the colliders that may touch
/// a group of blocks (at most [`crate::drive::GROUP`]): near the union of
/// the blocks' swept boxes and reaches first, then per block (see
/// [`BlockBounds::first_vertex`]); spheres, then capsules, then fields,
/// each in the rig's order.
pub(crate) fn select_strand_candidates(
    blocks: &[BlockBounds<'_>],
    margin: f32,
    rig: &LocalRig,
    out: &mut Vec<ShapeCandidate>,
) {
    out.clear();
    let Some(union) = blocks
        .iter()
        .map(|b| {
            let tip = b.arc.len().saturating_sub(1);
            b.swept.union(if b.arc.is_empty() {
                b.swept
            } else {
                b.reach(tip)
            })
        })
        .reduce(Aabb::union)
    else {
        return;
    };
    for (i, s) in rig.spheres.iter().enumerate() {
        if s.still() {
            let sphere = [s.to[0].x, s.to[0].y, s.to[0].z, s.radius];
            add(out, blocks, &union, Kind::Sphere, i, |b: &Aabb| {
                near(b, &sphere, margin)
            });
        } else {
            let swept = s.swept_box();
            add(out, blocks, &union, Kind::Sphere, i, |b: &Aabb| {
                boxes_near(b, &swept, margin)
            });
        }
    }
    for (i, c) in rig.capsules.iter().enumerate() {
        // Near both its swept box and a sphere holding it (each
        // conservative; together tighter than either).
        let swept = c.swept_box();
        let ball = c.bounding_sphere();
        add(out, blocks, &union, Kind::Capsule, i, |b: &Aabb| {
            boxes_near(b, &swept, margin) && near(b, &ball, margin)
        });
    }
    for (i, f) in rig.fields.iter().enumerate() {
        let swept = f.swept;
        add(out, blocks, &union, Kind::Field, i, |b: &Aabb| {
            boxes_near(b, &swept, margin)
        });
    }
}

/// Adds collider `index` of `kind` to `out` if it is `near` the group's
/// `union` and then some block of it, with the first vertex per block.
#[inline(always)]
fn add(
    out: &mut Vec<ShapeCandidate>,
    blocks: &[BlockBounds<'_>],
    union: &Aabb,
    kind: Kind,
    index: usize,
    near: impl Fn(&Aabb) -> bool,
) {
    if !near(union) {
        return;
    }
    let mut c = ShapeCandidate {
        kind,
        index: index as u32,
        blocks: 0,
        first: [0; crate::drive::GROUP],
    };
    for (k, b) in blocks.iter().enumerate().take(crate::drive::GROUP) {
        if let Some(v) = b.first_vertex(&near) {
            c.blocks |= 1 << k;
            c.first[k] = v as u32;
        }
    }
    if c.blocks != 0 {
        out.push(c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::LANES;

    /// A rig of still spheres `[x, y, z, r]`, local frame.
    fn rig(spheres: &[[f32; 4]]) -> LocalRig {
        let mut r = LocalRig::default();
        for s in spheres {
            let c = Vec3::new(s[0], s[1], s[2]);
            r.spheres.push(super::super::rig::LocalCapsule {
                from: [c; 2],
                to: [c; 2],
                radius: s[3],
            });
        }
        r
    }

    fn chosen(out: &[ShapeCandidate], spheres: &[[f32; 4]]) -> Vec<[f32; 4]> {
        out.iter().map(|c| spheres[c.index as usize]).collect()
    }

    /// A block known by its swept box alone.
    fn swept(b: Aabb) -> BlockBounds<'static> {
        BlockBounds {
            swept: b,
            roots: b,
            arc: &[],
            stretch_factor: 1.0,
        }
    }

    #[test]
    fn a_sphere_beyond_the_swept_box_within_reach_is_a_candidate_from_the_first_vertex_that_reaches_it(
    ) {
        // Roots at the origin, vertices 10 cm apart along the arc; the swept
        // box is the roots' own. A sphere of 5 cm at 0.5 m: vertex v reaches
        // 0.1 v (1.01 with the limit), plus the 5 cm radius and 1 cm margin,
        // so vertex 5 (0.505 + 0.06 in the box's corner-free x direction)
        // is the first; a sphere at 2 m is out of every vertex's reach.
        let roots = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        };
        let arc: Vec<f32> = (0..8).map(|v| 0.1 * v as f32).collect();
        let b = BlockBounds {
            swept: roots,
            roots,
            arc: &arc,
            stretch_factor: 1.01,
        };
        let spheres = [
            [0.5, 0.0, 0.0, 0.05],
            [2.0, 0.0, 0.0, 0.05],
            [0.0, 0.0, 0.0, 0.05],
        ];
        let mut out = Vec::new();
        select_strand_candidates(&[b], 0.01, &rig(&spheres), &mut out);
        assert_eq!(out.len(), 2);
        assert_eq!((chosen(&out, &spheres)[0], out[0].blocks), (spheres[0], 1));
        // 0.1 v 1.01 + 0.06 >= 0.5 first at v = 5 (0.565; v = 4: 0.464).
        assert_eq!(out[0].first[0], 5);
        assert_eq!(
            (chosen(&out, &spheres)[1], out[1].first[0]),
            (spheres[2], 0)
        );
    }

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
        // The strands' form, blocks known by their swept boxes alone: the
        // same spheres, every vertex of the near block.
        let mut strand_out = Vec::new();
        select_strand_candidates(
            &[swept(far), swept(aabb)],
            0.1,
            &rig(&spheres),
            &mut strand_out,
        );
        assert_eq!(chosen(&strand_out, &spheres), vec![spheres[0], spheres[2]]);
        let out = strand_out;
        assert!(out.iter().all(|c| c.blocks == 0b10 && c.first[1] == 0));
    }

    #[test]
    fn simd_and_scalar_boxes_agree_and_ignore_padding() {
        let mut pos = vec![Vec3Lanes::ZERO; 3];
        for (v, p) in pos.iter_mut().enumerate() {
            for l in 0..LANES {
                let far = if l >= 5 { 1000.0 } else { 0.0 };
                p.set_lane(l, Vec3::new(l as f32 + far, -(v as f32), 0.5 * l as f32));
            }
        }
        let active = F32Lanes::new(std::array::from_fn(|l| {
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
