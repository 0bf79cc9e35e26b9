//! A Monte Carlo path tracer through explicit hair fibres (placeholder docs).

mod bvh;
pub mod fibres;
pub mod tracer;
pub mod tuft;

pub use fibres::{FibreHit, FibreScene, T_MIN_RADII};
pub use tracer::{
    ray_seed, DirectionalLight, PathSample, PathTracer, RadianceEstimate, MAX_DEPTH_LIMIT,
    ROULETTE_AFTER, ROULETTE_THRESHOLD,
};
pub use tuft::{orthographic_rays, tuft, Tuft, TuftParams};
