//! Scalar references of the strand kernels: the same algorithms as the SIMD
//! paths, in the same order, one lane at a time, with plain `f32` arithmetic.
//! The files mirror the SIMD ones: `scalar/step.rs` is the twin of `step.rs`
//! (the strand step's generic body instantiated at `f32`),
//! `scalar/broad_phase.rs` of `broad_phase.rs`'s block boxes and
//! `scalar/constraints.rs` of the patch helpers in `constraints.rs`.

pub(crate) mod broad_phase;
mod constraints;
mod step;

pub(crate) use constraints::{dot, inv_len, outward, push_out};
pub(crate) use step::LaneBuffers;
pub use step::{step, step_colliders, step_colliders_with, step_with};
