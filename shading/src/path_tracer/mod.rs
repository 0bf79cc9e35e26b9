//! A Monte Carlo path tracer through explicit hair fibres (placeholder docs).

mod bvh;
pub mod fibres;

pub use fibres::{FibreHit, FibreScene};
