//! coif-testkit: fixtures the crates' own tests share (a dev-dependency
//! only, never part of the library).
//!
//! - [`counting`]: a counting global allocator for the "allocates nothing
//!   per frame" tests.
//! - [`executors`]: an executor that runs tasks backwards and says how many
//!   threads it has, for the "same bytes on any executor" tests.
//! - [`groom_path`]: where the shared TressFX grooms are, or a skip message.
//! - [`mesh_path`], [`load_obj`]: the shared meshes (the Sintel bust) and a
//!   loader of their positions and triangles.
#![warn(missing_docs)]

pub mod counting;
pub mod executors;
pub mod meshes;

use std::path::PathBuf;

/// The path of a shared groom (`shared/data/grooms/NAME` beside the
/// repository), or None with a message when the folder is absent, so that
/// tests needing it skip rather than fail.
pub fn groom_path(name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/grooms")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "skipping: {} is absent (the shared groom folder is not beside the repository)",
            p.display()
        );
        None
    }
}

/// The path of a shared mesh (`shared/data/meshes/NAME` beside the
/// repository), or None with a message when the folder is absent, so that
/// tests needing it skip rather than fail.
pub fn mesh_path(name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/meshes")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "skipping: {} is absent (the shared mesh folder is not beside the repository)",
            p.display()
        );
        None
    }
}

/// A triangle mesh: positions and the triangles that index them.
pub type Mesh = (Vec<glam::Vec3>, Vec<[u32; 3]>);

/// Loads a Wavefront OBJ file with `tobj` (faces triangulated, all models
/// concatenated), its positions multiplied by `scale` (0.01 takes the shared
/// meshes' centimetres to metres). Panics with the path on a read error
/// (a test fixture).
pub fn load_obj(path: &std::path::Path, scale: f32) -> Mesh {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj(path, &opts)
        .unwrap_or_else(|e| panic!("cannot load {}: {e}", path.display()));
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for m in &models {
        let base = positions.len() as u32;
        let mesh = &m.mesh;
        positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|p| glam::Vec3::new(p[0], p[1], p[2]) * scale),
        );
        triangles.extend(
            mesh.indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
    }
    (positions, triangles)
}

/// The shared Sintel bust in metres (3,046 vertices, 5,952 triangles, open
/// at the chest), or None with a skip message when the folder is absent.
pub fn sintel_bust() -> Option<Mesh> {
    mesh_path("sintel_bust.obj").map(|p| load_obj(&p, 0.01))
}
