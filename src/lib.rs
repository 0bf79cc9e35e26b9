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
//! | [`gpu`] | `coif-gpu` | GPU buffers and WGSL: render hairs made in shaders from the guides |
//! | [`glam`] | `glam` | the vector types of the API, re-exported |
//!
//! # Features
//!
//! Each module but [`base`] and [`glam`] is behind the feature of its name
//! (the links above assume the default features); a feature turns on the
//! stages its crate depends on. The default is all of them, with `rayon`.
//! An engine that needs only dynamics, LOD and shading builds only those
//! crates:
//!
//! ```toml
//! coif = { version = "0.1", default-features = false, features = ["kernels", "lod", "shading"] }
//! ```
//!
//! | feature | modules | also turns on | brings in |
//! |---|---|---|---|
//! | `kernels` | `kernels` | | |
//! | `lod` | `lod` | | faer (the P-spline fits) |
//! | `shading` | `shading` | `lod` | |
//! | `geometry` | `geometry`, `groom` | | tobj |
//! | `render` | `render` | `lod`, `shading` | png |
//! | `frame` | `frame` | `kernels`, `lod`, `shading`, `geometry`, `render` | |
//! | `gpu` | `gpu` | `lod` | |
//! | `rayon` | `base::tasks::Rayon` (and the kernels' and frame's use of it) | | rayon |
#![warn(missing_docs)]

pub use coif_base as base;
#[cfg(feature = "frame")]
pub use coif_frame as frame;
#[cfg(feature = "geometry")]
pub use coif_geometry as geometry;
#[cfg(feature = "geometry")]
pub use coif_geometry::groom;
#[cfg(feature = "gpu")]
pub use coif_gpu as gpu;
#[cfg(feature = "kernels")]
pub use coif_kernels as kernels;
#[cfg(feature = "lod")]
pub use coif_lod as lod;
#[cfg(feature = "render")]
pub use coif_render as render;
#[cfg(feature = "shading")]
pub use coif_shading as shading;
/// The vector types of coif's public API (glam 0.34): use `coif::glam` so
/// that your `Vec3` is the one coif takes, without naming its version.
///
/// ```
/// use coif::glam::Vec3;
/// let sphere = coif::base::Sphere { center: Vec3::new(0.0, 1.6, 0.0), radius: 0.1 };
/// assert_eq!(sphere.center.y, 1.6);
/// ```
pub use glam;
