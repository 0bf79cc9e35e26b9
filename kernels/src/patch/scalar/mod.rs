//! Scalar references of the patch kernels: the same algorithms as the SIMD
//! paths, in the same order, one particle at a time. `patch/scalar/step.rs`
//! mirrors `patch/step.rs`. (The row strain limit, `patch/row_limit.rs`, is
//! serial across lanes and has no twin: both steps call it.)

mod step;

pub use step::{step, step_all};
