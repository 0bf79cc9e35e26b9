//! The triangle rasteriser's coverage: pixel-centre counts against the
//! analytic area, and meshes that share edges cover each pixel once.

use coif_base::SplitMix64;
use coif_render::grid::draw_grid;
use coif_render::triangle::{fill_triangle, TriangleVertex};
use coif_render::{Camera, Framebuffer};
use glam::{Vec2, Vec3};

fn corner(p: Vec2) -> TriangleVertex {
    TriangleVertex {
        x: p.x,
        y: p.y,
        depth: 1.0,
        color: Vec3::ONE,
    }
}

/// Pixels drawn for triangle `t` into a fresh frame.
fn count(frame: &mut Framebuffer, t: [Vec2; 3]) -> usize {
    frame.clear_gradient(Vec3::ZERO, Vec3::ZERO);
    fill_triangle(frame, &corner(t[0]), &corner(t[1]), &corner(t[2]), |_| {})
}

fn area_and_perimeter(t: [Vec2; 3]) -> (f32, f32) {
    let area = 0.5 * (t[1] - t[0]).perp_dot(t[2] - t[0]).abs();
    let perimeter = t[0].distance(t[1]) + t[1].distance(t[2]) + t[2].distance(t[0]);
    (area, perimeter)
}

#[test]
fn pixel_counts_match_the_analytic_area() {
    // Random triangles inside a 128 x 128 frame, both windings. A convex
    // region holds its area's worth of lattice points up to half its
    // perimeter (plus one for rounding at the corners); averaged over an
    // 8 x 8 grid of sub-pixel offsets the count is the area sampled 64
    // times per pixel: within 1 % (or 1 px^2 for small triangles).
    let mut frame = Framebuffer::new(128, 128);
    let mut rng = SplitMix64::new(11);
    let mut worst_single = 0f32;
    let mut worst_mean = 0f32;
    for _ in 0..40 {
        let t = [0; 3].map(|_| Vec2::new(rng.range(8.0, 120.0), rng.range(8.0, 120.0)));
        let (area, perimeter) = area_and_perimeter(t);
        if area < 20.0 {
            continue;
        }
        let n = count(&mut frame, t) as f32;
        assert!(
            (n - area).abs() <= 0.5 * perimeter + 1.0,
            "{t:?}: {n} pixels for area {area}, perimeter {perimeter}"
        );
        worst_single = worst_single.max((n - area).abs() / perimeter);
        let mut sum = 0.0;
        for j in 0..8 {
            for i in 0..8 {
                let o = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) / 8.0;
                sum += count(&mut frame, t.map(|p| p + o)) as f32;
            }
        }
        let mean = sum / 64.0;
        let err = (mean - area).abs();
        assert!(
            err <= (0.01 * area).max(1.0),
            "{t:?}: mean {mean} over offsets for area {area}"
        );
        worst_mean = worst_mean.max(err / area);
    }
    eprintln!(
        "worst |count - area| / perimeter {worst_single:.3}; worst relative error of the offset mean {worst_mean:.4}"
    );
}

#[test]
fn a_mesh_sharing_edges_covers_each_pixel_centre_once() {
    // A jittered 9 x 9 grid of vertices over the square [4.3, 59.7]^2 (the
    // border vertices jittered along the border only): every pixel centre
    // inside the square is drawn by exactly one triangle, none outside.
    let (lo, hi, n) = (4.3f32, 59.7f32, 9usize);
    let mut rng = SplitMix64::new(5);
    let step = (hi - lo) / (n - 1) as f32;
    let mut points = Vec::new();
    for r in 0..n {
        for c in 0..n {
            let mut p = Vec2::new(lo + c as f32 * step, lo + r as f32 * step);
            if c > 0 && c < n - 1 {
                p.x += rng.range(-0.4, 0.4) * step;
            }
            if r > 0 && r < n - 1 {
                p.y += rng.range(-0.4, 0.4) * step;
            }
            points.push(p);
        }
    }
    let mut frame = Framebuffer::new(64, 64);
    let mut hits = vec![0u32; 64 * 64];
    for r in 0..n - 1 {
        for c in 0..n - 1 {
            let k = r * n + c;
            for t in [[k, k + 1, k + n], [k + 1, k + n + 1, k + n]] {
                frame.clear_gradient(Vec3::ZERO, Vec3::ZERO);
                let [a, b, d] = t.map(|i| corner(points[i]));
                fill_triangle(&mut frame, &a, &b, &d, |i| hits[i] += 1);
            }
        }
    }
    for y in 0..64 {
        for x in 0..64 {
            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let inside = centre.cmpgt(Vec2::splat(lo)).all() && centre.cmplt(Vec2::splat(hi)).all();
            assert_eq!(
                hits[y * 64 + x],
                inside as u32,
                "pixel ({x}, {y}) drawn {} times",
                hits[y * 64 + x]
            );
        }
    }
}

#[test]
fn a_grid_in_front_of_the_camera_covers_its_projected_area() {
    // A 0.2 m square facing a camera 1 m away, as a 5 x 4 grid: its pixels
    // are the projected square's area (half the perimeter's worth of pixels
    // of tolerance), its depth is 1 m, and with its corners behind the eye
    // nothing is drawn.
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 0.7, 128, 128);
    let (rows, cols) = (5, 4);
    let mut positions = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let u = c as f32 / (cols - 1) as f32 - 0.5;
            let v = r as f32 / (rows - 1) as f32 - 0.5;
            positions.push(Vec3::new(0.2 * u, -0.2 * v, 0.0));
        }
    }
    let colors = vec![Vec3::X; rows * cols];
    let mut frame = Framebuffer::new(128, 128);
    frame.clear_gradient(Vec3::ZERO, Vec3::ZERO);
    let n = draw_grid(&mut frame, &camera, &positions, &colors, rows, cols) as f32;
    let side = 0.2 * camera.pixels_per_metre(1.0);
    assert!(
        (n - side * side).abs() <= 2.0 * side + 1.0,
        "{n} pixels for a {side} px square"
    );
    let mid = frame.index(64, 64);
    assert!((frame.depth(mid) - 1.0).abs() < 1e-5);
    assert_eq!(frame.color(mid), Vec3::X);
    let behind: Vec<Vec3> = positions.iter().map(|p| *p + Vec3::Z * 2.0).collect();
    frame.clear_gradient(Vec3::ZERO, Vec3::ZERO);
    assert_eq!(
        draw_grid(&mut frame, &camera, &behind, &colors, rows, cols),
        0
    );
    // Wrong counts draw nothing rather than panic.
    assert_eq!(
        draw_grid(&mut frame, &camera, &positions, &colors[1..], rows, cols),
        0
    );
}

/// An engine-style executor of `threads` scoped threads: the indices
/// backwards, index `i` on thread `i % threads`.
struct Backwards {
    threads: usize,
}

// SAFETY: each index runs once, on one of the scoped threads, all joined
// before `run` returns.
unsafe impl coif_base::tasks::Executor for Backwards {
    fn threads(&self) -> usize {
        self.threads
    }

    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let n = self.threads;
        std::thread::scope(|s| {
            for k in 0..n {
                s.spawn(move || {
                    for i in (0..count).rev().filter(|i| i % n == k) {
                        task(i);
                    }
                });
            }
        });
    }
}

/// The frame's pixels as bits.
fn pixel_bits(frame: &Framebuffer) -> Vec<[u32; 4]> {
    (frame.pixels.iter())
        .map(|p| [p.color.x, p.color.y, p.color.z, p.depth].map(f32::to_bits))
        .collect()
}

#[test]
fn binned_triangles_are_the_same_bytes_as_one_pass_in_order() {
    use coif_base::tasks::{Executor, Serial};
    use coif_render::triangle_bins::TriangleBins;
    // 600 random triangles of every size (a pixel to most of the frame),
    // interleaved depths so that later triangles win some pixels and lose
    // others, some corners shared, some missing (behind the near plane),
    // one index out of range; a frame of 200 x 150 (partial tiles).
    let (w, h) = (200, 150);
    let mut rng = SplitMix64::new(42);
    let corners: Vec<Option<TriangleVertex>> = (0..900)
        .map(|k| {
            let scale = [4.0, 30.0, 250.0][k % 3];
            let c = Vec2::new(rng.next_f32() * w as f32, rng.next_f32() * h as f32);
            let p = c + (Vec2::new(rng.next_f32(), rng.next_f32()) - 0.5) * scale;
            (k % 97 != 5).then(|| TriangleVertex {
                x: p.x,
                y: p.y,
                depth: 1.0 + rng.next_f32(),
                color: Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()),
            })
        })
        .collect();
    let mut triangles: Vec<[u32; 3]> = (0..600u32)
        .map(|t| [t % 900, (t * 7 + 1) % 900, (t * 13 + 2) % 900])
        .collect();
    triangles[17][1] = 5000;
    let mut reference = Framebuffer::new(w, h);
    reference.clear_gradient(Vec3::ZERO, Vec3::ONE);
    let mut expected = 0;
    for t in &triangles {
        let [a, b, c] = t.map(|i| corners.get(i as usize).copied().flatten());
        if let (Some(a), Some(b), Some(c)) = (a, b, c) {
            expected += fill_triangle(&mut reference, &a, &b, &c, |_| {});
        }
    }
    assert!(expected > 10_000, "{expected} pixels written");
    let want = pixel_bits(&reference);
    let draw = |bins: &mut TriangleBins, executor: &dyn Executor| {
        let mut frame = Framebuffer::new(w, h);
        frame.clear_gradient(Vec3::ZERO, Vec3::ONE);
        let written = bins.draw(&mut frame, &corners, &triangles, executor);
        (written, pixel_bits(&frame))
    };
    // (Executors of one thread draw in one pass; 2, 3 and 8 through the
    // bins.)
    let spread = [1, 2, 3, 8].map(|threads| Backwards { threads });
    let mut executors: Vec<&dyn Executor> = vec![&Serial];
    executors.extend(spread.iter().map(|p| p as &dyn Executor));
    let mut bins = TriangleBins::new(w, h, triangles.len());
    for (k, executor) in executors.into_iter().enumerate() {
        let (written, got) = draw(&mut bins, executor);
        assert_eq!(written, expected, "executor {k}: pixels written");
        assert!(got == want, "executor {k}: the pixels differ");
    }
    // Bins made for fewer triangles, or for another frame size, draw in
    // one pass: the same bytes.
    for mut small in [TriangleBins::new(w, h, 10), TriangleBins::new(64, 64, 600)] {
        let (written, got) = draw(&mut small, &Backwards { threads: 2 });
        assert_eq!(written, expected);
        assert!(got == want, "the one-pass fallback differs");
    }
}
