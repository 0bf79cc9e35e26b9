//! coif-lod benchmarks: SIMD and scalar side by side, and time against error.
//!
//! Groups:
//! - `refine/{simd,scalar}`: output vertices per second at 4 segments per span.
//! - `refine_level/N=../err=..`: time of the SIMD batch at 1..16 segments per
//!   span, with the measured chord error of a curly strand (metres) in the id.
//! - `interpolate/{simd,scalar}`: a Nalu-size head (4,095 render hairs,
//!   about 123,000 vertices).
//! - `fitter`: strands per second, 64 points to 12 controls (batch `Fitter`
//!   and one-shot `fit`).
//! - `fit_quality/controls=../lambda=../rms=..`: time of the batch fit and
//!   the fit error against the noise-free helix.
//! - `refine_interpolate/{simd,scalar}`: refinement plus the row-by-row
//!   group interpolation of the fused prepare pass, in cache, per render
//!   vertex (the whole-groups head).
//! - `cull`: frustum culling of the head.

use coif::kernels::rng::SplitMix64;
use coif::kernels::Strands;
use coif::lod::{
    self, level, quality, Fitter, Interpolation, RefinedGuides, RenderHairs, Visibility,
};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::{Vec3, Vec4};
use std::hint::black_box;

/// `count` curly guide strands of `verts` control points, 1 cm apart.
fn guides(count: usize, verts: usize, seed: u64) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut rng = SplitMix64::new(seed);
    let side = (count as f32).sqrt().ceil() as usize;
    let mut roots = Vec::new();
    let mut pts = Vec::new();
    for k in 0..count {
        let root = Vec3::new((k % side) as f32 * 0.01, 0.0, (k / side) as f32 * 0.01);
        roots.push(root);
        let phase = rng.range(0.0, std::f32::consts::TAU);
        for v in 0..verts {
            let a = phase + v as f32 * 0.9;
            pts.push(root + Vec3::new(0.01 * a.cos(), -0.02 * v as f32, 0.01 * a.sin()));
        }
    }
    (roots, pts)
}

fn refine(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    let (_, pts) = guides(512, 16, 1);
    let strands = Strands::from_polylines(&pts, 16).unwrap();
    let mut out = RefinedGuides::new(strands.blocks(), 16).unwrap();
    out.set_segments_per_span(4).unwrap();
    let verts = (strands.strand_count() * out.verts_per_strand()) as u64;
    let mut g = c.benchmark_group("refine");
    g.throughput(Throughput::Elements(verts));
    g.bench_function("simd", |b| {
        b.iter(|| lod::refine_strands(black_box(strands.blocks()), None, &mut out).unwrap())
    });
    g.bench_function("scalar", |b| {
        b.iter(|| lod::scalar::refine_strands(black_box(strands.blocks()), None, &mut out).unwrap())
    });
    g.bench_function("positions_simd", |b| {
        b.iter(|| {
            lod::refine_strands_positions(black_box(strands.blocks()), None, &mut out).unwrap()
        })
    });
    g.bench_function("positions_scalar", |b| {
        b.iter(|| {
            lod::scalar::refine_strands_positions(black_box(strands.blocks()), None, &mut out)
                .unwrap()
        })
    });
    g.finish();

    let mut g = c.benchmark_group("refine_level");
    let curl = quality::helix(16, 0.01, 0.3, 2.0);
    for n in [1usize, 2, 3, 4, 6, 8, 12, 16] {
        out.set_segments_per_span(n).unwrap();
        let err = quality::chord_error(&curl, n);
        let bound = level::chord_error_bound(level::max_second_difference(&curl), n);
        g.throughput(Throughput::Elements(
            (strands.strand_count() * out.verts_per_strand()) as u64,
        ));
        let id = BenchmarkId::new(format!("N={n}"), format!("err={err:.2e}_bound={bound:.2e}"));
        g.bench_function(id, |b| {
            b.iter(|| lod::refine_strands(black_box(strands.blocks()), None, &mut out).unwrap())
        });
    }
    g.finish();
}

/// A Nalu-size head: 144 guides of 11 controls at N = 3 (31 vertices), and
/// about 4,095 render hairs over 242 scalp triangles (exact per-triangle
/// counts, or whole groups of 8).
fn head(whole_groups: bool) -> (Strands, Interpolation, RefinedGuides) {
    let (roots, pts) = guides(144, 11, 2);
    let mut tris = Vec::new();
    for j in 0..11u32 {
        for i in 0..11u32 {
            let g = |j: u32, i: u32| j * 12 + i;
            tris.push([g(j, i), g(j, i + 1), g(j + 1, i)]);
            tris.push([g(j, i + 1), g(j + 1, i + 1), g(j + 1, i)]);
        }
    }
    let strands = Strands::from_polylines(&pts, 11).unwrap();
    // 121 cm^2 of scalp: 4,095 / 121 hairs per cm^2.
    let density = 4095.0 / 121.0;
    let interp = if whole_groups {
        Interpolation::with_whole_groups(&roots, &tris, density, 7).unwrap()
    } else {
        Interpolation::new(&roots, &tris, density, 7).unwrap()
    };
    let mut guides = RefinedGuides::new(strands.blocks(), 8).unwrap();
    guides.set_segments_per_span(3).unwrap();
    lod::refine_strands(strands.blocks(), None, &mut guides).unwrap();
    (strands, interp, guides)
}

fn interpolate(c: &mut Criterion) {
    let mut g = c.benchmark_group("interpolate");
    for whole in [false, true] {
        let (_, interp, guides) = head(whole);
        let mut out = RenderHairs::new(&interp, &guides);
        let groups = interp.group_count();
        let verts = interp.hair_count() * guides.verts_per_strand();
        let tag = if whole {
            "whole_groups"
        } else {
            "exact_counts"
        };
        eprintln!(
            "interpolate {tag}: {} render hairs, {} vertices, {} groups ({:.0}% of lanes used)",
            interp.hair_count(),
            verts,
            groups,
            100.0 * interp.hair_count() as f64 / (groups * 8) as f64
        );
        g.throughput(Throughput::Elements(verts as u64));
        g.bench_function(format!("{tag}/simd"), |b| {
            b.iter(|| {
                lod::interpolate(black_box(&interp), &guides, None, groups, &mut out).unwrap()
            })
        });
        g.bench_function(format!("{tag}/scalar"), |b| {
            b.iter(|| {
                lod::scalar::interpolate(black_box(&interp), &guides, None, groups, &mut out)
                    .unwrap()
            })
        });
        g.bench_function(format!("{tag}/positions_simd"), |b| {
            b.iter(|| {
                lod::interpolate_positions(black_box(&interp), &guides, None, groups, &mut out)
                    .unwrap()
            })
        });
        let prefix = groups / 8;
        g.throughput(Throughput::Elements(
            (interp.hairs_in_prefix(prefix) * guides.verts_per_strand()) as u64,
        ));
        g.bench_function(format!("{tag}/positions_simd_eighth"), |b| {
            b.iter(|| {
                lod::interpolate_positions(black_box(&interp), &guides, None, prefix, &mut out)
                    .unwrap()
            })
        });
        g.bench_function(format!("{tag}/simd_eighth"), |b| {
            b.iter(|| {
                lod::interpolate(black_box(&interp), &guides, None, prefix, &mut out).unwrap()
            })
        });
        g.throughput(Throughput::Elements(verts as u64));
        g.bench_function(format!("{tag}/positions_scalar"), |b| {
            b.iter(|| {
                lod::scalar::interpolate_positions(
                    black_box(&interp),
                    &guides,
                    None,
                    groups,
                    &mut out,
                )
                .unwrap()
            })
        });
    }
    g.finish();
}

/// Refine + interpolate as the fused prepare pass runs them, per render
/// vertex: `refine_strands` of the head's guides, then every group's rows
/// (`GroupBlend::position_simd` and `tangent_simd`) consumed at once instead of
/// stored (a running sum stands in for the shading), so everything stays
/// in cache; the scalar twin refines with `scalar::refine_strands` and
/// blends one lane at a time. Elements = render vertices.
fn refine_and_interpolate(c: &mut Criterion) {
    let mut g = c.benchmark_group("refine_interpolate");
    let (strands, interp, mut guides) = head(true);
    let groups = interp.group_count();
    let verts = interp.hair_count() * guides.verts_per_strand();
    g.throughput(Throughput::Elements(verts as u64));
    g.bench_function("simd", |b| {
        b.iter(|| {
            lod::refine_strands(strands.blocks(), None, &mut guides).unwrap();
            let mut acc = coif::base::Vec3Lanes::ZERO;
            for k in 0..groups {
                let Some(blend) = interp.group_blend(&guides, k) else {
                    continue;
                };
                for r in 0..blend.verts() {
                    acc = acc + blend.position_simd(r) + blend.tangent_simd(r);
                }
            }
            black_box(acc)
        })
    });
    g.bench_function("scalar", |b| {
        b.iter(|| {
            lod::scalar::refine_strands(strands.blocks(), None, &mut guides).unwrap();
            let mut acc = Vec3::ZERO;
            for k in 0..groups {
                let Some(blend) = interp.group_blend(&guides, k) else {
                    continue;
                };
                for l in 0..blend.hairs() {
                    for r in 0..blend.verts() {
                        acc += blend.position(l, r) + blend.tangent(l, r);
                    }
                }
            }
            black_box(acc)
        })
    });
    g.finish();
}

fn cull(c: &mut Criterion) {
    let (strands, interp, _) = head(false);
    let mut vis = Visibility::new(strands.strand_count(), interp.group_count());
    let big = Vec4::new(0.0, 1.0, 0.0, 100.0);
    let frustum =
        lod::Frustum::from_planes([Vec4::new(-1.0, 0.0, 0.0, 0.05), big, big, big, big, big]);
    c.bench_function("cull/head", |b| {
        b.iter(|| {
            lod::cull(
                black_box(strands.blocks()),
                Some(&interp),
                interp.group_count(),
                &frustum,
                1e-4,
                &mut vis,
            )
            .unwrap()
        })
    });
}

fn fitter(c: &mut Criterion) {
    let (p, n, strands) = (64usize, 12usize, 1024usize);
    let mut rng = SplitMix64::new(3);
    let mut pts = Vec::with_capacity(p * strands);
    for _ in 0..strands {
        let curl = quality::helix(p, rng.range(0.005, 0.02), 0.25, rng.range(1.0, 3.0));
        pts.extend(quality::with_noise(&curl, 5e-4, rng.next_u64()));
    }
    let mut fit = Fitter::new(p, n, 0.1).unwrap();
    let mut out = vec![Vec3::ZERO; n * strands];
    let mut g = c.benchmark_group("fitter");
    g.throughput(Throughput::Elements(strands as u64));
    g.bench_function("batch_64_to_12", |b| {
        b.iter(|| fit.fit_into(black_box(&pts), &mut out).unwrap())
    });
    g.throughput(Throughput::Elements(1));
    g.bench_function("one_shot_fit_64_to_12", |b| {
        b.iter(|| lod::fit(black_box(&pts[..p]), n, 0.1).unwrap())
    });
    g.finish();

    // Time against error: controls and lambda vs the error of the fit to a
    // noisy helix, measured against the noise-free helix.
    let truth = quality::helix(p, 0.015, 0.25, 2.0);
    let noisy = quality::with_noise(&truth, 1e-3, 9);
    let batch: Vec<Vec3> = noisy.iter().copied().cycle().take(p * 256).collect();
    let mut g = c.benchmark_group("fit_quality");
    g.throughput(Throughput::Elements(256));
    for controls in [6usize, 8, 12, 16, 24] {
        for lambda in [0.0f32, 0.1, 1.0, 10.0] {
            let e = quality::fit_error(&truth, &noisy, controls, lambda).unwrap();
            let mut f = Fitter::new(p, controls, lambda).unwrap();
            let mut out = vec![Vec3::ZERO; controls * 256];
            let id = BenchmarkId::new(
                format!("controls={controls}"),
                format!("lambda={lambda}_rms={:.2e}", e.rms),
            );
            g.bench_function(id, |b| {
                b.iter(|| f.fit_into(black_box(&batch), &mut out).unwrap())
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = refine, interpolate, refine_and_interpolate, cull, fitter
}
criterion_main!(benches);
