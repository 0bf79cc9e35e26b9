//! The software renderer's anti-aliased lines and back-to-front blending.

use coif_lod::RenderVertex;
use coif_render::line::{draw_segment, ScreenVertex};
use coif_render::sort::DepthOrder;
use coif_render::{hair, Camera, Framebuffer};
use coif_shading::RgbBuffer;
use glam::Vec3;

fn vertex(x: f32, y: f32, width_px: f32) -> ScreenVertex {
    ScreenVertex {
        x,
        y,
        depth: 1.0,
        width_px,
        color: Vec3::ONE,
    }
}

/// Sum of the coverage a segment blends into a 128 x 128 frame.
fn covered_area(a: ScreenVertex, b: ScreenVertex) -> f32 {
    let mut frame = Framebuffer::new(128, 128);
    let mut sum = 0.0;
    draw_segment(&mut frame, &a, &b, 1.0, |_, alpha| sum += alpha);
    sum
}

#[test]
fn line_coverage_sums_to_the_analytic_area_width_times_length() {
    // Lines of 60-80 px at several angles (not aligned with the grid, so no
    // line's centre runs exactly along pixel centres) and widths from a tenth
    // of a pixel to three pixels.
    for (angle_deg, width) in [
        (0.0f32, 0.1f32),
        (7.0, 0.3),
        (30.0, 0.5),
        (45.0, 0.8),
        (62.0, 1.0),
        (90.0, 1.6),
        (133.0, 2.4),
        (201.0, 3.0),
    ] {
        let a = angle_deg.to_radians();
        let length = 70.0;
        let start = (64.3 - 0.5 * length * a.cos(), 64.7 - 0.5 * length * a.sin());
        let end = (start.0 + length * a.cos(), start.1 + length * a.sin());
        let area = covered_area(vertex(start.0, start.1, width), vertex(end.0, end.1, width));
        let analytic = width * length;
        // Pixel centres along the line are counted within one pixel of
        // length at each end: at most 2 / 70 = 3 % off, whatever the width.
        assert!(
            (area - analytic).abs() <= 0.03 * analytic + 0.02,
            "angle {angle_deg}, width {width}: covered {area}, analytic {analytic}"
        );
    }
}

#[test]
fn a_thin_line_is_fainter_not_narrower_and_the_head_hides_hair_behind_it() {
    let mut frame = Framebuffer::new(32, 32);
    draw_segment(
        &mut frame,
        &vertex(2.0, 16.5, 0.25),
        &vertex(30.0, 16.5, 0.25),
        1.0,
        |_, _| {},
    );
    let centre = frame.color(frame.index(15, 16));
    assert!(
        (centre.x - 0.25).abs() < 1e-5,
        "a quarter-pixel line on a pixel centre: {centre}"
    );
    assert!(frame.color(frame.index(15, 15)).max_element() < 1e-6);

    let mut frame = Framebuffer::new(32, 32);
    frame.pixels.iter_mut().for_each(|p| p.depth = 0.5); // an opaque surface nearer than the line (depth 1)
    draw_segment(
        &mut frame,
        &vertex(2.0, 16.5, 2.0),
        &vertex(30.0, 16.5, 2.0),
        1.0,
        |_, _| {},
    );
    assert!(frame.pixels.iter().all(|p| p.color == Vec3::ZERO));
}

/// Two vertical strands crossing the same pixels, a red one nearer the
/// camera and a blue one farther, drawn with `order`.
fn draw_crossing(order_far_first: bool) -> Vec3 {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 0.5, 65, 65);
    let strand = |z: f32| -> Vec<RenderVertex> {
        (0..5)
            .map(|k| RenderVertex {
                position: [0.0, -0.1 + 0.05 * k as f32, z],
                width: 0.01,
                tangent: [0.0, 1.0, 0.0],
                strand_parameter: k as f32 / 4.0,
            })
            .collect()
    };
    let mut vertices = strand(0.2); // strand 0: near
    vertices.extend(strand(-0.2)); // strand 1: far
    let mut colors = RgbBuffer::zeros(10);
    for k in 0..10 {
        colors.set(k, if k < 5 { Vec3::X } else { Vec3::Z });
    }
    let mut order = DepthOrder::with_capacity(2);
    if order_far_first {
        order.sort(&camera, &vertices, 5);
        assert_eq!(
            order.strands().collect::<Vec<_>>(),
            vec![1, 0],
            "far strand first"
        );
    } else {
        // Depths negated: the near strand is blended first (wrong order).
        order.sort_by_depths([-0.8f32, -1.2]);
        assert_eq!(order.strands().collect::<Vec<_>>(), vec![0, 1]);
    }
    let mut frame = Framebuffer::new(65, 65);
    let drawn = hair::draw_strands(&mut frame, &camera, &vertices, &colors, 5, &order, 0.8);
    assert_eq!(drawn, 8);
    frame.color(frame.index(32, 32))
}

#[test]
fn back_to_front_blending_puts_the_near_strand_on_top() {
    let sorted = draw_crossing(true);
    let wrong = draw_crossing(false);
    // Both strands are over a pixel wide and centred on pixel 32 (alpha =
    // opacity a = 0.8). Over black, far first gives red a, blue a (1 - a).
    assert!(
        sorted.x > 0.5 && sorted.x > 2.0 * sorted.z,
        "sorted: {sorted}"
    );
    assert!(
        wrong.z > 0.5 && wrong.z > 2.0 * wrong.x,
        "reversed: {wrong}"
    );
    let a = sorted.x;
    assert!((sorted.z - a * (1.0 - a)).abs() < 1e-4, "{sorted}");
}
