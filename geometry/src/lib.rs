//! coif-geometry: where hair comes from, before anything moves.
//!
//! - [`groom`]: authored grooms, TressFX 4 `.tfx` and cyHair `.hair`, loaded
//!   from bytes with every count and offset checked.
//! - [`grow`]: the one strand grower: strands from roots and normals, with
//!   optional curl.
//! - [`mesh`]: body meshes (a character's head and shoulders) read from
//!   Wavefront OBJ, validated, with vertex normals.
//! - [`scalp`]: scalp triangle meshes with area-weighted vertex normals,
//!   guides grown from their vertices.
//! - [`triangulate`]: scalp triangles from guide roots (a groom file has
//!   none): the spherical Delaunay triangulation of their directions.
//! - [`scene`]: built-in scenes that need no files: hair grown on a sphere
//!   head, collision rigs, a stand-in head for grooms that come without one.
//!
//! Everything here is geometry at rest: it depends on `coif-base` only.
//! Draping hair under gravity is a simulation (`coif_frame::drape`).
#![warn(missing_docs)]

pub mod groom;
pub mod grow;
pub mod mesh;
pub mod scalp;
pub mod scene;
pub mod triangulate;
