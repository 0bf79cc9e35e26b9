//! coif-kernels: structure-of-arrays strand containers, lane math, and the
//! hair simulation kernels (DESIGN.md sections 3 and 4).
//!
//! Data flow of one simulation step ([`step`], SIMD; [`scalar::step`], its
//! scalar twin): Verlet integration -> shape keeping -> broad phase against
//! the sphere rig -> `iterations` sweeps of (length and bending constraints,
//! strain limit, sphere and pearl collisions) -> non-finite strands restored.

mod broad_phase;
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
pub use params::{SimParams, MAX_PEARLS_PER_SEGMENT};
pub use patch::{Patch, Ribbon};
pub use step::step;
pub use strands::Strands;
