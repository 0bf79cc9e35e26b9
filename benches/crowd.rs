//! What skipping unneeded simulation saves.
//!
//! - `sleep/hanging_256x16`: one step of 256 hanging strands (16 x 16
//!   roots, 16 vertices) at rest, awake (`sleep_speed` 0) and asleep (0.02,
//!   after 4 s: every block sleeps), SIMD.
//! - `crowd/16`: one step of the standard crowd of 16 characters
//!   (`coif::frame::crowd::standard_layout`: 4 near, 4 off screen, 8 far,
//!   every other one turning and nodding) of the built-in head with 512
//!   guides of 32 points, with simulation LOD, off-screen following and
//!   sleeping (`skip`) and simulating everyone fully (`full`), one thread,
//!   after 2 s of motion.
//!
//! `cargo bench --bench crowd` (add `-- --quick` for a fast pass).

use coif::base::tasks::Serial;
use coif::frame::crowd::{settled_head, Crowd};
use coif::kernels::{self, SimParams, Strands};
use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use std::hint::black_box;
use std::time::Duration;

#[path = "../kernels/tests/common/mod.rs"]
mod kernels_fixtures;

fn hanging() -> (Vec<Vec3>, usize) {
    (kernels_fixtures::hanging_grid(16, 0.03, 16, 0.02), 16)
}

fn sleep(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    let (pts, verts) = hanging();
    let mut group = c.benchmark_group("sleep/hanging_256x16");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for (name, speed) in [("awake", 0.0f32), ("asleep", 0.02)] {
        let params = SimParams {
            sleep_speed: speed,
            ..Default::default()
        };
        let mut s = Strands::from_polylines(&pts, verts).unwrap();
        for _ in 0..240 {
            kernels::step(&mut s, &params, &[]);
        }
        assert_eq!(s.awake_strands(), if speed > 0.0 { 0 } else { 256 });
        group.bench_function(name, |b| {
            b.iter(|| kernels::step(black_box(&mut s), &params, &[]))
        });
    }
    group.finish();
}

fn crowd(c: &mut Criterion) {
    let (scene, settled) = settled_head(512, 32).unwrap();
    let params = SimParams::default();
    let mut group = c.benchmark_group("crowd/16");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for (name, skip) in [("skip", true), ("full", false)] {
        let mut crowd = Crowd::standard(&scene, &settled, 16, &params, skip).unwrap();
        let mut frame = 0usize;
        for _ in 0..120 {
            crowd.step(frame as f32 / 60.0, &Serial);
            frame += 1;
        }
        group.bench_function(name, |b| {
            b.iter(|| {
                crowd.step(frame as f32 / 60.0, &Serial);
                frame += 1;
            })
        });
    }
    group.finish();
}

criterion_group!(benches, sleep, crowd);
criterion_main!(benches);
