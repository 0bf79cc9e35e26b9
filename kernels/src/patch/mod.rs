//! Patches: small cloth grids simulated with the strand code, blended with
//! skinned geometry by a weight map (fins, ribbons, skirts, capes).
//!
//! The Nalu demo made its fins from the hair code turned into a cloth
//! simulation and blended the result with the skinned fin by a weight map;
//! Alice: Madness Returns used the same mass-spring code for the skirt and
//! bows (GDC 2011, "Hair and Cloth in Alice"). A [`Patch`] is one
//! grid of `rows x cols` particles:
//!
//! - **Layout** (`grid.rs`): columns in SIMD lanes. Column block `b` holds
//!   columns `8b .. 8b + 8`; particle `(r, c)` lives at index
//!   `(c / 8) * rows + r`, lane `c % 8`, of every per-particle array, so a
//!   column is a contiguous chain like a strand and one register holds eight
//!   neighbours of a row. Vertical constraints are lane-parallel (the strand
//!   code); horizontal, shear and horizontal bending ones pair neighbouring
//!   lanes and run as two colour passes with a lane permutation
//!   (`pairs.rs`). `PATCH.md` beside this crate gives the measurements behind this choice.
//! - **Step** ([`step`], SIMD; [`scalar::step`], its scalar twin): Verlet
//!   with damping, pinned particles placed on their skinned positions,
//!   `iterations` sweeps of distance constraints, long range attachments,
//!   column and row strain limits (`max_stretch`; `row_limit.rs`), the
//!   max-distance clamp around
//!   the skinned positions, sphere and pearl collisions after a broad phase,
//!   and a guard that restores a blown-up patch to its skin.
//! - **Many patches** ([`step_all`], [`scalar::step_all`]): each patch
//!   whole as (part of) one task of a `coif_base::tasks::Executor`; the
//!   same bytes as stepping them one by one.
//! - **Output** (`blend.rs`): `lerp(skinned, simulated, weight)` per
//!   particle, and area-weighted vertex normals of the blended grid.
//!
//! All public slices are world-space grids in **row-major** order: particle
//! `(r, c)` is element `r * cols + c`. Row 0 is usually the attached edge.

mod blend;
mod grid;
mod pairs;
pub mod quality;
mod ribbon;
mod row_limit;
pub mod scalar;
mod step;

pub use blend::grid_normals;
pub use grid::{Patch, MAX_PATCH_COLUMNS};
pub use ribbon::{ribbon_on_sphere, Ribbon};
pub use step::{step, step_all};
