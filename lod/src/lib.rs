//! coif-lod: the level-of-detail stage of a hair frame.
//!
//! - [`refine`] (one strand) and [`refine_strands`] (a whole `Strands` (coif-kernels) set,
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
//! Errors instead of silent truncation: every call that writes into a
//! caller's buffer or takes containers whose counts must agree returns
//! [`Error::BufferTooSmall`] or [`Error::CountMismatch`] (and writes
//! nothing) when they do not.
//!
//! Every SIMD batch path has a scalar twin of the same name in [`scalar`]
//! (`refine_strands` / `scalar::refine_strands`, `interpolate` /
//! `scalar::interpolate`), with the same numbered steps.
//!
//! A frame, with every buffer sized once up front:
//!
//! ```
//! use coif_kernels::Strands;
//! use coif_lod::{self as lod, level, HairWidth, Interpolation, RefinedGuides, RenderHairs, RenderVertex, Visibility};
//! use glam::{Mat4, Vec3};
//!
//! // Three guides of four points on a 1 cm scalp triangle.
//! let roots = [Vec3::ZERO, Vec3::new(0.01, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.01)];
//! let pts: Vec<Vec3> = roots
//!     .iter()
//!     .flat_map(|r| (0..4).map(move |v| *r + Vec3::new(0.002 * v as f32, -0.03 * v as f32, 0.0)))
//!     .collect();
//! let strands = Strands::from_polylines(&pts, 4)?;
//! let interp = Interpolation::new(&roots, &[[0, 1, 2]], 150.0, 7)?;
//!
//! let mut vis = Visibility::new(strands.strand_count(), interp.group_count());
//! let mut guides = RefinedGuides::new(strands.blocks(), 16)?;
//! let mut hairs = RenderHairs::new(&interp, &guides);
//! let mut vertices = vec![RenderVertex::default(); interp.hair_count() * lod::refined_len(4, 16)];
//!
//! // Per frame: no allocation.
//! let frustum = lod::Frustum::from_view_projection(Mat4::IDENTITY); // your camera's view-projection
//! let px_per_m = level::pixels_per_metre(0.5, 0.8, 1080.0);
//! let d = lod::distance_lod(&interp, 80e-6 * px_per_m, 0.1);
//! lod::cull(strands.blocks(), Some(&interp), d.groups_drawn, &frustum, 1e-3, &mut vis)?;
//! let n = level::segments_per_span(level::max_second_difference_strands(strands.blocks()), px_per_m, 0.5, 16);
//! guides.set_segments_per_span(n)?;
//! lod::refine_strands(strands.blocks(), Some(&vis), &mut guides)?;
//! lod::interpolate(&interp, &guides, Some(&vis), d.groups_drawn, &mut hairs)?;
//! let count = lod::write_render_vertices(&interp, &hairs, d.groups_drawn, HairWidth::default(), d.width_factor, &mut vertices)?;
//! let upload: &[u8] = lod::vertex_bytes(&vertices[..count]); // positions relative to strands.origin()
//! # assert_eq!(upload.len(), 32 * count);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

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
    barycentric, interpolate, interpolate_positions, GroupBlend, HairGroup, Interpolation,
    RenderHairs, M2_PER_CM2, MAX_RENDER_HAIRS,
};
pub use refine_batch::{
    refine_strands, refine_strands_positions, RefinedGuides, DEFAULT_MAX_SEGMENTS_PER_SPAN,
};
pub use vertex::{render_vertex_len, vertex_bytes, write_render_vertices, HairWidth, RenderVertex};

pub mod scalar;
