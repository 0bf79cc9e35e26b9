//! coif-geometry: where hair comes from, before anything moves.
//!
//! - [`groom`]: authored grooms, TressFX 4 `.tfx` and cyHair `.hair`, loaded
//!   from bytes with every count and offset checked.
//! - [`scalp`]: scalp triangle meshes with area-weighted vertex normals, and
//!   guide strands grown from them along the normals.
//! - [`scene`]: built-in scenes that need no files: hair grown on a sphere
//!   head, collision rigs, a stand-in head for grooms that come without one.

pub mod groom;
pub mod scalp;
pub mod scene;
