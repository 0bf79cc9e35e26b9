//! The hair rasteriser: the direct reference (`hair::draw_shaded`) against
//! the binned rasteriser (`raster::HairRaster::draw`, SIMD) and its scalar
//! twin (`scalar::draw`), in ns per segment (elements = segments drawn).
//!
//! Groups:
//! - `raster/cache/{reference,binned-scalar,binned-simd}`: 120 short
//!   strands (840 segments, 3-4 px each, 0.4-1.5 px wide) inside a 32 x 32
//!   region of a 64 x 64 frame (one tile): everything in L1/L2, the
//!   per-segment cost.
//! - `raster/frame/{reference,binned-scalar,binned-simd,binned-simd-culled}`:
//!   the default scene's last frame (835,016 segments at 512 x 512, built
//!   once through `coif_frame`'s public API), over the frame's head and
//!   ribbons: streaming, projection, binning and tiles included;
//!   `binned-simd-culled` declares the head's spheres as occluders
//!   (`HairRaster::set_occluders`, as the frame pipeline does), the others
//!   draw every segment.
//! - `raster/sort/{comparison,radix}`: the strand sort of the default frame.
//!
//! Before timing, the binned frames are checked against the reference bit
//! for bit (the test suite does the same on smaller scenes).

use coif::base::tasks::Serial;
use coif::frame::{motion, FramePipeline, FrameSettings, HairScene};
use coif::geometry::scene::GrowOptions;
use coif::kernels::rng::SplitMix64;
use coif::kernels::Sphere;
use coif::render::raster::HairRaster;
use coif::render::sort::DepthOrder;
use coif::render::{hair, scalar, Camera, Framebuffer, ShadedVertex};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;

/// One scene to draw: camera, vertices, order, backdrop.
struct Scene {
    camera: Camera,
    shaded: Vec<ShadedVertex>,
    vps: usize,
    order: DepthOrder,
    backdrop: Framebuffer,
    /// Opaque spheres drawn in the backdrop (the head), for the culled run.
    occluders: Vec<Sphere>,
}

impl Scene {
    fn new(
        camera: Camera,
        shaded: Vec<ShadedVertex>,
        vps: usize,
        backdrop: Framebuffer,
        occluders: Vec<Sphere>,
    ) -> Scene {
        let mut order = DepthOrder::with_capacity(shaded.len() / vps);
        order.sort(&camera, &shaded, vps);
        Scene {
            camera,
            shaded,
            vps,
            order,
            backdrop,
            occluders,
        }
    }

    fn reference(&self, frame: &mut Framebuffer) -> usize {
        frame.pixels.copy_from_slice(&self.backdrop.pixels);
        hair::draw_shaded(
            frame,
            &self.camera,
            &self.shaded,
            self.vps,
            &self.order,
            0.8,
        )
    }

    fn binned(
        &self,
        raster: &mut HairRaster,
        frame: &mut Framebuffer,
        simd: bool,
        culled: bool,
    ) -> usize {
        frame.pixels.copy_from_slice(&self.backdrop.pixels);
        raster.set_occluders(if culled { &self.occluders } else { &[] });
        let (c, v, o) = (&self.camera, &self.shaded[..], &self.order);
        if simd {
            raster.draw(frame, c, v, self.vps, o, 0.8, &Serial)
        } else {
            scalar::draw(raster, frame, c, v, self.vps, o, 0.8, &Serial)
        }
    }
}

/// 120 strands of 8 vertices inside pixels 16..48 of a 64 x 64 frame.
fn tile_scene() -> Scene {
    let size = 64;
    let camera = Camera::look_at(
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::ZERO,
        Vec3::Y,
        0.6,
        size,
        size,
    );
    let mut rng = SplitMix64::new(9);
    let px = 1.0 / camera.pixels_per_metre(1.0);
    let mut shaded = Vec::new();
    for _ in 0..120 {
        let mut p = Vec3::new(
            rng.range(-10.0, 10.0) * px,
            rng.range(4.0, 13.0) * px,
            rng.range(-0.01, 0.01),
        );
        let width = rng.range(0.4, 1.5) * px;
        let mut dir = Vec3::new(rng.range(-0.5, 0.5), -1.0, 0.0).normalize();
        for k in 0..8 {
            shaded.push(ShadedVertex {
                position: p.into(),
                width,
                color: [0.3, 0.2, 0.1],
                strand_parameter: k as f32 / 7.0,
            });
            dir = (dir + Vec3::new(rng.range(-0.2, 0.2), 0.0, 0.0)).normalize();
            p += dir * rng.range(3.0, 4.0) * px;
        }
    }
    let mut backdrop = Framebuffer::new(size, size);
    backdrop.clear_gradient(Vec3::splat(0.2), Vec3::splat(0.05));
    Scene::new(camera, shaded, 8, backdrop, Vec::new())
}

/// The default scene's last frame as `cargo run --release` draws it (90
/// frames of its motion), with the head and ribbons in the backdrop.
fn frame_scene() -> Scene {
    let scene = HairScene::procedural(&GrowOptions {
        strand_count: 2048,
        curl: 0.15,
        ..GrowOptions::default()
    })
    .unwrap();
    let mut p = FramePipeline::new(&scene, FrameSettings::default(), 1.5).unwrap();
    let pivot = p.pivot();
    let run = |p: &mut FramePipeline| {
        for f in 0..90 {
            let pose = motion::turn_and_nod(f as f32 / 30.0, pivot);
            // As the demo: every tenth frame rendered, and the last.
            if f % 10 == 0 || f == 89 {
                p.frame(1.0 / 30.0, pose);
            } else {
                p.simulate(1.0 / 30.0, pose);
            }
        }
    };
    run(&mut p);
    let camera = p.camera().shifted(p.strands().origin().as_vec3());
    let (_, vps) = p.render_vertices();
    let shaded = p.shaded_vertices().to_vec();
    // The head and ribbons alone: the same frame with invisible hair.
    let settings = FrameSettings {
        hair_opacity: 0.0,
        ..FrameSettings::default()
    };
    let mut bare = FramePipeline::new(&scene, settings, 1.5).unwrap();
    run(&mut bare);
    let occluders = p.head_spheres().to_vec();
    Scene::new(camera, shaded, vps, bare.framebuffer().clone(), occluders)
}

fn bench_scene(c: &mut Criterion, name: &str, s: &Scene) {
    let (w, h) = (s.backdrop.width(), s.backdrop.height());
    let mut raster = HairRaster::new(w, h, s.shaded.len()).unwrap();
    let mut want = s.backdrop.clone();
    let segments = s.reference(&mut want);
    for (simd, culled) in [(false, false), (true, false), (true, true)] {
        let mut got = s.backdrop.clone();
        assert_eq!(s.binned(&mut raster, &mut got, simd, culled), segments);
        assert!(
            got.pixels == want.pixels,
            "{name}: binned (simd {simd}, culled {culled}) differs from the reference"
        );
    }
    eprintln!("raster/{name}: {segments} segments, {:?}", raster.stats());
    let mut frame = s.backdrop.clone();
    let mut g = c.benchmark_group(format!("raster/{name}"));
    g.throughput(Throughput::Elements(segments as u64));
    if segments > 100_000 {
        g.sample_size(10);
    }
    g.bench_function("reference", |b| b.iter(|| s.reference(&mut frame)));
    g.bench_function("binned-scalar", |b| {
        b.iter(|| s.binned(&mut raster, &mut frame, false, false))
    });
    g.bench_function("binned-simd", |b| {
        b.iter(|| s.binned(&mut raster, &mut frame, true, false))
    });
    if !s.occluders.is_empty() {
        g.bench_function("binned-simd-culled", |b| {
            b.iter(|| s.binned(&mut raster, &mut frame, true, true))
        });
    }
    g.finish();
}

fn raster(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    bench_scene(c, "cache", &tile_scene());
    let s = frame_scene();
    bench_scene(c, "frame", &s);
    let mut g = c.benchmark_group("raster/sort");
    g.throughput(Throughput::Elements(s.order.len() as u64));
    let mut order = DepthOrder::with_capacity(s.order.len());
    g.bench_function("radix", |b| {
        b.iter(|| order.sort(&s.camera, &s.shaded, s.vps))
    });
    // Below the radix threshold: strands one at a time in 1000-strand chunks.
    let chunk = 1000 * s.vps;
    let mut small = DepthOrder::with_capacity(1000);
    g.bench_function("comparison", |b| {
        b.iter(|| {
            for part in s.shaded.chunks_exact(chunk) {
                small.sort(&s.camera, part, s.vps);
            }
        })
    });
    g.finish();
}

criterion_group!(benches, raster);
criterion_main!(benches);
