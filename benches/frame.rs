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

use coif::base::tasks::Serial;
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
    let default = HairScene::procedural(&GrowOptions {
        strand_count: 2048,
        curl: 0.15,
        ..GrowOptions::default()
    })
    .unwrap();
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
    let scene = HairScene::procedural(&GrowOptions {
        strand_count: 2048,
        curl: 0.15,
        ..GrowOptions::default()
    })
    .unwrap();
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

criterion_group!(benches, frames, prepare, raster, shade);
criterion_main!(benches);
