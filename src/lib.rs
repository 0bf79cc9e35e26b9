//! coif: structure-of-arrays SIMD kernels for real-time hair.
pub use coif_kernels as kernels;
pub use coif_lod as lod;
pub use coif_shading as shading;
