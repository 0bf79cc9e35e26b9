//! Opacity shadow map benchmarks: build time per hair segment, lookup time
//! per sample (SIMD and scalar side by side), and build time against error
//! for slice counts and modes.
//!
//! Groups (throughput in segments or samples, so criterion reports time per
//! element):
//! - `shadow_build/<mode>_L<layers>/{simd,scalar}`: rebuild a 256^2 map of
//!   a draped head (2048 strands x 32 vertices, 63,488 segments), per
//!   segment, with `build` (SIMD) and `shadow::scalar::build`.
//! - `shadow_build/deep_L3/{lanes_simd,lanes_scalar}`: the same head in
//!   lane layout (eight strands per block, `to_lane_rows`) with
//!   `build_lanes` (one task, serial) and `shadow::scalar::build_lanes`,
//!   the fused prepare pass's build.
//! - `shadow_lookup/<mode>_L<layers>/{simd,scalar}`: transmittance at all
//!   65,536 vertices of the head, per sample.
//! - `shadow_time_vs_error/<mode>/L<layers>_err<mean |error|>`: build time
//!   (SIMD `build`) of a 128^2 map of a smaller draped head (512 x 16) for slices 4..64 and
//!   deep layers 2..16, with the mean |T error| against the footprint
//!   reference (16 rays over 2 mm, every 8th strand's vertices) in the id;
//!   the full error table (mean, RMS, max, bias) is printed first.
//! - `shadow_cache_stream/{build,lookup}/{cache,stream}`: the frame's map
//!   (deep, 3 layers, 128^2) built from and looked up at 256 draped strands
//!   x 32 (in cache) and the same head repeated 64 times side by side
//!   (16,384 strands, 6 MiB of points and 2 MiB of output per pass; the
//!   map itself stays in cache, which is the point of the build's layout).

use coif::base::tasks::Serial;
use coif::frame::drape::draped_on_sphere;
use coif::shading::shadow::quality::{error_of_map, reference_transmittance, Footprint};
use coif::shading::shadow::{
    to_lane_rows, BuildScratch, LaneRows, OpacityShadowMap, ShadowMode, ShadowSettings,
};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;

/// Hair grown on a sphere head, draped under gravity for 60 steps.
fn draped_head(strands: usize, verts: usize) -> (Vec<Vec3>, usize) {
    draped_on_sphere(strands, verts, 60)
}

fn light() -> Vec3 {
    Vec3::new(1.0, -0.5, 0.3).normalize()
}

fn name(s: &ShadowSettings) -> String {
    let mode = match s.mode {
        ShadowMode::Slices => "slices",
        ShadowMode::Deep => "deep",
    };
    format!("{mode}_L{}", s.layers)
}

fn configurations() -> [ShadowSettings; 3] {
    [
        ShadowSettings::default(),
        ShadowSettings {
            layers: 64,
            ..Default::default()
        },
        ShadowSettings::deep(),
    ]
}

fn build_and_lookup(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    let (pts, verts) = draped_head(2048, 32);
    let segments = pts.len() / verts * (verts - 1);
    let mut g = c.benchmark_group("shadow_build");
    g.throughput(Throughput::Elements(segments as u64));
    for s in configurations() {
        let mut map = OpacityShadowMap::new(s.clone()).unwrap();
        g.bench_function(BenchmarkId::new(name(&s), "simd"), |b| {
            b.iter(|| map.build(black_box(light()), black_box(&pts), verts))
        });
        g.bench_function(BenchmarkId::new(name(&s), "scalar"), |b| {
            b.iter(|| {
                coif::shading::shadow::scalar::build(
                    &mut map,
                    black_box(light()),
                    black_box(&pts),
                    verts,
                )
            })
        });
        if s.mode == ShadowMode::Deep {
            let mut rows = Vec::new();
            let strands = to_lane_rows(&pts, verts, Vec3::ZERO, &mut rows);
            let hair = LaneRows {
                rows: &rows,
                verts,
                strands,
            };
            let mut scratch = BuildScratch::new(&s, 1).unwrap();
            g.bench_function(BenchmarkId::new(name(&s), "lanes_simd"), |b| {
                b.iter(|| {
                    map.build_lanes(&Serial, &mut scratch, black_box(light()), &hair)
                        .unwrap()
                })
            });
            g.bench_function(BenchmarkId::new(name(&s), "lanes_scalar"), |b| {
                b.iter(|| {
                    coif::shading::shadow::scalar::build_lanes(&mut map, black_box(light()), &hair)
                })
            });
        }
    }
    g.finish();

    let mut out = vec![0.0; pts.len()];
    let mut g = c.benchmark_group("shadow_lookup");
    g.throughput(Throughput::Elements(pts.len() as u64));
    for s in configurations() {
        let mut map = OpacityShadowMap::new(s.clone()).unwrap();
        map.build(light(), &pts, verts);
        g.bench_function(BenchmarkId::new(name(&s), "simd"), |b| {
            b.iter(|| map.transmittance_batch(black_box(&pts), &mut out).unwrap())
        });
        g.bench_function(BenchmarkId::new(name(&s), "scalar"), |b| {
            b.iter(|| {
                coif::shading::shadow::scalar::transmittance_batch(&map, black_box(&pts), &mut out)
                    .unwrap()
            })
        });
    }
    g.finish();
}

fn time_vs_error(c: &mut Criterion) {
    let (pts, verts) = draped_head(512, 16);
    let stride = 8;
    let footprint = Footprint {
        rays: 16,
        radius: 0.002,
    };
    let reference = reference_transmittance(
        &ShadowSettings::default(),
        light(),
        &pts,
        verts,
        stride,
        footprint,
    );
    let settings: Vec<ShadowSettings> = [4, 8, 16, 32, 64]
        .map(|layers| (ShadowMode::Slices, layers))
        .into_iter()
        .chain([2, 3, 4, 8, 16].map(|layers| (ShadowMode::Deep, layers)))
        .map(|(mode, layers)| ShadowSettings {
            mode,
            layers,
            resolution: 128,
            ..Default::default()
        })
        .collect();
    println!("shadow map error against the footprint reference (512 x 16 draped head, 128^2):");
    println!("setting     mean|e|  rms     max     bias    mean T_ref");
    let mut g = c.benchmark_group("shadow_time_vs_error");
    g.throughput(Throughput::Elements(
        (pts.len() / verts * (verts - 1)) as u64,
    ));
    for s in &settings {
        let mut map = OpacityShadowMap::new(s.clone()).unwrap();
        map.build(light(), &pts, verts);
        let e = error_of_map(&map, &pts, verts, stride, &reference);
        println!(
            "{:<11} {:.4}  {:.4}  {:.4}  {:+.4}  {:.3}",
            name(s),
            e.mean_abs,
            e.rms,
            e.max_abs,
            e.bias,
            e.mean_reference
        );
        let mode = if s.mode == ShadowMode::Deep {
            "deep"
        } else {
            "slices"
        };
        let id = BenchmarkId::new(mode, format!("L{}_err{:.4}", s.layers, e.mean_abs));
        g.bench_function(id, |b| {
            b.iter(|| map.build(black_box(light()), black_box(&pts), verts))
        });
    }
    g.finish();
}

fn cache_and_stream(c: &mut Criterion) {
    let (one, verts) = draped_head(256, 32);
    let settings = ShadowSettings {
        resolution: 128,
        ..ShadowSettings::deep()
    };
    let mut g = c.benchmark_group("shadow_cache_stream");
    g.sample_size(10);
    for (size, copies) in [("cache", 1), ("stream", 64)] {
        let pts: Vec<Vec3> = (0..copies)
            .flat_map(|k| {
                let shift = Vec3::new(0.4 * k as f32, 0.0, 0.0);
                one.iter().map(move |p| *p + shift)
            })
            .collect();
        let mut map = OpacityShadowMap::new(settings.clone()).unwrap();
        g.throughput(Throughput::Elements(
            (pts.len() / verts * (verts - 1)) as u64,
        ));
        g.bench_function(BenchmarkId::new("build", size), |b| {
            b.iter(|| map.build(black_box(light()), black_box(&pts), verts))
        });
        map.build(light(), &pts, verts);
        let mut out = vec![0.0; pts.len()];
        g.throughput(Throughput::Elements(pts.len() as u64));
        g.bench_function(BenchmarkId::new("lookup", size), |b| {
            b.iter(|| map.transmittance_batch(black_box(&pts), &mut out).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, build_and_lookup, time_vs_error, cache_and_stream);
criterion_main!(benches);
