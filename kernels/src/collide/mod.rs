//! Collisions: what hair collides with, and how a step finds and resolves
//! contacts.
//!
//! - [`Colliders`]: the borrowed set one step collides with: rig spheres
//!   ([`crate::Sphere`]), [`Capsule`]s (bones, limbs) and signed distance
//!   fields of meshes ([`Sdf`]), any number of each.
//! - `rig.rs`: the colliders in the strands' local frame for one step, where
//!   each was at the last step and is now (the step moves them on the
//!   straight line between over its substeps, as it moves the roots), and
//!   the boxes of those that moved (they wake sleeping hair).
//! - `broad_phase.rs`: which colliders can touch a block of eight strands,
//!   from which vertex on (once per step).
//! - `narrow.rs`: the contacts in lanes: pearls, vertex push-out, Coulomb
//!   friction, the roots rule; one generic body for the SIMD path and the
//!   scalar twin.
//! - `sdf/`: the signed distance field of a triangle mesh.

pub(crate) mod broad_phase;
mod capsule;
pub(crate) mod narrow;
pub(crate) mod rig;
pub(crate) mod sdf;

pub use capsule::Capsule;
pub use sdf::{Sdf, MARGIN_CELLS, MAX_SDF_CELLS};

use crate::Sphere;

/// What hair collides with in one step, borrowed, so that an engine updates
/// its own arrays every frame without allocating. `Copy + Default` (no
/// colliders); there is no cap on the count of any kind: the broad phase
/// keeps the cost to the colliders near each block of eight strands.
///
/// Spheres and capsules are in world coordinates; each field is placed by
/// its own transform ([`Sdf::set_transform`]). The step remembers where
/// every collider was at the last step (by its index in these slices), so
/// that it moves them on the straight line to where they are now over its
/// substeps and gives contact friction their motion; keep each collider at
/// the same index from step to step (a set whose length changes is taken
/// as not moving for that step; so is every collider in the step after
/// [`crate::Strands::teleport`] or [`crate::Strands::set_state`], and one
/// that moved more than [`crate::COLLIDER_JUMP`]). The record is per
/// [`crate::Strands`], so several hair objects may share the same fields.
#[derive(Clone, Copy, Debug, Default)]
pub struct Colliders<'a> {
    /// Rig spheres.
    pub spheres: &'a [Sphere],
    /// Capsules.
    pub capsules: &'a [Capsule],
    /// Signed distance fields of meshes, each placed by its transform.
    pub sdfs: &'a [Sdf],
}

impl<'a> Colliders<'a> {
    /// Spheres alone (what [`crate::step`] collides with).
    pub fn spheres(spheres: &'a [Sphere]) -> Self {
        Colliders {
            spheres,
            ..Default::default()
        }
    }

    /// Total count of colliders of every kind.
    pub fn len(&self) -> usize {
        self.spheres.len() + self.capsules.len() + self.sdfs.len()
    }

    /// True if there is nothing to collide with.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// `[spheres, capsules, fields]` in `c`.
pub(crate) fn counts(c: &Colliders<'_>) -> [usize; 3] {
    [c.spheres.len(), c.capsules.len(), c.sdfs.len()]
}
