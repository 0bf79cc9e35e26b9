//! Local shape: the groom's segment vectors kept by linear springs in the
//! head's frame, solved implicitly per substep, and the sag-free rest
//! state that makes the groomed pose their equilibrium under gravity.
//!
//! **The energy.** Segment `s` of a strand (`e_s = x_{s+1} - x_s`) is
//! pulled toward its rest vector `t_s` turned by the groom frame's
//! rotation `R` (the head's, [`crate::Strands::set_head_pose`]):
//!
//! ```text
//! E = sum_s (kappa_s / 2) m |e_s - R t_s|^2,   kappa_s = (c / l_s)^2
//! ```
//!
//! with `m` the vertex mass (1 in the step's units), `l_s` the rest length
//! and `c` a wave speed set by `SimParams::local_shape_stiffness`
//! ([`wave_speed`]). It is the energy of a string under tension `c^2` per
//! unit mass whose rest shape is the groom: a strand of length `L`
//! swings about its groom at `omega_1 = (pi / 2) c / L` (its lowest
//! mode), whatever its vertex count, and bends smoothly where it is
//! loaded. Its forces come in equal and opposite pairs on the two ends of
//! a segment, so it exchanges momentum only with the head through the
//! roots and conserves energy in the rest of the strand.
//!
//! The rule it replaces (TressFX 4's local shape constraints, each
//! segment pulled toward its rest vector carried by the minimal rotation
//! of its parent, the child taking the whole correction) had no reaction
//! on the parent: a follower load, which pumps energy into a strand.
//! Measured on Sintel's groom with no gravity and no collider, where the
//! groom is the rule's exact equilibrium, the strands left it at every
//! stiffness below 1 (p95 16 mm at 0.9, 92 mm at 0.5 after 3 s; more than
//! half the interior vertices kinked by 30 degrees or more in a head
//! turn), and more substeps made it worse (`kernels/README.md`, "Styled
//! hair that moves").
//!
//! **The solve** (implicit Euler of `E` after the Verlet prediction `x*`,
//! the projective step of Bouaziz et al. 2014 for a quadratic energy):
//! per substep `h`, per vertex `j` with inverse mass `w_j`,
//!
//! ```text
//! (x_j - x*_j) + w_j [a_{j-1} (x_j - x_{j-1} - R t_{j-1})
//!                    - a_j (x_{j+1} - x_j - R t_j)] = 0,   a_s = (c h / l_s)^2
//! ```
//!
//! a tridiagonal system per coordinate with the same matrix for x, y and
//! z, diagonally dominant (every pivot at least 1), solved exactly by the
//! Thomas algorithm. The matrix and the rest vectors' part of the
//! right-hand side change only with the step (the rotation, `h`), so the
//! elimination's factors are made once per step (`Factors::factor`) and
//! a substep runs a forward and a back substitution (`Factors::solve`).
//! Implicit Euler damps a mode of frequency `omega` by `1 / sqrt(1 + (omega h)^2)` per
//! substep: 0.3 % per substep for a strand's lowest mode at
//! `omega = 20 rad/s`, more for the stiff modes.
//!
//! **Damping.** Each spring also resists the rate of change of its
//! segment (Rayleigh stiffness damping, `beta kappa` with `beta =`
//! [`DAMPING_TIME`]): in the implicit solve this is a blend of each rest
//! vector with the segment as it was at the substep's start, weighted by
//! `h / (h + beta)`. A mode of frequency `omega` is damped at the ratio
//! `beta omega / 2`: 4 % for a 20 cm strand's swing at stiffness 0.7
//! (7.9 rad/s), critically or more for the zig-zag modes above 200
//! rad/s. On Sintel at 0.7 it brought the tips back within 0.1 mm 2.5 s
//! after a turn (0.6 mm without) for 2 mm less swing (measured with the
//! length projection still on; `beta` 0.003 and 0.03 bracket it).
//!
//! **Lengths.** While the springs are on, the length projection (step 4)
//! is skipped and the strain limit (step 6, `max_stretch`) holds the
//! lengths. An isotropic spring pulls along a turned segment too (by
//! `l (1 - cos theta)`); the exact projection undid that every substep along
//! other directions than the spring's implicit solve spread it, and the
//! pair pumped energy into short strands: on Sintel at 0.5, 5 cm locks of
//! 1.7 mm segments curled into loops after a head turn with no gravity
//! and no collider (0.7 % of the vertices kinked by 30 degrees or more;
//! none with the projection off, none at twice the substeps). Springs
//! projected across the segment instead were worse under gravity.
//!
//! **The head's turn** moves the roots on a straight line over a step's
//! substeps; the rest vectors turn with them, from the last step's groom
//! frame to this one's, linearly per substep, so that the springs' targets
//! and the roots agree within a step (no figure of the style run changed:
//! a turn is a few degrees per step).
//!
//! **Sag-free rest** ([`crate::Strands::solve_sag_free`]; the idea of Hsu
//! et al. 2023, "Sag-free initialization for strand-based hybrid hair
//! simulation", derived here for this energy and step): at a pose `x` at
//! rest, the springs balance the steady acceleration `g` (gravity plus the
//! wind's pull, `SimParams::steady_acceleration`) at every free vertex
//! when the spring force of segment `s` carries the weight of every free
//! vertex below it:
//!
//! ```text
//! kappa_s (e_s - R t_s) = g M_s,   M_s = #{free vertices j > s}
//! =>  R t_s = e_s - g M_s l_s^2 / c^2
//! ```
//!
//! Then one substep from `x` at rest predicts `x* = x + g h^2`, and `x`
//! solves the system above exactly; the lengths are met and the contacts
//! only push, so `x` is a fixed point of the whole step where it is
//! outside the colliders' skins.

use crate::constraints::MIN_LENGTH;
use crate::fused::{madd, rotate};
use crate::lanes::{Lane, V3};
use glam::Mat3;

/// The shape springs' wave speed at stiffness 1 (m/s).
pub const WAVE_SPEED_AT_1: f32 = 4.0;
/// Decades of wave speed between stiffness 1 and stiffness 0 (exclusive):
/// `c = WAVE_SPEED_AT_1 10^(-WAVE_SPEED_DECADES (1 - k))`.
pub const WAVE_SPEED_DECADES: f32 = 2.0;

/// The shape springs' wave speed `c` (m/s) for `local_shape_stiffness`
/// `k` in [0, 1]: `WAVE_SPEED_AT_1 10^(-WAVE_SPEED_DECADES (1 - k))`, 0
/// (off) at `k <= 0` or NaN. The lowest mode of a strand of length `L`
/// swings at `(pi / 2) c / L` rad/s.
pub fn wave_speed(k: f32) -> f32 {
    if k.is_nan() || k <= 0.0 {
        return 0.0;
    }
    let k = k.min(1.0);
    WAVE_SPEED_AT_1 * 10f32.powf(-WAVE_SPEED_DECADES * (1.0 - k))
}

/// `(c h)^2` for stiffness `k` and substep `h` (0 when off or `h` is not
/// a finite positive number).
pub(crate) fn alpha_scale(k: f32, h: f32) -> f32 {
    let c = wave_speed(k);
    let ch = c * h;
    if ch.is_finite() && ch > 0.0 {
        ch * ch
    } else {
        0.0
    }
}

/// Rayleigh damping of the shape springs (s): each spring also resists
/// the rate of change of its segment with `beta kappa`, so a mode of
/// frequency `omega` is damped at the ratio `beta omega / 2`.
pub const DAMPING_TIME: f32 = 0.01;

/// The springs' share of the shape rows' coefficients for a substep of
/// `h`: `h / (h + DAMPING_TIME)` (1 for a substep that is not a finite
/// positive number).
pub(crate) fn keep(h: f32) -> f32 {
    if h.is_finite() && h > 0.0 {
        h / (h + DAMPING_TIME)
    } else {
        1.0
    }
}

/// `g / c^2` for `params` (the steady acceleration over the springs'
/// squared wave speed; zero with the springs off): the sag-free rest
/// vector of a segment of rest length `l` with `M` free vertices below it
/// is its pose less `g M l^2 / c^2`.
pub(crate) fn sag_per_length2(params: &crate::SimParams) -> glam::Vec3 {
    let c = wave_speed(params.local_shape_stiffness);
    if c > 0.0 {
        params.steady_acceleration() / (c * c)
    } else {
        glam::Vec3::ZERO
    }
}

/// The shape springs' elimination factors of one chain for one step.
#[derive(Clone, Debug, Default)]
pub(crate) struct Factors<T: Lane> {
    /// `-c'_v = a_v+ / den_v`: what the back substitution adds of vertex
    /// `v + 1`, and the share of `R t_v` in row `v`.
    up: Vec<T>,
    /// `1 / den_v`.
    inv: Vec<T>,
    /// `a_v- / den_v`: what the forward substitution carries from `v - 1`,
    /// and the share of `R t_{v-1}` in row `v`.
    down: Vec<T>,
    /// `R_0 t_v`: the rest vectors turned by the groom frame's rotation at
    /// the step's start.
    turned: Vec<V3<T>>,
    /// `R_1 t_v - R_0 t_v`: how they turn over the step.
    turning: Vec<V3<T>>,
}

impl<T: Lane> Factors<T> {
    pub(crate) fn new(verts: usize) -> Self {
        Factors {
            up: vec![T::splat(0.0); verts],
            inv: vec![T::splat(0.0); verts],
            down: vec![T::splat(0.0); verts],
            turned: vec![V3::zero(); verts],
            turning: vec![V3::zero(); verts],
        }
    }

    /// The factors for inverse masses `w`, rest lengths `len`, rest
    /// vectors `t` (groom frame) turned by `rotation`, and `alpha = (c
    /// h)^2`. Row `v`: `-a_v- x_{v-1} + (1 + a_v- + a_v+) x_v - a_v+
    /// x_{v+1} = x*_v + a_v- t'_{v-1} - a_v+ t'_v`, `a_v- = w_v a_{v-1}`,
    /// `a_v+ = w_v a_v`; a pinned vertex's row is `x_v = x*_v`. Segments
    /// shorter than `MIN_LENGTH` have no spring.
    #[inline(always)]
    pub(crate) fn factor(
        &mut self,
        w: &[T],
        len: &[T],
        t: &[V3<T>],
        [from, to]: [&Mat3; 2],
        alpha: T,
    ) {
        let verts = w.len();
        let (up, inv, down, turned, turning) = (
            &mut self.up[..verts],
            &mut self.inv[..verts],
            &mut self.down[..verts],
            &mut self.turned[..verts],
            &mut self.turning[..verts],
        );
        let (len, t) = (&len[..verts], &t[..verts]);
        let zero = T::splat(0.0);
        let one = T::splat(1.0);
        let min2 = T::splat(MIN_LENGTH * MIN_LENGTH);
        let mut a_prev = zero;
        let mut up_prev = zero;
        for v in 0..verts {
            // Segment v's `a_v` (zero past the tip).
            let a_next = if v + 1 < verts {
                let l2 = len[v] * len[v];
                T::select(l2.gt(min2), alpha * l2.max(min2).recip(), zero)
            } else {
                zero
            };
            (turned[v], turning[v]) = if v + 1 < verts {
                let a = rotate(from, t[v]);
                (a, rotate(to, t[v]) - a)
            } else {
                (V3::zero(), V3::zero())
            };
            let lo = w[v] * a_prev;
            let hi = w[v] * a_next;
            // den = 1 + lo + hi + lo c'_{v-1} = 1 + lo (1 - up_{v-1}) + hi.
            let den = lo.mul_add(one - up_prev, one + hi);
            let r = den.recip();
            up_prev = hi * r;
            up[v] = up_prev;
            // A pinned row is `x_v = x*_v` exactly: 1, not the reciprocal
            // estimate of 1 (which is not 1 on every processor, and moved
            // the roots by a rounding error every step, so that the hair
            // never fell asleep with the springs on).
            inv[v] = T::select(w[v].gt(zero), r, one);
            down[v] = lo * r;
            a_prev = a_next;
        }
    }

    /// Solves one substep's system in place: `pos` holds `x*` on entry
    /// and the springs' implicit step on return (pinned vertices
    /// unchanged: their rows are `x_v = x*_v`); `start` holds the
    /// positions at the substep's start, and `keep` is the springs' share
    /// `rho = h / (h + beta)` of the rows' coefficients (the rest, `1 -
    /// rho`, is their damping, which pulls each segment toward where it
    /// was at the substep's start: the targets are `rho R t_s + (1 - rho)
    /// e_s(start)`).
    #[inline(always)]
    pub(crate) fn solve(&self, pos: &mut [V3<T>], start: &[V3<T>], keep: T, along: T) {
        let verts = pos.len();
        let (up, inv, down, turned, turning, start) = (
            &self.up[..verts],
            &self.inv[..verts],
            &self.down[..verts],
            &self.turned[..verts],
            &self.turning[..verts],
            &start[..verts],
        );
        let rest = T::splat(1.0) - keep;
        // Forward: d_v = x*_v / den_v + down_v (t_{v-1} + d_{v-1}) - up_v t_v
        // with the blended targets t.
        let mut d = V3::zero();
        let mut t_prev = V3::zero();
        for v in 0..verts {
            let e = if v + 1 < verts {
                start[v + 1] - start[v]
            } else {
                V3::zero()
            };
            let t = madd(e, rest, madd(turning[v], along, turned[v]) * keep);
            d = madd(t, -up[v], madd(t_prev + d, down[v], pos[v] * inv[v]));
            pos[v] = d;
            t_prev = t;
        }
        // Back: x_v = d_v + up_v x_{v+1}.
        let mut x = pos[verts - 1];
        for v in (0..verts - 1).rev() {
            x = madd(x, up[v], pos[v]);
            pos[v] = x;
        }
    }
}
