//! The scalar twins of the renderer's SIMD paths: the same algorithms, in
//! the same order and with the same numbered steps, one pixel at a time.
//! Each file mirrors the SIMD file of the same name (`src/raster.rs` <->
//! `src/scalar/raster.rs`); the tests hold every pair to agreement.

pub(crate) mod raster;

pub use raster::draw;
