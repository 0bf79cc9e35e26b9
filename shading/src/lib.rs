//! coif-shading: hair shading models (Kajiya-Kay, Marschner 2003 and its
//! factored lookup tables, pbrt-v3's hair BSDF as the accuracy yardstick),
//! evaluated per sample (scalar) and in SIMD batches over [`ShadingSamples`].

mod batch;
mod error;
pub mod kajiya_kay;
pub mod marschner;
pub mod pbrt;
pub mod samples;
pub mod shadow;
pub mod yardstick;

pub use error::Error;
pub use samples::{RgbBuffer, ShadingSamples};
