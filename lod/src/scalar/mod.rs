//! The scalar twins of the SIMD batch paths: the same algorithms, in the
//! same order and with the same numbered steps, one strand (or hair) at a
//! time, no SIMD. Each file mirrors the SIMD file of the same name
//! (`src/refine_batch.rs` <-> `src/scalar/refine_batch.rs`,
//! `src/interpolation.rs` <-> `src/scalar/interpolation.rs`); the tests
//! hold every pair to agreement.

mod interpolation;
mod refine_batch;

pub use interpolation::{interpolate, interpolate_positions};
pub(crate) use refine_batch::unit_or_y;
pub use refine_batch::{refine_strands, refine_strands_positions};
