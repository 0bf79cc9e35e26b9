//! coif-kernels: structure-of-arrays strand containers, lane math, and the
//! hair simulation kernels (DESIGN.md sections 3 and 4).
//!
//! Data flow of one simulation step ([`step`], SIMD; [`scalar::step`], its
//! scalar twin): Verlet integration -> shape keeping -> broad phase against
//! the sphere rig -> `iterations` sweeps of (length and bending constraints,
//! strain limit, sphere and pearl collisions) -> non-finite strands restored.

mod error;
pub mod lanes;
mod params;
pub mod rng;
mod strands;

pub use error::Error;
pub use lanes::{Vec3x8, LANES};
pub use params::{SimParams, Sphere, MAX_PEARLS_PER_SEGMENT};
pub use strands::Strands;
