//! Scalar references of the strand kernels: the same algorithms as the SIMD
//! paths, in the same order, one lane at a time, with plain `f32` arithmetic.
//! The files mirror the SIMD ones: `scalar/step.rs` is the twin of `step.rs`,
//! `scalar/broad_phase.rs` of `broad_phase.rs`'s block box.

pub(crate) mod broad_phase;
mod step;

pub use step::step;
pub(crate) use step::{dot, inv_len, outward, push_out};
