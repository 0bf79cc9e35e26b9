//! Fixtures shared by the frame tests.
#![allow(dead_code)]

pub mod counting;

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

/// The small procedural head of the frame tests: 384 guides of 16
/// vertices, light curl.
pub fn small_hair_scene() -> coif_frame::HairScene {
    coif_frame::HairScene::procedural(&coif_geometry::scene::GrowOptions {
        strand_count: 384,
        verts_per_strand: 16,
        curl: 0.15,
        ..Default::default()
    })
    .expect("the small procedural scene is valid")
}
