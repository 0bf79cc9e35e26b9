//! coif-base: what every coif crate shares.
//!
//! - [`lanes`]: [`Vec3Lanes`], [`LANES`] 3-vectors in three [`F32Lanes`]
//!   registers: strands (or shading samples) in SIMD lanes, 8 or 16 wide
//!   (a build-time choice: `avx512f` or the `lanes16` feature give 16).
//! - [`StrandBlocks`]: a read-only view of strands stored in lane blocks.
//! - [`Sphere`]: the collision rig's primitive.
//! - [`polyline`]: [`polyline::arc_length_samples`], a polyline resampled
//!   uniformly in arc length (grooms of any vertex counts to the step's).
//! - [`rng`]: [`SplitMix64`], the small deterministic generator behind every
//!   random choice (scenes, sampling, tests), so the same seed gives the
//!   same bytes on every machine.
//! - [`tasks`]: the [`tasks::Executor`] a stage's independent tasks run
//!   on: the calling thread, a rayon pool (feature `rayon`, default) or an
//!   engine's own job system.
#![warn(missing_docs)]

pub mod lanes;
pub mod polyline;
pub mod rng;
mod sphere;
mod strand_blocks;
pub mod tasks;

pub use lanes::{F32Lanes, I32Lanes, Vec3Lanes, LANES};
pub use rng::SplitMix64;
pub use sphere::Sphere;
pub use strand_blocks::StrandBlocks;
