//! Shading benchmarks: nanoseconds per sample, SIMD and scalar side by side,
//! and time against error for the Marschner lookup tables.
//!
//! Groups (throughput in samples, so criterion reports time per sample):
//! - `baseline/read9_write3`: the memory floor (read a sample, write RGB).
//! - `kajiya_kay/{simd,scalar}`: diffuse + two shifted highlights.
//! - `marschner/{direct_scalar, lut128_simd, lut128_scalar}`: the direct model
//!   (scalar only: its root finding branches per sample) and the default
//!   (angular) 128 x 128 tables.
//! - `shading_cache_stream/<model>/{cache,stream}`: Kajiya-Kay and the
//!   Marschner table 128 (SIMD batch) on 2,048 samples (in cache) and on
//!   1,048,576 samples (60 MiB in and out, past the last-level cache):
//!   the in-cache and streaming columns of the report's roofline.
//! - `dual_scattering/<model>/{single_simd, dual_simd, dual_scalar}` on
//!   2,048 samples (in cache): the model's table alone (Marschner 128,
//!   pbrt 64) against the table plus dual scattering, eight samples at a
//!   time as the frame's fused pass runs them (`scattering_simd` then
//!   `DualScattering::shade_layered_simd`, 20 fibres behind), and the scalar
//!   twin (infinitely deep); hair counts 0-40.
//! - `marschner_lut_time_vs_error/<layout>/res<N>_err<relative RMS>`: SIMD
//!   lookup time for every layout and resolution 32..256, with the relative
//!   RMS error against the direct model in the benchmark id (also printed).

use coif::base::lanes::F32Lanes;
use coif::base::{Vec3Lanes, LANES};
use coif::kernels::rng::SplitMix64;
use coif::shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::marschner::{self, accuracy, Lut, LutLayout, Params};
use coif::shading::pbrt;
use coif::shading::{RgbBuffer, ShadingSamples};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;

const N: usize = 4096;

fn random_samples(n: usize, seed: u64) -> ShadingSamples {
    let mut rng = SplitMix64::new(seed);
    let mut s = ShadingSamples::with_capacity(n);
    for _ in 0..n {
        s.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
    }
    s
}

/// The floor of any batch kernel here: read the nine input floats of a
/// sample and write three (their sums), scalar loop the compiler vectorises.
/// Puts the per-sample figures of a loaded machine in proportion.
fn baseline(c: &mut Criterion) {
    let samples = random_samples(N, 1);
    let mut out = RgbBuffer::zeros(N);
    let mut g = c.benchmark_group("baseline");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("read9_write3", |b| {
        b.iter(|| {
            let s = black_box(&samples);
            let (t, wi, wo) = (s.t(), s.wi(), s.wo());
            for i in 0..N {
                out.r[i] = t[0][i] + wi[0][i] + wo[0][i];
                out.g[i] = t[1][i] + wi[1][i] + wo[1][i];
                out.b[i] = t[2][i] + wi[2][i] + wo[2][i];
            }
        })
    });
    g.finish();
}

fn kajiya_kay(c: &mut Criterion) {
    let samples = random_samples(N, 1);
    let kk = KajiyaKay::default();
    let mut out = RgbBuffer::zeros(N);
    let mut g = c.benchmark_group("kajiya_kay");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("simd", |b| {
        b.iter(|| kk.shade_batch(black_box(&samples), &mut out))
    });
    g.bench_function("scalar", |b| {
        b.iter(|| {
            coif::shading::kajiya_kay::scalar::shade_batch(&kk, black_box(&samples), &mut out)
        })
    });
    g.finish();
}

fn marschner_direct_and_lut(c: &mut Criterion) {
    let params = Params::default();
    let samples = random_samples(N, 2);
    let lut = Lut::new(&params, 128);
    let mut out = RgbBuffer::zeros(N);
    let mut g = c.benchmark_group("marschner");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("direct_scalar", |b| {
        b.iter(|| marschner::scattering_batch(&params, black_box(&samples), &mut out))
    });
    g.bench_function("lut128_simd", |b| {
        b.iter(|| lut.scattering_batch(black_box(&samples), &mut out))
    });
    g.bench_function("lut128_scalar", |b| {
        b.iter(|| {
            coif::shading::marschner::lut::scalar::scattering_batch(
                &lut,
                black_box(&samples),
                &mut out,
            )
        })
    });
    g.finish();
}

/// Samples of the in-cache and the streaming batches.
const CACHE: usize = 2048;
const STREAM: usize = 1 << 20;

fn cache_and_stream(c: &mut Criterion) {
    let kk = KajiyaKay::default();
    let lut = Lut::new(&Params::default(), 128);
    let mut g = c.benchmark_group("shading_cache_stream");
    g.sample_size(10);
    for (size, n) in [("cache", CACHE), ("stream", STREAM)] {
        let samples = random_samples(n, 4);
        let mut out = RgbBuffer::zeros(n);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function(BenchmarkId::new("kajiya_kay", size), |b| {
            b.iter(|| kk.shade_batch(black_box(&samples), &mut out))
        });
        g.bench_function(BenchmarkId::new("marschner_lut128", size), |b| {
            b.iter(|| lut.scattering_batch(black_box(&samples), &mut out))
        });
    }
    g.finish();
}

fn marschner_lut_time_vs_error(c: &mut Criterion) {
    let params = Params::default();
    let samples = random_samples(N, 3);
    let mut out = RgbBuffer::zeros(N);
    let mut g = c.benchmark_group("marschner_lut_time_vs_error");
    g.throughput(Throughput::Elements(N as u64));
    for layout in LutLayout::ALL {
        for res in [32, 64, 128, 256] {
            let err = accuracy::lut_relative_rms_error(&params, res, layout, 20_000, 1);
            eprintln!("marschner lut {layout:?} {res}: relative RMS vs direct {err:.4}");
            let lut = Lut::with_layout(&params, res, layout);
            let id = BenchmarkId::new(format!("{layout:?}"), format!("res{res}_err{err:.4}"));
            g.bench_with_input(id, &lut, |b, lut| {
                b.iter(|| lut.scattering_batch(black_box(&samples), &mut out))
            });
        }
    }
    g.finish();
}

/// Every model's error against the yardstick, pbrt-v3's far field, printed
/// beside the timings (Marschner matched to pbrt's material; see
/// `coif::shading::yardstick`). Table sizes 32..256.
fn error_against_pbrt(_c: &mut Criterion) {
    let params = coif::shading::pbrt::Params::default();
    for res in [32, 64, 128, 256] {
        match coif::shading::yardstick::versus_pbrt(&params, res, 20_000, 5) {
            Ok(rows) => {
                for r in rows
                    .iter()
                    .filter(|r| res == 128 || r.model.contains("table"))
                {
                    eprintln!(
                        "vs pbrt far field: {:>22}: relative RMS {:.4}, shape (after gain {:.3}) {:.4}",
                        r.model, r.relative_rms, r.gain, r.relative_rms_after_gain
                    );
                }
            }
            Err(e) => eprintln!("vs pbrt far field: {e}"),
        }
    }
}

/// Single scattering by `single_simd` alone, then with dual scattering, in
/// blocks of eight as the frame's fused pass shades.
fn dual_scattering(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    const M: usize = 2048;
    let samples = random_samples(M, 6);
    let mut rng = SplitMix64::new(7);
    let fibres: Vec<f32> = (0..M).map(|_| rng.range(0.0, 40.0)).collect();
    let direct: Vec<f32> = fibres.iter().map(|n| (-0.4 * n).exp()).collect();
    let blond = pbrt::sigma_a_from_concentration(0.3, 0.0);
    let lut = Lut::new(
        &Params {
            absorption: blond * 0.5,
            ..Params::default()
        },
        128,
    );
    let table = pbrt::Table::new(
        &pbrt::Params {
            sigma_a: blond,
            ..pbrt::Params::default()
        },
        64,
    )
    .expect("valid parameters");
    let settings = DualScatteringSettings::default();
    let ds_lut = DualScattering::from_marschner(&lut, settings).expect("valid settings");
    let ds_table = DualScattering::from_pbrt(&table, settings).expect("valid settings");
    let mut out = RgbBuffer::zeros(M);
    let mut single = RgbBuffer::zeros(M);
    // The frame's hair behind each point (the deep map's last plane minus
    // the point's count): 20 fibres.
    let behind = F32Lanes::splat(20.0);
    let mut g = c.benchmark_group("dual_scattering");
    g.throughput(Throughput::Elements(M as u64));
    type Single<'a> = &'a dyn Fn(Vec3Lanes, Vec3Lanes, Vec3Lanes) -> Vec3Lanes;
    let models: [(&str, Single, &DualScattering); 2] = [
        (
            "marschner_lut128",
            &|t, wi, wo| lut.scattering_simd(t, wi, wo),
            &ds_lut,
        ),
        (
            "pbrt_table64",
            &|t, wi, wo| table.scattering_simd(t, wi, wo),
            &ds_table,
        ),
    ];
    for (name, single_simd, ds) in models {
        g.bench_function(BenchmarkId::new(name, "single_simd"), |b| {
            b.iter(|| {
                let s = black_box(&samples);
                for start in (0..M).step_by(LANES) {
                    let (t, wi, wo) = s.load_block(start);
                    out.store_block(start, single_simd(t, wi, wo));
                }
            })
        });
        g.bench_function(BenchmarkId::new(name, "dual_simd"), |b| {
            b.iter(|| {
                let s = black_box(&samples);
                for start in (0..M).step_by(LANES) {
                    let (t, wi, wo) = s.load_block(start);
                    let n =
                        F32Lanes::new(fibres[start..start + LANES].try_into().expect("a block"));
                    let d =
                        F32Lanes::new(direct[start..start + LANES].try_into().expect("a block"));
                    let f = ds.shade_layered_simd(single_simd(t, wi, wo), t, wi, wo, n, behind, d);
                    out.store_block(start, f);
                }
            })
        });
        for k in 0..M {
            let (t, wi, wo) = samples.get(k);
            single.set(
                k,
                single_simd(
                    Vec3Lanes::splat(t),
                    Vec3Lanes::splat(wi),
                    Vec3Lanes::splat(wo),
                )
                .lane(0),
            );
        }
        g.bench_function(BenchmarkId::new(name, "dual_scalar"), |b| {
            b.iter(|| {
                coif::shading::dual_scattering::scalar::shade_batch(
                    ds,
                    black_box(&samples),
                    &single,
                    &fibres,
                    &direct,
                    &mut out,
                )
            })
        });
    }
    g.finish();
}

criterion_group!(
    benches,
    dual_scattering,
    baseline,
    kajiya_kay,
    marschner_direct_and_lut,
    cache_and_stream,
    marschner_lut_time_vs_error,
    error_against_pbrt
);
criterion_main!(benches);
