//! A crowd: many characters with the same groom, simulation only, with
//! every way of skipping simulation a scene does not need, or none.
//!
//! Each character is a [`SimLod`] placed in the world, standing still or
//! turning and nodding ([`crate::motion::turn_and_nod`], looped every 4 s).
//! With `skip` on ([`Crowd::new`]), per step:
//!
//! - a character outside the camera's frustum ([`CrowdCamera::sees`], its
//!   hair's bounding sphere) is carried rigidly by its head
//!   ([`SimLod::follow_rigidly`]): nothing is stepped;
//! - one on screen simulates the level its height on screen picks
//!   ([`SimLod::level_for_height`]: every guide at 240 px and above, one
//!   level more per halving);
//! - sleeping (`SimParams::sleep_speed`) skips the blocks of a character
//!   that stands still.
//!
//! With `skip` off, every character simulates every guide every step,
//! never sleeping: the reference the cost and the error are measured
//! against. Characters are independent tasks (`coif_base::tasks`); counts
//! are summed afterwards in character order, so any thread count gives the
//! same bytes.

use crate::motion::turn_and_nod;
use crate::sim_lod::SimLod;
use crate::{Error, HairScene};
use coif_base::tasks::{for_each_chunk_mut, Executor};
use coif_kernels::{SimParams, Sphere};
use glam::{Affine3A, Vec3};

/// A pinhole camera for visibility and on-screen size (no pixels drawn).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrowdCamera {
    /// Eye position.
    pub eye: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit up direction (orthogonal to `forward`).
    pub up: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Width over height.
    pub aspect: f32,
    /// Image height in pixels.
    pub height_px: f32,
}

impl Default for CrowdCamera {
    /// At the origin looking down -z, 40 degrees, 16:9, 1080 pixels tall.
    fn default() -> Self {
        CrowdCamera {
            eye: Vec3::ZERO,
            forward: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y: 40f32.to_radians(),
            aspect: 16.0 / 9.0,
            height_px: 1080.0,
        }
    }
}

/// Nearest distance the camera sees (metres).
const NEAR: f32 = 0.05;

impl CrowdCamera {
    /// True if the sphere (`centre`, `radius`) reaches into the view
    /// frustum (beyond the near plane and inside the four side planes;
    /// conservative near the frustum's edges, like every sphere test).
    pub fn sees(&self, centre: Vec3, radius: f32) -> bool {
        let d = centre - self.eye;
        let right = self.forward.cross(self.up);
        let (z, x, y) = (d.dot(self.forward), d.dot(right), d.dot(self.up));
        let ty = (0.5 * self.fov_y).tan();
        let tx = ty * self.aspect;
        // Distance of the centre to a side plane through the eye whose
        // slope is t: (|c| - t z) / sqrt(1 + t^2), positive outside.
        let out = |c: f32, t: f32| (c.abs() - t * z) / (1.0 + t * t).sqrt() > radius;
        z + radius > NEAR && !out(x, tx) && !out(y, ty)
    }

    /// The sphere's diameter on screen in pixels (its depth clamped to the
    /// near plane): `2 r / (2 z tan(fov_y / 2)) * height_px`.
    pub fn height_on_screen(&self, centre: Vec3, radius: f32) -> f32 {
        let z = (centre - self.eye).dot(self.forward).max(NEAR);
        radius / (z * (0.5 * self.fov_y).tan()) * self.height_px
    }
}

/// Where a character stands and whether it moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The groom's rest pose (head pose identity) moved to its place.
    pub place: Affine3A,
    /// Turns and nods (looped), or stands still.
    pub moving: bool,
    /// Seconds added to the time of its motion.
    pub phase: f32,
}

/// How the standard crowd of `n` stands in front of [`CrowdCamera::default`]:
/// a quarter (rounded up) near the camera (2.5-4 m), a quarter (rounded
/// down) off screen (behind the camera or far to the side), the rest far
/// (25-60 m); every other character moves. `focus` is the point of the
/// groom that is placed (its hair's centre).
pub fn standard_layout(n: usize, focus: Vec3) -> Vec<Placement> {
    let near = n.div_ceil(4);
    let off = n / 4;
    (0..n)
        .map(|i| {
            let spot = if i < near {
                let k = i as f32;
                Vec3::new(-0.9 + 0.6 * k, 0.0, -2.5 - 0.5 * k)
            } else if i < near + off {
                let k = (i - near) as f32;
                if (i - near).is_multiple_of(2) {
                    Vec3::new(2.0 * k - 3.0, 0.0, 6.0 + k)
                } else {
                    Vec3::new(60.0 + 5.0 * k, 0.0, -5.0)
                }
            } else {
                let k = (i - near - off) as f32;
                Vec3::new(-6.0 + 2.0 * k, 0.0, -25.0 - 5.0 * k)
            };
            Placement {
                place: Affine3A::from_translation(spot - focus),
                moving: i % 2 == 0,
                phase: 0.37 * i as f32,
            }
        })
        .collect()
}

/// Steps a crowd's groom is draped for before it starts (7 s of 1/60 s:
/// grown hair falls from straight out and comes to rest on the head).
pub const SETTLE_STEPS: usize = 420;

/// The built-in head for a crowd: `strand_count` roots grown
/// ([`HairScene::procedural`], curl 0.15, `verts` points each, the face
/// left bare, no ribbons) and the guides draped for [`SETTLE_STEPS`]
/// steps: the rest shape and the settled pose a crowd starts from.
pub fn settled_head(strand_count: usize, verts: usize) -> Result<(HairScene, Vec<Vec3>), Error> {
    let scene = HairScene::procedural(&coif_geometry::scene::GrowOptions {
        strand_count,
        verts_per_strand: verts,
        curl: 0.15,
        ..Default::default()
    })?
    .without_ribbons();
    let settled = crate::drape::drape(&scene.guides, verts, &scene.rig, SETTLE_STEPS)?;
    Ok((scene, settled))
}

/// What one character did in the last step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CharacterStep {
    /// Inside the frustum.
    pub visible: bool,
    /// The simulation level used (0 = every guide).
    pub level: usize,
    /// Strands the step advanced (awake strands of the level; 0 off screen).
    pub simulated: usize,
    /// Guides of the character (simulated or not).
    pub guides: usize,
}

/// One character.
#[derive(Clone, Debug)]
struct Character {
    lod: SimLod,
    at: Placement,
    /// The rig at rest (head pose identity) and this step's, world space.
    rig_rest: Vec<Sphere>,
    rig: Vec<Sphere>,
    last: CharacterStep,
}

/// Many characters, stepped together.
#[derive(Clone, Debug)]
pub struct Crowd {
    characters: Vec<Character>,
    camera: CrowdCamera,
    params: SimParams,
    skip: bool,
    pivot: Vec3,
    focus: Vec3,
    extent: f32,
}

impl Crowd {
    /// A crowd of `scene`'s groom at `placements`, starting from `settled`
    /// (the guides at rest, e.g. draped; `scene.guides` gives the rest
    /// shape), simulating with `params` (validated). With `skip`, the
    /// simulation LOD of [`SimLod`] (levels of `strides`), off-screen
    /// following and sleeping are on; without, every character simulates
    /// every guide with `sleep_speed` 0.
    pub fn new(
        scene: &HairScene,
        settled: &[Vec3],
        placements: &[Placement],
        camera: CrowdCamera,
        params: &SimParams,
        strides: &[usize],
        skip: bool,
    ) -> Result<Crowd, Error> {
        params.validate()?;
        let strides: &[usize] = if skip { strides } else { &[1] };
        let mut lod = SimLod::new(&scene.guides, settled, scene.verts_per_strand, strides)?;
        lod.reserve_rig(scene.rig.len());
        let params = if skip {
            params.clone()
        } else {
            SimParams {
                sleep_speed: 0.0,
                ..params.clone()
            }
        };
        let characters = placements
            .iter()
            .map(|at| {
                let mut lod = lod.clone();
                // Moved to its place rigidly: no velocity.
                lod.follow_rigidly(at.place);
                Character {
                    lod,
                    at: *at,
                    rig_rest: scene.rig.clone(),
                    rig: scene.rig.clone(),
                    last: CharacterStep::default(),
                }
            })
            .collect();
        Ok(Crowd {
            characters,
            camera,
            params,
            skip,
            pivot: scene.pivot,
            focus: scene.focus,
            extent: scene.extent,
        })
    }

    /// The standard crowd of `n` ([`standard_layout`]) before
    /// [`CrowdCamera::default`], levels of [`crate::sim_lod::STRIDES`].
    pub fn standard(
        scene: &HairScene,
        settled: &[Vec3],
        n: usize,
        params: &SimParams,
        skip: bool,
    ) -> Result<Crowd, Error> {
        let layout = standard_layout(n, scene.focus);
        let strides = crate::sim_lod::STRIDES;
        Crowd::new(
            scene,
            settled,
            &layout,
            CrowdCamera::default(),
            params,
            &strides,
            skip,
        )
    }

    /// One step of every character at time `t` (seconds), as independent
    /// tasks on `executor`.
    pub fn step(&mut self, t: f32, executor: &dyn Executor) {
        let (camera, params, skip) = (self.camera, &self.params, self.skip);
        let (pivot, focus, extent) = (self.pivot, self.focus, self.extent);
        for_each_chunk_mut(executor, &mut self.characters, 1, &|_, chunk| {
            for c in chunk {
                c.step(t, &camera, params, skip, (pivot, focus, extent));
            }
        });
    }

    /// Number of characters.
    pub fn len(&self) -> usize {
        self.characters.len()
    }

    /// True for a crowd of nobody.
    pub fn is_empty(&self) -> bool {
        self.characters.is_empty()
    }

    /// What character `i` did in the last step.
    pub fn character_step(&self, i: usize) -> Option<CharacterStep> {
        self.characters.get(i).map(|c| c.last)
    }

    /// Character `i`'s guides, world space, strand after strand, as of
    /// its last step on screen, and the rigid motion its head has carried
    /// them by since ([`SimLod::carried`]; identity on screen).
    pub fn positions(&self, i: usize) -> Option<(&[Vec3], Affine3A)> {
        self.characters
            .get(i)
            .map(|c| (c.lod.positions(), c.lod.carried()))
    }

    /// Strands advanced by the last step, summed over characters in order.
    pub fn simulated_strands(&self) -> usize {
        self.characters.iter().map(|c| c.last.simulated).sum()
    }

    /// Every character's guides (what simulating everyone fully advances).
    pub fn guide_count(&self) -> usize {
        self.characters.iter().map(|c| c.lod.guide_count()).sum()
    }

    /// Points per guide.
    pub fn verts_per_strand(&self) -> usize {
        self.characters
            .first()
            .map_or(0, |c| c.lod.verts_per_strand())
    }
}

impl Character {
    fn step(
        &mut self,
        t: f32,
        camera: &CrowdCamera,
        params: &SimParams,
        skip: bool,
        (pivot, focus, extent): (Vec3, Vec3, f32),
    ) {
        let motion = if self.at.moving {
            turn_and_nod((t + self.at.phase).rem_euclid(4.0), pivot)
        } else {
            Affine3A::IDENTITY
        };
        let pose = self.at.place * motion;
        let centre = pose.transform_point3(focus);
        let visible = camera.sees(centre, extent);
        let guides = self.lod.guide_count();
        if skip && !visible {
            self.lod.follow_rigidly(pose);
            self.last = CharacterStep {
                visible,
                level: self.lod.level(),
                simulated: 0,
                guides,
            };
            return;
        }
        let level = if skip {
            self.lod
                .level_for_height(camera.height_on_screen(centre, extent))
        } else {
            0
        };
        for (s, r) in self.rig.iter_mut().zip(&self.rig_rest) {
            s.center = pose.transform_point3(r.center);
        }
        self.lod.set_level(level, &self.rig, params.pearl_radius);
        self.lod.step(params, pose, &self.rig);
        self.last = CharacterStep {
            visible,
            level: self.lod.level(),
            simulated: self.lod.strands().awake_strands(),
            guides,
        };
    }
}

/// Root-mean-square vertex distance between two crowds of the same
/// characters, per group of `a`'s last step: index `l` for characters on
/// screen at level `l`, the last index for those off screen; each entry is
/// `(sum of squared distances, vertices)`, added to `acc` (so that a run
/// can add every step). Characters whose vertex counts differ are skipped.
pub fn add_distances(a: &Crowd, b: &Crowd, acc: &mut [(f64, usize)]) {
    if acc.is_empty() {
        return;
    }
    let off = acc.len() - 1;
    for (ca, cb) in a.characters.iter().zip(&b.characters) {
        let (pa, pb) = (ca.lod.positions(), cb.lod.positions());
        if pa.len() != pb.len() {
            continue;
        }
        // Off screen, `a`'s hair is where its head carried it.
        let (ma, mb) = (ca.lod.carried(), cb.lod.carried());
        let group = if ca.last.visible {
            ca.last.level.min(off.saturating_sub(1))
        } else {
            off
        };
        let sum: f64 = pa
            .iter()
            .zip(pb)
            .map(|(x, y)| {
                ma.transform_point3(*x)
                    .distance_squared(mb.transform_point3(*y)) as f64
            })
            .sum();
        acc[group].0 += sum;
        acc[group].1 += pa.len();
    }
}
