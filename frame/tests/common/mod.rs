//! Fixtures shared by the frame tests.
#![allow(dead_code)]

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
