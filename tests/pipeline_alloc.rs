//! A frame of the pipeline allocates nothing: every buffer is sized once
//! at construction (counting global allocator, as tests/lod_pipeline.rs).
//!
//! Known exception, outside this crate: when the LOD level (segments per
//! span) changes, `coif_lod::RefinedGuides::set_segments_per_span` builds a
//! `SpanWeights` (two small `Vec`s) although its doc says it does not
//! allocate. The test therefore runs one warm-up frame (which sets the
//! level) and checks that the level stays put over the counted frames.

use coif::pipeline::{motion, FramePipeline, FrameSettings, HairScene, ShadingModel};
use coif::scene::GrowOptions;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> usize {
    ALLOCATIONS.with(|a| a.get())
}

#[test]
fn frames_allocate_nothing_for_every_shading_model() {
    let scene = HairScene::procedural(&GrowOptions {
        strand_count: 256,
        verts_per_strand: 12,
        ..GrowOptions::default()
    })
    .unwrap();
    for model in ShadingModel::ALL {
        let settings = FrameSettings {
            shading: model,
            ..FrameSettings::small(64)
        };
        let mut p = FramePipeline::new(&scene, settings, 0.1).unwrap();
        let pivot = p.pivot();
        let level = p
            .frame(1.0 / 60.0, motion::turn_and_nod(0.0, pivot))
            .segments_per_span;
        let before = allocations();
        let mut drawn = 0;
        // Frames with 0, 1, 2 and 4 (capped) substeps, while the head turns.
        for (f, dt) in [0.01f32, 1.0 / 60.0, 1.0 / 30.0, 0.2].iter().enumerate() {
            let stats = p.frame(*dt, motion::turn_and_nod(0.3 * f as f32, pivot));
            assert_eq!(stats.segments_per_span, level, "the level stays put");
            drawn += stats.segments;
        }
        assert_eq!(
            allocations() - before,
            0,
            "{model}: allocations during frames"
        );
        assert!(
            drawn > 1000,
            "{model}: the frames drew hair ({drawn} segments)"
        );
    }
}
