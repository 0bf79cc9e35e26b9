//! The GPU draw path's per-frame work on the CPU allocates nothing after
//! warm-up: the level chosen from the camera, the guides packed into the
//! hair's persistent buffer, the view filled (`gpu::prepare_frame`, what
//! `update_gpu_hairs` does before its two `write_buffer` calls, whose
//! staging is wgpu's). One test in this binary, so the all-threads count is
//! this test's.
#![cfg(feature = "render")]
mod common;

use coif::glam as cg;
use coif_bevy::gpu::prepare_frame;
use coif_bevy::render::View;
use coif_bevy::*;
use coif_gpu::{GuideVertex, HairView};
use coif_testkit::counting::{allocations_all_threads, Counting};
use common::*;

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn gpu_path_prepares_a_frame_without_allocating() {
    let groom = sintel_groom();
    let hair = Hair::new(Default::default());
    let state = HairState::for_draw_path(&hair, &groom, cg::Affine3A::IDENTITY, HairDrawPath::Gpu)
        .expect("Sintel's state");
    let mut guides = vec![GuideVertex::default(); state.positions().len()];
    let mut view = HairView::default();
    let near = View {
        eye: cg::Vec3::new(0.0, 0.35, 0.8),
        fov_y: std::f32::consts::FRAC_PI_4,
        height: 720.0,
    };
    let far = View {
        eye: cg::Vec3::new(0.0, 0.35, 12.0),
        ..near
    };
    // Warm-up, then frames alternating between two levels.
    let all = prepare_frame(&hair, &state, Some(near), &mut guides, &mut view);
    let before = allocations_all_threads();
    let mut drawn = [0; 2];
    for f in 0..100 {
        let camera = if f % 2 == 0 { near } else { far };
        drawn[f % 2] = prepare_frame(&hair, &state, Some(camera), &mut guides, &mut view);
    }
    let allocated = allocations_all_threads() - before;
    println!(
        "render hairs drawn: near {}, far {}; {allocated} allocations in 100 frames",
        drawn[0], drawn[1]
    );
    assert_eq!(allocated, 0, "the GPU path's frame allocated");
    assert_eq!(drawn[0], all);
    assert!(
        drawn[1] < drawn[0] / 4 && drawn[1] > 0,
        "the far view draws fewer: {drawn:?}"
    );
    assert_eq!(view.hairs as usize, drawn[1]);
    // The guides packed are the strands' positions (origin-relative).
    let origin = view.world_from_local[3];
    for (g, p) in guides.iter().zip(state.positions()) {
        let world = cg::Vec3::from(g.position) + cg::Vec3::new(origin[0], origin[1], origin[2]);
        assert!(world.distance(*p) < 1e-5, "{world} vs {p}");
    }
}
