//! coif-lod: the level-of-detail stage of a hair frame (DESIGN.md section 5).
//!
//! - [`refine`] (one strand) and [`refine_strands`] (a whole [`Strands`] set,
//!   SIMD, into a caller-owned [`RefinedGuides`]): uniform cubic B-splines
//!   with phantom ends, positions and unit tangents.
//! - [`level`]: segments per span from projected size and a pixel budget.
//! - [`Interpolation`] + [`interpolate`]: dense render hair from guides over
//!   scalp triangles, into a caller-owned [`RenderHairs`].
//! - [`cull`] / [`distance_lod`]: frustum culling of guide blocks and hair
//!   groups, and prefix thinning with coverage-keeping width.
//! - [`RenderVertex`]: a `bytemuck::Pod` vertex for engines.
//! - [`fit`], [`Fitter`], [`Resampler`]: P-spline fits with faer.
//! - [`quality`]: error measurements for time-against-error reports.
//!
//! Every batch path has a scalar twin in [`scalar`].
//!
//! [`Strands`]: coif_kernels::Strands

pub mod bspline;
mod culling;
mod error;
mod fit;
mod interpolation;
pub mod level;
pub mod quality;
mod refine_batch;
mod vertex;

pub use bspline::{refine, refine_with_tangents, refined_len, SpanWeights};
pub use culling::{cull, distance_lod, DistanceLod, Frustum, Visibility};
pub use error::Error;
pub use fit::{arc_length_samples, fit, Fitter, Resampler};
pub use interpolation::{
    barycentric, interpolate, interpolate_positions, HairGroup, Interpolation, RenderHairs,
    M2_PER_CM2, MAX_RENDER_HAIRS,
};
pub use refine_batch::{
    refine_strands, refine_strands_positions, RefinedGuides, DEFAULT_MAX_SEGMENTS_PER_SPAN,
};
pub use vertex::{render_vertex_len, vertex_bytes, write_render_vertices, HairWidth, RenderVertex};

/// Scalar twins of the SIMD batch paths: the same algorithms, in the same
/// order, one strand (or hair) at a time.
pub mod scalar {
    pub use crate::interpolation::scalar::{interpolate, interpolate_positions};
    pub use crate::refine_batch::scalar::{refine_strands, refine_strands_positions};
}
