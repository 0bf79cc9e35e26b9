//! Collision shapes for the hair: the signed distance field of a mesh.
pub(crate) mod sdf;
pub use sdf::{Sdf, MARGIN_CELLS, MAX_SDF_CELLS};
