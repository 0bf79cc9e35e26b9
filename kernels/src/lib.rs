//! coif-kernels: the hair simulation. [`Strands`] holds equal-length strands
//! in SIMD lanes (vertex `v` of block `b` at index `b * V + v`, lane `l` =
//! strand `b * 8 + l`); [`step`] advances them by one fixed step and
//! [`scalar::step`] is its scalar twin; [`step_with`] hands the blocks to a
//! [`tasks::Executor`] as tasks (the same bytes on any number of threads).
//! [`step_colliders`] steps against a [`Colliders`] set: spheres,
//! [`Capsule`]s and signed distance fields of meshes ([`Sdf`]), in wind
//! and linear drag ([`SimParams::wind`], [`SimParams::drag`], gusts) with
//! Coulomb friction (`README.md`, "The world around the hair"), with hair
//! against hair: volume and friction through a grid of the hair
//! ([`SimParams::volume_stiffness`], [`SimParams::hair_friction`];
//! [`hair_grid`], `README.md`, "Hair against hair"). [`patch`]
//! simulates small cloth grids (fins, ribbons) with the same code, columns
//! in lanes.
//!
//! One strand step ([`step`]; `README.md` beside this crate gives every
//! formula, its source and the measurements behind the design) runs
//! `ceil(dt / max_substep)` substeps (default 4 of 1/240 s): 1 broad phase
//! against the colliders (once per step) -> 2 Verlet prediction -> 3 local
//! shape springs, an implicit solve from a sag-free rest state
//! ([`shape`], [`Strands::solve_sag_free`]), and global shape -> 4
//! projection of the
//! length constraints along blended directions by a tridiagonal (Thomas)
//! solve per chain (fast projection, Goldenthal et al. 2007; SHAKE, Ryckaert
//! et al. 1977; the trapezoidal rule, Newmark 1959) -> 5 pearls (Nalu's
//! point-on-segment rule) -> 6 two-sided strain limit (Provot 1995,
//! Follow-The-Leader order, Muller et al. 2012) alternated with the
//! push-out and Coulomb friction -> 7 velocity over the step and a guard that restores a lane
//! gone non-finite. One generic body over [`lanes::Lane`] serves the SIMD
//! path and its scalar twin. Blocks of eight strands that stay still for
//! [`SLEEP_AFTER`] seconds sleep and are skipped until their roots, a moving
//! sphere or a state change wake them ([`SimParams::sleep_speed`],
//! [`Strands::awake_strands`]).
//!
//! The lane math (`Vec3Lanes`, `LANES`, `inv_sqrt_simd`), the RNG, [`Sphere`] and
//! [`StrandBlocks`] come from `coif-base` and are re-exported here.

#![warn(missing_docs)]

mod collide;
mod constraints;
mod drive;
mod error;
mod fixed_step;
mod fused;
pub mod hair_grid;
pub mod measure;
mod params;
pub mod patch;
mod sag_free;
pub mod scalar;
pub mod shape;
mod step;
mod strands;
mod wind;

pub use coif_base::{lanes, rng, tasks, Sphere, StrandBlocks, Vec3Lanes, LANES};
pub use collide::narrow::FIELD_EXIT_SPEED;
pub use collide::rig::COLLIDER_JUMP;
pub use collide::{Capsule, Colliders, Sdf, MARGIN_CELLS, MAX_SDF_CELLS};
pub use drive::MAX_STEP_TASKS;
pub use error::Error;
pub use fixed_step::FixedStep;
pub use measure::{measure, Measures};
pub use params::{SimParams, MAX_ITERATIONS, MAX_PEARLS_PER_SEGMENT, MAX_SUBSTEPS, SLEEP_AFTER};
pub use patch::{Patch, Ribbon};
pub use step::{step, step_colliders, step_colliders_with, step_with};
pub use strands::Strands;
pub use wind::GUST_MODES;
