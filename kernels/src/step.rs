//! One fixed simulation step, SIMD path: eight strands per instruction stream.
//!
//! Per block of [`LANES`] strands, in this order (the numbers are the step
//! comments of [`step`]'s body and of its scalar twin [`crate::scalar::step`]):
//!
//! 1. **Verlet** with damping (Yip 2011):
//!    `x' = x + d (x - x_prev) + g dt^2`; pinned vertices (inverse mass 0) stay.
//! 2. **Shape keeping** (optional): `x += k w_v (root + R rest_v - x)` with
//!    `w_v = 1 - arc(v)/arc(tip)`, strongest at the root (Yip; TressFX).
//! 3. **Broad phase**: each block's bounding box against every rig sphere
//!    (`broad_phase.rs`); only spheres near a block are tested against it.
//! 4. `iterations` Gauss-Seidel sweeps, root to tip, of the mass-weighted
//!    length constraint (Jakobsen 2001): `delta = x2 - x1`,
//!    `k = (|delta| - l) / |delta|`, `x1 += w1/(w1+w2) k delta`,
//!    `x2 -= w2/(w1+w2) k delta` (`1/|delta|` by [`inv_sqrt_x8`] of
//!    `max(|delta|^2, 1e-14)`, so zero-length segments stay finite); with
//!    bending on, the same rule between v and v + 2 scaled by `bend_stiffness`
//!    right after segment v. Before the last sweep, one collision pass
//!    (vertices and pearls, as in 6), so that the sweep smooths what the
//!    push-out did.
//! 5. **Strain limit with collisions**, root to tip: each vertex is pulled
//!    toward its parent until `|x_v - x_{v-1}| <= (1 + max_stretch) l_{v-1}`
//!    (Provot 1995; Follow-The-Leader order, Muller et al. 2012), then pushed
//!    out of every nearby sphere to distance `R + r`, twice over; a pushed
//!    vertex loses the share `friction` of its tangential velocity
//!    (`x_prev += mu (v - n (v.n))`). Summed over segments the limit gives
//!    Yip's root spheres `|x_v - root| <= (1 + max_stretch) arc(v)`, and unlike
//!    them it holds for hair wrapped round the head. Alternating the two per
//!    vertex is what lets neither undo the other: with collisions last, root
//!    jumps stretched segments by 50 %; with the limit last, hair was pulled
//!    9 cm into the head.
//! 6. **Pearls**: `k` points `p = (1-t) x_i + t x_{i+1}`, `t = j/(k+1)`, per
//!    segment, pushed out by the point-on-segment rule of the Nalu demo
//!    (Nguyen and Donnelly 2005, "Hair animation and rendering in the Nalu
//!    demo", GPU Gems 2):
//!    `C = |p - c| - (R + r)`, `s = -C / (w_i (1-t)^2 + w_{i+1} t^2)`,
//!    `x_i += w_i (1-t) s n`, `x_{i+1} += w_{i+1} t s n`. Segments with a
//!    pinned end carry no pearls: the root sits on the scalp, inside the
//!    collision skin, and a pearl there pushed against the pin every step
//!    (5 m/s jitter at the tips with 1 iteration). Pearls must be spaced
//!    closer than a sphere's diameter or the sphere slips between them.
//! 7. **Guard**: a lane with a non-finite coordinate, or one beyond 10^6 m of
//!    the local origin, is restored to its rest pose at its root and counted;
//!    lanes never exchange data, so no other strand is touched.
//!
//! Collision passes cost most of a step, so there are two per step (before
//! the last sweep in 4, and 5-6), not one per sweep: the same outcomes in every
//! test at 104 instead of 167 instructions per vertex-step on the mohawk.
//! With only the final pass (83 instructions) hair draped on a head flapped
//! at 3-5 m/s at rest.
//!
//! Blocks are processed in groups of [`GROUP`], interleaved segment by
//! segment, so that four independent constraint chains are in flight.
//!
//! [`crate::scalar::step`] runs the same operations in the same order, one
//! lane at a time; neither path uses fused multiply-adds and both read the
//! same inverse-square-root estimate, so the two agree bit for bit on
//! x86-64 with AVX.

use crate::broad_phase::{block_aabb, select_candidates, spheres_to_local, Aabb, Candidate};
use crate::lanes::{inv_sqrt_x8, Vec3x8, LANES};
use crate::{SimParams, Sphere, Strands};
use glam::{Mat3, Vec3};
use wide::f32x8;

/// Coordinates beyond this (metres from the local origin) count as blown up.
pub(crate) const BLOWN_UP: f32 = 1.0e6;
/// Alternations of strain limit and vertex push-out per vertex at the end of
/// a step.
pub(crate) const STRAIN_COLLIDE_ROUNDS: usize = 2;
/// Smallest length a constraint divides by (TressFX clamps with 1e-7 too).
pub(crate) const MIN_LENGTH: f32 = 1.0e-7;

/// Per-step values shared by the SIMD and scalar paths.
pub(crate) struct StepSetup {
    pub damping: f32,
    pub gravity_dt2: Vec3,
    pub iterations: u32,
    pub pearls: u32,
    pub pearl_radius: f32,
    pub stretch_factor: f32,
    pub bend: f32,
    pub shape: f32,
    pub friction: f32,
    pub rest_rotation: Mat3,
    /// Broad-phase margin: pearl radius plus one longest rest segment.
    pub margin: f32,
}

impl StepSetup {
    pub(crate) fn new(strands: &Strands, p: &SimParams) -> Self {
        StepSetup {
            damping: p.damping,
            gravity_dt2: p.gravity * (p.dt * p.dt),
            iterations: p.iterations,
            pearls: p.pearls_per_segment.min(crate::MAX_PEARLS_PER_SEGMENT),
            pearl_radius: p.pearl_radius,
            stretch_factor: 1.0 + p.max_stretch,
            bend: p.bend_stiffness,
            shape: p.shape_stiffness,
            friction: p.friction,
            rest_rotation: strands.rest_rotation,
            margin: p.pearl_radius.max(0.0) + strands.max_rest_segment,
        }
    }

    /// Pearl parameter t = j / (k + 1).
    #[inline(always)]
    pub(crate) fn pearl_t(&self, j: u32) -> f32 {
        j as f32 / (self.pearls + 1) as f32
    }
}

/// `m * v` for eight vectors: `x_axis v.x + y_axis v.y + z_axis v.z`.
#[inline(always)]
fn rotate(m: &Mat3, v: Vec3x8) -> Vec3x8 {
    Vec3x8::splat(m.x_axis) * v.x + Vec3x8::splat(m.y_axis) * v.y + Vec3x8::splat(m.z_axis) * v.z
}

/// Blocks processed together: their constraint chains are independent, so
/// interleaving them hides the latency of each chain's sqrt and division.
pub(crate) const GROUP: usize = 4;

/// Advances every strand by one fixed step of `params.dt` (SIMD path).
///
/// Never panics; `params` should pass [`SimParams::validate`], and strands
/// that bad values drive non-finite are restored and counted
/// ([`Strands::restored_strands`]). Allocates only when the rig has more
/// spheres than any earlier step.
pub fn step(strands: &mut Strands, params: &SimParams, spheres: &[Sphere]) {
    let setup = StepSetup::new(strands, params);
    let mut scratch = std::mem::take(&mut strands.scratch);
    spheres_to_local(spheres, strands.origin, &mut scratch.spheres_local);
    let mut first = 0;
    while first < strands.blocks {
        let n = GROUP.min(strands.blocks - first);
        step_group(
            strands,
            &setup,
            first,
            n,
            &scratch.spheres_local,
            &mut scratch.candidates,
        );
        first += n;
    }
    strands.scratch = scratch;
}

/// Steps blocks `first .. first + n`; index `g * V + v` is vertex v of block
/// `first + g`.
fn step_group(
    s: &mut Strands,
    k: &StepSetup,
    first: usize,
    n: usize,
    spheres: &[[f32; 4]],
    candidates: &mut Vec<Candidate>,
) {
    let verts = s.verts;
    let range = first * verts..(first + n) * verts;
    let pos = &mut s.pos[range.clone()];
    let prev = &mut s.prev[range.clone()];
    let w = &s.inv_mass[range.clone()];
    let zero = f32x8::ZERO;

    // 1. Verlet.
    let d = f32x8::splat(k.damping);
    let g = Vec3x8::splat(k.gravity_dt2);
    for i in 0..pos.len() {
        let x = pos[i];
        let moved = x + (x - prev[i]) * d + g;
        pos[i] = Vec3x8::select(w[i].simd_gt(zero), moved, x);
        prev[i] = x;
    }

    // 2. Shape keeping.
    if k.shape > 0.0 {
        let rest = &s.rest_offset[range.clone()];
        let weight = &s.shape_weight[range.clone()];
        let stiffness = f32x8::splat(k.shape);
        for b in 0..n {
            let root = pos[b * verts];
            for i in b * verts + 1..(b + 1) * verts {
                let target = root + rotate(&k.rest_rotation, rest[i]);
                let pulled = pos[i] + (target - pos[i]) * (stiffness * weight[i]);
                pos[i] = Vec3x8::select(w[i].simd_gt(zero), pulled, pos[i]);
            }
        }
    }

    // 3. Broad phase: the group's blocks' boxes against the rig.
    let mut boxes = [Aabb {
        min: Vec3::ZERO,
        max: Vec3::ZERO,
    }; GROUP];
    for (b, bx) in boxes.iter_mut().enumerate().take(n) {
        *bx = block_aabb(&pos[b * verts..(b + 1) * verts], s.active[first + b]);
    }
    select_candidates(&boxes[..n], k.margin, spheres, candidates);

    // 4. Constraint sweeps (length, then bending), the blocks interleaved
    // segment by segment; one collision pass before the last sweep.
    let rest_len = &s.rest_len[range.clone()];
    let bend_len = &s.bend_len[range.clone()];
    let share = &s.share[range.clone()];
    let bend_share = &s.bend_share[range.clone()];
    let bend = f32x8::splat(k.bend);
    for it in 0..k.iterations {
        if it + 1 == k.iterations {
            collide_group(pos, w, verts, n, candidates, k);
        }
        for v in 0..verts - 1 {
            for b in 0..n {
                let i = b * verts + v;
                distance_constraint(pos, i, i + 1, rest_len[i], share[i], f32x8::ONE);
                if k.bend > 0.0 && v + 2 < verts {
                    distance_constraint(pos, i, i + 2, bend_len[i], bend_share[i], bend);
                }
            }
        }
    }
    // 5. Strain limit alternated with the vertex collisions, root to tip.
    let factor = f32x8::splat(k.stretch_factor);
    strain_limit_and_collide(pos, prev, w, rest_len, verts, n, factor, candidates, k);

    // 6. Pearls.
    for c in candidates.iter() {
        let sphere = Reach::new(c.sphere, k.pearl_radius);
        for b in (0..n).filter(|&b| c.touches(b)) {
            let r = b * verts..(b + 1) * verts;
            collide_pearls(&mut pos[r.clone()], &w[r], &sphere, k);
        }
    }

    // 7. Guard: restore the lanes that went non-finite or blew up.
    let big = f32x8::splat(BLOWN_UP);
    let mut bad = [0u32; GROUP];
    for (b, bits) in bad.iter_mut().enumerate().take(n) {
        let mut ok = f32x8::ZERO.simd_eq(f32x8::ZERO);
        for p in &pos[b * verts..(b + 1) * verts] {
            ok = ok & p.x.abs().simd_lt(big) & p.y.abs().simd_lt(big) & p.z.abs().simd_lt(big);
        }
        *bits = (!ok).to_bitmask();
    }
    restore_lanes(s, first, &bad);
}

/// Restores the lanes flagged in `bad` (one bit mask per block of the
/// group); counts those that hold real strands (padding lanes are restored
/// silently).
pub(crate) fn restore_lanes(s: &mut Strands, first: usize, bad: &[u32; GROUP]) {
    for (b, &bits) in bad.iter().enumerate() {
        for l in 0..LANES {
            if bits & (1 << l) != 0 {
                s.reset_strand(first + b, l);
                if l < s.lanes_in_block(first + b) {
                    s.restored += 1;
                }
            }
        }
    }
}

/// `1 / max(|delta|, MIN_LENGTH)` by [`inv_sqrt_x8`] (shared with patches).
#[inline(always)]
pub(crate) fn inv_len(delta: Vec3x8) -> f32x8 {
    inv_sqrt_x8(
        delta
            .length_squared()
            .fast_max(f32x8::splat(MIN_LENGTH * MIN_LENGTH)),
    )
}

/// Mass-weighted distance constraint between vertices `i` and `j` of one
/// lane chain (a block of strands, or a column block of a patch):
/// `k = stiffness (|delta| - l) / |delta|`, `x_i += share_i k delta`,
/// `x_j -= share_j k delta` with `share_i = w_i / (w_i + w_j)` (Jakobsen
/// 2001's rule, with `1/|delta|` from [`inv_len`]).
#[inline(always)]
pub(crate) fn distance_constraint(
    pos: &mut [Vec3x8],
    i: usize,
    j: usize,
    rest: f32x8,
    share: [f32x8; 2],
    stiffness: f32x8,
) {
    let delta = pos[j] - pos[i];
    let inv_len = inv_len(delta);
    let k = stiffness * (f32x8::ONE - rest * inv_len);
    // A pinned end has share 0 and does not move. (A lane whose positions
    // went NaN can move its root; the guard then restores the whole strand,
    // root included, from `Strands::roots`.)
    pos[i] = pos[i] + delta * (k * share[0]);
    pos[j] = pos[j] - delta * (k * share[1]);
}

/// Step 5. Strain limit, root to tip, combined with the vertex collisions: every free
/// vertex is pulled toward its parent until `|x_v - x_{v-1}| <= factor l_{v-1}`
/// (Provot 1995's deformation limit, in Follow-The-Leader order, Muller et
/// al. 2012), then pushed out of the rig, twice. The parent is final and
/// outside the rig, so the two sets (a ball around the parent, the outside
/// of the spheres) meet, and alternating projections close in on a point of
/// both: the limit does not pull hair into the head and the push-out does not
/// stretch it. Summed over segments the limit gives Yip's root spheres
/// `|x_v - root| <= factor arc(v)`, and it also holds for hair wrapped round
/// the head, whose chord is shorter than its arc.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn strain_limit_and_collide(
    pos: &mut [Vec3x8],
    prev: &mut [Vec3x8],
    w: &[f32x8],
    rest_len: &[f32x8],
    verts: usize,
    n: usize,
    factor: f32x8,
    candidates: &[Candidate],
    k: &StepSetup,
) {
    let friction = f32x8::splat(k.friction);
    for v in 1..verts {
        for b in 0..n {
            let i = b * verts + v;
            let limit = rest_len[i - 1] * factor;
            for _ in 0..STRAIN_COLLIDE_ROUNDS {
                let d = pos[i] - pos[i - 1];
                let d2 = d.length_squared();
                let over = d2.simd_gt(limit * limit) & w[i].simd_gt(f32x8::ZERO);
                if over.any() {
                    let pulled = pos[i - 1] + d * (limit * inv_sqrt_x8(d2));
                    pos[i] = Vec3x8::select(over, pulled, pos[i]);
                }
                for c in candidates.iter().filter(|c| c.touches(b)) {
                    let (hit, normal) =
                        collide_vertex(pos, w, i, &Reach::new(c.sphere, k.pearl_radius));
                    if k.friction > 0.0 && hit.any() {
                        contact_friction(pos, prev, i, hit, normal, friction);
                    }
                }
            }
        }
    }
}

/// Step 4's collision pass: every block of the group against every
/// candidate sphere near it, vertices, then pearls. Run once before the last sweep, so that the sweep
/// smooths what the push-out did (without it, hair draped on a head flapped
/// at 3-5 m/s at rest).
#[inline(always)]
fn collide_group(
    pos: &mut [Vec3x8],
    w: &[f32x8],
    verts: usize,
    n: usize,
    candidates: &[Candidate],
    k: &StepSetup,
) {
    for c in candidates {
        let sphere = Reach::new(c.sphere, k.pearl_radius);
        for b in (0..n).filter(|&b| c.touches(b)) {
            let r = b * verts..(b + 1) * verts;
            for i in r.clone() {
                collide_vertex(pos, w, i, &sphere);
            }
            collide_pearls(&mut pos[r.clone()], &w[r], &sphere, k);
        }
    }
}

/// Outward unit normal and distance from `d` and `d2 = |d|^2`; +y and 0
/// where the point sits on the centre.
#[inline(always)]
pub(crate) fn outward(d: Vec3x8, d2: f32x8) -> (Vec3x8, f32x8) {
    let tiny = f32x8::splat(1e-30);
    let inv = inv_sqrt_x8(d2.max(tiny));
    let on_centre = d2.simd_gt(tiny);
    (
        Vec3x8::select(on_centre, d * inv, Vec3x8::splat(Vec3::Y)),
        on_centre.select(d2 * inv, f32x8::ZERO),
    )
}

/// A rig sphere grown by the pearl radius, as lanes.
#[derive(Clone, Copy)]
pub(crate) struct Reach {
    centre: Vec3x8,
    reach: f32x8,
    reach2: f32x8,
}

impl Reach {
    #[inline(always)]
    pub(crate) fn new(sphere: [f32; 4], pearl_radius: f32) -> Self {
        let reach = f32x8::splat(sphere[3] + pearl_radius);
        Reach {
            centre: Vec3x8::splat(Vec3::new(sphere[0], sphere[1], sphere[2])),
            reach,
            reach2: reach * reach,
        }
    }
}

/// Pushes free vertex `i` out of the sphere to distance `R + r`; returns the
/// lanes it pushed and their outward normals.
#[inline(always)]
pub(crate) fn collide_vertex(
    pos: &mut [Vec3x8],
    w: &[f32x8],
    i: usize,
    s: &Reach,
) -> (f32x8, Vec3x8) {
    let d = pos[i] - s.centre;
    let d2 = d.length_squared();
    let hit = d2.simd_lt(s.reach2) & w[i].simd_gt(f32x8::ZERO);
    if !hit.any() {
        return (hit, Vec3x8::ZERO);
    }
    let (n, dist) = outward(d, d2);
    let pushed = pos[i] + n * (s.reach - dist);
    pos[i] = Vec3x8::select(hit, pushed, pos[i]);
    (hit, n)
}

/// Contact friction: removes the share `mu` of the tangential part of the
/// velocity `x - x_prev` of the lanes in `hit` (outward normals `n`), by
/// moving `x_prev`: `v_t = v - n (v.n)`, `x_prev += mu v_t`.
#[inline(always)]
fn contact_friction(
    pos: &[Vec3x8],
    prev: &mut [Vec3x8],
    i: usize,
    hit: f32x8,
    n: Vec3x8,
    mu: f32x8,
) {
    let v = pos[i] - prev[i];
    let tangential = v - n * v.dot(n);
    prev[i] = Vec3x8::select(hit, prev[i] + tangential * mu, prev[i]);
}

/// Every pearl of one block (a slice of V vertices) against one sphere.
#[inline(always)]
pub(crate) fn collide_pearls(pos: &mut [Vec3x8], w: &[f32x8], s: &Reach, k: &StepSetup) {
    let zero = f32x8::ZERO;
    for j in 1..=k.pearls {
        let t = f32x8::splat(k.pearl_t(j));
        let u = f32x8::ONE - t;
        for v in 0..pos.len() - 1 {
            let p = pos[v] * u + pos[v + 1] * t;
            let d = p - s.centre;
            let d2 = d.length_squared();
            let denom = w[v] * (u * u) + w[v + 1] * (t * t);
            let both_free = w[v].simd_gt(zero) & w[v + 1].simd_gt(zero);
            let hit = d2.simd_lt(s.reach2) & both_free;
            if hit.any() {
                let (n, dist) = outward(d, d2);
                let push = (s.reach - dist) / denom;
                pos[v] = Vec3x8::select(hit, pos[v] + n * (w[v] * u * push), pos[v]);
                pos[v + 1] =
                    Vec3x8::select(hit, pos[v + 1] + n * (w[v + 1] * t * push), pos[v + 1]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strands(count: usize) -> Strands {
        let pts: Vec<Vec3> = (0..count)
            .flat_map(|s| (0..12).map(move |v| Vec3::new(0.01 * s as f32, 0.1, 0.01 * v as f32)))
            .collect();
        Strands::from_polylines(&pts, 12).unwrap()
    }

    #[test]
    fn a_poisoned_strand_is_restored_and_no_other_strand_notices() {
        let rig = [Sphere {
            center: Vec3::ZERO,
            radius: 0.12,
        }];
        let params = SimParams::default();
        for stepper in [
            step as fn(&mut Strands, &SimParams, &[Sphere]),
            crate::scalar::step,
        ] {
            let mut clean = strands(21);
            for _ in 0..10 {
                stepper(&mut clean, &params, &rig);
            }
            let mut poisoned = clean.clone();
            // Strand 13 = block 1, lane 5: one vertex goes NaN mid-flight.
            poisoned.pos[12 + 7].set_lane(5, Vec3::NAN);
            stepper(&mut clean, &params, &rig);
            stepper(&mut poisoned, &params, &rig);
            assert_eq!(poisoned.restored_strands(), 1);
            assert_eq!(clean.restored_strands(), 0);
            let (a, b) = (clean.positions_local(), poisoned.positions_local());
            for s in 0..21 {
                for v in 0..12 {
                    let k = s * 12 + v;
                    if s == 13 {
                        let rest = poisoned.pos[12].lane(5) + poisoned.rest_offset[12 + v].lane(5);
                        assert_eq!(b[k], rest, "restored to rest at its root");
                    } else {
                        assert_eq!(a[k], b[k], "strand {s} vertex {v} was touched");
                    }
                }
            }
        }
    }
}
