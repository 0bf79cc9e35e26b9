//! The colliders of one step in the strands' local frame (positions
//! relative to [`crate::Strands::origin`]), where each was at the end of
//! the last step (`from`) and is now (`to`): the substeps move them on the
//! straight line between (fields: their rotation by spherical linear
//! interpolation), as they move the roots, so a collider that travels
//! several centimetres in one step sweeps through the hair rather than
//! jumping over it. The record of the last step is per set of strands and
//! by index in [`Colliders`]' slices; a slice whose length changed counts
//! as not moving for that step. A collider that moves more than
//! [`COLLIDER_JUMP`] in one step has jumped (a teleport with its
//! character, a respawn): it stands where it is now for the whole step
//! rather than sweeping through the space between.

use super::broad_phase::Aabb;
use super::{Capsule, Colliders};
use crate::Sphere;
use glam::{Affine3A, DVec3, Quat, Vec3};

/// A move larger than this in one step (metres, any point of a collider)
/// is a jump, not a sweep: 1 m per step is 60 m/s at 1/60 s, far beyond
/// any bone.
pub const COLLIDER_JUMP: f32 = 1.0;

/// A sphere (`a == b`) or capsule over one step, local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LocalCapsule {
    /// Ends at the start of the step.
    pub from: [Vec3; 2],
    /// Ends at the end of the step.
    pub to: [Vec3; 2],
    pub radius: f32,
}

impl LocalCapsule {
    /// True if it did not move over the step.
    pub(crate) fn still(&self) -> bool {
        self.from == self.to
    }

    /// Stands where it is now for the whole step if it jumped.
    fn unless_jumped(mut self) -> Self {
        let far = |a: Vec3, b: Vec3| (a - b).length_squared() > COLLIDER_JUMP * COLLIDER_JUMP;
        if far(self.from[0], self.to[0]) || far(self.from[1], self.to[1]) {
            self.from = self.to;
        }
        self
    }

    /// A sphere `[x, y, z, r]` holding it over the whole step: centred
    /// between its ends' extremes, reaching the farthest end plus the
    /// radius (for a sphere that does not move, the sphere itself).
    pub(crate) fn bounding_sphere(&self) -> [f32; 4] {
        let b = self.swept_box();
        let c = (b.min + b.max) * 0.5;
        let far = [self.from[0], self.from[1], self.to[0], self.to[1]]
            .iter()
            .map(|p| (*p - c).length())
            .fold(0.0f32, f32::max);
        [c.x, c.y, c.z, far + self.radius]
    }

    /// The box it sweeps over the step, grown by its radius.
    pub(crate) fn swept_box(&self) -> Aabb {
        let lo = self.from[0]
            .min(self.from[1])
            .min(self.to[0])
            .min(self.to[1]);
        let hi = self.from[0]
            .max(self.from[1])
            .max(self.to[0])
            .max(self.to[1]);
        let r = Vec3::splat(self.radius);
        Aabb {
            min: lo - r,
            max: hi + r,
        }
    }
}

/// A mesh field over one step: `local_from_mesh` at the start and at the
/// end of the step as rotation and translation, and the local box its grid
/// sweeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LocalField {
    /// Index in [`Colliders::sdfs`].
    pub index: usize,
    pub from_rotation: Quat,
    pub from_translation: Vec3,
    pub to_rotation: Quat,
    pub to_translation: Vec3,
    pub swept: Aabb,
}

impl LocalField {
    /// True if it did not move over the step.
    pub(crate) fn still(&self) -> bool {
        self.from_rotation == self.to_rotation && self.from_translation == self.to_translation
    }

    /// `local_from_mesh` at the share `f` in [0, 1] of the step.
    #[inline]
    pub(crate) fn at(&self, f: f32) -> Affine3A {
        if f >= 1.0 {
            return Affine3A::from_rotation_translation(self.to_rotation, self.to_translation);
        }
        let q = self.from_rotation.slerp(self.to_rotation, f);
        let t = self.from_translation + (self.to_translation - self.from_translation) * f;
        Affine3A::from_rotation_translation(q, t)
    }
}

/// The step's colliders in the local frame and the record of the last
/// step's, sized once (no allocation while the set does not grow).
#[derive(Clone, Debug, Default)]
pub(crate) struct LocalRig {
    pub spheres: Vec<LocalCapsule>,
    pub capsules: Vec<LocalCapsule>,
    pub fields: Vec<LocalField>,
    /// The local boxes swept by the colliders that moved since the last step
    /// (they wake the sleeping blocks near them).
    pub movers: Vec<Aabb>,
    last_spheres: Vec<Sphere>,
    last_capsules: Vec<Capsule>,
    last_fields: Vec<Affine3A>,
}

/// World to local, through f64 (the origin may be kilometres away).
fn local(p: Vec3, origin: DVec3) -> Vec3 {
    (p.as_dvec3() - origin).as_vec3()
}

fn sphere_valid(s: &Sphere) -> bool {
    s.center.is_finite() && s.radius.is_finite() && s.radius >= 0.0
}

impl LocalRig {
    /// Room for `[spheres, capsules, fields]` colliders (allocates only
    /// when a kind grew).
    pub(crate) fn reserve(&mut self, [spheres, capsules, fields]: [usize; 3]) {
        fn grow<T>(v: &mut Vec<T>, n: usize) {
            v.reserve(n.saturating_sub(v.len()));
        }
        grow(&mut self.spheres, spheres);
        grow(&mut self.capsules, capsules);
        grow(&mut self.fields, fields);
        grow(&mut self.movers, spheres + capsules + fields);
        grow(&mut self.last_spheres, spheres);
        grow(&mut self.last_capsules, capsules);
        grow(&mut self.last_fields, fields);
    }

    /// This step's colliders relative to `origin`, each with where it was
    /// at the last step; invalid spheres and capsules (non-finite, negative
    /// radius) are left out. Fills `movers` with the boxes of those that
    /// moved (every one when the count of its kind changed).
    pub(crate) fn update(&mut self, c: &Colliders<'_>, origin: DVec3) {
        self.reserve(super::counts(c));
        self.spheres.clear();
        self.capsules.clear();
        self.fields.clear();
        self.movers.clear();
        let same = c.spheres.len() == self.last_spheres.len();
        for (i, s) in c.spheres.iter().enumerate() {
            if !sphere_valid(s) {
                continue;
            }
            let was = if same { &self.last_spheres[i] } else { s };
            let now = local(s.center, origin);
            let moved = !same || was != s;
            let from = if sphere_valid(was) {
                local(was.center, origin)
            } else {
                now
            };
            let shape = LocalCapsule {
                from: [from; 2],
                to: [now; 2],
                radius: s.radius,
            };
            // The wake is conservative: a jump wakes what it passed over.
            if moved {
                let r = s.radius.max(was.radius);
                self.movers.push(grown(&shape, r));
            }
            self.spheres.push(shape.unless_jumped());
        }
        let same = c.capsules.len() == self.last_capsules.len();
        for (i, k) in c.capsules.iter().enumerate() {
            if !k.is_valid() {
                continue;
            }
            let was = if same && self.last_capsules[i].is_valid() {
                &self.last_capsules[i]
            } else {
                k
            };
            let shape = LocalCapsule {
                from: [local(was.a, origin), local(was.b, origin)],
                to: [local(k.a, origin), local(k.b, origin)],
                radius: k.radius,
            };
            if !same || was != k {
                self.movers.push(grown(&shape, k.radius.max(was.radius)));
            }
            self.capsules.push(shape.unless_jumped());
        }
        let same = c.sdfs.len() == self.last_fields.len();
        for (i, f) in c.sdfs.iter().enumerate() {
            let now = f.transform();
            let was = if same { self.last_fields[i] } else { now };
            let (lo, hi) = f.bounds();
            // A jump: some corner of the grid's box moved more than
            // COLLIDER_JUMP.
            let jumped = (0..8).any(|k| {
                let c = Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                (now.transform_point3(c) - was.transform_point3(c)).length() > COLLIDER_JUMP
            });
            let was = if jumped { now } else { was };
            let (from_rotation, from_translation) = rigid_local(was, origin);
            let (to_rotation, to_translation) = rigid_local(now, origin);
            let mut field = LocalField {
                index: i,
                from_rotation,
                from_translation,
                to_rotation,
                to_translation,
                swept: Aabb {
                    min: Vec3::INFINITY,
                    max: Vec3::NEG_INFINITY,
                },
            };
            field.swept = field_swept_box(&field, lo, hi);
            if !same || was != now {
                self.movers.push(field.swept);
            }
            self.fields.push(field);
        }
    }

    /// Forgets the last step's colliders: the next step takes every
    /// collider as standing still (after a teleport or a state set from
    /// elsewhere, where the record would describe another place or time).
    pub(crate) fn forget(&mut self) {
        self.last_spheres.clear();
        self.last_capsules.clear();
        self.last_fields.clear();
    }

    /// Remembers this step's colliders (world space) for the next step.
    pub(crate) fn remember(&mut self, c: &Colliders<'_>) {
        self.last_spheres.clear();
        self.last_spheres.extend_from_slice(c.spheres);
        self.last_capsules.clear();
        self.last_capsules.extend_from_slice(c.capsules);
        self.last_fields.clear();
        self.last_fields
            .extend(c.sdfs.iter().map(|f| f.transform()));
    }
}

/// A capsule's swept box grown to radius `r`.
fn grown(shape: &LocalCapsule, r: f32) -> Aabb {
    LocalCapsule {
        radius: r,
        ..*shape
    }
    .swept_box()
}

/// A rigid world transform as local rotation and translation.
fn rigid_local(world_from_mesh: Affine3A, origin: DVec3) -> (Quat, Vec3) {
    let q = Quat::from_mat3a(&world_from_mesh.matrix3).normalize();
    (q, local(world_from_mesh.translation.into(), origin))
}

/// The local box a field's grid box (`lo..hi`, mesh frame) sweeps over the
/// step: its corners at the start, the end and the middle of the step,
/// grown by what the arcs between may bulge beyond those (a corner at
/// distance `R` from the rotation's centre turning by `theta` in one half
/// leaves the chord by at most `R (1 - cos(theta / 2))`; this grows by
/// `R theta^2 / 8`, which bounds it).
fn field_swept_box(f: &LocalField, lo: Vec3, hi: Vec3) -> Aabb {
    let mut b = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };
    let mut radius: f32 = 0.0;
    for share in [0.0, 0.5, 1.0] {
        let x = f.at(share);
        for k in 0..8 {
            let c = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let p = x.transform_point3(c);
            radius = radius.max(c.length());
            b.min = b.min.min(p);
            b.max = b.max.max(p);
        }
    }
    let half_angle = f.from_rotation.angle_between(f.to_rotation) * 0.5;
    let bulge = Vec3::splat(radius * half_angle * half_angle / 8.0 + 1e-6);
    Aabb {
        min: b.min - bulge,
        max: b.max + bulge,
    }
}
