//! A frame of the pipeline allocates nothing: every buffer is sized once
//! at construction (a counting global allocator, `common::counting`),
//! from the very first frame on, including the frame that sets the LOD level,
//! with the ribbons on (cloth steps, blend, normals, shading, triangles).

mod common;

use coif_frame::{motion, FramePipeline, FrameSettings, HairScene, PrepareMode, ShadingModel};
use coif_geometry::scene::GrowOptions;
use coif_testkit::counting::allocations;

#[global_allocator]
static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;

#[test]
fn frames_allocate_nothing_for_every_shading_model() {
    let scene = HairScene::procedural(&GrowOptions {
        strand_count: 256,
        verts_per_strand: 12,
        ..GrowOptions::default()
    })
    .unwrap();
    let modes = [PrepareMode::Fused, PrepareMode::Reference];
    for (model, prepare) in ShadingModel::ALL
        .into_iter()
        .flat_map(|m| modes.map(|p| (m, p)))
    {
        let settings = FrameSettings {
            shading: model,
            prepare,
            ..FrameSettings::small(64)
        };
        let mut p = FramePipeline::new(&scene, settings, 0.1).unwrap();
        assert_eq!(p.ribbons().len(), 2, "the ribbons are on");
        let pivot = p.pivot();
        let mut levels = Vec::with_capacity(8);
        let before = allocations();
        let mut drawn = 0;
        let mut ribbon_pixels = 0;
        // The first frame sets the level; then frames with 0, 1, 2 and 4
        // (capped) substeps while the head turns.
        for (f, dt) in [1.0f32 / 60.0, 0.01, 1.0 / 60.0, 1.0 / 30.0, 0.2]
            .iter()
            .enumerate()
        {
            let stats = p.frame(*dt, motion::turn_and_nod(0.3 * f as f32, pivot));
            levels.push(stats.segments_per_span);
            drawn += stats.segments;
            ribbon_pixels += stats.ribbon_pixels;
        }
        assert_eq!(
            allocations() - before,
            0,
            "{model} {prepare:?}: allocations during frames"
        );
        assert!(levels.iter().all(|&l| l >= 1), "{model}: levels {levels:?}");
        assert!(
            ribbon_pixels > 0,
            "{model}: the frames drew the ribbons ({ribbon_pixels} pixels)"
        );
        assert!(
            drawn > 1000,
            "{model}: the frames drew hair ({drawn} segments)"
        );
    }
}
