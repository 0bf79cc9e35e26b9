//! The scalar reference of the simulation step: the same algorithm as
//! [`crate::step`], in the same order, one strand (lane) at a time, with
//! plain `f32` arithmetic and no SIMD. Tests compare the two; benchmarks run
//! them side by side. Blocks are grouped as in the SIMD path only so that the
//! broad phase sees the same boxes and picks the same spheres.
//!
//! The numbered steps are those of `step.rs`'s header:
//!
//! 1. Verlet with damping (Yip 2011), per lane.
//! 2. Shape keeping toward the groomed pose (optional).
//! 3. Broad phase: the group's block boxes against the rig.
//! 4. `iterations` sweeps of length (and bending) constraints (Jakobsen
//!    2001), one collision pass before the last sweep.
//! 5. Strain limit (Provot 1995, Follow-The-Leader order) alternated with the
//!    vertex collisions and contact friction, root to tip.
//! 6. Pearls, by the point-on-segment rule.
//! 7. Guard: a lane that went non-finite or beyond 10^6 m is restored.

use super::broad_phase::block_aabb;
use crate::broad_phase::{select_candidates, spheres_to_local, Aabb, Candidate};
use crate::lanes::inv_sqrt;
use crate::step::{restore_lanes, StepSetup, BLOWN_UP, GROUP, MIN_LENGTH, STRAIN_COLLIDE_ROUNDS};
use crate::{SimParams, Sphere, Strands};
use glam::{Mat3, Vec3};

/// Advances every strand by one fixed step of `params.dt`, one lane at a time.
pub fn step(strands: &mut Strands, params: &SimParams, spheres: &[Sphere]) {
    let setup = StepSetup::new(strands, params);
    let mut scratch = std::mem::take(&mut strands.scratch);
    spheres_to_local(spheres, strands.origin, &mut scratch.spheres_local);
    let verts = strands.verts;
    let mut first = 0;
    while first < strands.blocks {
        let n = GROUP.min(strands.blocks - first);
        // 1. Verlet and 2. shape keeping.
        for b in first..first + n {
            for l in 0..strands.lanes_in_block(b) {
                integrate_lane(strands, &setup, b, l);
            }
        }
        // 3. Broad phase.
        let mut boxes = [Aabb {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        }; GROUP];
        for (g, bx) in boxes.iter_mut().enumerate().take(n) {
            let b = first + g;
            *bx = block_aabb(
                &strands.pos[b * verts..(b + 1) * verts],
                strands.lanes_in_block(b),
            );
        }
        select_candidates(
            &boxes[..n],
            setup.margin,
            &scratch.spheres_local,
            &mut scratch.candidates,
        );
        // 4.-6. per lane; 7. the lanes that blew up are restored.
        let mut bad = [0u32; GROUP];
        for (g, bits) in bad.iter_mut().enumerate().take(n) {
            for l in 0..strands.lanes_in_block(first + g) {
                if !solve_lane(strands, &setup, first + g, g, l, &scratch.candidates) {
                    *bits |= 1 << l;
                }
            }
        }
        restore_lanes(strands, first, &bad);
        first += n;
    }
    strands.scratch = scratch;
}

/// One strand's vertices, read and written through its lane.
struct Lane<'a> {
    s: &'a mut Strands,
    base: usize,
    l: usize,
}

impl Lane<'_> {
    fn x(&self, v: usize) -> Vec3 {
        self.s.pos[self.base + v].lane(self.l)
    }
    fn set_x(&mut self, v: usize, p: Vec3) {
        self.s.pos[self.base + v].set_lane(self.l, p);
    }
    fn w(&self, v: usize) -> f32 {
        self.s.inv_mass[self.base + v].as_array()[self.l]
    }
    fn get(&self, a: &[wide::f32x8], v: usize) -> f32 {
        a[self.base + v].as_array()[self.l]
    }
    fn shares(&self, a: &[[wide::f32x8; 2]], v: usize) -> [f32; 2] {
        let s = &a[self.base + v];
        [s[0].as_array()[self.l], s[1].as_array()[self.l]]
    }
}

/// `1 / max(|delta|, MIN_LENGTH)`, the twin of `step::inv_len`.
pub(crate) fn inv_len(delta: Vec3) -> f32 {
    inv_sqrt(dot(delta, delta).max(MIN_LENGTH * MIN_LENGTH))
}

/// `a.b` summed x, y, z in that order (the SIMD paths' order).
pub(crate) fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// `m * v` as `x_axis v.x + y_axis v.y + z_axis v.z`, the SIMD path's order.
fn rotate(m: &Mat3, v: Vec3) -> Vec3 {
    m.x_axis * v.x + m.y_axis * v.y + m.z_axis * v.z
}

fn integrate_lane(s: &mut Strands, k: &StepSetup, b: usize, l: usize) {
    let base = b * s.verts;
    let n = s.verts;
    let mut lane = Lane { s, base, l };
    // 1. Verlet.
    for v in 0..n {
        let x = lane.x(v);
        let p = lane.s.prev[base + v].lane(l);
        if lane.w(v) > 0.0 {
            lane.set_x(v, x + (x - p) * k.damping + k.gravity_dt2);
        }
        lane.s.prev[base + v].set_lane(l, x);
    }
    // 2. Shape keeping.
    if k.shape > 0.0 {
        let root = lane.x(0);
        for v in 1..n {
            if lane.w(v) > 0.0 {
                let target = root + rotate(&k.rest_rotation, lane.s.rest_offset[base + v].lane(l));
                let x = lane.x(v);
                let weight = lane.get(&lane.s.shape_weight, v);
                lane.set_x(v, x + (target - x) * (k.shape * weight));
            }
        }
    }
}

/// Steps 4 to 7 of one lane: constraint sweeps, strain limit and
/// collisions, pearls, and the guard's test; false if the
/// lane blew up (non-finite or beyond [`BLOWN_UP`]). `g` is the block's place
/// in its group (its bit in [`Candidate::blocks`]).
fn solve_lane(
    s: &mut Strands,
    k: &StepSetup,
    b: usize,
    g: usize,
    l: usize,
    candidates: &[Candidate],
) -> bool {
    let base = b * s.verts;
    let n = s.verts;
    let mut lane = Lane { s, base, l };
    // 4. Constraint sweeps; one collision pass before the last.
    for it in 0..k.iterations {
        if it + 1 == k.iterations {
            for c in candidates.iter().filter(|c| c.touches(g)) {
                for v in 0..n {
                    collide_vertex(&mut lane, v, c.sphere, k.pearl_radius);
                }
                collide_pearls(&mut lane, c.sphere, k);
            }
        }
        for v in 0..n - 1 {
            let (rest, share) = (lane.get(&lane.s.rest_len, v), lane.shares(&lane.s.share, v));
            distance_constraint(&mut lane, v, v + 1, rest, share, 1.0);
            if k.bend > 0.0 && v + 2 < n {
                let (rest, share) = (
                    lane.get(&lane.s.bend_len, v),
                    lane.shares(&lane.s.bend_share, v),
                );
                distance_constraint(&mut lane, v, v + 2, rest, share, k.bend);
            }
        }
    }
    // 5. Strain limit alternated with the vertex collisions.
    strain_limit_and_collide(&mut lane, k, g, candidates);
    // 6. Pearls.
    for c in candidates.iter().filter(|c| c.touches(g)) {
        collide_pearls(&mut lane, c.sphere, k);
    }
    // 7. Guard: finite and within BLOWN_UP.
    (0..n).all(|v| {
        let p = lane.x(v);
        p.x.abs() < BLOWN_UP && p.y.abs() < BLOWN_UP && p.z.abs() < BLOWN_UP
    })
}

fn distance_constraint(
    lane: &mut Lane,
    i: usize,
    j: usize,
    rest: f32,
    share: [f32; 2],
    stiffness: f32,
) {
    let (xi, xj) = (lane.x(i), lane.x(j));
    let delta = xj - xi;
    let k = stiffness * (1.0 - rest * inv_len(delta));
    lane.set_x(i, xi + delta * (k * share[0]));
    lane.set_x(j, xj - delta * (k * share[1]));
}

/// Step 5 for one lane (the twin of `step::strain_limit_and_collide`).
fn strain_limit_and_collide(lane: &mut Lane, k: &StepSetup, g: usize, candidates: &[Candidate]) {
    for v in 1..lane.s.verts {
        let limit = lane.get(&lane.s.rest_len, v - 1) * k.stretch_factor;
        for _ in 0..STRAIN_COLLIDE_ROUNDS {
            let (parent, x) = (lane.x(v - 1), lane.x(v));
            let d = x - parent;
            let d2 = dot(d, d);
            if d2 > limit * limit && lane.w(v) > 0.0 {
                lane.set_x(v, parent + d * (limit * inv_sqrt(d2)));
            }
            for c in candidates.iter().filter(|c| c.touches(g)) {
                if let Some(normal) = collide_vertex(lane, v, c.sphere, k.pearl_radius) {
                    if k.friction > 0.0 {
                        contact_friction(lane, v, normal, k.friction);
                    }
                }
            }
        }
    }
}

/// Outward unit normal and distance; +y and 0 where the point sits on the centre.
pub(crate) fn outward(d: Vec3, d2: f32) -> (Vec3, f32) {
    let inv = inv_sqrt(d2.max(1e-30));
    if d2 > 1e-30 {
        (d * inv, d2 * inv)
    } else {
        (Vec3::Y, 0.0)
    }
}

/// A free point `x` (inverse mass `w`) pushed out of the sphere to distance
/// `R + r`: the new position and the outward normal, or None if it is outside
/// (or pinned). The scalar twin of `step::collide_vertex`, shared by strands
/// and patches.
pub(crate) fn push_out(
    x: Vec3,
    w: f32,
    sphere: [f32; 4],
    pearl_radius: f32,
) -> Option<(Vec3, Vec3)> {
    let centre = Vec3::new(sphere[0], sphere[1], sphere[2]);
    let reach = sphere[3] + pearl_radius;
    let d = x - centre;
    let d2 = dot(d, d);
    if d2 < reach * reach && w > 0.0 {
        let (n, dist) = outward(d, d2);
        Some((x + n * (reach - dist), n))
    } else {
        None
    }
}

/// Pushes vertex `v` out of the sphere; returns the outward normal if it did.
fn collide_vertex(lane: &mut Lane, v: usize, sphere: [f32; 4], pearl_radius: f32) -> Option<Vec3> {
    let (x, n) = push_out(lane.x(v), lane.w(v), sphere, pearl_radius)?;
    lane.set_x(v, x);
    Some(n)
}

/// `v_t = v - n (v.n)`, `x_prev += mu v_t` with `v = x - x_prev`.
fn contact_friction(lane: &mut Lane, v: usize, n: Vec3, mu: f32) {
    let k = lane.base + v;
    let prev = lane.s.prev[k].lane(lane.l);
    let vel = lane.x(v) - prev;
    let tangential = vel - n * dot(vel, n);
    lane.s.prev[k].set_lane(lane.l, prev + tangential * mu);
}

fn collide_pearls(lane: &mut Lane, sphere: [f32; 4], k: &StepSetup) {
    let centre = Vec3::new(sphere[0], sphere[1], sphere[2]);
    let reach = sphere[3] + k.pearl_radius;
    let reach2 = reach * reach;
    for j in 1..=k.pearls {
        let t = k.pearl_t(j);
        let u = 1.0 - t;
        for v in 0..lane.s.verts - 1 {
            let (xi, xj) = (lane.x(v), lane.x(v + 1));
            let (wi, wj) = (lane.w(v), lane.w(v + 1));
            let p = xi * u + xj * t;
            let d = p - centre;
            let d2 = dot(d, d);
            let denom = wi * (u * u) + wj * (t * t);
            if d2 < reach2 && wi > 0.0 && wj > 0.0 {
                let (normal, dist) = outward(d, d2);
                let push = (reach - dist) / denom;
                lane.set_x(v, xi + normal * (wi * u * push));
                lane.set_x(v + 1, xj + normal * (wj * t * push));
            }
        }
    }
}
