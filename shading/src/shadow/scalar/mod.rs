//! The scalar twins of the shadow map's SIMD paths: the same algorithms, in
//! the same order and with the same numbered steps, one sample (or point)
//! at a time. Each file mirrors the SIMD file of the same name
//! (`shadow/build.rs` <-> `shadow/scalar/build.rs`, `shadow/raster.rs` <->
//! `shadow/scalar/raster.rs`, `shadow/lookup.rs` <-> `shadow/scalar/lookup.rs`).

mod build;
mod lookup;
pub(crate) mod raster;

pub use build::{build, build_lanes};
pub use lookup::transmittance_batch;
