//! coif-kernels: the hair simulation. [`Strands`] holds equal-length strands
//! in SIMD lanes (vertex `v` of block `b` at index `b * V + v`, lane `l` =
//! strand `b * 8 + l`); [`step`] advances them by one fixed step and
//! [`scalar::step`] is its scalar twin. [`patch`] simulates small cloth grids
//! (fins, ribbons) with the same code, columns in lanes.
//!
//! One strand step ([`step`]; `README.md` beside this crate gives every
//! formula and its source): 1 Verlet with damping (Yip 2011) -> 2 shape
//! keeping -> 3 broad phase against the sphere rig -> 4 `iterations` sweeps of
//! length and bending constraints (Jakobsen 2001) -> 5 strain limit
//! (Provot 1995, Follow-The-Leader order, Muller et al. 2012) alternated with
//! the sphere collisions -> 6 pearls (Nalu's point-on-segment rule) -> 7 a
//! guard that restores a lane gone non-finite.
//!
//! The lane math (`Vec3x8`, `LANES`, `inv_sqrt_x8`), the RNG, [`Sphere`] and
//! [`StrandBlocks`] come from `coif-base` and are re-exported here.

#![warn(missing_docs)]

mod broad_phase;
mod constraints;
mod error;
mod fixed_step;
pub mod measure;
mod params;
pub mod patch;
pub mod scalar;
mod step;
mod strands;

pub use coif_base::{lanes, rng, Sphere, StrandBlocks, Vec3x8, LANES};
pub use error::Error;
pub use fixed_step::FixedStep;
pub use measure::{measure, Measures};
pub use params::{SimParams, MAX_PEARLS_PER_SEGMENT, MAX_SUBSTEPS};
pub use patch::{Patch, Ribbon};
pub use step::step;
pub use strands::Strands;
