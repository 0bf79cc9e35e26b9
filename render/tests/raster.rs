//! The binned rasteriser against the direct reference and its scalar twin:
//! the same frames bit for bit (tolerance 0: all three share the per-pixel
//! step `Segment::pixel`, which uses no fused multiply-add, and the bins
//! keep every pixel's segments in the sorted order), with bad data, far-off
//! and huge segments, overflowing bins and any task order.

use coif_base::tasks::{Executor, Serial};
use coif_base::SplitMix64;
use coif_lod::RenderVertex;
use coif_render::raster::HairRaster;
use coif_render::sort::DepthOrder;
use coif_render::{hair, scalar, Camera, Framebuffer, ShadedVertex};
use coif_shading::RgbBuffer;
use coif_testkit::executors::Backwards;
use glam::Vec3;

const SIZE: usize = 160;

/// Runs the tasks on two scoped threads, odd and even indices.
struct TwoThreads;
// SAFETY: each index runs once (on one of the two threads), both joined before `run` returns.
unsafe impl Executor for TwoThreads {
    fn threads(&self) -> usize {
        2
    }
    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        std::thread::scope(|s| {
            for parity in 0..2 {
                s.spawn(move || (parity..count).step_by(2).for_each(task));
            }
        });
    }
}

fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::ZERO,
        Vec3::Y,
        0.6,
        SIZE,
        SIZE,
    )
}

/// Hair-like strands of `vps` vertices hanging around the origin (lengths
/// of a few pixels per segment, widths 0.2 to 3 px, colours varied).
fn strands(count: usize, vps: usize, seed: u64) -> Vec<ShadedVertex> {
    let mut rng = SplitMix64::new(seed);
    let mut out = Vec::with_capacity(count * vps);
    for _ in 0..count {
        let mut p = Vec3::new(
            rng.range(-0.2, 0.2),
            rng.range(0.0, 0.2),
            rng.range(-0.2, 0.2),
        );
        let mut dir = Vec3::new(rng.range(-0.3, 0.3), -1.0, rng.range(-0.3, 0.3)).normalize();
        let width = rng.range(0.3e-3, 4e-3);
        let color = Vec3::new(
            rng.range(0.1, 0.9),
            rng.range(0.1, 0.6),
            rng.range(0.0, 0.3),
        );
        for k in 0..vps {
            out.push(ShadedVertex {
                position: p.into(),
                width,
                color: (color * (0.5 + k as f32 / vps as f32)).into(),
                strand_parameter: k as f32 / (vps - 1) as f32,
            });
            dir = (dir + rng.unit_vector() * 0.3).normalize();
            p += dir * 0.008;
        }
    }
    out
}

/// A frame with a gradient and an opaque disc (the head's depth) in it.
fn backdrop() -> Framebuffer {
    let mut f = Framebuffer::new(SIZE, SIZE);
    f.clear_gradient(Vec3::new(0.2, 0.2, 0.3), Vec3::new(0.0, 0.05, 0.1));
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (dx, dy) = (x as f32 - 70.0, y as f32 - 90.0);
            if dx * dx + dy * dy < 30.0 * 30.0 {
                let i = f.index(x, y);
                f.pixels[i].color = Vec3::new(0.6, 0.4, 0.3);
                f.pixels[i].depth = 0.95 + 0.002 * dy;
            }
        }
    }
    f
}

/// The reference frame: `hair::draw_strands` over the same vertices.
fn reference(vertices: &[ShadedVertex], vps: usize, order: &DepthOrder) -> (Framebuffer, usize) {
    let render: Vec<RenderVertex> = vertices
        .iter()
        .map(|v| RenderVertex {
            position: v.position,
            width: v.width,
            tangent: [0.0, 1.0, 0.0],
            strand_parameter: v.strand_parameter,
        })
        .collect();
    let mut colors = RgbBuffer::zeros(vertices.len());
    for (k, v) in vertices.iter().enumerate() {
        colors.set(k, Vec3::from(v.color));
    }
    let mut frame = backdrop();
    let n = hair::draw_strands(&mut frame, &camera(), &render, &colors, vps, order, 0.8);
    (frame, n)
}

fn binned(
    raster: &mut HairRaster,
    vertices: &[ShadedVertex],
    vps: usize,
    order: &DepthOrder,
    simd: bool,
    executor: &dyn Executor,
) -> (Framebuffer, usize) {
    let mut frame = backdrop();
    let cam = camera();
    let n = if simd {
        raster.draw(&mut frame, &cam, vertices, vps, order, 0.8, executor)
    } else {
        scalar::draw(
            raster, &mut frame, &cam, vertices, vps, order, 0.8, executor,
        )
    };
    (frame, n)
}

fn sorted(vertices: &[ShadedVertex], vps: usize) -> DepthOrder {
    let mut order = DepthOrder::with_capacity(vertices.len() / vps);
    order.sort(&camera(), vertices, vps);
    order
}

/// Pixels whose colour differs from the backdrop's.
fn changed_pixels(frame: &Framebuffer) -> usize {
    let back = backdrop();
    frame
        .pixels
        .iter()
        .zip(&back.pixels)
        .filter(|(p, q)| p.color != q.color)
        .count()
}

/// Bit-for-bit equality of two frames' colours, with the first difference.
fn assert_same(a: &Framebuffer, b: &Framebuffer, what: &str) {
    for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        assert!(
            p.color.to_array().map(f32::to_bits) == q.color.to_array().map(f32::to_bits),
            "{what}: pixel {i} ({}, {}): {} vs {}",
            i % SIZE,
            i / SIZE,
            p.color,
            q.color
        );
    }
}

#[test]
fn binned_simd_scalar_and_reference_agree_bit_for_bit() {
    let vps = 24;
    let vertices = strands(600, vps, 11);
    let order = sorted(&vertices, vps);
    let (want, n) = reference(&vertices, vps, &order);
    assert!(n > 10_000, "{n} segments");
    let changed = changed_pixels(&want);
    assert!(
        changed > SIZE * SIZE / 4,
        "the hair covers {changed} pixels"
    );
    // The reference over shaded vertices is the same function.
    let mut shaded = backdrop();
    let cam = camera();
    assert_eq!(
        hair::draw_shaded(&mut shaded, &cam, &vertices, vps, &order, 0.8),
        n
    );
    assert_same(&shaded, &want, "draw_shaded");
    let mut raster = HairRaster::new(SIZE, SIZE, vertices.len()).unwrap();
    let mut entries = Vec::new();
    for simd in [true, false] {
        for (executor, name) in [
            (&Serial as &dyn Executor, "serial"),
            (&Backwards(1), "reversed"),
            (&Backwards(3), "reversed, split for 3 threads"),
            (&Backwards(16), "reversed, split for 16 threads"),
            (&TwoThreads, "two threads"),
        ] {
            let (got, m) = binned(&mut raster, &vertices, vps, &order, simd, executor);
            assert_eq!(m, n, "segments drawn");
            assert_same(&got, &want, &format!("simd {simd}, {name}"));
            assert_eq!(raster.stats().batches, 1);
            entries.push(raster.stats().entries);
        }
    }
    // Every split of the binning writes the same number of list entries.
    assert!(
        entries.iter().all(|&e| e == entries[0] && e >= n),
        "{entries:?}"
    );
}

#[test]
fn overflowing_bins_draw_in_batches_with_the_same_bytes() {
    // Every segment in one tile (a tight bundle), and bins far too small.
    let vps = 16;
    let mut vertices = strands(400, vps, 5);
    for v in &mut vertices {
        let p = Vec3::from(v.position);
        v.position = (p * Vec3::new(0.05, 0.05, 1.0) + Vec3::new(0.0, 0.02, 0.0)).into();
    }
    let order = sorted(&vertices, vps);
    let (want, n) = reference(&vertices, vps, &order);
    let mut small = HairRaster::with_bin_capacity(SIZE, SIZE, vertices.len(), 1000).unwrap();
    for simd in [true, false] {
        for executor in [&Serial as &dyn Executor, &TwoThreads, &Backwards(8)] {
            let (got, m) = binned(&mut small, &vertices, vps, &order, simd, executor);
            assert_eq!(m, n);
            assert!(small.stats().batches > 3, "{:?}", small.stats());
            assert_same(&got, &want, "batched");
        }
    }
}

#[test]
fn bad_vertices_are_skipped_without_touching_other_strands() {
    let vps = 12;
    let clean = strands(200, vps, 7);
    let order = sorted(&clean, vps);
    let mut raster = HairRaster::new(SIZE, SIZE, clean.len()).unwrap();
    // Strand 17 gone (every vertex behind the camera) ...
    let mut gone = clean.clone();
    for v in &mut gone[17 * vps..18 * vps] {
        v.position = [0.0, 0.0, 5.0];
    }
    let (without, _) = binned(&mut raster, &gone, vps, &order, true, &Serial);
    // ... equals it with one bad value and the rest behind the camera.
    let bad: [fn(&mut ShadedVertex); 6] = [
        |v| v.position[1] = f32::NAN,
        |v| v.position[0] = f32::INFINITY,
        |v| v.width = f32::NAN,
        |v| v.width = f32::INFINITY,
        |v| v.width = -1.0,
        |v| v.color[2] = f32::NAN,
    ];
    for (case, poison) in bad.iter().enumerate() {
        let mut v = gone.clone();
        v[17 * vps + 5] = clean[17 * vps + 5];
        poison(&mut v[17 * vps + 5]);
        for simd in [true, false] {
            let (got, _) = binned(&mut raster, &v, vps, &order, simd, &Serial);
            assert!(
                got.pixels.iter().all(|p| p.color.is_finite()),
                "case {case}"
            );
            assert_same(&got, &without, &format!("case {case}, simd {simd}"));
        }
    }
}

#[test]
fn extreme_segments_match_the_reference() {
    // Behind the near plane, crossing it, far off screen, across the whole
    // frame from far outside, zero length, and a few hundred pixels wide.
    let v = |x: f32, y: f32, z: f32, width: f32| ShadedVertex {
        position: [x, y, z],
        width,
        color: [0.9, 0.5, 0.2],
        strand_parameter: 0.0,
    };
    let vertices = vec![
        v(0.0, 0.0, 1.5, 1e-3),
        v(0.01, 0.0, 0.5, 1e-3), // crosses the camera plane
        v(1e4, 0.0, 0.0, 1e-3),
        v(1e4, 1.0, 0.0, 1e-3), // far off screen
        v(-1e3, 0.001, 0.0, 2e-3),
        v(1e3, -0.001, 0.0, 2e-3), // across the frame from far outside
        v(0.05, 0.05, 0.0, 1e-3),
        v(0.05, 0.05, 0.0, 1e-3), // zero length
        v(-0.02, -0.1, 0.0, 0.2),
        v(0.02, 0.1, 0.0, 0.3), // hundreds of pixels wide
    ];
    let order = sorted(&vertices, 2);
    let (want, n) = reference(&vertices, 2, &order);
    assert_eq!(n, 4, "the segment through the camera plane is skipped");
    let mut raster = HairRaster::new(SIZE, SIZE, vertices.len()).unwrap();
    for simd in [true, false] {
        let (got, m) = binned(&mut raster, &vertices, 2, &order, simd, &Serial);
        assert_eq!(m, n);
        assert_same(&got, &want, &format!("simd {simd}"));
    }
    // The wide segment covers thousands of pixels over several tiles.
    let changed = changed_pixels(&want);
    assert!(changed > 1000, "{changed} pixels drawn");
    assert!(raster.stats().entries >= 9, "{:?}", raster.stats());
}

#[test]
fn constructors_refuse_empty_frames_and_draws_leave_other_sizes_alone() {
    assert!(HairRaster::new(0, 10, 10).is_err());
    assert!(HairRaster::new(10, 0, 10).is_err());
    let vertices = strands(10, 8, 3);
    let order = sorted(&vertices, 8);
    let mut raster = HairRaster::new(SIZE + 1, SIZE, vertices.len()).unwrap();
    let (got, n) = binned(&mut raster, &vertices, 8, &order, true, &Serial);
    assert_eq!(n, 0);
    assert_same(&got, &backdrop(), "untouched");
}

#[test]
fn lane_projection_matches_the_scalar_one_bit_for_bit() {
    use coif_render::raster::{project, project_simd};
    let cam = camera();
    let mut vertices = strands(20, 9, 11);
    // Poison some: behind the camera, on the eye, NaN / infinite positions,
    // widths and colours, a negative width.
    let poisons: [fn(&mut ShadedVertex); 8] = [
        |v| v.position[2] = 2.0,
        |v| v.position = [0.0, 0.0, 1.0],
        |v| v.position[0] = f32::NAN,
        |v| v.position[1] = f32::INFINITY,
        |v| v.width = f32::NAN,
        |v| v.width = -1e-3,
        |v| v.color[1] = f32::NAN,
        |v| v.width = f32::INFINITY,
    ];
    for (k, poison) in poisons.iter().enumerate() {
        poison(&mut vertices[k * 13 + 1]);
    }
    let bits = |v: &coif_render::line::ScreenVertex| {
        [
            v.x, v.y, v.depth, v.width_px, v.color.x, v.color.y, v.color.z,
        ]
        .map(f32::to_bits)
    };
    let mut invalid = 0;
    // Whole blocks, and every shorter chunk, 1 to LANES - 1.
    let lanes = coif_base::LANES;
    let short = (1..lanes).map(|n| &vertices[n..2 * n]);
    for chunk in vertices.chunks(lanes).chain(short) {
        let lanes_out = project_simd(&cam, chunk);
        for (l, v) in chunk.iter().enumerate() {
            let one = project(&cam, v);
            invalid += one.depth.is_nan() as usize;
            if one.depth.is_nan() {
                assert!(lanes_out[l].depth.is_nan());
            } else {
                assert_eq!(bits(&one), bits(&lanes_out[l]), "lane {l}");
            }
        }
        assert!(lanes_out[chunk.len()..].iter().all(|v| v.depth.is_nan()));
    }
    assert!(invalid >= 8, "{invalid}");
}

#[test]
fn band_walks_draw_the_reference_pixels_at_every_angle() {
    // Two-vertex strands on the plane z = 0 (depth 1, so pixel size is
    // linear in metres): 96 directions (axis-aligned and diagonal ones
    // included), lengths 0.3 to 40 px, widths 0.1 to 3 px, at sub-pixel
    // offsets; then long segments with ends 500 to 3,000 px outside the
    // frame (band walks) and beyond `BAND_REACH` (the reference's rows).
    let cam = camera();
    let f = cam.pixels_per_metre(1.0);
    let mut rng = SplitMix64::new(29);
    let mut vertices = Vec::new();
    let mut push = |p: Vec3, q: Vec3, width_px: f32, rng: &mut SplitMix64| {
        let color = [
            rng.range(0.2, 1.0),
            rng.range(0.1, 0.8),
            rng.range(0.0, 0.5),
        ];
        for (k, at) in [p, q].into_iter().enumerate() {
            vertices.push(ShadedVertex {
                position: at.into(),
                width: width_px / f,
                color: color.map(|c| c * (0.7 + 0.3 * k as f32)),
                strand_parameter: k as f32,
            });
        }
    };
    for i in 0..96 {
        let angle = i as f32 * std::f32::consts::TAU / 96.0;
        let dir = Vec3::new(angle.cos(), angle.sin(), 0.0);
        for length_px in [0.3f32, 1.0, 3.7, 9.0, 40.0] {
            let width_px = rng.range(0.1, 3.0);
            let centre = Vec3::new(rng.range(-60.0, 60.0), rng.range(-60.0, 60.0), 0.0) / f;
            let half = dir * (0.5 * length_px / f);
            push(centre - half, centre + half, width_px, &mut rng);
        }
    }
    for (reach_px, count) in [(500.0f32, 12), (3_000.0, 12), (20_000.0, 4)] {
        for _ in 0..count {
            let angle = rng.range(0.0, std::f32::consts::TAU);
            let dir = Vec3::new(angle.cos(), angle.sin(), 0.0);
            let centre = Vec3::new(rng.range(-40.0, 40.0), rng.range(-40.0, 40.0), 0.0) / f;
            let half = dir * (reach_px / f);
            push(centre - half, centre + half, rng.range(0.2, 1.5), &mut rng);
        }
    }
    let order = sorted(&vertices, 2);
    let (want, n) = reference(&vertices, 2, &order);
    assert_eq!(n, vertices.len() / 2, "every segment is in front");
    assert!(changed_pixels(&want) > SIZE * SIZE / 4);
    let mut raster = HairRaster::new(SIZE, SIZE, vertices.len()).unwrap();
    for simd in [true, false] {
        let (got, m) = binned(&mut raster, &vertices, 2, &order, simd, &Serial);
        assert_eq!(m, n);
        assert_same(&got, &want, &format!("simd {simd}"));
    }
}

/// Hair around and behind two opaque spheres drawn into the frame: with
/// the spheres declared as occluders the rasteriser leaves out the
/// segments they hide, and the frame is still the reference's (which
/// draws every segment) bit for bit, in both twins and on any executor.
/// The strands cross the discs' rims at every angle and depth, 0.1 to 10
/// pixels wide (beyond the widest culled reach), some from behind a sphere
/// to in front of it.
#[test]
fn segments_hidden_behind_occluders_are_culled_without_changing_a_bit() {
    use coif_base::Sphere;
    use coif_render::head::{draw_spheres, HeadShading};
    let spheres = [
        Sphere {
            center: Vec3::new(0.02, 0.0, -0.05),
            radius: 0.12,
        },
        Sphere {
            center: Vec3::new(-0.09, -0.09, -0.02),
            radius: 0.07,
        },
    ];
    let cam = camera();
    let shading = HeadShading {
        albedo: Vec3::new(0.7, 0.5, 0.4),
        to_light: Vec3::new(0.3, 0.8, 0.5).normalize(),
        light: Vec3::ONE,
        ambient: Vec3::splat(0.1),
    };
    let backdrop_with_head = || {
        let mut f = Framebuffer::new(SIZE, SIZE);
        f.clear_gradient(Vec3::new(0.2, 0.2, 0.3), Vec3::new(0.0, 0.05, 0.1));
        assert!(draw_spheres(&mut f, &cam, &spheres, &shading, |_| 1.0) > 2000);
        f
    };
    // Straight strands through random points of a box around the spheres,
    // in random directions, mostly behind them.
    let (vps, count) = (12, 1500);
    let mut rng = SplitMix64::new(21);
    let mut vertices = Vec::with_capacity(vps * count);
    for i in 0..count {
        let mut p = Vec3::new(
            rng.range(-0.25, 0.25),
            rng.range(-0.25, 0.25),
            rng.range(-0.3, 0.12),
        );
        let dir = rng.unit_vector();
        let step = rng.range(0.002, 0.02);
        // 0.1 to 10 px at the scene's depth (f is about 270 px).
        let width = 0.004 * (i % 100) as f32 / 100.0 + 4e-4;
        let color = Vec3::new(rng.range(0.1, 0.9), rng.range(0.1, 0.9), 0.2);
        for k in 0..vps {
            vertices.push(ShadedVertex {
                position: p.into(),
                width,
                color: color.into(),
                strand_parameter: k as f32 / (vps - 1) as f32,
            });
            p += dir * step;
        }
    }
    let order = sorted(&vertices, vps);
    let mut want = backdrop_with_head();
    let n = hair::draw_shaded(&mut want, &cam, &vertices, vps, &order, 0.8);
    let mut raster = HairRaster::new(SIZE, SIZE, vertices.len()).unwrap();
    let mut draw = |occluders: &[Sphere], simd: bool, executor: &dyn Executor| {
        raster.set_occluders(occluders);
        let mut got = backdrop_with_head();
        let m = if simd {
            raster.draw(&mut got, &cam, &vertices, vps, &order, 0.8, executor)
        } else {
            scalar::draw(
                &mut raster,
                &mut got,
                &cam,
                &vertices,
                vps,
                &order,
                0.8,
                executor,
            )
        };
        assert_eq!(m, n, "segments with both ends valid");
        (got, raster.stats().hidden)
    };
    let (plain, none) = draw(&[], true, &Serial);
    assert_eq!(none, 0, "no occluders, nothing culled");
    assert_same(&plain, &want, "no occluders");
    let mut hidden = Vec::new();
    for simd in [true, false] {
        for (executor, name) in [
            (&Serial as &dyn Executor, "serial"),
            (&Backwards(3), "reversed, split for 3 threads"),
            (&TwoThreads, "two threads"),
        ] {
            let (got, h) = draw(&spheres, simd, executor);
            assert_same(&got, &want, &format!("occluders, simd {simd}, {name}"));
            hidden.push(h);
        }
    }
    // The twins cull the same segments, a good share of them.
    assert!(hidden.iter().all(|&h| h == hidden[0]), "{hidden:?}");
    assert!(
        hidden[0] > n / 10 && hidden[0] < n,
        "{} of {n} segments culled",
        hidden[0]
    );
}

#[test]
fn frames_and_capacities_that_would_not_fit_in_memory_are_refused() {
    use coif_render::raster::{Error, MAX_RASTER_PIXELS, MAX_RASTER_VERTICES};
    // 65,535 tiles of 64 along each side passed before: 17 TB of pixels.
    let side = 64 * 65_535;
    assert!(matches!(
        HairRaster::new(side, side, 0),
        Err(Error::Size { .. })
    ));
    // Within the tile bound per side, above the pixel bound in all.
    const _: () = assert!(64 * 65_535 * 65 > MAX_RASTER_PIXELS);
    assert!(matches!(
        HairRaster::new(64 * 65_535, 65, 0),
        Err(Error::Size { .. })
    ));
    assert!(matches!(
        HairRaster::new(64, 64, MAX_RASTER_VERTICES + 1),
        Err(Error::Capacity { .. })
    ));
    assert!(HairRaster::new(64, 64, 1024).is_ok());
}
