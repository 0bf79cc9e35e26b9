//! The step's driver, shared by the SIMD path and its scalar twin: the
//! colliders to the local frame, the tasks (runs of whole pairs of
//! blocks), per group the sleep decision and the broad phase, per pair of
//! blocks that run the chains (`step.rs`), per block the guard's restore
//! and the stillness that puts blocks to sleep.

use crate::collide::broad_phase::{roots_aabb, select_strand_candidates, Aabb, BlockBounds};
use crate::collide::Colliders;
use crate::hair_grid::{GridSetup, HairGrid};
use crate::lanes::{Vec3Lanes, LANES};
use crate::step::{Setup, StepColliders};
use crate::strands::{rest_pose, BlockSleep, Scratch};
use crate::{SimParams, Strands};
use coif_base::lanes::{lanes_below, F32Lanes, GROUP_LANES};
use coif_base::tasks::{for_each_chunk_mut, Executor};
use glam::Vec3;
use std::ops::Range;

/// What a step writes in one block: its `V` positions and previous
/// positions. The rest of the set is shared read-only by every task.
pub(crate) struct BlockState<'a> {
    pub pos: &'a mut [Vec3Lanes],
    pub prev: &'a mut [Vec3Lanes],
}

/// One task's share of a step: the positions of its blocks and its buffers.
pub(crate) struct TaskParts<'a> {
    pos: &'a mut [Vec3Lanes],
    prev: &'a mut [Vec3Lanes],
    sleep: &'a mut [BlockSleep],
    scratch: &'a mut Scratch,
}

/// The most tasks one step makes, whatever the set's size (an engine's
/// fixed-size job pool never runs dry; 64 keeps 16 cores busy with four
/// tasks each).
pub const MAX_STEP_TASKS: usize = 64;

/// Blocks stepped together: the SIMD path walks two blocks' strain limits
/// side by side (`step::step_chains`), the scalar twin one after the other.
pub(crate) const PAIR: usize = 2;

/// The fewest blocks a task of a large set takes (128 strands): about
/// 0.1 ms of work at 32 vertices (about 30 ns per vertex-step), so a job
/// system's cost per job (about a microsecond) stays near 1 %; a
/// 2,048-guide head makes 16 tasks.
const MIN_TASK_BLOCKS: usize = 16;

/// Tasks a small set is cut into, at most (one [`PAIR`] of blocks each at
/// the least): a set of fewer than `SMALL_SET_TASKS x MIN_TASK_BLOCKS`
/// blocks takes smaller tasks, so that a small groom still balances over
/// the threads (Sintel's 228 guides, 29 blocks: fifteen tasks of at most
/// two blocks, split 14 and 15 over two threads, where tasks of a whole
/// broad-phase group, four blocks, split them 16 and 13, and sixteen
/// blocks a task made two tasks of 16 and 13).
const SMALL_SET_TASKS: usize = 16;

/// Blocks per task for a set of `blocks`: at most [`MAX_STEP_TASKS`]
/// tasks, at least [`MIN_TASK_BLOCKS`] blocks a task where the set has
/// [`SMALL_SET_TASKS`] tasks of them and fewer otherwise, a whole number of
/// [`PAIR`]s. A function of the set alone, never of the threads. (No
/// result depends on it: a task's blocks form broad-phase groups of up to
/// [`GROUP`] among themselves, and a block's candidates are the colliders
/// near its own bounds, in collider order, whatever blocks share its
/// group; a block's step is the same alone or in a pair. Tested: the same
/// bytes with tasks of 1, 2, 3, 4, 5 and 8 blocks.)
pub(crate) fn task_blocks(blocks: usize) -> usize {
    let small = blocks.div_ceil(SMALL_SET_TASKS).min(MIN_TASK_BLOCKS);
    let per = blocks.div_ceil(MAX_STEP_TASKS).max(small).max(1);
    per.div_ceil(PAIR) * PAIR
}

/// Tasks per step for a set of `blocks`.
#[cfg(test)]
pub(crate) fn task_count(blocks: usize) -> usize {
    blocks.div_ceil(task_blocks(blocks))
}

/// The step's driver, shared by the SIMD path and its scalar twin: the
/// colliders to local coordinates and those that moved since the last step,
/// then per task (a run of whole pairs, see [`task_blocks`]) and per group
/// of [`GROUP`] blocks: 0. the sleep decision of each block (awake, or
/// asleep and woken by its roots or a moving sphere, or asleep and
/// skipped), 1. the broad phase (`block_box` gives block `b`'s swept box; a
/// sleeping block's is the one kept when it fell asleep) and steps 2.-7. of
/// the group's blocks that run, [`PAIR`] at a time in block order (the
/// last alone when their count is odd: `block(strands, states, scratch,
/// world, setup, ids)` with one state and one `(b, g)`, set index and
/// index in the group, per block, which returns each block's lanes that
/// went bad); those lanes are restored; 8. each block's stillness.
///
/// The moving state (`pos`, `prev`, the blocks' sleep) leaves the set for
/// the step, so the tasks share the rest of it read-only and each writes
/// only its own blocks; everything a block's sleep decision reads is its
/// own state and the step's read-only rig (this step's and the last one's).
/// The awake and restored counts are summed afterwards in block and task
/// order.
pub(crate) fn drive(
    strands: &mut Strands,
    params: &SimParams,
    colliders: &Colliders<'_>,
    executor: &dyn Executor,
    block_box: impl Fn(&Strands, &BlockState<'_>, usize, Range<usize>, &Setup) -> Aabb + Sync,
    block: impl Fn(
            &Strands,
            &mut [BlockState<'_>],
            &mut Scratch,
            &StepColliders<'_>,
            &Setup,
            &[(usize, usize)],
        ) -> [u32; PAIR]
        + Sync,
    hair: impl Fn(&Strands, &mut BlockState<'_>, &HairGrid, &GridSetup, usize) -> u32 + Sync,
) {
    // The first run (the hair grid's splat, or the blocks) comes after
    // the set-up below: sleeping workers start waking now.
    executor.wake();
    let k = Setup::new(strands, params);
    if strands.params_seen.as_ref() != Some(params) {
        // Other parameters: what was still may not be any more.
        strands.wake();
        strands.params_seen = Some(params.clone());
    }
    let mut scratch = std::mem::take(&mut strands.scratch);
    // Sized for the whole set of colliders once, so that no later step
    // allocates (allocates only when a kind grows).
    scratch.rig.update(colliders, strands.origin);
    for t in &mut scratch.tasks {
        t.candidates.clear();
        t.reserve(crate::collide::counts(colliders));
    }
    let mut pos = std::mem::take(&mut strands.pos);
    let mut prev = std::mem::take(&mut strands.prev);
    let mut sleep = std::mem::take(&mut strands.sleep);
    // The hair grid, between the blocks' steps: splatted from every block
    // in parts as tasks (integer sums: the same bytes on any thread
    // count), its fields on this thread, read by each block in its task
    // (`hair_grid/`).
    let mut grid = std::mem::take(&mut strands.hair_grid);
    let grid_setup = (params.volume_stiffness > 0.0 || params.hair_friction > 0.0).then(|| {
        grid.build(
            strands,
            &pos,
            &prev,
            params.dt,
            params.hair_grid_cell,
            executor,
        );
        let wind = if params.wind.is_finite() {
            params.wind
        } else {
            glam::Vec3::ZERO
        };
        GridSetup {
            volume: params.volume_stiffness,
            friction: params.hair_friction,
            dt: params.dt,
            pull: wind * params.effective_drag(),
            wind_dir: wind.normalize_or_zero(),
            wake_move2: k.still_move2,
        }
    });
    {
        let s: &Strands = strands;
        let verts = s.verts;
        let per_task = scratch.task_blocks.max(1);
        let span = per_task * verts;
        let mut parts: [Option<TaskParts<'_>>; MAX_STEP_TASKS] = std::array::from_fn(|_| None);
        let chunks = pos
            .chunks_mut(span)
            .zip(prev.chunks_mut(span))
            .zip(sleep.chunks_mut(per_task * SLEEP_GROUPS));
        let mut tasks = 0;
        for (slot, (((pos, prev), sleep), scratch)) in
            parts.iter_mut().zip(chunks.zip(&mut scratch.tasks))
        {
            *slot = Some(TaskParts {
                pos,
                prev,
                sleep,
                scratch,
            });
            tasks += 1;
        }
        let world = StepColliders {
            rig: &scratch.rig,
            sdfs: colliders.sdfs,
        };
        let movers = &scratch.rig.movers;
        for_each_chunk_mut(executor, &mut parts[..tasks], 1, &|t, part| {
            let Some(TaskParts {
                pos,
                prev,
                sleep,
                scratch,
            }) = part.first_mut().and_then(Option::as_mut)
            else {
                return;
            };
            scratch.restored = 0;
            let blocks = pos.len() / verts;
            let mut first = 0;
            while first < blocks {
                let n = GROUP.min(blocks - first);
                // 0. Sleep, per group of eight lanes (`SLEEP_GROUPS` per
                // block): a sleeping group runs only if its roots moved or a
                // moving sphere's sweep reaches its box; a block runs if one
                // of its groups does.
                let mut boxes = [EMPTY_BOX; GROUP];
                let mut bounds = [BlockBounds {
                    swept: EMPTY_BOX,
                    roots: EMPTY_BOX,
                    arc: &[],
                    stretch_factor: k.stretch_factor,
                }; GROUP];
                let mut runs = [[true; SLEEP_GROUPS]; GROUP];
                // The grid's volume and friction, asleep or awake: a group
                // they move wakes.
                if let Some(gk) = &grid_setup {
                    for g in 0..n {
                        let (b, r) = (t * per_task + first + g, (first + g) * verts);
                        let mut st = BlockState {
                            pos: &mut pos[r..r + verts],
                            prev: &mut prev[r..r + verts],
                        };
                        let moved = hair(s, &mut st, &grid, gk, b);
                        for (q, sl) in sleep[(first + g) * SLEEP_GROUPS..][..SLEEP_GROUPS]
                            .iter_mut()
                            .enumerate()
                        {
                            if moved & group_bits(q) != 0 {
                                sl.asleep = false;
                                sl.still = 0;
                            }
                        }
                    }
                }
                for g in 0..n {
                    let (b, r) = (t * per_task + first + g, (first + g) * verts);
                    let st = BlockState {
                        pos: &mut pos[r..r + verts],
                        prev: &mut prev[r..r + verts],
                    };
                    let mut asleep_box: Option<Aabb> = None;
                    let mut all_asleep = true;
                    for (q, run) in runs[g].iter_mut().enumerate() {
                        let sl = sleep[(first + g) * SLEEP_GROUPS + q];
                        let lanes = s.active[b] & group_mask(q);
                        if k.sleep && sl.asleep && !roots_moved(&st, lanes) {
                            asleep_box = Some(asleep_box.map_or(sl.bounds, |a| a.union(sl.bounds)));
                            *run = movers.iter().any(|m| {
                                crate::collide::broad_phase::boxes_near(m, &sl.bounds, k.margin)
                            });
                        } else {
                            all_asleep = false;
                        }
                    }
                    boxes[g] = match asleep_box {
                        Some(kept) if all_asleep => kept,
                        // 1. (box) The block's swept box.
                        _ => block_box(s, &st, b, 0..LANES, &k),
                    };
                    // 1. (reach) And the reach the strain limit leaves it.
                    bounds[g] = BlockBounds {
                        swept: boxes[g],
                        roots: roots_aabb(st.prev[0], st.pos[0], s.active[b]),
                        arc: &s.reach_arc[b * verts..(b + 1) * verts],
                        stretch_factor: k.stretch_factor,
                    };
                }
                let block_runs = |g: usize| runs[g].iter().any(|&r| r);
                // 1. Broad phase: the group's swept block boxes against the rig.
                if (0..n).any(block_runs) {
                    select_strand_candidates(
                        &bounds[..n],
                        k.margin,
                        world.rig,
                        &mut scratch.candidates,
                    );
                }
                // 2.-7. The blocks that run, two at a time (the last one
                // alone when their count is odd).
                let mut g = 0;
                while g < n {
                    let mut ids = [(0, 0); PAIR];
                    let mut count = 0;
                    while g < n && count < PAIR {
                        if block_runs(g) {
                            ids[count] = (t * per_task + first + g, g);
                            count += 1;
                        } else {
                            for sl in &mut sleep[(first + g) * SLEEP_GROUPS..][..SLEEP_GROUPS] {
                                sl.stepped = false;
                            }
                        }
                        g += 1;
                    }
                    if count == 0 {
                        break;
                    }
                    let ids = &ids[..count];
                    // The blocks' states, cut from the task's positions in
                    // block order.
                    let mut states: [BlockState<'_>; PAIR] = std::array::from_fn(|_| BlockState {
                        pos: &mut [],
                        prev: &mut [],
                    });
                    let (mut pos_rest, mut prev_rest) = (&mut pos[..], &mut prev[..]);
                    let mut cut = 0;
                    for (st, &(_, g)) in states.iter_mut().zip(ids) {
                        let at = (first + g) * verts - cut;
                        let (block_pos, tail) = pos_rest[at..].split_at_mut(verts);
                        pos_rest = tail;
                        let (block_prev, tail) = prev_rest[at..].split_at_mut(verts);
                        prev_rest = tail;
                        (st.pos, st.prev) = (block_pos, block_prev);
                        cut = (first + g + 1) * verts;
                    }
                    let states = &mut states[..count];
                    let mut moved = [[false; SLEEP_GROUPS]; PAIR];
                    for (i, (st, &(b, g))) in states.iter().zip(ids).enumerate() {
                        for (q, m) in moved[i].iter_mut().enumerate() {
                            *m = roots_moved(st, s.active[b] & group_mask(q));
                        }
                        if k.sleep {
                            let at = i * verts..(i + 1) * verts;
                            scratch.start[at.clone()].copy_from_slice(st.pos);
                            if !runs[g].iter().all(|&r| r) {
                                scratch.start_prev[at].copy_from_slice(st.prev);
                            }
                        }
                    }
                    let bad = block(s, states, scratch, &world, &k, ids);
                    for (i, (st, &(b, g))) in states.iter_mut().zip(ids).enumerate() {
                        let at = i * verts..(i + 1) * verts;
                        // A sleeping group of a block that ran keeps its
                        // state, as if its block had not (a block of 16
                        // lanes sleeps and runs as its two groups of 8).
                        let mut running = 0u32;
                        for (q, &run) in runs[g].iter().enumerate() {
                            if run {
                                running |= group_bits(q);
                            } else {
                                let m = group_mask(q);
                                let kept = scratch.start[at.clone()].iter();
                                let kept_prev = scratch.start_prev[at.clone()].iter();
                                for (((x, xp), a), ap) in st
                                    .pos
                                    .iter_mut()
                                    .zip(st.prev.iter_mut())
                                    .zip(kept)
                                    .zip(kept_prev)
                                {
                                    *x = Vec3Lanes::select(m, *a, *x);
                                    *xp = Vec3Lanes::select(m, *ap, *xp);
                                }
                            }
                        }
                        scratch.restored += restore_lanes(s, st, b, bad[i] & running);
                        // 8. Stillness: a group still for `still_steps` steps
                        // in a row (roots included) falls asleep at rest.
                        let start = &scratch.start[at];
                        for q in 0..SLEEP_GROUPS {
                            let sl = &mut sleep[(first + g) * SLEEP_GROUPS + q];
                            if !runs[g][q] {
                                sl.stepped = false;
                                continue;
                            }
                            let lanes = s.active[b] & group_mask(q);
                            let still = k.sleep
                                && !moved[i][q]
                                && block_is_still(st.pos, start, lanes, k.still_move2);
                            sl.stepped = true;
                            sl.still = if still { sl.still.saturating_add(1) } else { 0 };
                            sl.asleep = false;
                            if sl.still >= k.still_steps {
                                fall_asleep(st, group_mask(q));
                                sl.asleep = true;
                                sl.bounds = block_box(s, st, b, group_lanes(q), &k);
                            }
                        }
                    }
                }
                first += n;
            }
        });
    }
    strands.pos = pos;
    strands.prev = prev;
    strands.sleep = sleep;
    strands.hair_grid = grid;
    strands.restored += scratch.tasks.iter().map(|t| t.restored).sum::<u64>();
    strands.awake = (0..strands.blocks * SLEEP_GROUPS)
        .filter(|&i| strands.sleep[i].stepped)
        .map(|i| strands.lanes_in_sleep_group(i))
        .sum();
    scratch.rig.remember(colliders);
    strands.scratch = scratch;
    strands.time += params.dt as f64;
    strands.stepped_rotation = strands.rest_rotation;
}

/// True if a root of block `b` (an active lane) was moved since the last
/// step: `set_roots` changed its target (`pos[0]`) away from where the step
/// left it (`prev[0]`). Any change counts, however small: a sleeping strand
/// stays attached to its root.
fn roots_moved(st: &BlockState<'_>, active: F32Lanes) -> bool {
    let d = st.pos[0] - st.prev[0];
    let moved =
        d.x.simd_ne(F32Lanes::ZERO) | d.y.simd_ne(F32Lanes::ZERO) | d.z.simd_ne(F32Lanes::ZERO);
    (moved & active).any()
}

/// True if every vertex of the active lanes of a block moved at most
/// `sqrt(still_move2)` over the step (`|x_end - x_start|^2 <= still_move2`;
/// the displacement, not the last substep's velocity, which a vertex
/// resting on a sphere keeps at a few cm/s while it does not move); a NaN
/// is never still. The same code for both paths (like the guard's restore),
/// so their sleep decisions agree by construction.
fn block_is_still(
    pos: &[Vec3Lanes],
    start: &[Vec3Lanes],
    active: F32Lanes,
    still_move2: f32,
) -> bool {
    let limit = F32Lanes::splat(still_move2);
    let mut still = active | !active;
    for (x, p) in pos.iter().zip(start) {
        let d = *x - *p;
        still &= d.dot(d).simd_le(limit) | !active;
    }
    still.all()
}

/// A group of a block falls asleep at rest: previous positions = current
/// ones in the lanes of `group` (padding included).
fn fall_asleep(st: &mut BlockState<'_>, group: F32Lanes) {
    for (xp, x) in st.prev.iter_mut().zip(st.pos.iter()) {
        *xp = Vec3Lanes::select(group, *x, *xp);
    }
}

/// Sleep is decided per group of eight lanes ([`GROUP_LANES`]), so a strand
/// sleeps and wakes with the same seven neighbours at 8 and 16 lanes: one
/// group per block in an 8-lane build, two in a 16-lane one.
pub(crate) const SLEEP_GROUPS: usize = LANES / SLEEP_GROUP_LANES;

/// Lanes per sleep group: eight at every width.
pub(crate) const SLEEP_GROUP_LANES: usize = GROUP_LANES;

/// The lanes of sleep group `q` of a block.
pub(crate) fn group_lanes(q: usize) -> Range<usize> {
    q * SLEEP_GROUP_LANES..(q + 1) * SLEEP_GROUP_LANES
}

/// [`group_lanes`] as a lane mask.
fn group_mask(q: usize) -> F32Lanes {
    lanes_below((q + 1) * SLEEP_GROUP_LANES) & !lanes_below(q * SLEEP_GROUP_LANES)
}

/// [`group_lanes`] as bits of a lane bitmask.
fn group_bits(q: usize) -> u32 {
    ((1u32 << SLEEP_GROUP_LANES) - 1) << (q * SLEEP_GROUP_LANES)
}

/// Blocks whose boxes are tested against the rig together (the union first,
/// then each block's own box): with a 256-sphere body rig, one test per
/// sphere per group rejects the far spheres.
pub(crate) const GROUP: usize = 4;

/// A placeholder box (never tested: only the first `n` of a group are).
pub(crate) const EMPTY_BOX: Aabb = Aabb {
    min: Vec3::ZERO,
    max: Vec3::ZERO,
};

/// Restores the lanes of block `b` (its state `st`) flagged in `bad`;
/// returns how many hold real strands (padding lanes are restored
/// silently).
pub(crate) fn restore_lanes(s: &Strands, st: &mut BlockState<'_>, b: usize, bad: u32) -> u64 {
    let mut restored = 0;
    if bad == 0 {
        return restored;
    }
    let rest_offset = &s.rest_offset[b * s.verts..(b + 1) * s.verts];
    for l in 0..LANES {
        if bad & (1 << l) != 0 {
            rest_pose(s.roots[b], s.rest_rotation, rest_offset, l, st.pos, st.prev);
            if l < s.lanes_in_block(b) {
                restored += 1;
            }
        }
    }
    restored
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::step::{step, step_with};
    use crate::{SimParams, Sphere, Strands};
    use coif_base::tasks::Serial;
    use coif_testkit::executors::Backwards;
    use glam::Vec3;

    #[test]
    fn tasks_are_whole_pairs_and_at_most_max_step_tasks() {
        for blocks in [0, 1, 5, 16, 17, 100, 1024, 1250, 5000, 100_000] {
            let per = task_blocks(blocks);
            assert_eq!(per % PAIR, 0, "{blocks}: whole pairs");
            assert!(per >= PAIR);
            if blocks >= SMALL_SET_TASKS * MIN_TASK_BLOCKS {
                assert!(
                    per >= MIN_TASK_BLOCKS,
                    "{blocks}: large tasks of a large set"
                );
            } else {
                // A small set is cut finer: as many tasks as it has
                // pairs, up to SMALL_SET_TASKS.
                let pairs = blocks.div_ceil(PAIR);
                assert!(
                    task_count(blocks) >= pairs.min(SMALL_SET_TASKS) / 2,
                    "{blocks}"
                );
            }
            assert!(task_count(blocks) <= MAX_STEP_TASKS, "{blocks}");
            assert!(task_count(blocks) * per >= blocks, "{blocks}: covered");
        }
        // Sintel's 228 guides: 29 blocks in fifteen tasks (were eight).
        assert_eq!(task_count(228usize.div_ceil(8)), 15);
    }

    #[test]
    fn the_same_bytes_whatever_the_tasks_size() {
        // 20 x LANES + 3 strands (21 blocks at eight lanes) falling onto
        // the head sphere, swung by their roots, with the hair grid's
        // volume and friction and local shape: every result of every
        // split (tasks of 1 to 8 blocks, so groups and pairs of every
        // make-up) is the bytes of the step's own.
        let rig = head();
        let params = SimParams {
            local_shape_stiffness: 0.5,
            volume_stiffness: 1.0,
            hair_friction: 0.3,
            ..SimParams::default()
        };
        let count = 20 * LANES + 3;
        let run =
            |task_blocks: Option<usize>,
             stepper: fn(&mut Strands, &SimParams, &[Sphere], &dyn Executor)| {
                let mut s = strands(count);
                if let Some(per) = task_blocks {
                    s.scratch =
                        crate::strands::StepScratch::with_task_blocks(s.blocks, s.verts, per);
                }
                let roots0: Vec<Vec3> = (0..count).map(|i| s.vertex(i, 0).unwrap()).collect();
                for k in 0..40 {
                    let shift = Vec3::new(0.02 * (k as f32 * 0.3).sin(), 0.0, 0.0);
                    let roots: Vec<Vec3> = roots0.iter().map(|r| *r + shift).collect();
                    s.set_roots(&roots).unwrap();
                    stepper(&mut s, &params, &rig, &Backwards(2));
                }
                (s.positions_local(), s.restored_strands())
            };
        for stepper in [
            step_with as fn(&mut Strands, &SimParams, &[Sphere], &dyn Executor),
            crate::scalar::step_with,
        ] {
            let own = run(None, stepper);
            assert!(own.0.iter().all(|p| p.is_finite()));
            for per in [1, 2, 3, 4, 5, 8] {
                let split = run(Some(per), stepper);
                assert!(
                    split
                        .0
                        .iter()
                        .zip(&own.0)
                        .all(|(a, b)| a.to_array().map(f32::to_bits)
                            == b.to_array().map(f32::to_bits)),
                    "tasks of {per} blocks"
                );
                assert_eq!(split.1, own.1);
            }
        }
    }

    #[test]
    fn a_lane_restored_inside_a_later_task_is_counted_once() {
        // 25 blocks, thirteen tasks of two; the strand in block 20 (task
        // 10), lane 3.
        let (rig, params) = (head(), SimParams::default());
        let mut runs = vec![];
        for exec in [&Serial as &dyn Executor, &Backwards(2)] {
            let mut s = strands(25 * LANES);
            assert_eq!(s.scratch.tasks.len(), 13);
            step_with(&mut s, &params, &rig, exec);
            s.pos[20 * 12 + 7].set_lane(3, Vec3::NAN);
            step_with(&mut s, &params, &rig, exec);
            step_with(&mut s, &params, &rig, exec);
            assert_eq!(s.restored_strands(), 1);
            let p = s.positions_local();
            assert!(p.iter().all(|x| x.is_finite()));
            runs.push(p);
        }
        assert_eq!(runs[0], runs[1]);
    }

    /// The rig of the tests: one head sphere at the origin.
    fn head() -> [Sphere; 1] {
        [Sphere {
            center: Vec3::ZERO,
            radius: 0.12,
        }]
    }

    fn strands(count: usize) -> Strands {
        let pts: Vec<Vec3> = (0..count)
            .flat_map(|s| (0..12).map(move |v| Vec3::new(0.01 * s as f32, 0.1, 0.01 * v as f32)))
            .collect();
        Strands::from_polylines(&pts, 12).unwrap()
    }

    #[test]
    fn a_poisoned_strand_is_restored_and_no_other_strand_notices() {
        let (rig, params) = (head(), SimParams::default());
        for stepper in [
            step as fn(&mut Strands, &SimParams, &[Sphere]),
            crate::scalar::step,
        ] {
            // Block 1, lane 5: one vertex goes NaN mid-flight.
            let (count, poisoned_strand) = (LANES + 13, LANES + 5);
            let mut clean = strands(count);
            for _ in 0..10 {
                stepper(&mut clean, &params, &rig);
            }
            let mut poisoned = clean.clone();
            poisoned.pos[12 + 7].set_lane(5, Vec3::NAN);
            stepper(&mut clean, &params, &rig);
            stepper(&mut poisoned, &params, &rig);
            assert_eq!(poisoned.restored_strands(), 1);
            assert_eq!(clean.restored_strands(), 0);
            let (a, b) = (clean.positions_local(), poisoned.positions_local());
            for s in 0..count {
                for v in 0..12 {
                    let k = s * 12 + v;
                    if s == poisoned_strand {
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
