//! Patches (fins, ribbons): SIMD against scalar step, in particle-steps per
//! second, at a few sizes and iteration counts; what each constraint kind
//! costs; the layout question (one patch with columns in lanes, against the
//! strand layout where one patch would fill one lane); and time against
//! error over iterations (the error table is printed first, from
//! `coif::kernels::patch::quality::convergence`).
//!
//! `patch/threads`: 64 demo-sized ribbons (18 x 8) stepped together by
//! `patch::step_all` on `Serial` and on rayon pools of 1 and 2 threads.
//!
//! `cargo bench --bench patch -- --warm-up-time 0.5 --measurement-time 2`

use coif::kernels::patch::{self, quality, ribbon_on_sphere};
mod common;

use coif::kernels::{Patch, SimParams, Sphere};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;
use std::time::Duration;

fn head() -> Sphere {
    Sphere {
        center: Vec3::new(0.0, 1.6, 0.0),
        radius: 0.1,
    }
}

/// A `rows x cols` ribbon on the head, 1 cm between particles, settled for
/// 30 steps so it drapes on the head as in a running game.
fn settled_ribbon(rows: usize, cols: usize, params: &SimParams, shear: f32) -> Patch {
    let ribbon = ribbon_on_sphere(
        &head(),
        Vec3::new(0.2, 0.5, -1.0),
        0.01 * (cols - 1) as f32,
        0.01 * (rows - 1) as f32,
        rows,
        cols,
    );
    let mut p = ribbon.patch().unwrap();
    p.set_shear_stiffness(shear).unwrap();
    for _ in 0..30 {
        patch::step(&mut p, params, &[head()]);
    }
    p
}

fn configure(group: &mut criterion::BenchmarkGroup<criterion::measurement::WallTime>) {
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
}

fn step_sizes(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    let mut group = c.benchmark_group("patch/step");
    configure(&mut group);
    for (rows, cols) in [(16usize, 8usize), (16, 16), (32, 32)] {
        group.throughput(Throughput::Elements((rows * cols) as u64));
        for iterations in [4u32, 16] {
            let params = SimParams {
                iterations,
                ..Default::default()
            };
            let rig = [head()];
            let settled = settled_ribbon(rows, cols, &params, 1.0);
            let id = format!("{rows}x{cols}/it{iterations}");
            let mut p = settled.clone();
            group.bench_function(BenchmarkId::new("simd", &id), |b| {
                b.iter(|| patch::step(black_box(&mut p), &params, &rig))
            });
            let mut p = settled.clone();
            group.bench_function(BenchmarkId::new("scalar", &id), |b| {
                b.iter(|| patch::scalar::step(black_box(&mut p), &params, &rig))
            });
        }
    }
    group.finish();
}

/// 32 x 32, 4 iterations: rows and columns only, + shear, + bending, + pearls.
fn constraint_kinds(c: &mut Criterion) {
    let mut group = c.benchmark_group("patch/constraints");
    configure(&mut group);
    group.throughput(Throughput::Elements(32 * 32));
    let rig = [head()];
    for (name, shear, bend, pearls) in [
        ("grid", 0.0, 0.0, 0),
        ("grid+shear", 1.0, 0.0, 0),
        ("grid+shear+bend", 1.0, 0.5, 0),
        ("grid+shear+bend+pearls", 1.0, 0.5, 1),
    ] {
        let params = SimParams {
            bend_stiffness: bend,
            pearls_per_segment: pearls,
            ..Default::default()
        };
        let mut p = settled_ribbon(32, 32, &params, shear);
        group.bench_function(BenchmarkId::new("simd", name), |b| {
            b.iter(|| patch::step(black_box(&mut p), &params, &rig))
        });
    }
    group.finish();
}

/// The layout question. A 32 x 8 patch is one column block with every lane
/// busy; a 32 x 2 patch is one block with 2 of 8 lanes in use. If both cost
/// the same per step, a block's cost does not depend on how many lanes hold
/// particles, and the strand layout (patches in lanes), which gives a lone
/// patch one lane of each block, would pay 8 times per particle.
fn layout(c: &mut Criterion) {
    let mut group = c.benchmark_group("patch/layout");
    configure(&mut group);
    let params = SimParams::default();
    let rig = [head()];
    for cols in [8usize, 2] {
        let mut p = settled_ribbon(32, cols, &params, 1.0);
        group.throughput(Throughput::Elements(32 * cols as u64));
        group.bench_function(
            BenchmarkId::new("one_block_32_rows", format!("{cols}_lanes")),
            |b| b.iter(|| patch::step(black_box(&mut p), &params, &rig)),
        );
    }
    group.finish();
}

/// Time against error: the 16 x 16 quality scene's cost per step at each
/// iteration count (errors printed from `quality::convergence`).
fn iterations(c: &mut Criterion) {
    let settings = [1u32, 2, 4, 8, 16, 32];
    eprintln!("patch quality, 16 x 16 flag, one step against 256 iterations, 60 steps:");
    eprintln!("iterations | rms distance (mm) | max distance (mm) | max edge stretch");
    for it in settings {
        let q = quality::convergence(16, 16, it, 60).expect("valid scene");
        eprintln!(
            "{:10} | {:17.3} | {:17.3} | {:.4}",
            it,
            q.rms_distance * 1e3,
            q.max_distance * 1e3,
            q.max_stretch
        );
    }
    let mut group = c.benchmark_group("patch/iterations");
    configure(&mut group);
    group.throughput(Throughput::Elements(16 * 16));
    let (points, pinned) = quality::flag_scene(16, 16);
    for it in settings {
        let params = SimParams {
            iterations: it,
            ..Default::default()
        };
        let mut p = Patch::new(&points, 16, 16, &pinned).unwrap();
        for _ in 0..30 {
            patch::step(&mut p, &params, &[]);
        }
        group.bench_function(BenchmarkId::new("simd", it), |b| {
            b.iter(|| patch::step(black_box(&mut p), &params, &[]))
        });
    }
    group.finish();
}

/// 64 ribbons of 18 x 8 particles (the demo's bow tails), 4 iterations,
/// stepped as tasks.
fn threads(c: &mut Criterion) {
    let params = SimParams {
        iterations: 4,
        ..Default::default()
    };
    let settled = vec![settled_ribbon(18, 8, &params, 0.0); 64];
    let rig = [head()];
    let mut group = c.benchmark_group("patch/threads");
    configure(&mut group);
    group.throughput(Throughput::Elements(64 * 18 * 8));
    let executors = common::executors();
    for (name, exec) in &executors {
        let mut ps = settled.clone();
        group.bench_function(BenchmarkId::new("64x18x8/it4", name), |b| {
            b.iter(|| patch::step_all(black_box(&mut ps), &params, &rig, exec.as_ref()))
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    step_sizes,
    constraint_kinds,
    layout,
    iterations,
    threads
);
criterion_main!(benches);
