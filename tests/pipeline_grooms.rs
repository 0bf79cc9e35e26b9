//! Both shared TressFX grooms load, become guides with scalp triangles and
//! render a frame with hair in it.

use coif::groom;
use coif::pipeline::{FramePipeline, FrameSettings, HairScene};
use glam::Affine3A;
use std::path::PathBuf;

fn groom_path(name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/data/grooms")
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

#[test]
fn both_shared_grooms_render_a_frame_with_hair() {
    for (name, max_guides) in [("ratboy_mohawk.tfx", 600), ("sintel_lite.tfx", 600)] {
        let Some(path) = groom_path(name) else {
            continue;
        };
        let g = groom::load(&std::fs::read(&path).unwrap()).unwrap();
        let scene = HairScene::from_groom(&g, max_guides, 16).unwrap();
        assert!(
            scene.guide_count() <= max_guides && scene.guide_count() > 100,
            "{name}: {}",
            scene.guide_count()
        );
        assert!(
            scene.triangles.len() > scene.guide_count() / 2,
            "{name}: {} triangles",
            scene.triangles.len()
        );
        // Metres: a head-sized groom.
        assert!(
            scene.extent > 0.05 && scene.extent < 1.0,
            "{name}: extent {} m",
            scene.extent
        );
        let settings = FrameSettings {
            render_hairs_per_cm2: 10.0,
            ..FrameSettings::small(96)
        };
        let mut p = FramePipeline::new(&scene, settings.clone(), 0.2).unwrap();
        let stats = p.frame(1.0 / 30.0, Affine3A::IDENTITY);
        assert!(stats.hairs > 100, "{name}: {stats:?}");
        let with_hair = p.image();
        let mut bare = FramePipeline::new(
            &scene,
            FrameSettings {
                hair_opacity: 0.0,
                ..settings
            },
            0.2,
        )
        .unwrap();
        bare.frame(1.0 / 30.0, Affine3A::IDENTITY);
        let bare = bare.image();
        let changed = with_hair
            .data
            .chunks_exact(3)
            .zip(bare.data.chunks_exact(3))
            .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 12))
            .count();
        assert!(
            changed > 96 * 96 / 20,
            "{name}: hair covers {changed} pixels"
        );
        assert!(p.vertex_colors().r.iter().all(|c| c.is_finite()));
    }
}
