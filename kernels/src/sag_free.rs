//! The sag-free rest state ([`Strands::solve_sag_free`]): the shape
//! springs' rest vectors (`shape.rs`) for which the hair's pose is the
//! step's equilibrium under the steady acceleration.

use crate::lanes::{Vec3Lanes, LANES};
use crate::{Colliders, Error, SimParams, Strands};
use glam::Vec3;

impl Strands {
    /// Makes the hair's current pose its rest state under `params`: the
    /// shape springs' rest vectors become, per segment `s` (`shape.rs`,
    /// "Sag-free rest"),
    ///
    /// ```text
    /// R t_s = e_s - g M_s l_s^2 / c^2
    /// ```
    ///
    /// with `e_s` the segment now, `g` the steady acceleration
    /// (`params.steady_acceleration()`: gravity and the wind's pull),
    /// `M_s` the free vertices below the segment, `l_s` its rest length,
    /// `c` the springs' wave speed at `params.local_shape_stiffness` and
    /// `R` the groom frame's rotation now. One substep from that pose at
    /// rest then leaves every vertex where it is: the springs carry the
    /// hair's weight, so hair groomed onto a scalp or a shoulder stays
    /// there, and the colliders, which only push, have nothing to push
    /// where the hair lies outside their skins. Hsu et al. 2023 ("Sag-free
    /// initialization for strand-based hybrid hair simulation") solve the
    /// same balance for an elastic rod; for these springs it has the
    /// closed form above.
    ///
    /// Hair groomed into a collider's skin (56 of Sintel's 228 guides come
    /// within her bust's 2 mm skin, a few pass through it) is pushed out by
    /// the step and held there by its springs: measured on Sintel, 0.7 mm
    /// from the groom at the 95th percentile and 0.4 % of the vertices
    /// kinked at stiffness 0.7 (`kernels/README.md`, "Styled hair that
    /// moves"). Relaxing such hair out of the skins first and taking that
    /// pose as the rest was tried: 0.0 mm but 0.9 % kinked, the strands
    /// bent where the body pushed them.
    ///
    /// Call it after [`Strands::from_polylines`] and the first
    /// [`Strands::set_head_pose`] (or [`Strands::set_rest_rotation`]),
    /// before stepping; again when `local_shape_stiffness`, gravity or the
    /// wind change. It reads the positions and writes only the rest
    /// vectors, so calling it twice changes nothing, and a pose that has
    /// settled under the step is kept as that settled pose. With
    /// `local_shape_stiffness` 0 there are no springs (the rest vectors
    /// become the pose's segments, unused). O(strands x vertices), no
    /// allocation: under 0.1 ms for Sintel's 228 x 32 guides and about 1
    /// ms for the mohawk's 2,226 x 32.
    ///
    /// # Errors
    /// [`SimParams::validate`]'s; [`Error::NonFinite`] for a sphere or
    /// capsule with a non-finite value (its index over the spheres, then
    /// the capsules) and [`Error::InvalidParameter`] for a negative
    /// radius: the colliders the step will see, checked as it needs them;
    /// nothing changes on an error.
    pub fn solve_sag_free(
        &mut self,
        params: &SimParams,
        colliders: &Colliders<'_>,
    ) -> Result<(), Error> {
        params.validate()?;
        check_colliders(colliders)?;
        let pose = std::mem::take(&mut self.pos);
        self.set_shape_rest(&pose, crate::shape::sag_per_length2(params));
        self.pos = pose;
        self.wake();
        Ok(())
    }

    /// The shape springs' rest vectors from the local positions `pose`
    /// (this set's layout), less `sag` (`g / c^2`) times each segment's
    /// squared rest length and the free vertices below it; stored in the
    /// groom frame.
    fn set_shape_rest(&mut self, pose: &[Vec3Lanes], sag: Vec3) {
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
