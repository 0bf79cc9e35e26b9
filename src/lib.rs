//! coif: structure-of-arrays SIMD kernels for real-time hair.
//!
//! The data flow of a frame: geometry ([`scene`], [`scalp`], [`groom`]) -> dynamics
//! ([`kernels`]: Verlet, constraints, collisions) -> LOD ([`lod`]) ->
//! shading ([`shading`]). [`pipeline`] runs a whole frame into buffers
//! sized once, and [`render`] draws it in software for the demo.

pub use coif_kernels as kernels;
pub use coif_lod as lod;
pub use coif_shading as shading;

pub mod groom;
pub mod pipeline;
pub mod quality;
pub mod render;
pub mod report;
pub mod scalp;
pub mod scene;
