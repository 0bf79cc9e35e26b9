//! One fixed strand step, SIMD path: eight strands per instruction stream,
//! one generic body ([`step_chain`], written over [`Lane`]) that the scalar
//! twin [`crate::scalar::step`] instantiates at `f32`, one lane at a time.
//!
//! A step of `dt` runs `n = ceil(dt / max_substep)` substeps of `h = dt / n`
//! (default 4 of 1/240 s). Per block of [`LANES`] strands, in this order
//! (the numbers are the step comments of [`step_chain`]):
//!
//! 1. **Broad phase** (once per step): the boxes of a group of four blocks,
//!    swept over the step's predicted motion, and the reach the strain
//!    limit leaves them, against every collider (`collide/broad_phase.rs`;
//!    the group's union first, then each block); only the colliders near a
//!    block enter its narrow phase, from the first vertex that may touch
//!    them.
//! 2. **Prediction** (per substep): the root moves on the straight line from
//!    where it was to its target; free vertices take a position-Verlet step
//!    `x* = x + d^(1/n) e^(-c h) (x - x_prev) + (g + c w) h^2` (Yip 2011's
//!    damping `d` spread over the substeps; linear drag `c` toward the wind
//!    `w`, plus the gusts' pull per vertex when on: `wind.rs`). The
//!    colliders move to where they are after the substep. The same pass stores the fixed part of the
//!    constraint directions, `(1/2) d_s(x_n) + (1/4 - a) d_s(x_{n-1})` with
//!    `d_s(x) = x_{s+1} - x_s`.
//! 3. **Shape** (optional): the local shape springs, an implicit step of
//!    `E = sum_s (c / l_s)^2 / 2 |e_s - R t_s|^2` (one tridiagonal solve
//!    per chain with the same matrix for x, y and z; its factors made once
//!    per step; `R` turned from the last step's groom frame to this one's
//!    over the substeps; Rayleigh damping as a blend of each rest vector
//!    with the segment at the substep's start: `shape.rs`); then the global
//!    shape pull toward `root + R rest_v`, weighted `1 - arc(v)/arc(tip)`
//!    (Yip 2011).
//! 4. **Projection** of the length constraints, `iterations` times: per
//!    chain, with `e_s` the current unit segment directions and the blended
//!    constraint directions
//!    `q_s = (1/4 + a) d_s(x*) + (1/2) d_s(x_n) + (1/4 - a) d_s(x_{n-1})`,
//!    solve the tridiagonal system
//!    `e_s . (dx_{s+1} - dx_s) = l_s - |x*_{s+1} - x*_s|`,
//!    `dx_v = w_v (lambda_{v-1} q_{v-1} - lambda_v q_v)`
//!    for the multipliers (Thomas algorithm, no pivoting: the matrix is
//!    diagonally dominant while the `e . q` stay near `|q|`), then move the
//!    vertices. `a = 0` is the trapezoidal (average-acceleration) rule
//!    (Newmark 1959) of the constrained dynamics; `[1, 0, 0]` would be fast
//!    projection (Goldenthal et al. 2007), `[0, 1, 0]` SHAKE (Ryckaert et al.
//!    1977; Andersen 1983's RATTLE is its velocity form). `q_s` is not
//!    normalised (its multiplier absorbs the scale); it falls back to `e_s`
//!    where its cosine with `e_s` is below 1/2. With bending on, a sweep of
//!    i..i+2 distance constraints (Jakobsen 2001) follows each projection.
//!    With the shape springs on, the projection is skipped and the strain
//!    limit (6.) holds the lengths: the springs' pull along a turned
//!    segment asks the exact projection to undo a stretch every substep,
//!    and the two together pumped energy into short strands (Sintel's
//!    5 cm locks curled into loops after a head turn; `shape.rs`,
//!    "Lengths").
//! 5. **Pearls** against the block's spheres and capsules: `k` points per
//!    segment pushed out by the Nalu demo's point-on-segment rule (Nguyen
//!    and Donnelly 2005; `collide/narrow.rs`).
//! 6. **Strain limit with push-out**, root to tip: each vertex is moved
//!    along its segment until `(1 - s) l <= |x_v - x_{v-1}| <= (1 + s) l`
//!    (Provot 1995, Follow-The-Leader order, Muller et al. 2012), then pushed
//!    out of the spheres, capsules and fields, with Coulomb friction
//!    (Macklin et al. 2014) and the roots rule (`collide/narrow.rs`); one
//!    round per substep, two on the last (the second without friction). A
//!    field's lookup is skipped where it cannot push: eight lanes far from
//!    the surface, or inside the clear balls of their last lookup in this
//!    step (`narrow::ClearBall`, `collide/sdf/slope.rs`).
//! 7. **Velocity and guard** (end of step): `x_prev` is rewritten so that
//!    `(x - x_prev) / dt` is the last substep's velocity (what `set_velocity`
//!    and `measure::max_speed` read); a lane with a non-finite coordinate or
//!    one beyond 10^6 m is restored to its rest pose at its root and counted.
//!    Lanes never exchange data, so no other strand is touched.
//! 8. **Sleep** (`sleep_speed > 0`, in the driver `drive`): a sleeping
//!    block whose roots did not move and which no moving sphere's sweep
//!    reaches is skipped before 1.; after 7., a block whose vertices all
//!    moved at most `sleep_speed dt` per step for `SLEEP_AFTER` seconds
//!    falls asleep at rest.
//!
//! **Two blocks side by side.** Steps 4 and 6 walk each strand from root
//! to tip, each vertex waiting on its parent: a chain of dependent
//! operations (a square root, the pushes, Coulomb friction) that leaves
//! most of the core idle. The SIMD path steps the blocks that run two at
//! a time ([`step_chains`]): each block's every operation is its own and
//! in its own order (the same bytes as alone, tested), but the strain
//! limit's walk takes vertex `v` of both blocks before `v + 1` of either,
//! so the core overlaps two independent chains. Measured on the mohawk at
//! the defaults: 41.0 -> 38.0 ns per vertex-step for 3 % more
//! instructions (`kernels/README.md`, "Two blocks side by side"). The
//! projection's elimination walked in step too was slower (two chains'
//! running values do not fit the registers), and so were four blocks
//! side by side.
//!
//! No division and no square root in the body: `1/sqrt` and `1/x` are the
//! hardware estimates plus one Newton step ([`Lane::inv_sqrt`],
//! [`Lane::recip`]), which read the same tables in both widths, so the SIMD
//! and scalar paths agree bit for bit on x86-64 with AVX.

use crate::collide::broad_phase::{block_sweep_aabb, Kind, ShapeCandidate};
use crate::collide::narrow::{ClearBall, ContactSetup, FieldReach, ShapeReach, FIELD_EXIT_SPEED};
use crate::collide::rig::LocalRig;
use crate::collide::sdf::{Sdf, SdfLane};
use crate::collide::Colliders;
use crate::constraints::{BLOWN_UP, MIN_LENGTH};
use crate::drive::{drive, BlockState, PAIR};
use crate::fused::{dot, length_dir, madd, offset_unless, rotate};
use crate::hair_grid::apply_block;
use crate::lanes::{Lane, V3};
use crate::wind::Gusts;
use crate::{SimParams, Sphere, Strands};
use coif_base::lanes::{lanes_below, F32Lanes};
use coif_base::tasks::{Executor, Serial};
use glam::{Mat3, Vec3};

/// Constraint directions whose cosine with the current segment falls below
/// this are replaced by the current direction (the blend means nothing once
/// a segment turned by more than 60 degrees within a substep).
pub(crate) const MIN_DIRECTION_COSINE: f32 = 0.5;
/// Per-step values shared by the SIMD and scalar paths.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Setup {
    pub substeps: u32,
    /// Velocity kept per substep, `damping^(1/n)`.
    pub damping: f32,
    pub gravity_h2: Vec3,
    /// `g dt^2`, the broad phase's sweep.
    pub gravity_dt2: Vec3,
    pub iterations: u32,
    /// Weights of `d(x*)`, `d(x_n)`, `d(x_{n-1})` in the directions.
    pub direction: [f32; 3],
    pub stretch_factor: f32,
    pub shrink_factor: f32,
    pub pearls: u32,
    /// Contacts: the pearl radius, friction, the push cap of fields, the
    /// roots rule.
    pub contact: ContactSetup,
    /// Gusts on: `turbulence > 0` and `drag > 0`.
    pub gusts: Option<Gusts>,
    /// `FIELD_EXIT_SPEED dt`: the most a lane that was deep in a field
    /// keeps as its velocity over the step.
    pub exit_move: f32,
    /// Local shape: `(c h)^2` for the shape springs' wave speed `c`
    /// ([`crate::shape::wave_speed`]) and the substep `h` (0 = off); a
    /// segment of rest length `l` gets `alpha = (c h / l)^2`.
    pub shape_alpha: f32,
    /// The springs' share `h / (h + beta)` of the shape rows (the rest is
    /// their damping; `crate::shape::DAMPING_TIME`).
    pub shape_keep: f32,
    /// Per substep: global shape pull, bending stiffness.
    pub shape: f32,
    pub bend: f32,
    /// The groom frame's orientation at the end of this step and of the
    /// last one (the shape springs turn from one to the other over the
    /// substeps).
    pub rotation: Mat3,
    pub rotation_from: Mat3,
    /// Broad-phase margin: pearl radius plus one longest rest segment.
    pub margin: f32,
    /// Sleeping on (`sleep_speed > 0`).
    pub sleep: bool,
    /// `(sleep_speed dt)^2`: a vertex moved less than this (squared) over
    /// the step is still.
    pub still_move2: f32,
    /// Still steps in a row before a block sleeps, `ceil(SLEEP_AFTER / dt)`.
    pub still_steps: u32,
}

/// A per-step pull `k` in [0, 1] spread over `n` substeps: `1 - (1 - k)^(1/n)`.
fn per_substep(k: f32, n: u32) -> f32 {
    let k = k.clamp(0.0, 1.0);
    if k >= 1.0 {
        1.0
    } else {
        1.0 - (1.0 - k).powf(1.0 / n as f32)
    }
}

impl Setup {
    pub(crate) fn new(s: &Strands, p: &SimParams) -> Setup {
        let n = p.substeps();
        let h = p.dt / n as f32;
        let a = p.stiff_mode_damping.clamp(0.0, 0.25);
        // Drag toward the air: velocity kept exp(-c h) per substep, the
        // air's pull c w added to gravity (crate README, "Wind and drag").
        let drag = p.effective_drag();
        let accel = p.steady_acceleration();
        Setup {
            substeps: n,
            damping: p.damping.powf(1.0 / n as f32) * (-drag * h).exp(),
            gravity_h2: accel * (h * h),
            gravity_dt2: accel * (p.dt * p.dt),
            iterations: p.iterations,
            direction: [0.25 + a, 0.5, 0.25 - a],
            stretch_factor: 1.0 + p.max_stretch,
            shrink_factor: (1.0 - p.max_stretch).max(0.0),
            pearls: p.pearls_per_segment.min(crate::MAX_PEARLS_PER_SEGMENT),
            contact: ContactSetup {
                pearl_radius: p.pearl_radius,
                friction: p.friction.max(0.0),
                static_friction: p.static_friction.max(0.0),
                friction_on: (p.friction > 0.0 || p.static_friction > 0.0),
                field_push: FIELD_EXIT_SPEED * h,
                accel_h2: accel * (h * h),
                slop: (accel * (h * h)).length(),
                root_exit: if p.root_exit.is_finite() {
                    p.root_exit.max(0.0)
                } else {
                    f32::MAX
                },
            },
            gusts: Gusts::new(p, drag, h, s.time, s.origin),
            exit_move: FIELD_EXIT_SPEED * p.dt,
            shape_alpha: crate::shape::alpha_scale(p.local_shape_stiffness, h)
                / crate::shape::keep(h),
            shape_keep: crate::shape::keep(h),
            shape: per_substep(p.shape_stiffness, n),
            bend: per_substep(p.bend_stiffness, n),
            rotation: s.rest_rotation,
            rotation_from: s.stepped_rotation,
            margin: p.pearl_radius.max(0.0) + s.max_rest_segment,
            sleep: p.sleep_speed > 0.0 && p.dt > 0.0 && !(p.turbulence > 0.0 && drag > 0.0),
            still_move2: (p.sleep_speed * p.dt) * (p.sleep_speed * p.dt),
            still_steps: ((crate::SLEEP_AFTER / p.dt).ceil() as u32).max(1),
        }
    }
}

/// One chain's data: eight chains in lanes (`T = F32Lanes`) or one (`f32`),
/// `V` entries each, root first.
pub(crate) struct Chain<'a, T: Lane> {
    pub pos: &'a mut [V3<T>],
    /// Previous positions: one step ago outside the step, one substep ago
    /// inside it.
    pub prev: &'a mut [V3<T>],
    /// Inverse mass (0 = pinned).
    pub w: &'a [T],
    /// Rest length of segment v -> v + 1.
    pub rest_len: &'a [T],
    /// The shape springs' rest vector of segment v -> v + 1, groom frame
    /// (the groom's segment, or its sag-free rest).
    pub rest_vec: &'a [V3<T>],
    /// Rest offset of vertex v from the root, groom frame.
    pub rest_offset: &'a [V3<T>],
    /// Rest distance v -> v + 2 and the mass shares of that constraint.
    pub bend_len: &'a [T],
    pub bend_share: &'a [[T; 2]],
    /// Global shape weight `1 - arc(v) / arc(tip)`.
    pub shape_weight: &'a [T],
    /// Rest arc length from the root (the roots rule of the contacts).
    pub arc: &'a [T],
}

/// Per-chain scratch, `V` entries each, sized when the strands are built
/// (the collider lists hold one entry per collider: the step reserves them
/// when the set of colliders grows).
#[derive(Clone, Debug, Default)]
pub(crate) struct ChainScratch<T: Lane> {
    qfix: Vec<V3<T>>,
    n: Vec<V3<T>>,
    cp: Vec<T>,
    dp: Vec<T>,
    /// The shape springs' tridiagonal factors for this step
    /// (`shape::factor`): `-c'_v`, `1 / den_v`, `a_v / den_v`, and the
    /// rest vectors' part of the right-hand side over `den_v`.
    shape: crate::shape::Factors<T>,
    /// The gusts' pull per vertex over one substep (gusts on).
    gust: Vec<V3<T>>,
    /// Per segment: 0 where both ends are free, +inf where one is pinned
    /// (added to a pearl's squared distance, it keeps the pearl out of
    /// every collider).
    pearl_off: Vec<T>,
    /// Per vertex: 0 if free, +inf if pinned (the same for vertices).
    vertex_off: Vec<T>,
    /// The step's candidate colliders of this block, splatted, each list
    /// in the order of the first vertex that may touch them.
    spheres: Vec<ShapeReach<T>>,
    capsules: Vec<ShapeReach<T>>,
    fields: Vec<FieldReach<T>>,
    /// Per vertex and candidate field (`v * fields + f`, `f` the position
    /// in `fields`): the ball round its last lookup that the skin provably
    /// does not reach (`narrow::ClearBall`), reset every block step.
    field_balls: Vec<ClearBall<T>>,
    /// The block's candidates as (first vertex that may touch it, index
    /// in the step's candidate list), sorted by the first: the collider
    /// lists are filled in this order, so no collider is moved to sort.
    order: Vec<(usize, usize)>,
    /// The vertices `..rooted_end` fall under some candidate's roots rule
    /// (set once per block step).
    rooted_end: usize,
}

impl<T: Lane> ChainScratch<T> {
    pub(crate) fn new(verts: usize) -> Self {
        ChainScratch {
            qfix: vec![V3::zero(); verts],
            n: vec![V3::zero(); verts],
            cp: vec![T::splat(0.0); verts],
            dp: vec![T::splat(0.0); verts],
            shape: crate::shape::Factors::new(verts),
            gust: vec![V3::zero(); verts],
            pearl_off: vec![T::splat(0.0); verts],
            vertex_off: vec![T::splat(0.0); verts],
            spheres: Vec::new(),
            capsules: Vec::new(),
            fields: Vec::new(),
            field_balls: Vec::new(),
            order: Vec::new(),
            rooted_end: 0,
        }
    }

    /// Room for the candidates of `counts` colliders (spheres, capsules,
    /// fields; allocates only when a kind grew).
    pub(crate) fn reserve(&mut self, [spheres, capsules, fields]: [usize; 3]) {
        fn grow<X>(v: &mut Vec<X>, n: usize) {
            v.reserve(n.saturating_sub(v.len()));
        }
        grow(&mut self.spheres, spheres);
        grow(&mut self.capsules, capsules);
        grow(&mut self.fields, fields);
        grow(&mut self.order, spheres + capsules + fields);
        let balls = self.qfix.len() * fields;
        if self.field_balls.len() < balls {
            self.field_balls.resize(balls, ClearBall::none());
        }
    }
}

/// Sorts a block's candidates by the first vertex that may touch them
/// (rig order among equals: a stable insertion sort, the lists are short),
/// so that the colliders a vertex meets are a prefix.
fn sort_by_first<X>(list: &mut [X], first: impl Fn(&X) -> usize) {
    for i in 1..list.len() {
        let mut j = i;
        while j > 0 && first(&list[j - 1]) > first(&list[j]) {
            list.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// One block's chain with its scratch: what [`step_chains`] advances.
pub(crate) struct ChainJob<'c, 'a, T: Lane> {
    pub c: &'c mut Chain<'a, T>,
    pub s: &'c mut ChainScratch<T>,
    /// The block's index (its candidates' first vertices).
    pub block: usize,
}

/// Advances one chain (or eight, in lanes) by one step; returns the lanes
/// that stayed finite and within [`BLOWN_UP`] (the caller restores the
/// others). On entry `pos[0]` is the root's target and `prev[0]` where it was.
#[inline(always)]
pub(crate) fn step_chain<T: SdfLane>(
    c: &mut Chain<'_, T>,
    s: &mut ChainScratch<T>,
    k: &Setup,
    world: &StepColliders<'_>,
    candidates: &[ShapeCandidate],
    block: usize,
) -> T::Mask {
    let [ok] = step_chains([ChainJob { c, s, block }], k, world, candidates);
    ok
}

/// [`step_chain`] for `N` chains at once (two blocks, on the SIMD path):
/// each chain's every operation is its own and in the same order as
/// alone, so the bytes are those of `N` calls of [`step_chain`]; only the
/// strain limit's walk, a chain of dependent operations from root to tip,
/// visits vertex `v` of every chain before `v + 1` of any, which gives the
/// core `N` independent chains to overlap.
#[inline(always)]
pub(crate) fn step_chains<T: SdfLane, const N: usize>(
    mut jobs: [ChainJob<'_, '_, T>; N],
    k: &Setup,
    world: &StepColliders<'_>,
    candidates: &[ShapeCandidate],
) -> [T::Mask; N] {
    let mut ends = [(V3::zero(), V3::zero()); N];
    for (end, j) in ends.iter_mut().zip(jobs.iter_mut()) {
        *end = begin_chain(j.c, j.s, k, world, candidates, j.block);
    }
    // Lanes found deep in a field this step (their speed is capped in 7.).
    let mut deep = [!T::all_lanes(); N];
    let n = k.substeps;
    for sub in 0..n {
        // 2.-5. Chain by chain.
        for (j, &(from, to)) in jobs.iter_mut().zip(&ends) {
            substep_to_strain_limit(j.c, j.s, k, sub, from, to);
        }
        // 6. The loop compiled per case (fields or not, friction or not,
        // one round or two): no test of them per vertex.
        let last = sub + 1 == n;
        let fields = jobs.iter().any(|j| !j.s.fields.is_empty());
        let (friction, sdfs) = (k.contact.friction_on, world.sdfs);
        let j = &mut jobs;
        let found = match (fields, friction, last) {
            (false, false, false) => {
                strain_limit_and_collide::<T, false, false, false, N>(j, k, sdfs)
            }
            (false, false, true) => {
                strain_limit_and_collide::<T, false, false, true, N>(j, k, sdfs)
            }
            (false, true, false) => {
                strain_limit_and_collide::<T, false, true, false, N>(j, k, sdfs)
            }
            (false, true, true) => strain_limit_and_collide::<T, false, true, true, N>(j, k, sdfs),
            (true, false, false) => {
                strain_limit_and_collide::<T, true, false, false, N>(j, k, sdfs)
            }
            (true, false, true) => strain_limit_and_collide::<T, true, false, true, N>(j, k, sdfs),
            (true, true, false) => strain_limit_and_collide::<T, true, true, false, N>(j, k, sdfs),
            (true, true, true) => strain_limit_and_collide::<T, true, true, true, N>(j, k, sdfs),
        };
        for (d, f) in deep.iter_mut().zip(found) {
            *d = *d | f;
        }
    }
    let mut ok = [T::all_lanes(); N];
    for ((ok, j), &deep) in ok.iter_mut().zip(jobs.iter_mut()).zip(&deep) {
        *ok = finish_chain(j.c, k, deep);
    }
    ok
}

/// The step's set-up of one chain (2., 3., 5. and 6. below); returns where
/// the root was and its target.
#[inline(always)]
fn begin_chain<T: SdfLane>(
    c: &mut Chain<'_, T>,
    s: &mut ChainScratch<T>,
    k: &Setup,
    world: &StepColliders<'_>,
    candidates: &[ShapeCandidate],
    block: usize,
) -> (V3<T>, V3<T>) {
    let verts = c.pos.len();
    let zero = T::splat(0.0);
    let n = k.substeps;
    let (pos, prev, w) = (&mut c.pos[..verts], &mut c.prev[..verts], &c.w[..verts]);
    let root_from = prev[0];
    let root_to = pos[0];
    // 2. (set-up) Previous positions one substep back: the step's velocity
    // (x - x_prev) / dt, over h; the gusts at the step's start positions.
    let inv_n = T::splat(1.0 / n as f32);
    pos[0] = root_from;
    for v in 1..verts {
        let x = pos[v];
        prev[v] = x - (x - prev[v]) * inv_n;
    }
    if let Some(gusts) = &k.gusts {
        for (gust, x) in s.gust.iter_mut().zip(pos.iter()) {
            *gust = gusts.offset(*x);
        }
    }
    // 3. (set-up) The shape springs' factors, with the rest vectors in the
    // groom frame's current orientation.
    if k.shape_alpha > 0.0 {
        s.shape.factor(
            w,
            c.rest_len,
            c.rest_vec,
            [&k.rotation_from, &k.rotation],
            T::splat(k.shape_alpha),
        );
    }
    // 5., 6. (set-up) This block's candidate colliders, splatted, with the
    // depth of its roots' targets in each (the roots rule), and the pinned
    // vertices and segments kept out of the collisions.
    // Listed by the first vertex that may touch them (the rig's order
    // among equals), each kind a prefix per vertex: the small (first,
    // index) pairs are sorted, not the colliders.
    s.spheres.clear();
    s.capsules.clear();
    s.fields.clear();
    s.order.clear();
    for (at, cand) in candidates.iter().enumerate() {
        if cand.touches(block) {
            s.order.push((cand.first[block] as usize, at));
        }
    }
    sort_by_first(&mut s.order, |o| o.0);
    for &(_, at) in &s.order {
        let Some(cand) = candidates.get(at) else {
            continue;
        };
        let (i, first) = (cand.index as usize, cand.first[block]);
        match cand.kind {
            Kind::Sphere => s.spheres.push(ShapeReach::new(
                &world.rig.spheres[i],
                first,
                n,
                root_to,
                c.arc,
                &k.contact,
            )),
            Kind::Capsule => s.capsules.push(ShapeReach::new(
                &world.rig.capsules[i],
                first,
                n,
                root_to,
                c.arc,
                &k.contact,
            )),
            Kind::Field => {
                let f = world.rig.fields[i];
                if let Some(sdf) = world.sdfs.get(f.index) {
                    s.fields
                        .push(FieldReach::new(f, first, sdf, &k.contact, root_to, c.arc));
                }
            }
        }
    }
    // The vertices any candidate's roots rule reaches.
    s.rooted_end = s
        .spheres
        .iter()
        .chain(s.capsules.iter())
        .map(|r| r.rooted_until())
        .max()
        .unwrap_or(0);
    // No vertex has looked a field up yet this step (the slots follow the
    // new candidate list). Sized by `reserve`; grown here only if it was
    // not called.
    let balls = verts * s.fields.len();
    if s.field_balls.len() < balls {
        s.field_balls.resize(balls, ClearBall::none());
    }
    s.field_balls[..balls].fill(ClearBall::none());
    let (pearl_off, vertex_off) = (&mut s.pearl_off[..verts], &mut s.vertex_off[..verts]);
    for v in 0..verts {
        let free = w[v].gt(zero);
        vertex_off[v] = offset_unless::<T>(free);
        if v > 0 {
            pearl_off[v - 1] = offset_unless::<T>(free & w[v - 1].gt(zero));
        }
    }
    (root_from, root_to)
}

/// Substep `sub` of one chain up to its strain limit: 2. the prediction,
/// 3. shape, 4. the projections and 5. the pearls. (Not inlined: measured
/// the same time and instructions inlined or not, and apart it shows as
/// its own function in a profile, beside the strain limit's walk.)
#[inline(never)]
fn substep_to_strain_limit<T: SdfLane>(
    c: &mut Chain<'_, T>,
    s: &mut ChainScratch<T>,
    k: &Setup,
    sub: u32,
    root_from: V3<T>,
    root_to: V3<T>,
) {
    let n = k.substeps;
    let d = T::splat(k.damping);
    let g = V3::<T>::splat(k.gravity_h2);
    let a0 = T::splat(k.direction[1]);
    let am = T::splat(k.direction[2]);
    // 2. Prediction: the root on its path, Verlet for the free vertices
    // (with the gusts' pull when on), and the fixed part of the
    // directions of segment v - 1 from the positions before the
    // prediction; the colliders to where they are after this substep.
    let root = if sub + 1 == n {
        root_to
    } else {
        root_from + (root_to - root_from) * T::splat((sub + 1) as f32 / n as f32)
    };
    let (pos, prev, w) = (&mut *c.pos, &mut *c.prev, c.w);
    if k.gusts.is_some() {
        predict::<T, true>(pos, prev, w, &mut s.qfix, &s.gust, root, d, g, a0, am);
    } else {
        predict::<T, false>(pos, prev, w, &mut s.qfix, &s.gust, root, d, g, a0, am);
    }
    for r in s.spheres.iter_mut().chain(s.capsules.iter_mut()) {
        r.advance(sub, n);
    }
    for f in &mut s.fields {
        f.advance(sub, n);
    }
    // 3. Shape: the shape springs (implicit), then the global pull.
    if k.shape_alpha > 0.0 {
        let along = T::splat((sub + 1) as f32 / n as f32);
        s.shape.solve(c.pos, c.prev, T::splat(k.shape_keep), along);
    }
    if k.shape > 0.0 {
        global_shape(c, k);
    }
    let a1 = T::splat(k.direction[0]);
    // 4. Projections of the length constraints (and bending). With the
    // shape springs on, the strain limit (6.) holds the lengths instead
    // (`shape.rs`, "Lengths").
    for _ in 0..k.iterations {
        if k.shape_alpha <= 0.0 {
            project(c, s, a1);
        }
        if k.bend > 0.0 {
            bend(c, T::splat(k.bend));
        }
    }
    // 5. Pearls.
    for r in &s.spheres {
        r.push_pearls::<false>(c.pos, c.w, c.arc, &s.pearl_off, k.pearls);
    }
    for r in &s.capsules {
        r.push_pearls::<true>(c.pos, c.w, c.arc, &s.pearl_off, k.pearls);
    }
}

/// Step 7 of one chain: the velocity over the step (at most
/// [`FIELD_EXIT_SPEED`] in a lane that was deep in a field: hair pulled out
/// is not shot out), and the guard: the lanes that stayed finite and in
/// bounds.
#[inline(always)]
fn finish_chain<T: Lane>(c: &mut Chain<'_, T>, k: &Setup, deep: T::Mask) -> T::Mask {
    let verts = c.pos.len();
    let (pos, prev, w) = (&mut c.pos[..verts], &mut c.prev[..verts], &c.w[..verts]);
    let zero = T::splat(0.0);
    let nn = T::splat(k.substeps as f32);
    let big = T::splat(BLOWN_UP);
    let mut ok = T::all_lanes();
    let capped = T::any(deep);
    let cap = T::splat(k.exit_move);
    for v in 0..verts {
        let x = pos[v];
        let mut back = x - (x - prev[v]) * nn;
        if capped {
            let moved = x - back;
            let m2 = dot(moved, moved).max(T::splat(1.0e-30));
            let scale = (cap * m2.inv_sqrt()).min(T::splat(1.0));
            back = V3::select(deep, x - moved * scale, back);
        }
        prev[v] = V3::select(w[v].gt(zero), back, x);
        ok = ok & x.finite() & x.x.abs().lt(big) & x.y.abs().lt(big) & x.z.abs().lt(big);
    }
    ok
}

/// Step 4: one projection of the chain's length constraints along the
/// blended directions (tridiagonal solve, Thomas algorithm).
#[inline(always)]
fn project<T: Lane>(c: &mut Chain<'_, T>, s: &mut ChainScratch<T>, a1: T) {
    let verts = c.pos.len();
    let segs = verts - 1;
    let zero = T::splat(0.0);
    let min_cos = T::splat(MIN_DIRECTION_COSINE);
    let tiny = T::splat(1.0e-12);
    let (pos, w, rest_len) = (&mut c.pos[..verts], &c.w[..verts], &c.rest_len[..verts]);
    let (qfix, sn, cp, dp) = (
        &s.qfix[..verts],
        &mut s.n[..verts],
        &mut s.cp[..verts],
        &mut s.dp[..verts],
    );
    let dir = |pos: &[V3<T>], v: usize| -> (T, V3<T>, V3<T>) {
        let d = pos[v + 1] - pos[v];
        let (len, e) = length_dir(d);
        let n = blended(madd(d, a1, qfix[v]), e, min_cos);
        (len, e, n)
    };
    // Forward elimination. Row v reads `e_v . n_{v-1}`, `e_v . n_v` and
    // `e_v . n_{v+1}`: the first two are taken when `n_v` is known, the last
    // when `n_{v+1}` is, so only two segments' directions are live.
    let (mut len, mut e, mut n) = dir(pos, 0);
    let mut sub_dot = dot(e, V3::zero());
    let mut diag_dot = dot(e, n);
    let mut cp_prev = zero;
    let mut dp_prev = zero;
    // Row v of the elimination, given segment v + 1's blended direction
    // (zero past the last segment).
    let mut row =
        |v: usize, (len, e, n): (T, V3<T>, V3<T>), n_next: V3<T>, sub_dot: T, diag_dot: T| {
            let sub = -(w[v] * sub_dot);
            let diag = (w[v] + w[v + 1]) * diag_dot;
            let sup = -(w[v + 1] * dot(e, n_next));
            let rhs = rest_len[v] - len;
            let pivot = sub.mul_add(-cp_prev, diag);
            let live = pivot.gt(tiny);
            let inv = pivot.max(tiny).recip();
            cp_prev = T::select(live, sup * inv, zero);
            dp_prev = T::select(live, sub.mul_add(-dp_prev, rhs) * inv, zero);
            cp[v] = cp_prev;
            dp[v] = dp_prev;
            sn[v] = n;
        };
    // Every row but the last (the last is peeled: no zeros carried and no
    // branch in the loop).
    for v in 0..segs - 1 {
        let (len_next, e_next, n_next) = dir(pos, v + 1);
        row(v, (len, e, n), n_next, sub_dot, diag_dot);
        sub_dot = dot(e_next, n);
        diag_dot = dot(e_next, n_next);
        (len, e, n) = (len_next, e_next, n_next);
    }
    row(segs - 1, (len, e, n), V3::zero(), sub_dot, diag_dot);
    // Back substitution, moving vertices as the multipliers become known.
    let mut lambda_next = zero;
    let mut n_next = V3::zero();
    for v in (0..segs).rev() {
        let lambda = cp[v].mul_add(-lambda_next, dp[v]);
        let n = sn[v];
        pos[v + 1] = madd(madd(n_next, -lambda_next, n * lambda), w[v + 1], pos[v + 1]);
        lambda_next = lambda;
        n_next = n;
    }
    pos[0] = madd(n_next, -(lambda_next * w[0]), pos[0]);
}

/// The constraint direction: `q` itself (the multiplier absorbs its scale),
/// or `e` where `q` is shorter than [`MIN_LENGTH`] or its cosine with `e`
/// is below `min_cos` (`e.q < min_cos |q|`, tested squared).
#[inline(always)]
fn blended<T: Lane>(q: V3<T>, e: V3<T>, min_cos: T) -> V3<T> {
    let eq = dot(e, q);
    let q2 = dot(q, q);
    let bad = eq.lt(T::splat(0.0))
        | (eq * eq).lt(min_cos * min_cos * q2)
        | q2.lt(T::splat(MIN_LENGTH * MIN_LENGTH));
    V3::select(bad, e, q)
}

/// Step 4 (bending on): one sweep of the i..i+2 distance constraints,
/// `k = b (1 - l / |delta|)`, `x_i += share_i k delta`, `x_j -= share_j k delta`
/// (Jakobsen 2001).
#[inline(always)]
fn bend<T: Lane>(c: &mut Chain<'_, T>, stiffness: T) {
    let verts = c.pos.len();
    for v in 0..verts.saturating_sub(2) {
        let delta = c.pos[v + 2] - c.pos[v];
        let inv = dot(delta, delta)
            .max(T::splat(MIN_LENGTH * MIN_LENGTH))
            .inv_sqrt();
        let k = stiffness * c.bend_len[v].mul_add(-inv, T::splat(1.0));
        let share = c.bend_share[v];
        c.pos[v] = madd(delta, k * share[0], c.pos[v]);
        c.pos[v + 2] = madd(delta, -(k * share[1]), c.pos[v + 2]);
    }
}

/// Step 3: the global shape pull `x += k w_v (root + R rest_v - x)`.
#[inline(always)]
fn global_shape<T: Lane>(c: &mut Chain<'_, T>, k: &Setup) {
    let zero = T::splat(0.0);
    let stiff = T::splat(k.shape);
    let root = c.pos[0];
    for v in 1..c.pos.len() {
        let target = root + rotate(&k.rotation, c.rest_offset[v]);
        let pulled = madd(target - c.pos[v], stiff * c.shape_weight[v], c.pos[v]);
        c.pos[v] = V3::select(c.w[v].gt(zero), pulled, c.pos[v]);
    }
}

/// Step 2: the Verlet prediction of one substep,
/// `x* = x + d (x - x_prev) + (g + drag wind) h^2` (+ the gusts' pull when
/// `GUSTS`), the root on its path, and the fixed part of the directions
/// `(1/2) d_s(x_n) + (1/4 - a) d_s(x_{n-1})` of segment v - 1 from the
/// positions before it.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn predict<T: Lane, const GUSTS: bool>(
    pos: &mut [V3<T>],
    prev: &mut [V3<T>],
    w: &[T],
    qfix: &mut [V3<T>],
    gust: &[V3<T>],
    root: V3<T>,
    d: T,
    g: V3<T>,
    a0: T,
    am: T,
) {
    let verts = pos.len();
    let (prev, w, qfix, gust) = (
        &mut prev[..verts],
        &w[..verts],
        &mut qfix[..verts],
        &gust[..verts],
    );
    let zero = T::splat(0.0);
    let mut x_last = pos[0];
    let mut p_last = prev[0];
    for v in 0..verts {
        let x = pos[v];
        let xp = prev[v];
        if v > 0 {
            qfix[v - 1] = madd(x - x_last, a0, (xp - p_last) * am);
        }
        let pull = if GUSTS { x + g + gust[v] } else { x + g };
        let moved = madd(x - xp, d, pull);
        let pinned = if v == 0 { root } else { x };
        pos[v] = V3::select(w[v].gt(zero), moved, pinned);
        prev[v] = x;
        x_last = x;
        p_last = xp;
    }
}

/// Step 6: the two-sided strain limit, root to tip, alternating `rounds`
/// times per vertex with the push-out of every candidate collider (with
/// Coulomb friction in the first round: `collide/narrow.rs`). The parent
/// is final and outside the colliders, so the two sets meet and
/// alternating closes in on a point of both: the limit does not pull hair
/// into the head and the push-out does not stretch it. Returns the lanes
/// found deep in a field, per chain. (`FIELDS`: some field is a candidate
/// of some chain; without, the loop carries neither the previous
/// positions nor the deep lanes. `FRICTION`: `k.contact.friction_on`.
/// `TWO_ROUNDS`: the last substep.) The `N` chains walk in step, vertex
/// `v` of each before `v + 1` of any: each walk is a chain of dependent
/// operations, and `N` of them side by side let the core overlap them.
#[inline(always)]
fn strain_limit_and_collide<
    T: SdfLane,
    const FIELDS: bool,
    const FRICTION: bool,
    const TWO_ROUNDS: bool,
    const N: usize,
>(
    jobs: &mut [ChainJob<'_, '_, T>; N],
    k: &Setup,
    sdfs: &[Sdf],
) -> [T::Mask; N] {
    let mut deep = [!T::all_lanes(); N];
    let verts = jobs.first().map_or(0, |j| j.c.pos.len());
    if verts < 2 {
        return deep;
    }
    match jobs.as_mut_slice() {
        [a, b] => {
            let mut a = strain_walk(a.c, a.s, verts);
            let mut b = strain_walk(b.c, b.s, verts);
            for v in 1..verts {
                a.vertex::<FIELDS, FRICTION, TWO_ROUNDS>(v, k, sdfs);
                b.vertex::<FIELDS, FRICTION, TWO_ROUNDS>(v, k, sdfs);
            }
            deep[0] = a.deep;
            deep[1] = b.deep;
        }
        jobs => {
            for (j, deep) in jobs.iter_mut().zip(&mut deep) {
                let mut a = strain_walk(j.c, j.s, verts);
                for v in 1..verts {
                    a.vertex::<FIELDS, FRICTION, TWO_ROUNDS>(v, k, sdfs);
                }
                *deep = a.deep;
            }
        }
    }
    deep
}

/// Vertex `v`'s own values in [`StrainWalk`]: its position and previous
/// position, and its segment's rest length, its inverse mass, contact
/// offset and rest arc.
type VertexRefs<'w, T> = (
    ((&'w mut V3<T>, &'w mut V3<T>), (&'w T, &'w T)),
    (&'w T, &'w T),
);

/// One chain's walk of [`strain_limit_and_collide`]: its vertices from 1
/// (one zipped iterator, so one bound test per vertex), the parent's final
/// position, and where it stands in its candidate lists.
struct StrainWalk<'w, T: SdfLane, I> {
    verts: I,
    parent: V3<T>,
    spheres: &'w [ShapeReach<T>],
    capsules: &'w [ShapeReach<T>],
    fields: &'w [FieldReach<T>],
    balls: &'w mut [ClearBall<T>],
    rooted_end: usize,
    live: [usize; 3],
    deep: T::Mask,
}

/// The walk of chain `c` (`verts` vertices) with its scratch `s`.
#[inline(always)]
fn strain_walk<'w, T: SdfLane>(
    c: &'w mut Chain<'_, T>,
    s: &'w mut ChainScratch<T>,
    verts: usize,
) -> StrainWalk<'w, T, impl Iterator<Item = VertexRefs<'w, T>>> {
    let ChainScratch {
        spheres,
        capsules,
        fields,
        vertex_off,
        field_balls,
        rooted_end,
        ..
    } = s;
    let balls_n = verts * fields.len();
    let (root, pos) = c.pos[..verts].split_at_mut(1);
    let parent = root[0];
    let prev = &mut c.prev[1..verts];
    let own = c.rest_len[..verts - 1].iter().zip(&c.w[1..verts]);
    let contact = vertex_off[1..verts].iter().zip(&c.arc[1..verts]);
    StrainWalk {
        verts: pos.iter_mut().zip(prev.iter_mut()).zip(own).zip(contact),
        parent,
        spheres,
        capsules,
        fields,
        balls: &mut field_balls[..balls_n],
        rooted_end: *rooted_end,
        live: [0; 3],
        deep: !T::all_lanes(),
    }
}

impl<'w, T: SdfLane, I: Iterator<Item = VertexRefs<'w, T>>> StrainWalk<'w, T, I> {
    /// The next vertex, `v`: its strain limit and pushes (its parent final).
    #[inline(always)]
    fn vertex<const FIELDS: bool, const FRICTION: bool, const TWO_ROUNDS: bool>(
        &mut self,
        v: usize,
        k: &Setup,
        sdfs: &[Sdf],
    ) {
        let Some((((x_at, xp_at), (&rest_len, &w)), (&o, &a))) = self.verts.next() else {
            return;
        };
        let (spheres, capsules, fields) = (self.spheres, self.capsules, self.fields);
        let [live_s, live_c, live_f] = &mut self.live;
        while *live_s < spheres.len() && spheres[*live_s].first <= v {
            *live_s += 1;
        }
        while *live_c < capsules.len() && capsules[*live_c].first <= v {
            *live_c += 1;
        }
        if FIELDS {
            while *live_f < fields.len() && fields[*live_f].first <= v {
                *live_f += 1;
            }
        }
        let (live_s, live_c, live_f) = (*live_s, *live_c, *live_f);
        let zero = T::splat(0.0);
        let limit = rest_len * T::splat(k.stretch_factor);
        let floor = rest_len * T::splat(k.shrink_factor);
        let free = w.gt(zero);
        let parent = self.parent;
        let strain = |x: V3<T>| {
            let d = x - parent;
            let d2 = dot(d, d);
            let long = d2.gt(limit * limit);
            let short = d2.lt(floor * floor);
            let fix = (long | short) & free;
            if T::any(fix) {
                let target = T::select(long, limit, floor);
                let inv = d2.max(T::splat(MIN_LENGTH * MIN_LENGTH)).inv_sqrt();
                V3::select(fix, madd(d, target * inv, parent), x)
            } else {
                x
            }
        };
        let mut x = strain(*x_at);
        let mut xp = *xp_at;
        let (sp, ca) = (&spheres[..live_s], &capsules[..live_c]);
        let rooted = v < self.rooted_end;
        x = if rooted {
            push_shapes::<T, FRICTION, true>(sp, ca, v, x, xp, o, a, &k.contact)
        } else {
            push_shapes::<T, FRICTION, false>(sp, ca, v, x, xp, o, a, &k.contact)
        };
        let fields_n = fields.len();
        if FIELDS {
            let balls = &mut self.balls[v * fields_n..][..live_f];
            for (f, ball) in fields[..live_f].iter().zip(balls) {
                if let Some(sdf) = sdfs.get(f.field.index) {
                    let (pushed, was_deep) =
                        f.push_vertex(sdf, v, x, &mut xp, o, a, &k.contact, FRICTION, ball);
                    x = pushed;
                    self.deep = self.deep | was_deep;
                }
            }
        }
        // The last substep's second round: friction acts once per substep.
        if TWO_ROUNDS {
            x = strain(x);
            x = if rooted {
                push_shapes::<T, false, true>(sp, ca, v, x, xp, o, a, &k.contact)
            } else {
                push_shapes::<T, false, false>(sp, ca, v, x, xp, o, a, &k.contact)
            };
            if FIELDS {
                let balls = &mut self.balls[v * fields_n..][..live_f];
                for (f, ball) in fields[..live_f].iter().zip(balls) {
                    if let Some(sdf) = sdfs.get(f.field.index) {
                        let (pushed, was_deep) =
                            f.push_vertex(sdf, v, x, &mut xp, o, a, &k.contact, false, ball);
                        x = pushed;
                        self.deep = self.deep | was_deep;
                    }
                }
            }
        }
        *x_at = x;
        self.parent = x;
        if FIELDS {
            *xp_at = xp;
        }
    }
}

/// Every live sphere, then capsule, pushes vertex `v` (friction and the
/// roots rule's test compiled in or out).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn push_shapes<T: Lane, const FRICTION: bool, const ROOTED: bool>(
    spheres: &[ShapeReach<T>],
    capsules: &[ShapeReach<T>],
    v: usize,
    mut x: V3<T>,
    xp: V3<T>,
    off: T,
    arc: T,
    k: &ContactSetup,
) -> V3<T> {
    for r in spheres {
        x = r.push_vertex::<false, FRICTION, ROOTED>(v, x, xp, off, arc, k);
    }
    for r in capsules {
        x = r.push_vertex::<true, FRICTION, ROOTED>(v, x, xp, off, arc, k);
    }
    x
}

/// Advances every strand by one fixed step of `params.dt` (SIMD path)
/// against rig spheres: [`step_colliders`] with spheres only, on the
/// calling thread. A library call never starts threads of its own; pass an
/// executor to [`step_with`] to use more (the result is the same bytes).
///
/// Never panics; `params` should pass [`SimParams::validate`], and strands
/// that bad values drive non-finite are restored and counted
/// ([`Strands::restored_strands`]). Allocates only when the rig has more
/// spheres than any earlier step.
pub fn step(strands: &mut Strands, params: &SimParams, spheres: &[Sphere]) {
    step_colliders_with(strands, params, &Colliders::spheres(spheres), &Serial);
}

/// [`step`] with its blocks handed out as tasks to `executor`
/// ([`step_colliders_with`] with spheres only).
pub fn step_with(
    strands: &mut Strands,
    params: &SimParams,
    spheres: &[Sphere],
    executor: &dyn Executor,
) {
    step_colliders_with(strands, params, &Colliders::spheres(spheres), executor);
}

/// Advances every strand by one fixed step of `params.dt` (SIMD path)
/// against everything in `colliders`: spheres, capsules and mesh fields,
/// any number of each, with wind, drag and Coulomb friction; on the
/// calling thread ([`step_colliders_with`] on [`Serial`]).
///
/// Never panics, whatever the colliders hold (invalid spheres and capsules
/// are ignored); allocates only when a kind of collider has more entries
/// than at any earlier step ([`Strands::reserve_colliders`] sizes it
/// beforehand).
pub fn step_colliders(strands: &mut Strands, params: &SimParams, colliders: &Colliders<'_>) {
    step_colliders_with(strands, params, colliders, &Serial);
}

/// [`step_colliders`] with its blocks handed out as tasks to `executor`:
/// at most [`crate::MAX_STEP_TASKS`] tasks of whole pairs of blocks, split by the
/// block count alone. Blocks never exchange data within a step, each task
/// has its own buffers (sized when the set is built) and the restored
/// count is summed after the tasks, so the result is the same bytes with
/// any executor and any number of threads.
pub fn step_colliders_with(
    strands: &mut Strands,
    params: &SimParams,
    colliders: &Colliders<'_>,
    executor: &dyn Executor,
) {
    drive(
        strands,
        params,
        colliders,
        executor,
        |s, st, b, lanes, k| {
            let group = lanes_below(lanes.end) & !lanes_below(lanes.start);
            block_sweep_aabb(st.pos, st.prev, k.gravity_dt2, s.active[b] & group)
        },
        |strands, states, scratch, world, k, ids| {
            // 2.-7., two blocks side by side where two run.
            let cands = &scratch.candidates;
            let mut bad = [0; PAIR];
            match (states, ids, &mut scratch.chains) {
                ([sa, sb], &[(ba, ga), (bb, gb)], [ta, tb, ..]) => {
                    let (mut ca, mut cb) =
                        (block_chain(strands, ba, sa), block_chain(strands, bb, sb));
                    let jobs = [
                        ChainJob {
                            c: &mut ca,
                            s: ta,
                            block: ga,
                        },
                        ChainJob {
                            c: &mut cb,
                            s: tb,
                            block: gb,
                        },
                    ];
                    let ok: [F32Lanes; 2] = step_chains(jobs, k, world, cands);
                    bad[0] = (!ok[0]).to_bitmask();
                    bad[1] = (!ok[1]).to_bitmask();
                }
                (states, ids, [t, ..]) => {
                    for ((st, &(b, g)), bad) in states.iter_mut().zip(ids).zip(&mut bad) {
                        let mut c = block_chain(strands, b, st);
                        let ok: F32Lanes = step_chain(&mut c, t, k, world, cands, g);
                        *bad = (!ok).to_bitmask();
                    }
                }
            }
            bad
        },
        |s, st, grid, gk, b| {
            let r = b * s.verts..(b + 1) * s.verts;
            let moved = apply_block::<F32Lanes>(
                grid,
                st.pos,
                st.prev,
                &s.inv_mass[r.clone()],
                &s.rest_arc[r],
                gk,
            );
            (moved & s.active[b]).to_bitmask()
        },
    );
}

/// Block `b`'s chain: its moving state `st` and its rest data in `s`.
fn block_chain<'a>(s: &'a Strands, b: usize, st: &'a mut BlockState<'_>) -> Chain<'a, F32Lanes> {
    let r = b * s.verts..(b + 1) * s.verts;
    Chain {
        pos: &mut *st.pos,
        prev: &mut *st.prev,
        w: &s.inv_mass[r.clone()],
        rest_len: &s.rest_len[r.clone()],
        rest_vec: &s.rest_vec[r.clone()],
        rest_offset: &s.rest_offset[r.clone()],
        bend_len: &s.bend_len[r.clone()],
        bend_share: &s.bend_share[r.clone()],
        shape_weight: &s.shape_weight[r.clone()],
        arc: &s.rest_arc[r],
    }
}

/// The colliders of one step as a block's chain sees them: the local rig
/// and the fields it indexes.
pub(crate) struct StepColliders<'a> {
    pub rig: &'a LocalRig,
    pub sdfs: &'a [Sdf],
}

#[cfg(test)]
mod tests {
    use crate::collide::Colliders;
    use crate::{scalar, step_colliders, Sdf, SimParams, Strands};
    use coif_testkit::meshes::icosphere;
    use glam::{Affine3A, Quat, Vec3};

    /// A capsule across the hair at depth `z`, a sphere below it at `x`,
    /// and the parameters: a side wind of `wind` m/s along -z, drag 2 /s.
    /// The bits of every coordinate, point after point.
    fn bits(points: &[Vec3]) -> Vec<u32> {
        points
            .iter()
            .flat_map(|p| p.to_array())
            .map(f32::to_bits)
            .collect()
    }

    fn side_rig(z: f32, x: f32, wind: f32) -> ([crate::Capsule; 1], [crate::Sphere; 1], SimParams) {
        let caps = [crate::Capsule {
            a: Vec3::new(-0.3, -0.05, z),
            b: Vec3::new(0.3, -0.05, z),
            radius: 0.02,
        }];
        let spheres = [crate::Sphere {
            center: Vec3::new(x, -0.2, 0.0),
            radius: 0.04,
        }];
        let params = SimParams {
            wind: Vec3::new(0.0, 0.0, -wind),
            drag: 2.0,
            ..Default::default()
        };
        (caps, spheres, params)
    }

    /// `steps` steps over a ball field turning by up to `turn` radians
    /// about z (`rate` radians of phase per step) and swaying by `sway` m
    /// along x, `depth` m below the roots: each step its pose set, then the
    /// step against it and the side rig's shapes, SIMD or scalar.
    fn step_over_turning_field(
        s: &mut Strands,
        fields: &mut [Sdf],
        (caps, spheres, params): &([crate::Capsule; 1], [crate::Sphere; 1], SimParams),
        steps: usize,
        (turn, rate, sway, depth): (f32, f32, f32, f32),
        simd: bool,
    ) {
        for i in 0..steps {
            let q = Quat::from_rotation_z(turn * (i as f32 * rate).sin());
            let t = Vec3::new(sway * (i as f32 * 0.1).sin(), -depth, 0.0);
            for f in fields.iter_mut() {
                f.set_transform(Affine3A::from_rotation_translation(q, t))
                    .unwrap();
            }
            let c = Colliders {
                spheres,
                capsules: caps,
                sdfs: fields,
            };
            if simd {
                step_colliders(s, params, &c);
            } else {
                scalar::step_colliders(s, params, &c);
            }
        }
    }

    /// A curtain of 40 strands of 25 x 1.2 cm draped over a ball field of
    /// 7 cm that turns and shifts under it, with a capsule and a sphere
    /// beside, in a side wind: stepped with the field as built and with its
    /// clear balls removed (every vertex looked up every round), SIMD and
    /// scalar. The same bytes, and the balls did hold vertices (some have a
    /// radius at the end) while the hair touched the field (it ends
    /// elsewhere than without the field).
    #[test]
    fn skipping_lookups_in_clear_balls_gives_the_same_bytes() {
        let m = icosphere(3, 0.07);
        let built = Sdf::from_mesh(&m.0, &m.1, 0.004).unwrap();
        let pts: Vec<Vec3> = (0..40)
            .flat_map(|i| {
                let root = Vec3::new(i as f32 * 0.008 - 0.16, 0.0, 0.01);
                (0..25).map(move |v| root - Vec3::Y * (0.012 * v as f32))
            })
            .collect();
        let rig = side_rig(0.05, 0.12, 1.0);
        let run = |field: Option<Sdf>, simd: bool| {
            let mut fields: Vec<Sdf> = field.into_iter().collect();
            let mut s = Strands::from_polylines(&pts, 25).unwrap();
            step_over_turning_field(&mut s, &mut fields, &rig, 60, (0.3, 0.05, 0.02, 0.14), simd);
            s
        };
        let without_field = bits(&run(None, true).positions());
        for simd in [true, false] {
            let skipping = run(Some(built.clone()), simd);
            let looking = run(Some(built.clone().without_clear_balls()), simd);
            let skipped = bits(&skipping.positions());
            assert_eq!(skipped, bits(&looking.positions()), "SIMD {simd}");
            assert_ne!(skipped, without_field, "SIMD {simd}: no contact");
            let balls = skipping.scratch.tasks.iter().any(|t| {
                if simd {
                    t.chains.iter().any(|c| {
                        c.field_balls
                            .iter()
                            .any(|b| b.radius2().as_array().iter().any(|&r| r > 0.0))
                    })
                } else {
                    t.lane.chain.field_balls.iter().any(|b| b.radius2() > 0.0)
                }
            });
            assert!(balls, "SIMD {simd}: no clear ball");
        }
    }

    /// Three blocks of 8 strands (24 in a row, hanging over a ball field
    /// that turns under them, a capsule and a sphere beside, in a side
    /// wind, friction on), stepped in their order and with the last block
    /// moved first: the SIMD path pairs blocks 0 and 1 and steps 2 alone in
    /// the first set, pairs 2 with 0 and steps 1 alone in the second. Every
    /// strand ends with the same bytes in both, and as the scalar twin's,
    /// which steps one lane at a time: a chain's step does not depend on
    /// the chain beside it. (The roots' mean, the sets' local origin, is
    /// exactly the same in both: every root is on a 1/256 m grid.)
    #[test]
    fn two_blocks_side_by_side_give_the_bytes_of_each_alone() {
        let m = icosphere(3, 0.07);
        let sdf = Sdf::from_mesh(&m.0, &m.1, 0.004).unwrap();
        let strand = |i: usize| -> Vec<Vec3> {
            let root = Vec3::new((i as f32 - 11.5) / 128.0, 0.0, 0.0);
            (0..20)
                .map(move |v| root - Vec3::Y * (0.012 * v as f32))
                .collect()
        };
        let order_a: Vec<usize> = (0..24).collect();
        let order_b: Vec<usize> = (16..24).chain(0..16).collect();
        let rig = side_rig(0.04, 0.05, 1.5);
        let run = |order: &[usize], simd: bool| -> Vec<Vec<u32>> {
            let pts: Vec<Vec3> = order.iter().flat_map(|&i| strand(i)).collect();
            let mut s = Strands::from_polylines(&pts, 20).unwrap();
            let mut fields = vec![sdf.clone()];
            step_over_turning_field(&mut s, &mut fields, &rig, 40, (0.4, 0.07, 0.03, 0.13), simd);
            // Each strand's bits, by its index in `order_a`.
            let mut by_strand = vec![Vec::new(); 24];
            for (chunk, &i) in s.positions().chunks(20).zip(order) {
                by_strand[i] = bits(chunk);
            }
            by_strand
        };
        let a = run(&order_a, true);
        let still: Vec<Vec<u32>> = (0..24).map(|i| bits(&strand(i))).collect();
        assert!(
            a.iter().zip(&still).all(|(x, y)| x != y),
            "some strand never moved"
        );
        assert_eq!(
            a,
            run(&order_b, true),
            "SIMD: the pairing changed the bytes"
        );
        assert_eq!(a, run(&order_a, false), "SIMD against scalar");
        assert_eq!(a, run(&order_b, false), "scalar, reordered");
    }

    /// The shortest strands (two vertices, one segment) in two blocks that
    /// run side by side, swinging onto a sphere: the walk of a pair covers
    /// the single segment, SIMD as the scalar twin, bit for bit.
    #[test]
    fn two_vertex_strands_step_side_by_side() {
        let pts: Vec<Vec3> = (0..16)
            .flat_map(|i| {
                let root = Vec3::new(i as f32 * 0.01 - 0.08, 0.0, 0.0);
                [root, root + Vec3::new(0.1, 0.0, 0.02)]
            })
            .collect();
        let rig = [crate::Sphere {
            center: Vec3::new(0.0, -0.12, 0.0),
            radius: 0.06,
        }];
        let params = SimParams::default();
        let mut simd = Strands::from_polylines(&pts, 2).unwrap();
        let mut reference = simd.clone();
        for _ in 0..40 {
            crate::step(&mut simd, &params, &rig);
            scalar::step(&mut reference, &params, &rig);
        }
        assert_eq!(bits(&simd.positions()), bits(&reference.positions()));
        let tips = simd.positions();
        assert!(
            tips.iter().skip(1).step_by(2).all(|p| p.y < -0.05),
            "the tips did not swing down"
        );
    }
}
