//! The sag-free rest state ([`Strands::solve_sag_free`]): the shape
//! springs' rest vectors (`shape.rs`) for which the hair's pose, as the
//! colliders leave it, is the step's equilibrium under the steady
//! acceleration.

use crate::lanes::{Vec3x8, LANES};
use crate::{Colliders, Error, SimParams, Strands};
use glam::Vec3;

/// Most steps [`Strands::solve_sag_free`] takes to let the colliders push
/// the pose out of their skins.
pub const RELAX_STEPS: usize = 60;
/// The relaxation ends when no vertex moved more than this in a step (m).
pub const RELAX_TOLERANCE: f32 = 1.0e-5;

impl Strands {
    /// Makes the hair's current pose, as the colliders leave it, its rest
    /// state under `params`.
    ///
    /// 1. **The pose against the colliders.** Hair groomed into a
    ///    collider's skin (the pearl radius; a groom cut by the body it
    ///    was made for: 40 of Sintel's 228 guides pass within 2 mm of her
    ///    bust) would be pushed out by every step while its springs pull
    ///    it back in, a fight that crumples short strands. So the pose is
    ///    first relaxed: a copy of the set is stepped under `params`
    ///    without gravity, wind, gusts, the hair grid, friction, springs or
    ///    velocity, with substeps of `dt / MAX_SUBSTEPS`, until no vertex
    ///    moves more than [`RELAX_TOLERANCE`] in a step (at most
    ///    [`RELAX_STEPS`]); the step's own contacts push it out (the skins,
    ///    the roots rule, a field's exit speed). The hair is put there, at
    ///    rest. Hair outside every skin does not move.
    /// 2. **The rest vectors** of the shape springs become, per segment
    ///    `s` (`shape.rs`, "Sag-free rest"),
    ///
    ///    ```text
    ///    R t_s = e_s - g M_s l_s^2 / c^2
    ///    ```
    ///
    ///    with `e_s` the relaxed segment, `g` the steady acceleration
    ///    (`params.steady_acceleration()`: gravity and the wind's pull),
    ///    `M_s` the free vertices below the segment, `l_s` its rest length,
    ///    `c` the springs' wave speed at `params.local_shape_stiffness` and
    ///    `R` the groom frame's rotation now. One substep from that pose at
    ///    rest then leaves every vertex where it is: the springs carry the
    ///    hair's weight, and the colliders, which only push, have nothing
    ///    to push. Hsu et al. 2023 ("Sag-free initialization for
    ///    strand-based hybrid hair simulation") solve the same balance for
    ///    an elastic rod; for these springs it has the closed form above.
    ///
    /// Call it after [`Strands::from_polylines`] and the first
    /// [`Strands::set_head_pose`] (or [`Strands::set_rest_rotation`]),
    /// with the colliders placed there, before stepping; again when
    /// `local_shape_stiffness`, gravity or the wind change. Calling it
    /// twice changes nothing: the second call finds the pose it left
    /// (bit for bit) and only recomputes the rest vectors, which depend on
    /// the pose and `params` alone. A pose that has settled under the step
    /// is kept as that settled pose. With `local_shape_stiffness` 0 there
    /// are no springs to set (the rest vectors are the pose's segments).
    /// Bounded time: measured 40 ms for Sintel's 228 x 32 guides on her
    /// bust and 0.2 s for the TressFX mohawk's 2,226 x 32 under two
    /// spheres (`kernels/README.md`, "Styled hair that moves"); it
    /// allocates a copy of the set.
    ///
    /// # Errors
    /// [`SimParams::validate`]'s; [`Error::NonFinite`] for a sphere or
    /// capsule with a non-finite value (its index over the spheres, then
    /// the capsules) and [`Error::InvalidParameter`] for a negative
    /// radius; nothing changes then.
    pub fn solve_sag_free(
        &mut self,
        params: &SimParams,
        colliders: &Colliders<'_>,
    ) -> Result<(), Error> {
        params.validate()?;
        check_colliders(colliders)?;
        if self.relaxed_pose != Some(pose_hash(&self.pos)) {
            self.relax(params, colliders);
        }
        let pose = std::mem::take(&mut self.pos);
        self.set_shape_rest(&pose, crate::shape::sag_per_length2(params));
        self.pos = pose;
        self.relaxed_pose = Some(pose_hash(&self.pos));
        self.wake();
        Ok(())
    }

    /// The shape springs' rest vectors from the local positions `pose`
    /// (this set's layout), less `sag` (`g / c^2`) times each segment's
    /// squared rest length and the free vertices below it; stored in the
    /// groom frame.
    fn set_shape_rest(&mut self, pose: &[Vec3x8], sag: Vec3) {
        let to_groom = self.rest_rotation.transpose();
        let verts = self.verts;
        for b in 0..self.blocks {
            let r = b * verts..(b + 1) * verts;
            for l in 0..LANES {
                // Free vertices below segment s, counted from the tip.
                let mut below = 0.0f32;
                for v in (0..verts - 1).rev() {
                    let (i, j) = (r.start + v, r.start + v + 1);
                    if self.inv_mass[j].as_array()[l] > 0.0 {
                        below += 1.0;
                    }
                    let e = pose[j].lane(l) - pose[i].lane(l);
                    let len = self.rest_len[i].as_array()[l];
                    let t = e - sag * (len * len * below);
                    self.rest_vec[i].set_lane(l, to_groom * t);
                }
            }
        }
    }

    /// Step 1 of [`Strands::solve_sag_free`]: moves the hair to its pose
    /// as the colliders leave it, at rest.
    fn relax(&mut self, params: &SimParams, colliders: &Colliders<'_>) {
        if colliders.is_empty() {
            return;
        }
        let mut copy = self.clone();
        let relax = SimParams {
            gravity: Vec3::ZERO,
            wind: Vec3::ZERO,
            drag: 0.0,
            turbulence: 0.0,
            volume_stiffness: 0.0,
            hair_friction: 0.0,
            friction: 0.0,
            static_friction: 0.0,
            local_shape_stiffness: 0.0,
            iterations: 0,
            sleep_speed: 0.0,
            damping: 0.0,
            max_substep: params.dt / crate::MAX_SUBSTEPS as f32,
            ..params.clone()
        };
        let mut before = copy.pos.clone();
        for _ in 0..RELAX_STEPS {
            copy.prev.copy_from_slice(&copy.pos);
            before.copy_from_slice(&copy.pos);
            crate::step_colliders(&mut copy, &relax, colliders);
            let moved = copy
                .pos
                .iter()
                .zip(&before)
                .flat_map(|(a, b)| (*a - *b).length_squared().to_array())
                .fold(0.0f32, f32::max);
            if !(moved > RELAX_TOLERANCE * RELAX_TOLERANCE) {
                break;
            }
        }
        // The restored strands' count is the caller's, not the copy's.
        self.pos.copy_from_slice(&copy.pos);
        self.prev.copy_from_slice(&copy.pos);
    }
}

/// A hash of every coordinate's bits (FNV-1a): whether a pose is the one a
/// solve left.
fn pose_hash(pos: &[Vec3x8]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for p in pos {
        for c in [p.x, p.y, p.z] {
            for x in c.to_array() {
                h = (h ^ x.to_bits() as u64).wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    h
}

/// Spheres and capsules finite with radii >= 0.
fn check_colliders(colliders: &Colliders<'_>) -> Result<(), Error> {
    let spheres = colliders
        .spheres
        .iter()
        .map(|s| (s.center.to_array(), s.center.to_array(), s.radius));
    let capsules = colliders
        .capsules
        .iter()
        .map(|c| (c.a.to_array(), c.b.to_array(), c.radius));
    for (index, (a, b, radius)) in spheres.chain(capsules).enumerate() {
        if !a.iter().chain(&b).chain([&radius]).all(|x| x.is_finite()) {
            return Err(Error::NonFinite { index });
        }
        if radius < 0.0 {
            return Err(Error::InvalidParameter {
                name: "collider radius",
                value: radius,
                expected: ">= 0",
            });
        }
    }
    Ok(())
}
