//! The scalar reference of the patch step: the same algorithm as
//! [`crate::patch::step`], in the same order, one particle (lane) at a time, with
//! plain `f32` arithmetic. A horizontal, bending or shear edge is visited
//! once and moves both ends, where the SIMD path lets each lane apply its own
//! half; the two halves use `delta` and `-delta` and so give the same bits.
//!
//! The numbered steps are those of `patch/step.rs`'s header: 1 Verlet,
//! 2 broad phase, 3 sweeps (a columns, b rows, c shear, d push-out), 4 long
//! range attachments and 5 strain limits, max distance and push-out (row by
//! row), 6 pearls, 7 guard.

use crate::collide::broad_phase::{select_candidates, spheres_to_local, Candidate};
use crate::constraints::{StepSetup, BLOWN_UP, STRAIN_COLLIDE_ROUNDS};
use crate::lanes::{inv_sqrt, LANES};
use crate::patch::grid::Patch;
use crate::patch::pairs::{partner, PairSet};
use crate::patch::row_limit::limit_row;
use crate::patch::step::{padded_lanes, setup, step_each};
use crate::scalar::broad_phase::block_aabb;
use crate::scalar::{dot, inv_len, outward, push_out};
use crate::{SimParams, Sphere};
use coif_base::tasks::Executor;
use glam::Vec3;

/// Advances `patch` by one fixed step of `params.dt`, one particle at a time.
pub fn step(patch: &mut Patch, params: &SimParams, spheres: &[Sphere]) {
    let k = setup(patch, params);
    let mut scratch = std::mem::take(&mut patch.scratch);
    spheres_to_local(spheres, patch.origin, &mut scratch.spheres_local);
    // 1. Verlet; pinned particles onto the skin.
    integrate(patch, &k);
    // 2. Broad phase.
    let rows = patch.rows;
    scratch.boxes.clear();
    for b in 0..patch.blocks {
        let lanes = (patch.cols - b * LANES).min(LANES);
        let column = &patch.pos[b * rows..(b + 1) * rows];
        scratch.boxes.push(block_aabb(column, lanes));
    }
    select_candidates(
        &scratch.boxes,
        k.margin,
        &scratch.spheres_local,
        &mut scratch.candidates,
    );
    // 3. Constraint sweeps (a-c), each followed by the vertex push-out (d).
    for _ in 0..k.iterations {
        sweep(patch, &k);
        push_out_vertices(patch, &k, &scratch.candidates);
    }
    // 4. Long range attachments, 5. strain limits, max distance and
    // collisions, row by row; 6. pearls.
    clamp_and_collide(patch, &k, &scratch.candidates);
    // 7. Guard.
    let bad = (0..patch.particle_count()).any(|q| {
        let x = patch.get(q);
        !(x.x.abs() < BLOWN_UP && x.y.abs() < BLOWN_UP && x.z.abs() < BLOWN_UP)
    });
    if bad {
        patch.reset_to_skin();
        patch.restored += 1;
    }
    patch.scratch = scratch;
}

/// [`step`] for every patch of `patches`, handed out as tasks to
/// `executor` as [`crate::patch::step_all`] does: the same bytes as
/// stepping them one after another.
pub fn step_all(
    patches: &mut [Patch],
    params: &SimParams,
    spheres: &[Sphere],
    executor: &dyn Executor,
) {
    step_each(patches, executor, &|p| step(p, params, spheres));
}

/// Row-major particle access through the lane layout.
impl Patch {
    fn get(&self, q: usize) -> Vec3 {
        let (i, l) = self.slot(q);
        self.pos[i].lane(l)
    }
    fn put(&mut self, q: usize, x: Vec3) {
        let (i, l) = self.slot(q);
        self.pos[i].set_lane(l, x);
    }
    fn lane_value(&self, a: &[coif_base::lanes::F32Lanes], q: usize) -> f32 {
        let (i, l) = self.slot(q);
        a[i].as_array()[l]
    }
    fn w(&self, q: usize) -> f32 {
        self.lane_value(&self.inv_mass, q)
    }
}

fn integrate(p: &mut Patch, k: &StepSetup) {
    for q in 0..p.particle_count() {
        let (i, l) = p.slot(q);
        let x = p.pos[i].lane(l);
        let prev = p.prev[i].lane(l);
        let next = if p.w(q) > 0.0 {
            x + (x - prev) * k.damping + k.gravity_dt2
        } else {
            p.skin[i].lane(l)
        };
        p.pos[i].set_lane(l, next);
        p.prev[i].set_lane(l, x);
    }
}

/// The edge between particles `a` and `b`: `k = s (1 - rest / |delta|)`,
/// `x_a += share_a k delta`, `x_b -= share_b k delta`.
fn edge(p: &mut Patch, a: usize, b: usize, rest: f32, share: [f32; 2], stiffness: f32) {
    let (xa, xb) = (p.get(a), p.get(b));
    let delta = xb - xa;
    let k = stiffness * (1.0 - rest * inv_len(delta));
    p.put(a, xa + delta * (k * share[0]));
    p.put(b, xb - delta * (k * share[1]));
}

/// A lane-pair edge from `a` (its data in `from_a`) to `b` (in `from_b`).
fn pair_edge(p: &mut Patch, a: usize, b: usize, from_a: &PairSet, from_b: &PairSet, s: f32) {
    let rest = p.lane_value(&from_a.rest, a);
    let share = [
        p.lane_value(&from_a.share, a),
        p.lane_value(&from_b.share, b),
    ];
    edge(p, a, b, rest, share, s);
}

/// A shear edge from `a` (row r) to `b` (row r + 1), solved once:
/// `x_a += share_a (k delta)`, `x_b -= share_b (k delta)` (the SIMD path
/// permutes `k delta` to `b`'s lane).
fn shear_edge(p: &mut Patch, a: usize, b: usize, down: &PairSet, up: &PairSet, s: f32) {
    let (xa, xb) = (p.get(a), p.get(b));
    let delta = xb - xa;
    let k = s * (1.0 - p.lane_value(&down.rest, a) * inv_len(delta));
    let dk = delta * k;
    p.put(a, xa + dk * p.lane_value(&down.share, a));
    p.put(b, xb - dk * p.lane_value(&up.share, b));
}

fn sweep(p: &mut Patch, k: &StepSetup) {
    let (rows, cols, lanes) = (p.rows, p.cols, padded_lanes(p));
    // 3a. Columns.
    for c in 0..cols {
        for r in 0..rows - 1 {
            let a = r * cols + c;
            let (i, l) = p.slot(a);
            let rest = p.vert_rest[i].as_array()[l];
            let share = p.vert_share[i].map(|s| s.as_array()[l]);
            edge(p, a, a + cols, rest, share, 1.0);
            if k.bend > 0.0 && r + 2 < rows {
                let rest = p.vbend_rest[i].as_array()[l];
                let share = p.vbend_share[i].map(|s| s.as_array()[l]);
                edge(p, a, a + 2 * cols, rest, share, k.bend);
            }
        }
    }
    // 3b. Rows.
    let horiz = std::mem::take(&mut p.horiz);
    let hbend = std::mem::take(&mut p.hbend);
    for r in 0..rows {
        let strides: &[(usize, &[PairSet; 2], f32)] = if k.bend > 0.0 {
            &[(1, &horiz, 1.0), (2, &hbend, k.bend)]
        } else {
            &[(1, &horiz, 1.0)]
        };
        for &(s, sets, stiffness) in strides {
            for (colour, set) in sets.iter().enumerate() {
                for c in 0..cols {
                    match partner(c, s, colour, lanes) {
                        Some(pc) if pc > c && pc < cols => {
                            pair_edge(p, r * cols + c, r * cols + pc, set, set, stiffness);
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    p.horiz = horiz;
    p.hbend = hbend;
    // 3c. Shear.
    if p.shear_stiffness > 0.0 {
        let down = std::mem::take(&mut p.shear_down);
        let up = std::mem::take(&mut p.shear_up);
        for r in 0..rows - 1 {
            for colour in 0..2 {
                for c in 0..cols {
                    if let Some(pc) = partner(c, 1, colour, lanes).filter(|&pc| pc < cols) {
                        let (a, b) = (r * cols + c, (r + 1) * cols + pc);
                        shear_edge(p, a, b, &down[colour], &up[colour], p.shear_stiffness);
                    }
                }
            }
        }
        p.shear_down = down;
        p.shear_up = up;
    }
}

/// Pushes the pearl `p = u x_a + t x_b` of edge `(a, b)` out of the sphere
/// (`centre`, `reach`), moving both ends by their share.
fn pearl(p: &mut Patch, a: usize, b: usize, u: f32, t: f32, centre: Vec3, reach: f32) {
    let (xa, xb) = (p.get(a), p.get(b));
    let (wa, wb) = (p.w(a), p.w(b));
    let d = xa * u + xb * t - centre;
    let d2 = dot(d, d);
    let denom = wa * (u * u) + wb * (t * t);
    if d2 < reach * reach && wa > 0.0 && wb > 0.0 {
        let (n, dist) = outward(d, d2);
        let push = (reach - dist) / denom;
        p.put(a, xa + n * (wa * u * push));
        p.put(b, xb + n * (wb * t * push));
    }
}

fn collide_vertex(p: &mut Patch, q: usize, sphere: [f32; 4], pearl_radius: f32) {
    if let Some((x, _)) = push_out(p.get(q), p.w(q), sphere, pearl_radius) {
        p.put(q, x);
    }
}

/// Step 3d: every free particle pushed out of the nearby spheres to `R + r`.
fn push_out_vertices(p: &mut Patch, k: &StepSetup, candidates: &[Candidate]) {
    let cols = p.cols;
    for c in candidates {
        for q in (0..p.particle_count()).filter(|q| c.touches((q % cols) / LANES)) {
            collide_vertex(p, q, c.sphere, k.pearl_radius);
        }
    }
}

/// Steps 4 to 6 (the twin of `patch::step::clamp_and_collide`).
fn clamp_and_collide(p: &mut Patch, k: &StepSetup, candidates: &[Candidate]) {
    let (rows, cols) = (p.rows, p.cols);
    for r in 0..rows {
        // 4. Long range attachments of row r.
        for q in r * cols..(r + 1) * cols {
            let (i, l) = p.slot(q);
            let limit = p.tether_len[i].as_array()[l] * k.stretch_factor;
            let anchor = p.anchor_skin[i].lane(l);
            let d = p.get(q) - anchor;
            let d2 = dot(d, d);
            if d2 > limit * limit && p.w(q) > 0.0 {
                p.put(q, anchor + d * (limit * inv_sqrt(d2)));
            }
        }
        // 5. Column limit, row limit (last round), max distance, push-out.
        for round in 0..STRAIN_COLLIDE_ROUNDS {
            for q in (r * cols..(r + 1) * cols).filter(|&q| q >= cols) {
                let (i, l) = p.slot(q);
                let up = p.parent_up[i].as_array()[l].to_bits() != 0;
                let limit = p.lane_value(&p.vert_rest, q - cols) * k.stretch_factor;
                let (parent, x) = (p.get(q - cols), p.get(q));
                let d = x - parent;
                let d2 = dot(d, d);
                if d2 > limit * limit && up {
                    p.put(q, parent + d * (limit * inv_sqrt(d2)));
                }
            }
            if round + 1 == STRAIN_COLLIDE_ROUNDS {
                limit_row(p, r, k.stretch_factor);
            }
            for q in r * cols..(r + 1) * cols {
                let (i, l) = p.slot(q);
                let m = p.max_distance[i].as_array()[l];
                let s = p.skin[i].lane(l);
                let d = p.get(q) - s;
                let d2 = dot(d, d);
                if d2 > m * m && p.w(q) > 0.0 {
                    p.put(q, s + d * (m * inv_sqrt(d2)));
                }
                let block = (q % cols) / LANES;
                for c in candidates.iter().filter(|c| c.touches(block)) {
                    collide_vertex(p, q, c.sphere, k.pearl_radius);
                }
            }
        }
    }
    // 6. Pearls, along columns, then along rows.
    if k.pearls == 0 {
        return;
    }
    for c in candidates {
        let centre = Vec3::new(c.sphere[0], c.sphere[1], c.sphere[2]);
        let reach = c.sphere[3] + k.pearl_radius;
        for col in (0..cols).filter(|col| c.touches(col / LANES)) {
            for j in 1..=k.pearls {
                let t = k.pearl_t(j);
                for r in 0..rows - 1 {
                    let a = r * cols + col;
                    pearl(p, a, a + cols, 1.0 - t, t, centre, reach);
                }
            }
        }
    }
    for c in candidates {
        let centre = Vec3::new(c.sphere[0], c.sphere[1], c.sphere[2]);
        let reach = c.sphere[3] + k.pearl_radius;
        for r in 0..rows {
            for colour in 0..2 {
                for j in 1..=k.pearls {
                    let t = k.pearl_t(j);
                    for col in (colour..cols - 1).step_by(2) {
                        let a = r * cols + col;
                        pearl(p, a, a + 1, 1.0 - t, t, centre, reach);
                    }
                }
            }
        }
    }
}
