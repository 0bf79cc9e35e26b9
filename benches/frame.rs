//! The demo's frame pipeline and software renderer.
//!
//! Groups:
//! - `frame/default/{simulate,render,frame}` and `frame/mohawk/...`: one
//!   frame of the built-in head (2,048 guides) and of the ratboy mohawk groom
//!   (skipped if `../shared/data/grooms` is absent) at 512 x 512 with
//!   Kajiya-Kay; after each scene the per-stage means over every iteration
//!   (`StageTimings`) are printed, since criterion times whole calls.
//! - `raster/segments`: anti-aliased hair segments (3 px long, 0.3-1.5 px
//!   wide) blended into a 512 x 512 frame, elements = segments, so the
//!   reported time per element is ns per segment.
//! - `raster/sort`: back-to-front sort of 10,000 strands.
//! - `raster/triangles`: opaque, depth-tested triangles of a ribbon quad's
//!   size (random, edges 4-14 px, about 30 px^2) into a 512 x 512 frame,
//!   every pixel passing the depth test (each iteration is nearer than the
//!   last), elements = triangles.
//! - `prepare/{fused,fused_k4,reference}`: the prepare pass (LOD, shadow
//!   map, shading) of the default head streaming over the whole frame,
//!   fused (every hair in the shadow map / every 4th group) and the reference;
//!   `prepare/fused_group`: one task of the fused pass (one group of
//!   eight hairs) in cache; elements = render vertices.
//! - `shade/{kajiya-kay,marschner,pbrt}`: per-vertex shading batch of 65,536
//!   samples.
//! - `threads/{1,2}/{simulate,prepare,render,frame}`: the default scene's
//!   frame (Sintel, as the demo runs her) and its parts on
//!   `tasks::Workers` of 1 and of 2 threads (the caller and one worker)
//!   (`FramePipeline::frame_with`); after each thread count the per-stage
//!   means are printed, and after both the serial fraction of a frame at
//!   1 thread (the stages that never run as tasks, over the frame) with the
//!   Amdahl speed-ups it allows at 2, 8 and 16 cores.
//! - `characters4/{1,2}/{stages_on_pool,characters_as_tasks}`: four heads
//!   (four `FramePipeline`s, `FrameSettings::small(256)` each: 256 x 256,
//!   12 render hairs per cm^2, 2 segments per span) per frame sharing one pool:
//!   one after another with every stage's tasks on the pool, or the four
//!   characters' whole frames as four tasks (each on `Serial` inside).

use coif::base::tasks::Serial;
use coif::frame::Stage;
use coif::frame::{
    motion, FramePipeline, FrameSettings, HairScene, PrepareMode, Shader, ShadingModel,
    DEFAULT_SHADOW_THINNING,
};
use coif::geometry::scene::GrowOptions;
use coif::groom;
use coif::kernels::rng::SplitMix64;
use coif::render::line::{draw_segment, ScreenVertex};
use coif::render::sort::DepthOrder;
use coif::render::triangle::{fill_triangle, TriangleVertex};
use coif::render::Framebuffer;
use coif::shading::{RgbBuffer, ShadingSamples};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;
use std::path::PathBuf;

/// The demo's default head: 2,048 grown guides, light curl.
fn default_head() -> HairScene {
    HairScene::procedural(&GrowOptions {
        strand_count: 2048,
        curl: 0.15,
        ..GrowOptions::default()
    })
    .unwrap()
}

fn bench_scene(c: &mut Criterion, name: &str, scene: &HairScene) {
    let mut p = FramePipeline::new(scene, FrameSettings::default(), 1.0).unwrap();
    let pivot = p.pivot();
    let mut t = 0.0f32;
    let mut g = c.benchmark_group(format!("frame/{name}"));
    g.sample_size(10);
    p.reset_timings();
    g.bench_function("simulate", |b| {
        b.iter(|| {
            t += 1.0 / 30.0;
            p.simulate(1.0 / 30.0, motion::turn_and_nod(t % 3.0, pivot));
        })
    });
    g.bench_function("render", |b| b.iter(|| p.render()));
    g.bench_function("frame", |b| {
        b.iter(|| {
            t += 1.0 / 30.0;
            black_box(p.frame(1.0 / 30.0, motion::turn_and_nod(t % 3.0, pivot)))
        })
    });
    g.finish();
    let s = p.stats();
    eprintln!(
        "\nframe/{name}: {} hairs, {} vertices, {} segments; per-stage means over all iterations:\n{}\n",
        s.hairs,
        s.vertices,
        s.segments,
        p.timings()
    );
}

fn frames(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    let default = default_head();
    bench_scene(c, "default", &default);
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/grooms/ratboy_mohawk.tfx");
    match std::fs::read(&path) {
        Ok(bytes) => {
            let g = groom::load(&bytes).unwrap();
            let scene = HairScene::from_groom(&g, 2048, 32).unwrap();
            bench_scene(c, "mohawk", &scene);
        }
        Err(_) => eprintln!("skipping frame/mohawk: {} is absent", path.display()),
    }
}

fn raster(c: &mut Criterion) {
    let mut rng = SplitMix64::new(3);
    let segments: Vec<(ScreenVertex, ScreenVertex)> = (0..10_000)
        .map(|_| {
            let (x, y) = (rng.range(20.0, 490.0), rng.range(20.0, 490.0));
            let a = rng.range(0.0, std::f32::consts::TAU);
            let w = rng.range(0.3, 1.5);
            let v = |x: f32, y: f32| ScreenVertex {
                x,
                y,
                depth: 1.0,
                width_px: w,
                color: Vec3::new(0.3, 0.2, 0.1),
            };
            (v(x, y), v(x + 3.0 * a.cos(), y + 3.0 * a.sin()))
        })
        .collect();
    let mut frame = Framebuffer::new(512, 512);
    let mut g = c.benchmark_group("raster");
    g.throughput(Throughput::Elements(segments.len() as u64));
    g.bench_function("segments", |b| {
        b.iter(|| {
            for (a, e) in &segments {
                draw_segment(&mut frame, a, e, 0.9, |_, _| {});
            }
        })
    });
    let depths: Vec<f32> = (0..10_000).map(|_| rng.range(0.5, 1.5)).collect();
    let mut order = DepthOrder::with_capacity(depths.len());
    g.throughput(Throughput::Elements(depths.len() as u64));
    g.bench_function("sort", |b| {
        b.iter(|| order.sort_by_depths(depths.iter().copied()))
    });
    let triangles: Vec<[TriangleVertex; 3]> = (0..10_000)
        .map(|_| {
            let (x, y) = (rng.range(20.0, 490.0), rng.range(20.0, 490.0));
            [0.0f32, 2.1, 4.2].map(|turn| {
                let r = rng.range(3.0, 7.0);
                let a = turn + rng.range(-0.4, 0.4);
                TriangleVertex {
                    x: x + r * a.cos(),
                    y: y + r * a.sin(),
                    depth: 1.0,
                    color: Vec3::new(0.4, 0.03, 0.04),
                }
            })
        })
        .collect();
    let mut pass = 0u32;
    g.throughput(Throughput::Elements(triangles.len() as u64));
    g.bench_function("triangles", |b| {
        b.iter(|| {
            pass += 1;
            let depth = 1.0 / (1.0 + pass as f32 * 1e-4);
            let mut written = 0;
            for t in &triangles {
                let [a, e, f] = t.map(|v| TriangleVertex { depth, ..v });
                written += fill_triangle(&mut frame, &a, &e, &f, |_| {});
            }
            written
        })
    });
    g.finish();
}

fn shade(c: &mut Criterion) {
    let n = 65_536;
    let mut rng = SplitMix64::new(5);
    let mut samples = ShadingSamples::with_capacity(n);
    for _ in 0..n {
        samples.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
    }
    let mut out = RgbBuffer::zeros(n);
    let mut g = c.benchmark_group("shade");
    g.throughput(Throughput::Elements(n as u64));
    for model in ShadingModel::ALL {
        let shader = Shader::new(model).unwrap();
        g.bench_function(model.name(), |b| {
            b.iter(|| shader.shade_batch(&samples, &mut out))
        });
    }
    g.finish();
}

/// The prepare pass (LOD, shadow map, shading) of the default head,
/// fused (the default map of every hair, and the map of every 4th group)
/// against the stage-by-stage reference: `prepare/{fused,fused_k4,reference}` streams
/// the whole frame (elements = render vertices); `prepare/fused_group`
/// repeats one task of the fused pass, one interpolation group of eight
/// hairs, in cache (elements = its vertices).
fn prepare(c: &mut Criterion) {
    let scene = default_head();
    let mut g = c.benchmark_group("prepare");
    g.sample_size(10);
    for (name, prepare, k) in [
        ("fused", PrepareMode::Fused, DEFAULT_SHADOW_THINNING),
        ("fused_k4", PrepareMode::Fused, 4),
        ("reference", PrepareMode::Reference, 1),
    ] {
        let settings = FrameSettings {
            prepare,
            shadow_thinning: k,
            ..FrameSettings::default()
        };
        let mut p = FramePipeline::new(&scene, settings, 1.0).unwrap();
        p.frame(1.0 / 30.0, motion::turn_and_nod(0.5, p.pivot()));
        g.throughput(Throughput::Elements(p.stats().vertices as u64));
        p.reset_timings();
        g.bench_function(name, |b| b.iter(|| p.prepare_with(&Serial)));
        eprintln!("\nprepare/{name}: per-stage means:\n{}\n", p.timings());
        if name == "fused" {
            let n = p.shade_drawn_group(0);
            g.throughput(Throughput::Elements(n as u64));
            g.bench_function("fused_group", |b| b.iter(|| p.shade_drawn_group(0)));
        }
    }
    g.finish();
}

/// A frame's stages at 1 thread: (serial ms, frame ms). Serial: LOD setup
/// (and the reference's interpolation), the ribbons (placing, stepping two
/// patches, blending), the ribbons' triangles, the sort, and whatever the
/// frame spends outside its timed stages. Counted parallel: the guides'
/// step (its hair grid, a serial part, included), the shadow build, the
/// prepare tasks, background and head, the body (vertices, eyes, binned
/// triangles), the hair's runs of tiles.
fn serial_split(p: &FramePipeline) -> (f64, f64) {
    let t = p.timings();
    let ms = |s: Stage| t.mean(s).as_secs_f64() * 1e3;
    let frame = ms(Stage::Frame);
    let parallel = ms(Stage::Simulate) - ms(Stage::Ribbon)
        + ms(Stage::Shadow)
        + ms(Stage::Shade)
        + ms(Stage::Head)
        + ms(Stage::Body)
        + ms(Stage::Hair);
    (frame - parallel, frame)
}

fn threads(c: &mut Criterion) {
    use coif::base::tasks::Workers;
    // The default scene as the demo runs it: Sintel on her bust, pbrt with
    // dual scattering, 20 render hairs per cm^2, the gust's simulation.
    let scene = HairScene::sintel().unwrap();
    let settings = FrameSettings {
        shading: ShadingModel::Pbrt,
        render_hairs_per_cm2: 20.0,
        ..FrameSettings::default().with_body_simulation()
    };
    // The motion, looped: the turn, then the gust (its wind and turbulence
    // set before each step).
    let pose = |p: &mut FramePipeline, t: f32, pivot| {
        let t = t % 3.2;
        p.set_wind(motion::gust(t, motion::GUST_WIND));
        p.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
        motion::turn(t, pivot)
    };
    let mut frame_ms = Vec::new();
    let mut serial = (0.0, 1.0);
    for n in [1usize, 2] {
        let pool = Workers::new(n).unwrap();
        let mut p = FramePipeline::new(&scene, settings.clone(), 1.5).unwrap();
        let pivot = p.pivot();
        let mut t = 0.0f32;
        let start = pose(&mut p, 0.0, pivot);
        p.frame_with(1.0 / 30.0, start, &pool);
        p.reset_timings();
        let mut g = c.benchmark_group(format!("threads/{n}"));
        g.sample_size(10);
        g.bench_function("simulate", |b| {
            b.iter(|| {
                t += 1.0 / 30.0;
                let at = pose(&mut p, t, pivot);
                p.simulate_with(1.0 / 30.0, at, &pool);
            })
        });
        g.bench_function("prepare", |b| b.iter(|| p.prepare_with(&pool)));
        g.bench_function("render", |b| b.iter(|| p.render_with(&pool)));
        g.bench_function("frame", |b| {
            b.iter(|| {
                t += 1.0 / 30.0;
                let at = pose(&mut p, t, pivot);
                black_box(p.frame_with(1.0 / 30.0, at, &pool))
            })
        });
        g.finish();
        // The split from whole frames alone (the means above mix the
        // stages' own iterations in).
        p.reset_timings();
        for _ in 0..5 {
            t += 1.0 / 30.0;
            let at = pose(&mut p, t, pivot);
            p.frame_with(1.0 / 30.0, at, &pool);
        }
        eprintln!(
            "\nthreads/{n}: per-stage means over 5 frames after the bench ({} shadow tasks):\n{}\n",
            p.shadow_tasks(),
            p.timings()
        );
        let split = serial_split(&p);
        if n == 1 {
            serial = split;
        }
        frame_ms.push(split.1);
    }
    let f = serial.0 / serial.1;
    let amdahl = |cores: f64| 1.0 / (f + (1.0 - f) / cores);
    eprintln!(
        "serial parts {:.2} ms of a {:.2} ms frame at 1 thread: serial fraction {:.3}; Amdahl: {:.2}x at 2, {:.2}x at 8, {:.2}x at 16 cores; those 5 frames 1 -> 2 threads: {:.2}x\n",
        serial.0,
        serial.1,
        f,
        amdahl(2.0),
        amdahl(8.0),
        amdahl(16.0),
        frame_ms[0] / frame_ms[1]
    );

    // Four characters sharing one pool (the sphere head).
    let scene = default_head();
    let settings = FrameSettings::small(256);
    for n in [1usize, 2] {
        let pool = Workers::new(n).unwrap();
        let mut heads: Vec<FramePipeline> = (0..4)
            .map(|_| FramePipeline::new(&scene, settings.clone(), 1.0).unwrap())
            .collect();
        let pivot = heads[0].pivot();
        let mut t = 0.0f32;
        let mut g = c.benchmark_group(format!("characters4/{n}"));
        g.sample_size(10);
        g.bench_function("stages_on_pool", |b| {
            b.iter(|| {
                t += 1.0 / 30.0;
                for (k, h) in heads.iter_mut().enumerate() {
                    let pose = motion::turn_and_nod((t + 0.5 * k as f32) % 3.0, pivot);
                    h.frame_with(1.0 / 30.0, pose, &pool);
                }
            })
        });
        g.bench_function("characters_as_tasks", |b| {
            b.iter(|| {
                t += 1.0 / 30.0;
                let now = t;
                coif::base::tasks::for_each_chunk_mut(&pool, &mut heads, 1, &|k, h| {
                    let pose = motion::turn_and_nod((now + 0.5 * k as f32) % 3.0, pivot);
                    h[0].frame_with(1.0 / 30.0, pose, &Serial);
                });
            })
        });
        g.finish();
    }
}

criterion_group!(benches, frames, prepare, raster, shade, threads);
criterion_main!(benches);
