//! One fixed step of a patch, SIMD path: eight columns per register.
//!
//! In this order (the strand step's structure; the numbers are the step
//! comments of [`step`]'s body and of its scalar twin [`super::scalar::step`]):
//!
//! 1. **Verlet** with damping (Yip 2011): `x' = x + d (x - x_prev) + g dt^2`
//!    for free particles; pinned ones (inverse mass 0) move to their skinned
//!    position.
//! 2. **Broad phase**: each column block's bounding box, grown by the pearl
//!    radius plus the longest rest edge, against every rig sphere
//!    (`broad_phase.rs`).
//! 3. `iterations` sweeps of mass-weighted distance constraints (Jakobsen
//!    2001), `k = s (1 - l / |delta|)`, `x_i += w_i/(w_i+w_j) k delta`,
//!    `x_j -= w_j/(w_i+w_j) k delta`, with `1/|delta|` from [`inv_sqrt_simd`] of
//!    `max(|delta|^2, 1e-14)`: (a) vertical edges `(r, r+1)` top to bottom,
//!    lane-parallel, each followed by the vertical bending edge `(r, r+2)`
//!    when `bend_stiffness > 0`; (b) per row, horizontal edges `(c, c+1)` in
//!    two colour passes, then the horizontal bending edges `(c, c+2)` in two
//!    more; (c) per pair of rows, the shear edges (both diagonals of each
//!    quad) in two colour passes, scaled by the shear stiffness, each solved
//!    once as `x_i += share_i (k delta)`, `x_j -= share_j (k delta)`; (d) every
//!    free particle pushed out of the nearby spheres to `R + r`.
//!
//! Steps 4 and 5 run row by row, top to bottom: row `r` gets its long range
//! attachments (4), then its two rounds of 5, before row `r + 1` starts.
//!
//! 4. **Long range attachments** (Kim, Chentanez and Muller 2012): a free
//!    particle farther than `(1 + max_stretch) L` from its anchor, the
//!    pinned particle nearest along the grid (`L` = the shortest rest path
//!    over structural and diagonal edges), is pulled back onto that sphere.
//! 5. Twice per row (the strands' alternation of strain
//!    limit and collisions): the **column strain limit** (Provot 1995, in
//!    Follow-The-Leader order, Muller et al. 2012) pulls a particle whose
//!    shortest path to the pins goes through the particle above toward it
//!    until `|x_r - x_{r-1}| <= (1 + max_stretch) l`; in the second round
//!    the **row strain limit** (`row_limit.rs`) then walks the row from its
//!    root column outward, moving each particle to the nearest point within
//!    `(1 + max_stretch) l` of its row leader that keeps the column limit;
//!    the **max distance** moves a particle farther than `m` from its
//!    skinned position `s` to `s + m (x - s) / |x - s|` (the cloth
//!    constraint of PhysX and Unity); then the particle is pushed out of
//!    every nearby sphere to `R + r`.
//! 6. **Pearls** along columns and rows, pushed out by the point-on-segment
//!    rule of the Nalu demo (Nguyen and Donnelly 2005): `p = (1-t) x_i + t x_j`,
//!    `s = -C / (w_i (1-t)^2 + w_j t^2)`, `x_i += w_i (1-t) s n`,
//!    `x_j += w_j t s n`. Collisions run last so nothing is left inside a
//!    sphere.
//! 7. **Guard**: if any particle is non-finite or beyond 10^6 m of the
//!    local origin, the whole patch is restored to its skin and counted.
//!    Patches share no storage, so no other patch is touched.
//!
//! [`super::scalar::step`] performs the same operations in the same order,
//! one particle at a time, without fused multiply-adds; the two agree bit for
//! bit on x86-64 with AVX (compared with `==`, so `-0.0` and `0.0` count as
//! equal: a lane without a partner adds `0.0`, which the scalar path skips).

use super::grid::{Patch, PatchScratch};
use super::pairs::gather_row;
use super::row_limit::limit_row;
use crate::collide::broad_phase::{block_aabb, select_candidates, spheres_to_local, Candidate};
use crate::constraints::{
    collide_pearls, collide_vertex, distance_constraint, inv_len, outward, Reach, StepSetup,
    BLOWN_UP, STRAIN_COLLIDE_ROUNDS,
};
use crate::lanes::{inv_sqrt_simd, Vec3Lanes, LANES};
use crate::{SimParams, Sphere, MAX_PEARLS_PER_SEGMENT};
use coif_base::lanes::F32Lanes;
use coif_base::tasks::{for_each_chunk_mut, Executor};
use glam::Vec3;

/// Per-step constants of a patch ([`StepSetup`]; shape
/// keeping and contact friction are not used by patches).
pub(crate) fn setup(patch: &Patch, p: &SimParams) -> StepSetup {
    StepSetup {
        damping: p.damping,
        gravity_dt2: p.gravity * (p.dt * p.dt),
        iterations: p.iterations,
        pearls: p.pearls_per_segment.min(MAX_PEARLS_PER_SEGMENT),
        pearl_radius: p.pearl_radius,
        stretch_factor: 1.0 + p.max_stretch,
        bend: p.bend_stiffness,
        margin: p.pearl_radius.max(0.0) + patch.max_rest_edge,
    }
}

/// Advances `patch` by one fixed step of `params.dt` (SIMD path), toward the
/// skin given by the last [`Patch::set_skinned`].
///
/// Never panics and allocates only when the rig has more spheres than any
/// earlier step; `params` should pass [`SimParams::validate`]. A patch that
/// bad values drive non-finite is restored to its skin
/// ([`Patch::restored_count`]).
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
        let column = &patch.pos[b * rows..(b + 1) * rows];
        scratch.boxes.push(block_aabb(column, patch.active[b]));
    }
    select_candidates(
        &scratch.boxes,
        k.margin,
        &scratch.spheres_local,
        &mut scratch.candidates,
    );
    // 3. Constraint sweeps (a-c), each followed by the vertex push-out (d).
    for _ in 0..k.iterations {
        sweep(patch, &k, &mut scratch);
        push_out_vertices(patch, &k, &scratch.candidates);
    }
    // 4. Long range attachments, 5. strain limits, max distance and
    // collisions, row by row; 6. pearls.
    clamp_and_collide(patch, &k, &mut scratch);
    // 7. Guard.
    if blown_up(patch) {
        patch.reset_to_skin();
        patch.restored += 1;
    }
    patch.scratch = scratch;
}

/// Advances every patch of `patches` by one fixed step ([`step`] each,
/// against the same rig), the patches handed out as tasks to `executor`.
/// A patch is never split (its rows couple its column blocks); a task takes
/// a run of consecutive patches, about four tasks per thread. Patches share
/// nothing, so the result is the same bytes as stepping them one after
/// another, with any executor and any number of threads; nothing is
/// allocated beyond what [`step`] allocates.
pub fn step_all(
    patches: &mut [Patch],
    params: &SimParams,
    spheres: &[Sphere],
    executor: &dyn Executor,
) {
    step_each(patches, executor, &|p| step(p, params, spheres));
}

/// Runs `f` on every patch, runs of consecutive patches as tasks (the
/// split of [`step_all`] and of its scalar twin).
pub(crate) fn step_each(
    patches: &mut [Patch],
    executor: &dyn Executor,
    f: &(dyn Fn(&mut Patch) + Sync),
) {
    let per_task = patches.len().div_ceil(4 * executor.threads().max(1)).max(1);
    for_each_chunk_mut(executor, patches, per_task, &|_, run| {
        run.iter_mut().for_each(f)
    });
}

fn integrate(p: &mut Patch, k: &StepSetup) {
    let d = F32Lanes::splat(k.damping);
    let g = Vec3Lanes::splat(k.gravity_dt2);
    for i in 0..p.pos.len() {
        let x = p.pos[i];
        let moved = x + (x - p.prev[i]) * d + g;
        p.pos[i] = Vec3Lanes::select(p.inv_mass[i].simd_gt(F32Lanes::ZERO), moved, p.skin[i]);
        p.prev[i] = x;
    }
}

/// One lane's half of a pair constraint: `x` moves toward (or away from) its
/// partner `p` by its mass share.
#[inline(always)]
fn pair_half(
    x: Vec3Lanes,
    p: Vec3Lanes,
    rest: F32Lanes,
    share: F32Lanes,
    stiffness: F32Lanes,
) -> Vec3Lanes {
    let delta = p - x;
    let k = stiffness * (F32Lanes::ONE - rest * inv_len(delta));
    x + delta * (k * share)
}

fn sweep(p: &mut Patch, k: &StepSetup, scratch: &mut PatchScratch) {
    let (rows, blocks) = (p.rows, p.blocks);
    let one = F32Lanes::ONE;
    let bend = F32Lanes::splat(k.bend);
    // 3a. Columns.
    for r in 0..rows - 1 {
        for b in 0..blocks {
            let i = b * rows + r;
            distance_constraint(&mut p.pos, i, i + 1, p.vert_rest[i], p.vert_share[i], one);
            if k.bend > 0.0 && r + 2 < rows {
                distance_constraint(
                    &mut p.pos,
                    i,
                    i + 2,
                    p.vbend_rest[i],
                    p.vbend_share[i],
                    bend,
                );
            }
        }
    }
    // 3b. Rows.
    let pa = &mut scratch.partner_a;
    for r in 0..rows {
        for colour in 0..2 {
            gather_row(&p.pos, rows, r, 1, colour, pa);
            let set = &p.horiz[colour];
            for (b, partner) in pa.iter().enumerate() {
                let i = b * rows + r;
                p.pos[i] = pair_half(p.pos[i], *partner, set.rest[i], set.share[i], one);
            }
        }
        if k.bend > 0.0 {
            for colour in 0..2 {
                gather_row(&p.pos, rows, r, 2, colour, pa);
                let set = &p.hbend[colour];
                for (b, partner) in pa.iter().enumerate() {
                    let i = b * rows + r;
                    p.pos[i] = pair_half(p.pos[i], *partner, set.rest[i], set.share[i], bend);
                }
            }
        }
    }
    // 3c. Shear: each diagonal is solved once, in the upper row's lane, and
    // its correction `k delta` is permuted over to the lower row's lane.
    if p.shear_stiffness > 0.0 {
        let shear = F32Lanes::splat(p.shear_stiffness);
        let (pb, pc) = (&mut scratch.partner_b, &mut scratch.partner_c);
        for r in 0..rows - 1 {
            for colour in 0..2 {
                gather_row(&p.pos, rows, r + 1, 1, colour, pa);
                let (down, up) = (&p.shear_down[colour], &p.shear_up[colour]);
                for b in 0..blocks {
                    let i = b * rows + r;
                    let delta = pa[b] - p.pos[i];
                    let k = shear * (F32Lanes::ONE - down.rest[i] * inv_len(delta));
                    pb[b] = delta * k;
                    p.pos[i] = p.pos[i] + pb[b] * down.share[i];
                }
                gather_row(pb, 1, 0, 1, colour, pc);
                for (b, correction) in pc.iter().enumerate() {
                    let j = b * rows + r + 1;
                    p.pos[j] = p.pos[j] - *correction * up.share[j];
                }
            }
        }
    }
}

/// Step 3d: every free particle pushed out of the nearby spheres to `R + r`.
fn push_out_vertices(p: &mut Patch, k: &StepSetup, candidates: &[Candidate]) {
    let rows = p.rows;
    for c in candidates {
        let reach = Reach::new(c.sphere, k.pearl_radius);
        for b in (0..p.blocks).filter(|&b| c.touches(b)) {
            for i in b * rows..(b + 1) * rows {
                collide_vertex(&mut p.pos, &p.inv_mass, i, &reach);
            }
        }
    }
}

/// Steps 4 to 6: per row, long range attachments then two rounds of strain
/// limits, max distance and push-out; then the pearls.
fn clamp_and_collide(p: &mut Patch, k: &StepSetup, scratch: &mut PatchScratch) {
    let rows = p.rows;
    let zero = F32Lanes::ZERO;
    let candidates: &[Candidate] = &scratch.candidates;
    let factor = F32Lanes::splat(k.stretch_factor);
    for r in 0..rows {
        // 4. Long range attachments of row r.
        for b in 0..p.blocks {
            let i = b * rows + r;
            let free = p.inv_mass[i].simd_gt(zero);
            let limit = p.tether_len[i] * factor;
            let d = p.pos[i] - p.anchor_skin[i];
            let d2 = d.length_squared();
            let over = d2.simd_gt(limit * limit) & free;
            if over.any() {
                let pulled = p.anchor_skin[i] + d * (limit * inv_sqrt_simd(d2));
                p.pos[i] = Vec3Lanes::select(over, pulled, p.pos[i]);
            }
        }
        // 5. Column limit, row limit (last round), max distance, push-out.
        for round in 0..STRAIN_COLLIDE_ROUNDS {
            if r > 0 {
                for b in 0..p.blocks {
                    let i = b * rows + r;
                    let limit = p.vert_rest[i - 1] * factor;
                    let d = p.pos[i] - p.pos[i - 1];
                    let d2 = d.length_squared();
                    let over = d2.simd_gt(limit * limit) & p.parent_up[i];
                    if over.any() {
                        let pulled = p.pos[i - 1] + d * (limit * inv_sqrt_simd(d2));
                        p.pos[i] = Vec3Lanes::select(over, pulled, p.pos[i]);
                    }
                }
            }
            if round + 1 == STRAIN_COLLIDE_ROUNDS {
                limit_row(p, r, k.stretch_factor);
            }
            for b in 0..p.blocks {
                let i = b * rows + r;
                let free = p.inv_mass[i].simd_gt(zero);
                let m = p.max_distance[i];
                let d = p.pos[i] - p.skin[i];
                let d2 = d.length_squared();
                let over = d2.simd_gt(m * m) & free;
                if over.any() {
                    let clamped = p.skin[i] + d * (m * inv_sqrt_simd(d2));
                    p.pos[i] = Vec3Lanes::select(over, clamped, p.pos[i]);
                }
                for c in candidates.iter().filter(|c| c.touches(b)) {
                    let reach = Reach::new(c.sphere, k.pearl_radius);
                    collide_vertex(&mut p.pos, &p.inv_mass, i, &reach);
                }
            }
        }
    }
    // 6. Pearls, along columns (lane-parallel), then along rows.
    if k.pearls == 0 {
        return;
    }
    for c in candidates {
        let reach = Reach::new(c.sphere, k.pearl_radius);
        for b in (0..p.blocks).filter(|&b| c.touches(b)) {
            let r = b * rows..(b + 1) * rows;
            collide_pearls(&mut p.pos[r.clone()], &p.inv_mass[r], &reach, k);
        }
    }
    let pa = &mut scratch.partner_a;
    for c in candidates {
        let centre = Vec3Lanes::splat(Vec3::new(c.sphere[0], c.sphere[1], c.sphere[2]));
        let reach = F32Lanes::splat(c.sphere[3] + k.pearl_radius);
        let reach2 = reach * reach;
        for r in 0..rows {
            for colour in 0..2 {
                // Lanes whose partner is to their right hold the edge's
                // first end.
                let first = F32Lanes::new(std::array::from_fn(|l| {
                    if l % 2 == colour {
                        f32::from_bits(!0)
                    } else {
                        0.0
                    }
                }));
                let set = &p.horiz[colour];
                for j in 1..=k.pearls {
                    let (t, u) = (
                        F32Lanes::splat(k.pearl_t(j)),
                        F32Lanes::ONE - F32Lanes::splat(k.pearl_t(j)),
                    );
                    let (own, other) = (first.select(u, t), first.select(t, u));
                    gather_row(&p.pos, rows, r, 1, colour, pa);
                    for (b, partner) in pa.iter().enumerate() {
                        let i = b * rows + r;
                        let (x, w, pw) = (p.pos[i], p.inv_mass[i], set.partner_w[i]);
                        let pearl = x * own + *partner * other;
                        let d = pearl - centre;
                        let d2 = d.length_squared();
                        let denom = w * (own * own) + pw * (other * other);
                        let hit = d2.simd_lt(reach2) & w.simd_gt(zero) & pw.simd_gt(zero);
                        if hit.any() {
                            let (n, dist) = outward(d, d2);
                            let push = (reach - dist) / denom;
                            p.pos[i] = Vec3Lanes::select(hit, x + n * (w * own * push), x);
                        }
                    }
                }
            }
        }
    }
}

/// Step 7's test: true if a real particle is non-finite or beyond [`BLOWN_UP`].
fn blown_up(p: &Patch) -> bool {
    let big = F32Lanes::splat(BLOWN_UP);
    let rows = p.rows;
    (0..p.blocks).any(|b| {
        let mut ok = F32Lanes::ZERO.simd_eq(F32Lanes::ZERO);
        for x in &p.pos[b * rows..(b + 1) * rows] {
            ok = ok & x.x.abs().simd_lt(big) & x.y.abs().simd_lt(big) & x.z.abs().simd_lt(big);
        }
        (!ok & p.active[b]).any()
    })
}

/// Lanes of a padded row (kept for the scalar twin's partner rule).
pub(crate) fn padded_lanes(p: &Patch) -> usize {
    p.blocks * LANES
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 6 x 11 flag (two column blocks), top row pinned.
    fn flag() -> (Patch, Vec<Vec3>) {
        let (rows, cols) = (6, 11);
        let pts: Vec<Vec3> = (0..rows * cols)
            .map(|k| Vec3::new(0.02 * (k % cols) as f32, -0.02 * (k / cols) as f32, 0.0))
            .collect();
        let pinned: Vec<bool> = (0..rows * cols).map(|k| k < cols).collect();
        (Patch::new(&pts, rows, cols, &pinned).unwrap(), pts)
    }

    #[test]
    fn a_nan_particle_restores_its_patch_only_in_both_paths() {
        let params = SimParams::default();
        let rig = [Sphere {
            center: Vec3::new(0.1, -0.15, 0.02),
            radius: 0.05,
        }];
        for simd in [true, false] {
            let (mut poisoned, pts) = flag();
            let mut other = poisoned.clone();
            let mut reference = poisoned.clone();
            let run = |p: &mut Patch| {
                if simd {
                    step(p, &params, &rig)
                } else {
                    crate::patch::scalar::step(p, &params, &rig)
                }
            };
            for p in [&mut poisoned, &mut other, &mut reference] {
                for _ in 0..5 {
                    run(p);
                }
            }
            // A NaN in one lane of the second column block.
            let (i, l) = poisoned.slot(3 * 11 + 9);
            poisoned.pos[i].set_lane(l, Vec3::new(f32::NAN, 0.0, 0.0));
            run(&mut poisoned);
            run(&mut other);
            run(&mut reference);
            assert_eq!(poisoned.restored_count(), 1);
            for (x, s) in poisoned.positions().iter().zip(&pts) {
                assert!(x.distance(*s) < 1e-6, "restored onto the skin");
            }
            assert_eq!(other.positions(), reference.positions());
            assert_eq!(other.restored_count(), 0);
        }
    }
}
