//! The narrow phase in lanes: pearls and vertex push-out against spheres,
//! capsules and mesh fields, Coulomb friction, and the roots rule. Written
//! over [`Lane`]: the SIMD step runs it at `F32Lanes`, the scalar twin at
//! `f32`, one lane at a time, in the same order.
//!
//! **Contact** (every substep): a point `x` within `R + r` of a sphere or
//! capsule (`r` the pearl radius), or with field distance below `r`, is
//! pushed along the outward normal to the skin. For a capsule the distance
//! is to the closest point of its axis, `a + t (b - a)`,
//! `t = clamp(((x - a) . (b - a)) / |b - a|^2, 0, 1)` (Ericson 2005,
//! 5.1.2); for a field it is the trilinear distance and its gradient
//! (`sdf/`).
//!
//! **Coulomb friction, position-based** (Macklin, Muller, Chentanez, Kim
//! 2014, "Unified particle physics for real-time applications", 6.1): after
//! the push by depth `d` along `n`, the vertex's tangential motion over the
//! substep relative to the collider's surface,
//! `dx_t = (x - x_prev) - (c - c_prev)` less its `n` component, is removed
//! whole while `|dx_t| <= mu_s d` (static: the vertex sticks), and by
//! `dx_t min(mu_k d / |dx_t|, 1)` otherwise (kinetic). On a plane tilted by
//! `theta` gravity gives `d = g cos(theta) h^2` and `|dx_t| = g sin(theta)
//! h^2` per substep, so hair holds exactly when `mu_s > tan(theta)`.
//!
//! **Roots on or in a collider**: a strand whose root sits inside a
//! collider's skin (a scalp that is part of the body mesh, a head sphere
//! that cuts the roots) is allowed, at vertex `v` of rest arc `arc(v)`, the
//! depth `max(0, depth_root - root_exit arc(v))`
//! ([`crate::SimParams::root_exit`]): the depth a strand leaving the
//! surface at `asin(root_exit)` would have.
//!
//! **Deep in a field** (after a teleport or a fast bone): a vertex is
//! pushed out whole by what its motion relative to the surface over the
//! substep can have put it in, and beyond that by at most
//! `FIELD_EXIT_SPEED h` per substep; a vertex pushed that far gains no
//! velocity from it (its previous position moves with it);
//! a strand with a vertex that deep keeps at most `FIELD_EXIT_SPEED` as its
//! velocity at the end of the step (`step.rs`, 7.), so hair found deep
//! inside is never shot out, though the strain limit may pull a strand out
//! after its parent vertices within the step.

use super::rig::{LocalCapsule, LocalField};
use super::sdf::{Sdf, SdfLane};
use crate::fused::{dot, dot_add, madd};
use crate::lanes::{Lane, V3};
use glam::{Mat3, Vec3};

/// The fastest a vertex found deep inside a mesh field is moved out, m/s:
/// at most `FIELD_EXIT_SPEED h` per substep of `h`, with no velocity left
/// from it (crate README, "Deep inside a field").
pub const FIELD_EXIT_SPEED: f32 = 1.0;

/// Relative and absolute (metres) growth of a capsule's bounding ball
/// ([`ShapeReach::may_touch`]) over float rounding: a point the exact test
/// would push is never skipped.
const BOUND_SLACK: f32 = 1.0e-5;

/// Per-step constants of the contacts.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ContactSetup {
    pub pearl_radius: f32,
    /// Kinetic and static Coulomb coefficients.
    pub friction: f32,
    pub static_friction: f32,
    /// Either coefficient is above zero.
    pub friction_on: bool,
    /// Largest push out of a field per substep.
    pub field_push: f32,
    /// The steady acceleration over one substep, `(gravity + drag wind)
    /// h^2` (friction's least normal push).
    pub accel_h2: Vec3,
    /// How far outside the skin a vertex still counts as touching it for
    /// friction: `|accel_h2|`, what it settles per substep under the
    /// steady load.
    pub slop: f32,
    /// The roots rule's slope ([`crate::SimParams::root_exit`]).
    pub root_exit: f32,
}

/// Distance and outward unit normal; 0 and +y where the point sits on the
/// centre.
#[inline(always)]
pub(crate) fn outward<T: Lane>(d: V3<T>, d2: T) -> (T, V3<T>) {
    let tiny = T::splat(1.0e-30);
    let d2c = d2.max(tiny);
    let r = d2c.inv_sqrt();
    let on = d2.gt(tiny);
    let nrm = V3::select(on, d * r, V3::splat(Vec3::Y));
    (T::select(on, d2c * r, T::splat(0.0)), nrm)
}

/// The skin's reach at rest arc `arc` under the roots rule of slope
/// `exit`.
#[inline(always)]
fn reach_at<T: Lane>(reach: T, root_depth: T, arc: T, exit: f32) -> T {
    let allowed = arc.mul_add(T::splat(-exit), root_depth).max(T::splat(0.0));
    reach - allowed
}

/// Coulomb friction on a pushed point: the correction that removes its
/// tangential motion `dx` over the substep relative to the collider's
/// surface (`dx` = its motion less the surface's; `n` the contact normal,
/// `depth` the normal push): all of it while `|dx_t| <= mu_s depth`, else
/// `dx_t min(mu_k depth / |dx_t|, 1)`.
///
/// The normal push counted is at least the steady acceleration's push into
/// the surface over the substep, `max(0, -a . n) h^2` (`a = gravity + drag
/// wind`): a vertex resting on a surface is pressed by its weight however
/// the push is shared between it and the pearls beside it (which carry
/// none of the friction), so on a slope it holds exactly when
/// `mu_s > tan(theta)`.
#[inline(always)]
fn coulomb<T: Lane>(dx: V3<T>, n: V3<T>, depth: T, k: &ContactSetup) -> V3<T> {
    let a = V3::<T>::splat(k.accel_h2);
    let depth = depth.max(-dot(a, n));
    let tang = madd(n, -dot(dx, n), dx);
    let t2 = dot(tang, tang);
    let hold = T::splat(k.static_friction) * depth;
    let sticks = t2.lt(hold * hold) | t2.lt(T::splat(1.0e-30));
    if !T::any(!sticks) {
        // Every lane sticks (hair at rest): no kinetic share to compute.
        return -tang;
    }
    let inv = t2.max(T::splat(1.0e-30)).inv_sqrt();
    let slide = (T::splat(k.friction) * depth * inv).min(T::splat(1.0));
    let share = T::select(sticks, T::splat(1.0), slide);
    tang * -share
}

/// A sphere (`CAPSULE = false`) or capsule in lanes over one step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShapeReach<T: Lane> {
    from: [Vec3; 2],
    to: [Vec3; 2],
    /// The ends now (this substep), the axis and `1 / |axis|^2` (0 for a
    /// point).
    a: V3<T>,
    ab: V3<T>,
    inv_ab2: T,
    /// Capsules: the axis' midpoint now and the squares of the radii round
    /// it beyond which no point can reach the skin or touch it
    /// (`reach + |axis| / 2`, `touch + |axis| / 2`, grown by
    /// [`BOUND_SLACK`]): a test of eight lanes against this ball skips the
    /// closest point of the axis where none can.
    mid: V3<T>,
    bound2: T,
    touch_bound2: T,
    /// The ends' motion over one substep.
    a_sub: V3<T>,
    b_sub: V3<T>,
    /// It did not move over the step (`from == to`): placed once.
    still: bool,
    reach: T,
    reach2: T,
    /// `(reach + slop)^2`: touching, for friction.
    touch2: T,
    /// `reach` and `reach + slop` as numbers (for the bounds).
    reach_len: f32,
    touch_len: f32,
    /// The first vertex of the block that may touch it (broad phase).
    pub first: usize,
    /// The roots rule applies to vertices `..rooted_until` (a root of the
    /// block lies in the skin, and some lane's vertex is still allowed
    /// depth there); 0 when no root is in the skin.
    rooted_until: usize,
    root_depth: T,
    /// The roots rule's slope.
    exit: f32,
}

/// The vertices `..n` whose allowed depth `root_depth - exit arc(v)` is
/// above zero in some lane (`arc` grows along the strand).
fn rooted_until<T: Lane>(root_depth: T, arc: &[T], exit: f32) -> usize {
    arc.iter()
        .position(|&a| !T::any((a * T::splat(exit)).lt(root_depth)))
        .unwrap_or(arc.len())
}

impl<T: Lane> ShapeReach<T> {
    /// From the step's local shape, for a block whose roots' targets are
    /// `root` and whose vertices' rest arcs are `arc`.
    #[inline(always)]
    pub(crate) fn new(
        s: &LocalCapsule,
        first: u32,
        substeps: u32,
        root: V3<T>,
        arc: &[T],
        k: &ContactSetup,
    ) -> Self {
        let exit = k.root_exit;
        let reach = T::splat(s.radius + k.pearl_radius);
        let touch = s.radius + k.pearl_radius + k.slop;
        let inv_n = 1.0 / substeps as f32;
        let mut r = ShapeReach {
            from: s.from,
            to: s.to,
            a: V3::splat(s.to[0]),
            ab: V3::zero(),
            inv_ab2: T::splat(0.0),
            mid: V3::splat(s.to[0]),
            bound2: T::splat(0.0),
            touch_bound2: T::splat(0.0),
            a_sub: V3::splat((s.to[0] - s.from[0]) * inv_n),
            b_sub: V3::splat((s.to[1] - s.from[1]) * inv_n),
            still: s.still(),
            reach,
            reach2: reach * reach,
            touch2: T::splat(touch * touch),
            reach_len: s.radius + k.pearl_radius,
            touch_len: touch,
            first: first as usize,
            rooted_until: 0,
            root_depth: T::splat(0.0),
            exit,
        };
        r.place(s.to);
        // The roots rule: how deep the roots' targets lie in the skin.
        let (d, _) = r.offset::<true>(root);
        let dist2 = dot(d, d);
        let depth = reach - dist2.max(T::splat(1.0e-30)).inv_sqrt() * dist2;
        let inside = depth.gt(T::splat(0.0));
        r.root_depth = T::select(inside, depth, T::splat(0.0));
        if T::any(inside) {
            r.rooted_until = rooted_until(r.root_depth, arc, exit);
        }
        r
    }

    /// Places the ends (the axis and its inverse squared length).
    #[inline(always)]
    fn place(&mut self, ends: [Vec3; 2]) {
        let ab = ends[1] - ends[0];
        let ab2 = ab.x * ab.x + ab.y * ab.y + ab.z * ab.z;
        self.a = V3::splat(ends[0]);
        self.ab = V3::splat(ab);
        self.inv_ab2 = T::splat(if ab2 > 1.0e-20 {
            crate::lanes::recip(ab2)
        } else {
            0.0
        });
        let half = 0.5 * ab2.sqrt();
        let bound = |r: f32| {
            let b = (r + half) * (1.0 + BOUND_SLACK) + BOUND_SLACK;
            T::splat(b * b)
        };
        self.mid = V3::splat(ends[0] + ab * 0.5);
        self.bound2 = bound(self.reach_len);
        self.touch_bound2 = bound(self.touch_len);
    }

    /// Capsules: whether some lane of `x` (`off` +inf where pinned) lies
    /// within `bound2` of the axis' midpoint, without which it can neither
    /// reach nor touch the skin (`|x - m| <= |x - p| + |p - m|` for the
    /// closest point `p` of the axis, and `|p - m| <= |axis| / 2`). Always
    /// true for spheres, whose exact test is as cheap.
    #[inline(always)]
    fn may_touch<const CAPSULE: bool>(&self, x: V3<T>, off: T, bound2: T) -> bool {
        if !CAPSULE {
            return true;
        }
        let m = x - self.mid;
        T::any(dot_add(m, m, off).lt(bound2))
    }

    /// Moves it to where it is after substep `sub` of `n` (the end of the
    /// step on the last).
    #[inline(always)]
    pub(crate) fn advance(&mut self, sub: u32, n: u32) {
        // A still shape stays where `new` placed it.
        if self.still {
            return;
        }
        let ends = if sub + 1 >= n {
            self.to
        } else {
            let f = (sub + 1) as f32 / n as f32;
            [
                (self.to[0] - self.from[0]).mul_add(Vec3::splat(f), self.from[0]),
                (self.to[1] - self.from[1]).mul_add(Vec3::splat(f), self.from[1]),
            ]
        };
        self.place(ends);
    }

    /// `x` less the closest point of the axis, and the axis parameter `t`
    /// (a sphere, `CAPSULE = false`: `x - a` and 0, which is what a
    /// capsule with `a == b` computes too, in fewer operations).
    #[inline(always)]
    fn offset<const CAPSULE: bool>(&self, x: V3<T>) -> (V3<T>, T) {
        let ax = x - self.a;
        if !CAPSULE {
            return (ax, T::splat(0.0));
        }
        let t = (dot(ax, self.ab) * self.inv_ab2)
            .max(T::splat(0.0))
            .min(T::splat(1.0));
        (ax - self.ab * t, t)
    }

    /// The vertices `..rooted_until()` fall under the roots rule.
    pub(crate) fn rooted_until(&self) -> usize {
        self.rooted_until
    }

    /// The surface's motion over the substep at axis parameter `t`.
    #[inline(always)]
    fn motion<const CAPSULE: bool>(&self, t: T) -> V3<T> {
        if CAPSULE {
            madd(self.b_sub - self.a_sub, t, self.a_sub)
        } else {
            self.a_sub
        }
    }

    /// The skin's reach and its square at vertex (or segment) `v` of rest
    /// arc `arc`.
    #[inline(always)]
    fn reach(&self, v: usize, arc: T) -> (T, T) {
        if v < self.rooted_until {
            let r = reach_at(self.reach, self.root_depth, arc, self.exit);
            (r, r * r)
        } else {
            (self.reach, self.reach2)
        }
    }

    /// Pushes `x` (a free vertex unless `off` is +inf; `xp` where it was a
    /// substep ago, `arc` its rest arc) out of the skin, with friction if
    /// `FRICTION` (once per substep: the second round of the last substep
    /// only pushes, or friction would act five times per four substeps).
    #[inline(always)]
    pub(crate) fn push_vertex<const CAPSULE: bool, const FRICTION: bool, const ROOTED: bool>(
        &self,
        v: usize,
        x: V3<T>,
        xp: V3<T>,
        off: T,
        arc: T,
        k: &ContactSetup,
    ) -> V3<T> {
        // The roots rule only shortens the reach: the bounds hold.
        let bound2 = if FRICTION {
            self.touch_bound2
        } else {
            self.bound2
        };
        if !self.may_touch::<CAPSULE>(x, off, bound2) {
            return x;
        }
        let (d, t) = self.offset::<CAPSULE>(x);
        let d2 = dot_add(d, d, off);
        // `ROOTED`: `v` may be below `rooted_until` (the caller's loop
        // splits the vertices so that the rest skip the test).
        let (reach, reach2) = if ROOTED {
            self.reach(v, arc)
        } else {
            (self.reach, self.reach2)
        };
        if !FRICTION {
            let hit = d2.lt(reach2);
            if !T::any(hit) {
                return x;
            }
            let (dist, nrm) = outward(d, d2);
            return V3::select(hit, madd(nrm, reach - dist, x), x);
        }
        // With friction, a vertex touching the skin (within the slop: the
        // pearls beside it may have pushed it out already) is in contact.
        let contact = if ROOTED {
            let touch = reach + T::splat(k.slop);
            d2.lt(touch * touch)
        } else {
            d2.lt(self.touch2)
        };
        if !T::any(contact) {
            return x;
        }
        let (dist, nrm) = outward(d, d2);
        let depth = (reach - dist).max(T::splat(0.0));
        let pushed = madd(nrm, depth, x);
        let held = pushed + coulomb((pushed - xp) - self.motion::<CAPSULE>(t), nrm, depth, k);
        V3::select(contact, held, x)
    }

    /// Every pearl of segments `first - 1 ..` against it:
    /// `p = (1-t) x_i + t x_{i+1}`,
    /// `s = (R + r - |p - c|) / (w_i (1-t)^2 + w_{i+1} t^2)`,
    /// `x_i += w_i (1-t) s n`, `x_{i+1} += w_{i+1} t s n` (the Nalu demo's
    /// point-on-segment rule, Nguyen and Donnelly 2005). `off[v]` is +inf
    /// for segments with a pinned end. No friction here: a pearl's
    /// correction shared by the two ends of every segment over-corrects
    /// the vertices between (measured: a strand resting on a slope crept
    /// uphill); the vertices carry it (`push_vertex`).
    #[inline(always)]
    pub(crate) fn push_pearls<const CAPSULE: bool>(
        &self,
        pos: &mut [V3<T>],
        w: &[T],
        arc: &[T],
        off: &[T],
        pearls: u32,
    ) {
        let verts = pos.len();
        // One length for every slice, so the loops carry no bounds checks.
        let (w, arc, off) = (&w[..verts], &arc[..verts], &off[..verts]);
        for j in 1..=pearls {
            let tt = j as f32 / (pearls + 1) as f32;
            let t = T::splat(tt);
            let u = T::splat(1.0 - tt);
            let start = self.first.saturating_sub(1);
            // The roots rule's segments first, then the rest at one reach.
            let rooted = self.rooted_until.clamp(start, verts - 1);
            // (Tested first: most shapes hold no root, and the loop's
            // set-up is then not made.)
            if rooted > start {
                for v in start..rooted {
                    let reach = self.reach(v, arc[v].mul_add(u, arc[v + 1] * t));
                    self.push_pearl::<CAPSULE>(pos, w, off, v, t, u, reach);
                }
            }
            for v in rooted..verts - 1 {
                self.push_pearl::<CAPSULE>(pos, w, off, v, t, u, (self.reach, self.reach2));
            }
        }
    }

    /// One pearl at `t` (`u = 1 - t`) of segment `v`, against the skin's
    /// reach and its square.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn push_pearl<const CAPSULE: bool>(
        &self,
        pos: &mut [V3<T>],
        w: &[T],
        off: &[T],
        v: usize,
        t: T,
        u: T,
        (reach, reach2): (T, T),
    ) {
        let p = madd(pos[v], u, pos[v + 1] * t);
        if !self.may_touch::<CAPSULE>(p, off[v], self.bound2) {
            return;
        }
        let (d, _) = self.offset::<CAPSULE>(p);
        let d2 = dot_add(d, d, off[v]);
        let hit = d2.lt(reach2);
        if T::any(hit) {
            let (dist, nrm) = outward(d, d2);
            let denom = w[v].mul_add(u * u, w[v + 1] * (t * t));
            let push = (reach - dist) * denom.max(T::splat(1.0e-12)).recip();
            pos[v] = V3::select(hit, madd(nrm, w[v] * u * push, pos[v]), pos[v]);
            pos[v + 1] = V3::select(hit, madd(nrm, w[v + 1] * t * push, pos[v + 1]), pos[v + 1]);
        }
    }
}

/// `m v + t` with the matrix's columns splatted.
#[inline(always)]
fn affine<T: Lane>(m: &[V3<T>; 3], t: V3<T>, v: V3<T>) -> V3<T> {
    madd(m[0], v.x, madd(m[1], v.y, madd(m[2], v.z, t)))
}

fn columns<T: Lane>(m: Mat3) -> [V3<T>; 3] {
    [
        V3::splat(m.x_axis),
        V3::splat(m.y_axis),
        V3::splat(m.z_axis),
    ]
}

/// A ball in a field's mesh frame that the skin provably does not reach
/// (`SdfLane::clear_radius2`): a vertex whose mesh-frame point lies inside
/// it in every lane is not pushed, so its lookup is skipped. The strand
/// step keeps one per vertex and candidate field (the last real lookup's),
/// reset to [`ClearBall::none`] at every block step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ClearBall<T: Lane> {
    centre: V3<T>,
    /// The radius squared; -1 for none, `TOUCHED` for none after a
    /// lookup that pushed a lane.
    radius2: T,
}

/// [`ClearBall`]'s radius squared after a lookup that pushed a lane (no
/// ball, as -1 is for none).
const TOUCHED: f32 = -2.0;

impl<T: Lane> ClearBall<T> {
    /// No ball: every point is outside it.
    pub(crate) fn none() -> Self {
        ClearBall {
            centre: V3::zero(),
            radius2: T::splat(-1.0),
        }
    }

    /// The radius squared (-1 for none).
    #[cfg(test)]
    pub(crate) fn radius2(&self) -> T {
        self.radius2
    }

    /// The last lookup pushed some lane (its radius is `TOUCHED`).
    #[inline(always)]
    fn touched(&self) -> bool {
        !T::any(self.radius2.gt(T::splat(0.5 * (TOUCHED - 1.0))))
    }

    /// Every lane's point lies strictly inside (a NaN point never does).
    #[inline(always)]
    fn holds(&self, p: V3<T>) -> bool {
        let o = p - self.centre;
        !T::any(!dot(o, o).lt(self.radius2))
    }
}

/// A mesh field in lanes over one step: this substep's `mesh_from_local`
/// and `local_from_mesh` rotation, and the surface's motion over the
/// substep at a mesh point `p` (`dm p + dt`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FieldReach<T: Lane> {
    pub field: LocalField,
    pub first: usize,
    mesh_from_local: [V3<T>; 3],
    mesh_from_local_t: V3<T>,
    local_from_mesh: [V3<T>; 3],
    motion_m: [V3<T>; 3],
    motion_t: V3<T>,
    /// `local_from_mesh` after the previous substep.
    last: glam::Affine3A,
    /// It did not move over the step: placed once, no surface motion.
    still: bool,
    rooted_until: usize,
    root_depth: T,
}

impl<T: SdfLane> FieldReach<T> {
    #[inline(always)]
    pub(crate) fn new(
        field: LocalField,
        first: u32,
        sdf: &Sdf,
        k: &ContactSetup,
        root: V3<T>,
        arc: &[T],
    ) -> Self {
        // Placed at the end of the step for the roots rule; the first
        // substep then measures the surface's motion from the step's start.
        let end = field.at(1.0);
        let mut r = FieldReach {
            field,
            first: first as usize,
            mesh_from_local: columns(Mat3::IDENTITY),
            mesh_from_local_t: V3::zero(),
            local_from_mesh: columns(Mat3::IDENTITY),
            motion_m: columns(Mat3::ZERO),
            motion_t: V3::zero(),
            last: end,
            still: field.still(),
            rooted_until: 0,
            root_depth: T::splat(0.0),
        };
        r.place(end);
        let (d, _) = T::sample(sdf, r.mesh_point(root));
        let depth = T::splat(k.pearl_radius) - d;
        let inside = depth.gt(T::splat(0.0));
        r.root_depth = T::select(inside, depth, T::splat(0.0));
        if T::any(inside) {
            r.rooted_until = rooted_until(r.root_depth, arc, k.root_exit);
        }
        r.last = if r.still { end } else { field.at(0.0) };
        r
    }

    fn place(&mut self, local_from_mesh: glam::Affine3A) {
        let m = Mat3::from(local_from_mesh.matrix3);
        let inv = m.transpose();
        let t = Vec3::from(local_from_mesh.translation);
        self.local_from_mesh = columns(m);
        self.mesh_from_local = columns(inv);
        self.mesh_from_local_t = V3::splat(-(inv * t));
        let last_m = Mat3::from(self.last.matrix3);
        self.motion_m = columns(m - last_m);
        self.motion_t = V3::splat(t - Vec3::from(self.last.translation));
        self.last = local_from_mesh;
    }

    /// Moves it to where it is after substep `sub` of `n`.
    #[inline(always)]
    pub(crate) fn advance(&mut self, sub: u32, n: u32) {
        // A still field stays where `new` placed it.
        if self.still {
            return;
        }
        self.place(self.field.at((sub + 1) as f32 / n as f32));
    }

    #[inline(always)]
    fn mesh_point(&self, x: V3<T>) -> V3<T> {
        affine(&self.mesh_from_local, self.mesh_from_local_t, x)
    }

    /// Pushes `x` out of the field's skin (at most `field_push` per
    /// substep; a vertex pushed that far keeps no velocity from it), with
    /// friction; `prev` is its position a substep ago, moved with a deep
    /// push. Also returns the lanes pushed deep.
    ///
    /// `ball` is this vertex's [`ClearBall`] in this field: when its mesh
    /// point lies inside in every lane, nothing is looked up (no lane could
    /// be pushed: the same result); otherwise the lookup refreshes it,
    /// round the point looked up (or proved far).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn push_vertex(
        &self,
        sdf: &Sdf,
        v: usize,
        x: V3<T>,
        prev: &mut V3<T>,
        off: T,
        arc: T,
        k: &ContactSetup,
        friction: bool,
        ball: &mut ClearBall<T>,
    ) -> (V3<T>, T::Mask) {
        let p = self.mesh_point(x);
        if ball.holds(p) {
            return (x, !T::all_lanes());
        }
        let skin = T::splat(k.pearl_radius);
        // The far map proves every lane out of reach: no lookup; the far
        // clearance bounds the field from below. Not tried where the last
        // lookup pushed a lane (hair in contact stays near the surface).
        let mut entry = None;
        if k.pearl_radius < sdf.far_clearance() && !ball.touched() {
            let e = T::block_entry(sdf, p);
            if !T::any(!T::far(e, p)) {
                let d = T::splat(sdf.far_clearance());
                *ball = ClearBall {
                    centre: p,
                    radius2: T::clear_radius2(sdf, p, d, (d + off) - skin, e),
                };
                return (x, !T::all_lanes());
            }
            entry = Some(e);
        }
        let (d, g) = T::sample_for_skin(sdf, p, k.pearl_radius);
        let reach = if v < self.rooted_until {
            reach_at(T::splat(k.pearl_radius), self.root_depth, arc, k.root_exit)
        } else {
            T::splat(k.pearl_radius)
        };
        let n = affine(&self.local_from_mesh, V3::zero(), g);
        let n2 = dot(n, n);
        // `off` is +inf for a pinned vertex: never hit.
        let hit = (d + off).lt(reach) & n2.gt(T::splat(1.0e-12));
        if !T::any(hit) {
            let entry = entry.unwrap_or_else(|| T::block_entry(sdf, p));
            *ball = ClearBall {
                centre: p,
                radius2: T::clear_radius2(sdf, p, d, (d + off) - skin, entry),
            };
            return (x, !T::all_lanes());
        }
        // A lane is pushed: its margin `d + off - pearl_radius` is below
        // zero (`reach <= pearl_radius`), so it has no ball and the next
        // round looks up whatever the others' balls are: none for all,
        // marked as touched (the far map is not tried next round).
        ball.radius2 = T::splat(TOUCHED);
        let nrm = n * n2.max(T::splat(1.0e-12)).inv_sqrt();
        let depth = reach - d;
        // What this substep's motion relative to the surface can have put
        // it in is pushed out whole; beyond that it was found deep, and
        // leaves at FIELD_EXIT_SPEED.
        let motion = if self.still {
            V3::zero()
        } else {
            affine(&self.motion_m, self.motion_t, p)
        };
        let rel = (x - *prev) - motion;
        let rel2 = dot(rel, rel).max(T::splat(1.0e-30));
        let cap = T::splat(k.field_push) + rel2 * rel2.inv_sqrt();
        let push = depth.min(cap);
        let mut pushed = madd(nrm, push, x);
        if friction {
            pushed = pushed + coulomb((pushed - *prev) - motion, nrm, push, k);
        }
        let deep = hit & depth.gt(cap);
        *prev = V3::select(deep, madd(nrm, push, *prev), *prev);
        (V3::select(hit, pushed, x), deep)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup() -> ContactSetup {
        ContactSetup {
            pearl_radius: 0.002,
            friction: 0.3,
            static_friction: 0.4,
            friction_on: true,
            field_push: 0.01,
            accel_h2: Vec3::new(0.0, -9.81 / 57_600.0, 0.0),
            slop: 9.81 / 57_600.0,
            root_exit: 0.25,
        }
    }

    /// The capsules' bounding ball never skips a point the exact test
    /// reaches or touches: 200,000 points round 40 capsules of every
    /// length (a point among them), many of them at the skin, some far
    /// from the origin.
    #[test]
    fn the_bounding_ball_never_skips_a_point_in_reach() {
        let k = setup();
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut unit = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let (mut tested, mut near) = (0, 0);
        for c in 0..40 {
            let origin = if c % 4 == 3 { 300.0 } else { 0.0 };
            let a = Vec3::new(unit(), unit(), unit()) * 0.2 + Vec3::splat(origin);
            let half = if c % 5 == 0 { 0.0 } else { 0.2 * unit() };
            let axis = Vec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5).normalize() * half;
            let cap = LocalCapsule {
                from: [a, a + axis],
                to: [a, a + axis],
                radius: 0.01 + 0.1 * unit(),
            };
            let r = ShapeReach::<f32>::new(&cap, 0, 4, V3::splat(Vec3::splat(1.0e6)), &[], &k);
            for _ in 0..5_000 {
                // A point at the skin give or take a few ulps, or anywhere.
                let t = unit();
                let dir = Vec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5).normalize_or_zero();
                let scale = if unit() < 0.5 {
                    1.0 + (unit() - 0.5) * 1.0e-6
                } else {
                    0.5 + unit()
                };
                let x = V3::<f32>::splat(a + axis * t + dir * r.reach_len * scale);
                let (d, _) = r.offset::<true>(x);
                let d2 = dot(d, d);
                tested += 1;
                if d2 < r.reach2 {
                    near += 1;
                    assert!(r.may_touch::<true>(x, 0.0, r.bound2), "capsule {c}: {x:?}");
                }
                if d2 < r.touch2 {
                    assert!(
                        r.may_touch::<true>(x, 0.0, r.touch_bound2),
                        "capsule {c}: {x:?}"
                    );
                }
            }
        }
        assert!(near > tested / 4, "{near} of {tested} points in reach");
    }
}
