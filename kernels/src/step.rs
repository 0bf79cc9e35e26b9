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
//!    limit leaves them, against every rig sphere (`broad_phase.rs`; the
//!    group's union first, then each block); only the spheres near a block
//!    enter its narrow phase, from the first vertex that may touch them.
//! 2. **Prediction** (per substep): the root moves on the straight line from
//!    where it was to its target; free vertices take a position-Verlet step
//!    `x* = x + d^(1/n) (x - x_prev) + g h^2` (Yip 2011's damping `d` spread
//!    over the substeps). The same pass stores the fixed part of the
//!    constraint directions, `(1/2) d_s(x_n) + (1/4 - a) d_s(x_{n-1})` with
//!    `d_s(x) = x_{s+1} - x_s`.
//! 3. **Shape** (optional): TressFX 4's local shape constraints, root to tip
//!    (segment s is pulled toward its rest vector carried by the minimal
//!    rotation that takes the parent's rest direction to its current
//!    direction; the root segment toward the groom frame), the child taking
//!    the whole correction; then the global shape pull toward
//!    `root + R rest_v`, weighted `1 - arc(v)/arc(tip)` (Yip 2011).
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
//! 5. **Pearls** against the block's spheres: `k` points per segment pushed
//!    out by the Nalu demo's point-on-segment rule (Nguyen and Donnelly
//!    2005).
//! 6. **Strain limit with push-out**, root to tip: each vertex is moved
//!    along its segment until `(1 - s) l <= |x_v - x_{v-1}| <= (1 + s) l`
//!    (Provot 1995, Follow-The-Leader order, Muller et al. 2012), then pushed
//!    out of the spheres, with friction `x_prev += mu v_t`; one round per
//!    substep, two on the last.
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
//! No division and no square root in the body: `1/sqrt` and `1/x` are the
//! hardware estimates plus one Newton step ([`Lane::inv_sqrt`],
//! [`Lane::recip`]), which read the same tables in both widths, so the SIMD
//! and scalar paths agree bit for bit on x86-64 with AVX.

use crate::broad_phase::{
    block_sweep_aabb, roots_aabb, select_strand_candidates, spheres_to_local, Aabb, BlockBounds,
    Candidate,
};
use crate::constraints::{BLOWN_UP, MIN_LENGTH};
use crate::lanes::{Lane, Vec3x8, LANES, V3};
use crate::strands::{rest_pose, BlockSleep, Scratch};
use crate::{SimParams, Sphere, Strands};
use coif_base::tasks::{for_each_chunk_mut, Executor, Serial};
use glam::{DVec3, Mat3, Vec3};
use wide::f32x8;

/// Constraint directions whose cosine with the current segment falls below
/// this are replaced by the current direction (the blend means nothing once
/// a segment turned by more than 60 degrees within a substep).
pub(crate) const MIN_DIRECTION_COSINE: f32 = 0.5;
/// Local shape correction per [`LOCAL_SHAPE_H_REF`] at stiffness 1.
pub(crate) const LOCAL_SHAPE_MAX: f32 = 0.99;
/// Substep length at which [`LOCAL_SHAPE_MAX`] was measured (s).
pub(crate) const LOCAL_SHAPE_H_REF: f32 = 1.0 / 240.0;

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
    pub pearl_radius: f32,
    pub friction: f32,
    /// Per substep: local shape share, global shape pull, bending stiffness.
    pub local_shape: f32,
    pub shape: f32,
    pub bend: f32,
    pub rotation: Mat3,
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

/// The local shape correction per substep of length `h` for the user's
/// stiffness `k` in [0, 1]: `c / (1 - c) = (c_ref / (1 - c_ref)) (h / h_ref)`
/// with `c_ref = 0.99 k`, `h_ref = 1/240 s`. Measured on the mohawk, this
/// keeps the rest drift, lag and return flat from 4 to 8 substeps per 1/60 s;
/// the exponential `1 - (1 - c_ref)^(h / h_ref)` (the decay of an
/// undisturbed error) let the mohawk drift 66 % at 8 substeps.
pub(crate) fn local_shape_per_substep(k: f32, h: f32) -> f32 {
    let k = k.clamp(0.0, 1.0);
    if k <= 0.0 || h.is_nan() {
        return 0.0;
    }
    let c_ref = LOCAL_SHAPE_MAX * k;
    let s = c_ref / (1.0 - c_ref) * (h / LOCAL_SHAPE_H_REF);
    s / (1.0 + s)
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
        Setup {
            substeps: n,
            damping: p.damping.powf(1.0 / n as f32),
            gravity_h2: p.gravity * (h * h),
            gravity_dt2: p.gravity * (p.dt * p.dt),
            iterations: p.iterations,
            direction: [0.25 + a, 0.5, 0.25 - a],
            stretch_factor: 1.0 + p.max_stretch,
            shrink_factor: (1.0 - p.max_stretch).max(0.0),
            pearls: p.pearls_per_segment.min(crate::MAX_PEARLS_PER_SEGMENT),
            pearl_radius: p.pearl_radius,
            friction: p.friction,
            local_shape: local_shape_per_substep(p.local_shape_stiffness, h),
            shape: per_substep(p.shape_stiffness, n),
            bend: per_substep(p.bend_stiffness, n),
            rotation: s.rest_rotation,
            margin: p.pearl_radius.max(0.0) + s.max_rest_segment,
            sleep: p.sleep_speed > 0.0 && p.dt > 0.0,
            still_move2: (p.sleep_speed * p.dt) * (p.sleep_speed * p.dt),
            still_steps: ((crate::SLEEP_AFTER / p.dt).ceil() as u32).max(1),
        }
    }
}

/// One chain's data: eight chains in lanes (`T = f32x8`) or one (`f32`),
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
    /// Rest vector and unit rest direction of segment v -> v + 1, groom frame.
    pub rest_vec: &'a [V3<T>],
    pub rest_dir: &'a [V3<T>],
    /// Rest offset of vertex v from the root, groom frame.
    pub rest_offset: &'a [V3<T>],
    /// Rest distance v -> v + 2 and the mass shares of that constraint.
    pub bend_len: &'a [T],
    pub bend_share: &'a [[T; 2]],
    /// Global shape weight `1 - arc(v) / arc(tip)`.
    pub shape_weight: &'a [T],
}

/// Per-chain scratch, `V` entries each, sized when the strands are built
/// (`reach` holds one entry per rig sphere: the step reserves it when the
/// rig grows).
#[derive(Clone, Debug, Default)]
pub(crate) struct ChainScratch<T: Lane> {
    qfix: Vec<V3<T>>,
    n: Vec<V3<T>>,
    cp: Vec<T>,
    dp: Vec<T>,
    rvec: Vec<V3<T>>,
    rdir: Vec<V3<T>>,
    /// Per segment: 0 where both ends are free, +inf where one is pinned
    /// (added to a pearl's squared distance, it keeps the pearl out of
    /// every sphere).
    pearl_off: Vec<T>,
    /// Per vertex: 0 if free, +inf if pinned (the same for vertices).
    vertex_off: Vec<T>,
    /// The step's candidate spheres of this block, splatted.
    reach: Vec<Reach<T>>,
}

impl<T: Lane> ChainScratch<T> {
    pub(crate) fn new(verts: usize) -> Self {
        ChainScratch {
            qfix: vec![V3::zero(); verts],
            n: vec![V3::zero(); verts],
            cp: vec![T::splat(0.0); verts],
            dp: vec![T::splat(0.0); verts],
            rvec: vec![V3::zero(); verts],
            rdir: vec![V3::zero(); verts],
            pearl_off: vec![T::splat(0.0); verts],
            vertex_off: vec![T::splat(0.0); verts],
            reach: Vec::new(),
        }
    }

    /// Room for the candidates of a rig of `spheres` spheres (allocates only
    /// when the rig grew).
    pub(crate) fn reserve_spheres(&mut self, spheres: usize) {
        self.reach.reserve(spheres.saturating_sub(self.reach.len()));
    }
}

/// A rig sphere grown by the pearl radius, splatted.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Reach<T: Lane> {
    centre: V3<T>,
    reach: T,
    reach2: T,
    /// The first vertex of the block that may touch it (broad phase).
    first: usize,
}

impl<T: Lane> Reach<T> {
    #[inline(always)]
    fn new(s: [f32; 4], r: f32, first: u32) -> Self {
        let reach = T::splat(s[3] + r);
        Reach {
            centre: V3::splat(Vec3::new(s[0], s[1], s[2])),
            reach,
            reach2: reach * reach,
            first: first as usize,
        }
    }
}

/// `a s + c`, fused (`Lane::mul_add`).
#[inline(always)]
fn madd<T: Lane>(a: V3<T>, s: T, c: V3<T>) -> V3<T> {
    V3::new(
        a.x.mul_add(s, c.x),
        a.y.mul_add(s, c.y),
        a.z.mul_add(s, c.z),
    )
}

/// `a . b + c` as `x x' + (y y' + (z z' + c))`, fused.
#[inline(always)]
fn dot_add<T: Lane>(a: V3<T>, b: V3<T>, c: T) -> T {
    a.x.mul_add(b.x, a.y.mul_add(b.y, a.z.mul_add(b.z, c)))
}

/// `a . b` as `x x' + (y y' + z z')`, fused.
#[inline(always)]
fn dot<T: Lane>(a: V3<T>, b: V3<T>) -> T {
    a.x.mul_add(b.x, a.y.mul_add(b.y, a.z * b.z))
}

/// `a x b`, each component `p q - (r s)` fused.
#[inline(always)]
fn cross<T: Lane>(a: V3<T>, b: V3<T>) -> V3<T> {
    V3::new(
        a.y.mul_add(b.z, -(a.z * b.y)),
        a.z.mul_add(b.x, -(a.x * b.z)),
        a.x.mul_add(b.y, -(a.y * b.x)),
    )
}

/// `m * v` as `x_axis v.x + y_axis v.y + z_axis v.z`.
#[inline(always)]
fn rotate<T: Lane>(m: &Mat3, v: V3<T>) -> V3<T> {
    V3::splat(m.x_axis) * v.x + V3::splat(m.y_axis) * v.y + V3::splat(m.z_axis) * v.z
}

/// `|d|` and `d / |d|`, lengths clamped to [`MIN_LENGTH`].
#[inline(always)]
fn length_dir<T: Lane>(d: V3<T>) -> (T, V3<T>) {
    let d2 = dot(d, d).max(T::splat(MIN_LENGTH * MIN_LENGTH));
    let r = d2.inv_sqrt();
    (d2 * r, d * r)
}

/// 0 where `free`, +inf elsewhere.
#[inline(always)]
fn offset_unless<T: Lane>(free: T::Mask) -> T {
    T::select(free, T::splat(0.0), T::splat(f32::INFINITY))
}

/// Advances one chain (or eight, in lanes) by one step; returns the lanes
/// that stayed finite and within [`BLOWN_UP`] (the caller restores the
/// others). On entry `pos[0]` is the root's target and `prev[0]` where it was.
#[inline(always)]
pub(crate) fn step_chain<T: Lane>(
    c: &mut Chain<'_, T>,
    s: &mut ChainScratch<T>,
    k: &Setup,
    spheres: &[Candidate],
    block: usize,
) -> T::Mask {
    let verts = c.pos.len();
    let segs = verts - 1;
    let zero = T::splat(0.0);
    let n = k.substeps;
    let d = T::splat(k.damping);
    let g = V3::<T>::splat(k.gravity_h2);
    let a1 = T::splat(k.direction[0]);
    let a0 = T::splat(k.direction[1]);
    let am = T::splat(k.direction[2]);
    let (pos, prev, w) = (&mut c.pos[..verts], &mut c.prev[..verts], &c.w[..verts]);
    let root_from = prev[0];
    let root_to = pos[0];
    // 2. (set-up) Previous positions one substep back: the step's velocity
    // (x - x_prev) / dt, over h.
    let inv_n = T::splat(1.0 / n as f32);
    pos[0] = root_from;
    for v in 1..verts {
        let x = pos[v];
        prev[v] = x - (x - prev[v]) * inv_n;
    }
    // 3. (set-up) The rest vectors in the groom frame's current orientation.
    if k.local_shape > 0.0 {
        for v in 0..segs {
            s.rvec[v] = rotate(&k.rotation, c.rest_vec[v]);
            s.rdir[v] = rotate(&k.rotation, c.rest_dir[v]);
        }
    }
    // 5., 6. (set-up) This block's candidate spheres, splatted, and the
    // pinned vertices and segments kept out of the collisions.
    s.reach.clear();
    s.reach.extend(
        spheres
            .iter()
            .filter(|sp| sp.touches(block))
            .map(|sp| Reach::new(sp.sphere, k.pearl_radius, sp.first[block])),
    );
    // In the order of the first vertex that may touch them (rig order among
    // equals: a stable insertion sort, the lists are short), so that the
    // spheres a vertex meets are a prefix.
    for i in 1..s.reach.len() {
        let mut j = i;
        while j > 0 && s.reach[j - 1].first > s.reach[j].first {
            s.reach.swap(j - 1, j);
            j -= 1;
        }
    }
    let (pearl_off, vertex_off) = (&mut s.pearl_off[..verts], &mut s.vertex_off[..verts]);
    for v in 0..verts {
        let free = w[v].gt(zero);
        vertex_off[v] = offset_unless::<T>(free);
        if v > 0 {
            pearl_off[v - 1] = offset_unless::<T>(free & w[v - 1].gt(zero));
        }
    }
    for sub in 0..n {
        // 2. Prediction: the root on its path, Verlet for the free vertices,
        // and the fixed part of the directions of segment v - 1 from the
        // positions before the prediction.
        let root = if sub + 1 == n {
            root_to
        } else {
            root_from + (root_to - root_from) * T::splat((sub + 1) as f32 / n as f32)
        };
        let qfix = &mut s.qfix[..verts];
        let mut x_last = pos[0];
        let mut p_last = prev[0];
        for v in 0..verts {
            let x = pos[v];
            let xp = prev[v];
            if v > 0 {
                qfix[v - 1] = madd(x - x_last, a0, (xp - p_last) * am);
            }
            let moved = madd(x - xp, d, x + g);
            let pinned = if v == 0 { root } else { x };
            pos[v] = V3::select(w[v].gt(zero), moved, pinned);
            prev[v] = x;
            x_last = x;
            p_last = xp;
        }
        let mut c = Chain {
            pos: &mut *pos,
            prev: &mut *prev,
            ..*c
        };
        // 3. Shape: local (TressFX 4), then global.
        if k.local_shape > 0.0 {
            local_shape(&mut c, s, k);
        }
        if k.shape > 0.0 {
            global_shape(&mut c, k);
        }
        // 4. Projections of the length constraints (and bending).
        for _ in 0..k.iterations {
            project(&mut c, s, a1);
            if k.bend > 0.0 {
                bend(&mut c, T::splat(k.bend));
            }
        }
        // 5. Pearls, 6. strain limit with push-out.
        pearls(&mut c, k, s);
        let rounds = if sub + 1 == n { 2 } else { 1 };
        strain_limit_and_collide(&mut c, k, s, rounds);
    }
    // 7. Velocity over the step, and the guard.
    let nn = T::splat(n as f32);
    let big = T::splat(BLOWN_UP);
    let mut ok = T::all_lanes();
    for v in 0..verts {
        let x = pos[v];
        let back = x - (x - prev[v]) * nn;
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
    for v in 0..segs {
        let (len_next, e_next, n_next) = if v + 1 < segs {
            dir(pos, v + 1)
        } else {
            (zero, V3::zero(), V3::zero())
        };
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
        sub_dot = dot(e_next, n);
        diag_dot = dot(e_next, n_next);
        (len, e, n) = (len_next, e_next, n_next);
    }
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

/// Step 3: TressFX 4's local shape constraint, root to tip. Segment s should
/// point along its rest vector carried by the minimal rotation that takes
/// the parent's rest direction `a` to the parent's current direction `b`
/// (Rodrigues: `r cos + (a x b) x r + (a x b) ((a x b).r) / (1 + cos)`); the
/// root segment along its rest vector in the groom frame. The child takes
/// the whole correction (the parent is final, as in Follow-The-Leader):
/// sharing it with the parent, as TressFX does, let gravity win on the
/// mohawk (65 % tip drift at stiffness 1).
#[inline(always)]
fn local_shape<T: Lane>(c: &mut Chain<'_, T>, s: &ChainScratch<T>, k: &Setup) {
    let verts = c.pos.len();
    let segs = verts - 1;
    let zero = T::splat(0.0);
    let one = T::splat(1.0);
    let eps = T::splat(1.0e-6);
    let stiff = T::splat(k.local_shape);
    let (pos, w) = (&mut c.pos[..verts], &c.w[..verts]);
    let (rvec, rdir) = (&s.rvec[..verts], &s.rdir[..verts]);
    for v in 0..segs {
        let rest = rvec[v];
        let target = if v == 0 {
            rest
        } else {
            let a = rdir[v - 1];
            let (_, b) = length_dir(pos[v] - pos[v - 1]);
            let cos = dot(a, b);
            let axis = cross(a, b);
            let denom = one + cos;
            let ok = denom.gt(eps);
            let turned = madd(
                axis,
                dot(axis, rest) * denom.max(eps).recip(),
                madd(rest, cos, cross(axis, rest)),
            );
            V3::select(ok, turned, rest)
        };
        let err = pos[v] + target - pos[v + 1];
        // A pinned child moves by err * 0 (a select of the positions would
        // compile to masked stores, slow on AMD).
        let pull = T::select(w[v + 1].gt(zero), stiff, zero);
        pos[v + 1] = madd(err, pull, pos[v + 1]);
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

/// Step 5: every pearl `p = (1-t) x_i + t x_{i+1}` against every candidate
/// sphere, `s = (R + r - |p - c|) / (w_i (1-t)^2 + w_{i+1} t^2)`,
/// `x_i += w_i (1-t) s n`, `x_{i+1} += w_{i+1} t s n`. Segments with a pinned
/// end carry none (the root sits inside the collision skin).
#[inline(always)]
fn pearls<T: Lane>(c: &mut Chain<'_, T>, k: &Setup, s: &ChainScratch<T>) {
    let verts = c.pos.len();
    let (pos, w, off) = (&mut c.pos[..verts], &c.w[..verts], &s.pearl_off[..verts]);
    for r in &s.reach {
        for j in 1..=k.pearls {
            let tt = j as f32 / (k.pearls + 1) as f32;
            let t = T::splat(tt);
            let u = T::splat(1.0 - tt);
            for v in r.first.saturating_sub(1)..verts - 1 {
                let p = madd(pos[v], u, pos[v + 1] * t);
                let d = p - r.centre;
                let d2 = dot_add(d, d, off[v]);
                let hit = d2.lt(r.reach2);
                if T::any(hit) {
                    let (dist, nrm) = outward(d, d2);
                    let denom = w[v].mul_add(u * u, w[v + 1] * (t * t));
                    let push = (r.reach - dist) * denom.max(T::splat(1.0e-12)).recip();
                    pos[v] = V3::select(hit, madd(nrm, w[v] * u * push, pos[v]), pos[v]);
                    pos[v + 1] =
                        V3::select(hit, madd(nrm, w[v + 1] * t * push, pos[v + 1]), pos[v + 1]);
                }
            }
        }
    }
}

/// Step 6: the two-sided strain limit, root to tip, alternating `rounds`
/// times per vertex with the push-out (and contact friction). The parent is
/// final and outside the rig, so the two sets meet and alternating closes
/// in on a point of both: the limit does not pull hair into the head and
/// the push-out does not stretch it.
#[inline(always)]
fn strain_limit_and_collide<T: Lane>(
    c: &mut Chain<'_, T>,
    k: &Setup,
    s: &ChainScratch<T>,
    rounds: usize,
) {
    let verts = c.pos.len();
    let zero = T::splat(0.0);
    let factor = T::splat(k.stretch_factor);
    let shrink = T::splat(k.shrink_factor);
    let mu = T::splat(k.friction);
    let (pos, prev) = (&mut c.pos[..verts], &mut c.prev[..verts]);
    let (w, rest_len, off) = (&c.w[..verts], &c.rest_len[..verts], &s.vertex_off[..verts]);
    let mut live = 0;
    for v in 1..verts {
        while live < s.reach.len() && s.reach[live].first <= v {
            live += 1;
        }
        let limit = rest_len[v - 1] * factor;
        let floor = rest_len[v - 1] * shrink;
        let free = w[v].gt(zero);
        let mut x = pos[v];
        for _ in 0..rounds {
            let d = x - pos[v - 1];
            let d2 = dot(d, d);
            let long = d2.gt(limit * limit);
            let short = d2.lt(floor * floor);
            let fix = (long | short) & free;
            if T::any(fix) {
                let target = T::select(long, limit, floor);
                let inv = d2.max(T::splat(MIN_LENGTH * MIN_LENGTH)).inv_sqrt();
                x = V3::select(fix, madd(d, target * inv, pos[v - 1]), x);
            }
            for r in &s.reach[..live] {
                let d = x - r.centre;
                let d2 = dot_add(d, d, off[v]);
                let hit = d2.lt(r.reach2);
                if T::any(hit) {
                    let (dist, nrm) = outward(d, d2);
                    x = V3::select(hit, madd(nrm, r.reach - dist, x), x);
                    if k.friction > 0.0 {
                        let vel = x - prev[v];
                        let tang = madd(nrm, -dot(vel, nrm), vel);
                        prev[v] = V3::select(hit, madd(tang, mu, prev[v]), prev[v]);
                    }
                }
            }
        }
        pos[v] = x;
    }
}

/// Distance and outward unit normal; 0 and +y where the point sits on the
/// centre.
#[inline(always)]
fn outward<T: Lane>(d: V3<T>, d2: T) -> (T, V3<T>) {
    let tiny = T::splat(1.0e-30);
    let d2c = d2.max(tiny);
    let r = d2c.inv_sqrt();
    let on = d2.gt(tiny);
    let nrm = V3::select(on, d * r, V3::splat(Vec3::Y));
    (T::select(on, d2c * r, T::splat(0.0)), nrm)
}

/// Advances every strand by one fixed step of `params.dt` (SIMD path), on
/// the calling thread: [`step_with`] on [`Serial`]. A library call never
/// starts threads of its own; pass an executor to [`step_with`] to use
/// more (the result is the same bytes).
///
/// Never panics; `params` should pass [`SimParams::validate`], and strands
/// that bad values drive non-finite are restored and counted
/// ([`Strands::restored_strands`]). Allocates only when the rig has more
/// spheres than any earlier step.
pub fn step(strands: &mut Strands, params: &SimParams, spheres: &[Sphere]) {
    step_with(strands, params, spheres, &Serial);
}

/// [`step`] with its blocks handed out as tasks to `executor`: at most
/// [`MAX_STEP_TASKS`] tasks of whole groups of blocks, split by the block
/// count alone. Blocks never exchange data within a step, each task has its
/// own buffers (sized when the set is built) and the restored count is
/// summed after the tasks, so the result is the same bytes with any
/// executor and any number of threads. Allocates nothing more than [`step`].
pub fn step_with(
    strands: &mut Strands,
    params: &SimParams,
    spheres: &[Sphere],
    executor: &dyn Executor,
) {
    drive(
        strands,
        params,
        spheres,
        executor,
        |s, st, b, k| block_sweep_aabb(st.pos, st.prev, k.gravity_dt2, s.active[b]),
        |strands, st, scratch, k, b, g| {
            let r = b * strands.verts..(b + 1) * strands.verts;
            // 2.-7.
            let mut c = Chain {
                pos: st.pos,
                prev: st.prev,
                w: &strands.inv_mass[r.clone()],
                rest_len: &strands.rest_len[r.clone()],
                rest_vec: &strands.rest_vec[r.clone()],
                rest_dir: &strands.rest_dir[r.clone()],
                rest_offset: &strands.rest_offset[r.clone()],
                bend_len: &strands.bend_len[r.clone()],
                bend_share: &strands.bend_share[r.clone()],
                shape_weight: &strands.shape_weight[r],
            };
            let ok: f32x8 = step_chain(&mut c, &mut scratch.chain, k, &scratch.candidates, g);
            (!ok).to_bitmask()
        },
    );
}

/// What a step writes in one block: its `V` positions and previous
/// positions. The rest of the set is shared read-only by every task.
pub(crate) struct BlockState<'a> {
    pub pos: &'a mut [Vec3x8],
    pub prev: &'a mut [Vec3x8],
}

/// One task's share of a step: the positions of its blocks and its buffers.
struct TaskParts<'a> {
    pos: &'a mut [Vec3x8],
    prev: &'a mut [Vec3x8],
    sleep: &'a mut [BlockSleep],
    scratch: &'a mut Scratch,
}

/// The most tasks one step makes, whatever the set's size (an engine's
/// fixed-size job pool never runs dry; 64 keeps 16 cores busy with four
/// tasks each).
pub const MAX_STEP_TASKS: usize = 64;

/// The fewest blocks a task takes (128 strands): about 0.1 ms of work at
/// 32 vertices (about 30 ns per vertex-step), so a job system's cost per
/// job (about a microsecond) stays near 1 %; a 2,048-guide head makes 16
/// tasks.
const MIN_TASK_BLOCKS: usize = 16;

/// Blocks per task for a set of `blocks`: at least [`MIN_TASK_BLOCKS`],
/// at most [`MAX_STEP_TASKS`] tasks, a whole number of [`GROUP`]s (so the
/// broad phase's groups, and with them every result, do not depend on the
/// split).
pub(crate) fn task_blocks(blocks: usize) -> usize {
    let per = blocks.div_ceil(MAX_STEP_TASKS).max(MIN_TASK_BLOCKS);
    per.div_ceil(GROUP) * GROUP
}

/// Tasks per step for a set of `blocks`.
pub(crate) fn task_count(blocks: usize) -> usize {
    blocks.div_ceil(task_blocks(blocks))
}

/// The step's driver, shared by the SIMD path and its scalar twin: the rig
/// to local coordinates and the spheres that moved since the last step,
/// then per task (a run of whole groups, see [`task_blocks`]) and per group
/// of [`GROUP`] blocks: 0. the sleep decision of each block (awake, or
/// asleep and woken by its roots or a moving sphere, or asleep and
/// skipped), 1. the broad phase (`block_box` gives block `b`'s swept box; a
/// sleeping block's is the one kept when it fell asleep) and steps 2.-7. of
/// each block of the group that runs (`block(strands, state, scratch,
/// setup, b, g)`, which returns the lanes that went bad); those lanes are
/// restored; 8. the block's stillness.
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
    spheres: &[Sphere],
    executor: &dyn Executor,
    block_box: impl Fn(&Strands, &BlockState<'_>, usize, &Setup) -> Aabb + Sync,
    block: impl Fn(&Strands, &mut BlockState<'_>, &mut Scratch, &Setup, usize, usize) -> u32 + Sync,
) {
    let k = Setup::new(strands, params);
    if strands.params_seen.as_ref() != Some(params) {
        // Other parameters: what was still may not be any more.
        strands.wake();
        strands.params_seen = Some(params.clone());
    }
    let mut scratch = std::mem::take(&mut strands.scratch);
    spheres_to_local(spheres, strands.origin, &mut scratch.spheres_local);
    // Sized for the whole rig once, so that no later step allocates
    // (allocates only when the rig grows).
    for t in &mut scratch.tasks {
        t.candidates.clear();
        t.reserve_spheres(spheres.len());
    }
    scratch.movers.clear();
    scratch.movers.reserve(spheres.len());
    moving_spheres(
        spheres,
        &scratch.rig_prev,
        strands.origin,
        &mut scratch.movers,
    );
    let mut pos = std::mem::take(&mut strands.pos);
    let mut prev = std::mem::take(&mut strands.prev);
    let mut sleep = std::mem::take(&mut strands.sleep);
    {
        let s: &Strands = strands;
        let verts = s.verts;
        let per_task = task_blocks(s.blocks);
        let span = per_task * verts;
        let mut parts: [Option<TaskParts<'_>>; MAX_STEP_TASKS] = std::array::from_fn(|_| None);
        let chunks = pos
            .chunks_mut(span)
            .zip(prev.chunks_mut(span))
            .zip(sleep.chunks_mut(per_task));
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
        let spheres_local = &scratch.spheres_local;
        let movers = &scratch.movers;
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
                // 0. Sleep: a sleeping block runs only if its roots moved or a
                // moving sphere's sweep reaches its box.
                let mut boxes = [EMPTY_BOX; GROUP];
                let mut bounds = [BlockBounds {
                    swept: EMPTY_BOX,
                    roots: EMPTY_BOX,
                    arc: &[],
                    stretch_factor: k.stretch_factor,
                }; GROUP];
                let mut runs = [true; GROUP];
                for g in 0..n {
                    let (b, r) = (t * per_task + first + g, (first + g) * verts);
                    let st = BlockState {
                        pos: &mut pos[r..r + verts],
                        prev: &mut prev[r..r + verts],
                    };
                    let sl = sleep[first + g];
                    if k.sleep && sl.asleep && !roots_moved(&st, s.active[b]) {
                        boxes[g] = sl.bounds;
                        runs[g] = movers.iter().any(|m| boxes_near(m, &sl.bounds, k.margin));
                    } else {
                        // 1. (box) The block's swept box.
                        boxes[g] = block_box(s, &st, b, &k);
                    }
                    // 1. (reach) And the reach the strain limit leaves it.
                    bounds[g] = BlockBounds {
                        swept: boxes[g],
                        roots: roots_aabb(st.prev[0], st.pos[0], s.active[b]),
                        arc: &s.reach_arc[b * verts..(b + 1) * verts],
                        stretch_factor: k.stretch_factor,
                    };
                }
                // 1. Broad phase: the group's swept block boxes against the rig.
                if runs[..n].iter().any(|&r| r) {
                    select_strand_candidates(
                        &bounds[..n],
                        k.margin,
                        spheres_local,
                        &mut scratch.candidates,
                    );
                }
                for (g, &run) in runs.iter().enumerate().take(n) {
                    let (b, r) = (t * per_task + first + g, (first + g) * verts);
                    if !run {
                        sleep[first + g].stepped = false;
                        continue;
                    }
                    let mut st = BlockState {
                        pos: &mut pos[r..r + verts],
                        prev: &mut prev[r..r + verts],
                    };
                    let moved = roots_moved(&st, s.active[b]);
                    if k.sleep {
                        scratch.start.copy_from_slice(st.pos);
                    }
                    let bad = block(s, &mut st, scratch, &k, b, g);
                    scratch.restored += restore_lanes(s, &mut st, b, bad);
                    // 8. Stillness: a block still for `still_steps` steps in a
                    // row (roots included) falls asleep at rest.
                    let still = k.sleep
                        && !moved
                        && block_is_still(st.pos, &scratch.start, s.active[b], k.still_move2);
                    let sl = &mut sleep[first + g];
                    sl.stepped = true;
                    sl.still = if still { sl.still.saturating_add(1) } else { 0 };
                    sl.asleep = false;
                    if sl.still >= k.still_steps {
                        fall_asleep(&mut st);
                        sl.asleep = true;
                        sl.bounds = block_box(s, &st, b, &k);
                    }
                }
                first += n;
            }
        });
    }
    strands.pos = pos;
    strands.prev = prev;
    strands.sleep = sleep;
    strands.restored += scratch.tasks.iter().map(|t| t.restored).sum::<u64>();
    strands.awake = (0..strands.blocks)
        .filter(|&b| strands.sleep[b].stepped)
        .map(|b| strands.lanes_in_block(b))
        .sum();
    scratch.rig_prev.clear();
    scratch.rig_prev.extend(
        spheres
            .iter()
            .map(|s| [s.center.x, s.center.y, s.center.z, s.radius]),
    );
    strands.scratch = scratch;
}

/// True if a root of block `b` (an active lane) was moved since the last
/// step: `set_roots` changed its target (`pos[0]`) away from where the step
/// left it (`prev[0]`). Any change counts, however small: a sleeping strand
/// stays attached to its root.
fn roots_moved(st: &BlockState<'_>, active: f32x8) -> bool {
    let d = st.pos[0] - st.prev[0];
    let moved = d.x.simd_ne(f32x8::ZERO) | d.y.simd_ne(f32x8::ZERO) | d.z.simd_ne(f32x8::ZERO);
    (moved & active).any()
}

/// True if every vertex of the active lanes of a block moved at most
/// `sqrt(still_move2)` over the step (`|x_end - x_start|^2 <= still_move2`;
/// the displacement, not the last substep's velocity, which a vertex
/// resting on a sphere keeps at a few cm/s while it does not move); a NaN
/// is never still. The same code for both paths (like the guard's restore),
/// so their sleep decisions agree by construction.
fn block_is_still(pos: &[Vec3x8], start: &[Vec3x8], active: f32x8, still_move2: f32) -> bool {
    let limit = f32x8::splat(still_move2);
    let mut still = active | !active;
    for (x, p) in pos.iter().zip(start) {
        let d = *x - *p;
        still &= d.dot(d).simd_le(limit) | !active;
    }
    still.all()
}

/// A block falls asleep at rest: previous positions = current ones.
fn fall_asleep(st: &mut BlockState<'_>) {
    st.prev.copy_from_slice(st.pos);
}

/// The local boxes swept since the last step by the spheres that moved
/// (centre or radius changed; every sphere when the rig's length changed),
/// each the box of the sphere where it was and where it is.
fn moving_spheres(spheres: &[Sphere], prev: &[[f32; 4]], origin: DVec3, out: &mut Vec<Aabb>) {
    out.clear();
    let same_rig = prev.len() == spheres.len();
    for (i, s) in spheres.iter().enumerate() {
        let now = [s.center.x, s.center.y, s.center.z, s.radius];
        let was = if same_rig { prev[i] } else { now };
        if same_rig && now == was {
            continue;
        }
        let local =
            |c: [f32; 4]| (DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) - origin).as_vec3();
        let r = now[3].max(was[3]);
        let (a, c) = (local(now), local(was));
        out.push(Aabb {
            min: a.min(c) - Vec3::splat(r),
            max: a.max(c) + Vec3::splat(r),
        });
    }
}

/// True if the boxes are at most `margin` apart; false for a non-finite box.
fn boxes_near(a: &Aabb, b: &Aabb, margin: f32) -> bool {
    let gap = (a.min - b.max).max(b.min - a.max).max(Vec3::ZERO);
    a.min.is_finite() && a.max.is_finite() && gap.length_squared() <= margin * margin
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

    /// Runs the tasks last first.
    struct Reverse;
    // SAFETY: every index once, before `run` returns.
    unsafe impl Executor for Reverse {
        fn threads(&self) -> usize {
            2
        }
        fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
            (0..count).rev().for_each(task);
        }
    }

    #[test]
    fn tasks_are_whole_groups_and_at_most_max_step_tasks() {
        for blocks in [0, 1, 5, 16, 17, 100, 1024, 1250, 5000, 100_000] {
            let per = task_blocks(blocks);
            assert_eq!(per % GROUP, 0, "{blocks}: whole groups");
            assert!(per >= MIN_TASK_BLOCKS);
            assert!(task_count(blocks) <= MAX_STEP_TASKS, "{blocks}");
            assert!(task_count(blocks) * per >= blocks, "{blocks}: covered");
        }
    }

    #[test]
    fn a_lane_restored_inside_a_later_task_is_counted_once() {
        // 200 strands: 25 blocks, two tasks; strand 163 is block 20, lane 3.
        let (rig, params) = (head(), SimParams::default());
        let mut runs = vec![];
        for exec in [&Serial as &dyn Executor, &Reverse] {
            let mut s = strands(200);
            assert_eq!(s.scratch.tasks.len(), 2);
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
