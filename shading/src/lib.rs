//! coif-shading: hair shading models (Kajiya-Kay, Marschner 2003 and its
//! factored lookup tables, pbrt-v3's hair BSDF as the accuracy yardstick),
//! evaluated per sample (scalar) and in SIMD batches over [`ShadingSamples`]
//! or straight from LOD's render vertices ([`vertices::shade_vertices`]),
//! opacity shadow maps ([`shadow`]), multiple scattering by dual
//! scattering ([`dual_scattering`]) and a Monte Carlo path tracer through
//! explicit fibres as its reference ([`path_tracer`]).
//!
//! One convention for the twins: a per-sample function `name` (one `Vec3`)
//! has an eight-lane twin `name_simd` (`Vec3Lanes`), e.g.
//! [`kajiya_kay::KajiyaKay::shade`] / [`kajiya_kay::KajiyaKay::shade_simd`]; a
//! SIMD batch method `Type::name` has its scalar reference `scalar::name`
//! (a free function taking `&Type`) in the `scalar` submodule of its module,
//! e.g. [`shadow::OpacityShadowMap::build`] / [`shadow::scalar::build`].
#![warn(missing_docs)]

mod batch;
pub mod dual_scattering;
mod error;
pub mod kajiya_kay;
pub mod marschner;
pub mod path_tracer;
pub mod pbrt;
pub mod samples;
pub mod shadow;
pub mod vertices;
pub mod yardstick;

pub use error::Error;
pub use samples::{RgbBuffer, SampleColumns, ShadingSamples};
