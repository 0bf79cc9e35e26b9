//! coif: structure-of-arrays SIMD kernels for real-time hair.
//!
//! This crate is the facade: it re-exports the library crates under one
//! name, in the order a frame's data flows through them.
//!
//! | module | crate | stage |
//! |---|---|---|
//! | [`base`] | `coif-base` | lane math, the strand-block view, the rig sphere, the RNG |
//! | [`geometry`] (and [`groom`]) | `coif-geometry` | grooms, scalp meshes, built-in scenes |
//! | [`kernels`] | `coif-kernels` | dynamics: strands and cloth patches |
//! | [`lod`] | `coif-lod` | B-spline refinement, interpolation, fits, LOD and culling |
//! | [`shading`] | `coif-shading` | Kajiya-Kay, Marschner, pbrt-v3, opacity shadow maps |
//! | [`frame`] | `coif-frame` | the frame pipeline: simulation to pixels |
//! | [`render`] | `coif-render` | the small software renderer the frame draws with |
//! | [`glam`] | `glam` | the vector types of the API, re-exported |
#![warn(missing_docs)]

pub use coif_base as base;
pub use coif_frame as frame;
pub use coif_geometry as geometry;
pub use coif_geometry::groom;
pub use coif_kernels as kernels;
pub use coif_lod as lod;
pub use coif_render as render;
pub use coif_shading as shading;
/// The vector types of coif's public API (glam 0.34): use `coif::glam` so
/// that your `Vec3` is the one coif takes, without naming its version.
///
/// ```
/// use coif::glam::Vec3;
/// let sphere = coif::kernels::Sphere { center: Vec3::new(0.0, 1.6, 0.0), radius: 0.1 };
/// assert_eq!(sphere.center.y, 1.6);
/// ```
pub use glam;
