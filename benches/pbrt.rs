//! pbrt-v3 hair model: nanoseconds per sample for the exact model at one
//! offset h, the far field (integrated over h) at several quadrature orders,
//! and the lookup tables (scalar and SIMD) at several resolutions; each
//! quality setting's error against the reference far field is printed once
//! (time against error); `pbrt/cache_stream/table64/{cache,stream}`: the
//! default 64^2 table (SIMD batch) on 2,048 samples (in cache) and on
//! 1,048,576 (past the last-level cache), the roofline's two columns. Run:
//! `cargo bench --bench pbrt -- --warm-up-time 0.5 --measurement-time 2`

use coif::kernels::rng::SplitMix64;
use coif::shading::pbrt::{self, quality, FarField, Parameterisation, Params, Table};
use coif::shading::{RgbBuffer, ShadingSamples};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;

const N: usize = 4096;

fn samples() -> ShadingSamples {
    let mut rng = SplitMix64::new(42);
    let mut s = ShadingSamples::with_capacity(N);
    for _ in 0..N {
        s.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
    }
    s
}

fn exact(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    let p = Params::default();
    let lobes = pbrt::Lobes::new(&p);
    let s = samples();
    let mut g = c.benchmark_group("pbrt/exact");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("scattering_local", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for k in 0..N {
                let (t, wi, wo) = s.get(k);
                // t's x component as an offset h in [-1, 1].
                acc += pbrt::scattering_local_with(&lobes, &p, t.x, wo, wi);
            }
            black_box(acc)
        })
    });
    g.finish();
}

fn far_field(c: &mut Criterion) {
    let p = Params::default();
    let s = samples();
    let mut g = c.benchmark_group("pbrt/far_field");
    g.throughput(Throughput::Elements(N as u64));
    for order in [16usize, 36, 72, 144] {
        let err = quality::far_field_error(&p, order, 2000, 7).unwrap();
        eprintln!("pbrt far field order {order}: relative RMS error {err:.3e}");
        let ff = FarField::new(&p, order).unwrap();
        g.bench_with_input(BenchmarkId::new("order", order), &ff, |b, ff| {
            b.iter(|| {
                let mut acc = Vec3::ZERO;
                for k in 0..N {
                    let (t, wi, wo) = s.get(k);
                    acc += ff.eval(t, wi, wo);
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

fn table(c: &mut Criterion) {
    let p = Params::default();
    let s = samples();
    let mut out = RgbBuffer::zeros(N);
    let mut g = c.benchmark_group("pbrt/table");
    g.throughput(Throughput::Elements(N as u64));
    for axes in [Parameterisation::Angles, Parameterisation::Nalu] {
        for res in [32usize, 64, 128, 256] {
            let err = quality::table_error_with_axes(&p, res, axes, 2000, 7).unwrap();
            eprintln!("pbrt table {axes:?} {res}: relative RMS error {err:.3e}");
            let t = Table::with_axes(&p, res, axes).unwrap();
            let name = format!("{axes:?}/{res}");
            g.bench_function(BenchmarkId::new("scalar", &name), |b| {
                b.iter(|| {
                    coif::shading::pbrt::table::scalar::scattering_batch(
                        &t,
                        black_box(&s),
                        &mut out,
                    )
                })
            });
            g.bench_function(BenchmarkId::new("simd", &name), |b| {
                b.iter(|| t.scattering_batch(black_box(&s), &mut out))
            });
        }
    }
    g.finish();
}

fn build(c: &mut Criterion) {
    let p = Params::default();
    let mut g = c.benchmark_group("pbrt/table_build");
    g.sample_size(10);
    for res in [64usize, 128] {
        g.bench_with_input(BenchmarkId::new("angles", res), &res, |b, &res| {
            b.iter(|| Table::new(&p, res).unwrap())
        });
    }
    g.finish();
}

fn cache_and_stream(c: &mut Criterion) {
    let table = Table::new(&Params::default(), 64).expect("default table");
    let mut g = c.benchmark_group("pbrt/cache_stream");
    g.sample_size(10);
    for (size, n) in [("cache", 2048), ("stream", 1 << 20)] {
        let mut rng = SplitMix64::new(43);
        let mut s = ShadingSamples::with_capacity(n);
        for _ in 0..n {
            s.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
        }
        let mut out = RgbBuffer::zeros(n);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function(BenchmarkId::new("table64", size), |b| {
            b.iter(|| table.scattering_batch(black_box(&s), &mut out))
        });
    }
    g.finish();
}

criterion_group!(benches, exact, far_field, table, build, cache_and_stream);
criterion_main!(benches);
