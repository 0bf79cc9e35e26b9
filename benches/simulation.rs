//! Simulation step, SIMD against scalar, on the TressFX mohawk (2,226 x 32)
//! and a synthetic 10,000 x 32 head, over projections per substep
//! (`iterations`) {1, 2} at the default 4 substeps of 1/240 s, pearls {0, 1}
//! and rigs of {1, 16, 256} spheres (head, neck, and the rest of a body rig
//! a body length away: the broad phase keeps the 254 far ones out of the
//! narrow phase), plus the default with local shape constraints on
//! (`shape1`). Throughput is in vertex-steps per second.
//!
//! `cargo bench --bench simulation` (add `-- --quick` for a fast pass).

use coif::geometry::scene::{
    body_rig, grow_on_sphere, rig_with_distractors, scalp_spheres, GrowOptions,
};
use coif::groom::tfx;
use coif::kernels::{self, scalar, SimParams, Sphere, Strands};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;
use std::time::Duration;

/// The mohawk in metres with a rig builder: two 8 cm spheres tangent under
/// its scalp, then distractors; None when the shared grooms are absent.
fn mohawk() -> Option<(Vec<Vec3>, usize, Rig)> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/data/grooms/ratboy_mohawk.tfx"
    );
    let bytes = std::fs::read(path).ok()?;
    let (pts, v) = tfx::parse(&bytes).ok()?.uniform_points(0.01)?;
    let near = scalp_spheres(&pts, v, 2, 0.08);
    let anchor = near[0].center;
    let rig: Rig = Box::new(move |n| {
        rig_with_distractors(&near[..n.min(2)], anchor, 0.1, n.saturating_sub(2))
    });
    Some((pts, v, rig))
}

/// 10,000 grown strands on a 10 cm head, with a head-and-neck body rig.
fn synthetic() -> (Vec<Vec3>, usize, Rig) {
    let s = grow_on_sphere(&GrowOptions {
        strand_count: 10_000,
        verts_per_strand: 32,
        curl: 0.3,
        ..Default::default()
    });
    let head = s.head.clone();
    (
        s.points,
        s.verts_per_strand,
        Box::new(move |n| body_rig(&head, n)),
    )
}

/// Builds a rig of n spheres.
type Rig = Box<dyn Fn(usize) -> Vec<Sphere>>;

fn bench_set(c: &mut Criterion, name: &str, pts: &[Vec3], verts: usize, make_rig: &Rig) {
    let mut group = c.benchmark_group(format!("step/{name}"));
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    group.throughput(Throughput::Elements(pts.len() as u64));
    let mut rows = vec![];
    for iterations in [1u32, 2] {
        for pearls in [0u32, 1] {
            for spheres in [1usize, 16, 256] {
                rows.push((iterations, pearls, spheres, 0.0f32));
            }
        }
    }
    rows.push((1, 1, 16, 1.0));
    for (iterations, pearls, spheres, shape) in rows {
        let rig = make_rig(spheres);
        let params = SimParams {
            iterations,
            pearls_per_segment: pearls,
            local_shape_stiffness: shape,
            ..Default::default()
        };
        // Start from a draped state, as in a running game.
        let mut settled = Strands::from_polylines(pts, verts).unwrap();
        for _ in 0..30 {
            kernels::step(&mut settled, &params, &rig);
        }
        let id = if shape > 0.0 {
            format!("it{iterations}/pearls{pearls}/spheres{spheres}/shape1")
        } else {
            format!("it{iterations}/pearls{pearls}/spheres{spheres}")
        };
        let mut s = settled.clone();
        group.bench_function(BenchmarkId::new("simd", &id), |b| {
            b.iter(|| kernels::step(black_box(&mut s), &params, &rig))
        });
        let mut s = settled.clone();
        group.bench_function(BenchmarkId::new("scalar", &id), |b| {
            b.iter(|| scalar::step(black_box(&mut s), &params, &rig))
        });
    }
    group.finish();
}

fn simulation(c: &mut Criterion) {
    match mohawk() {
        Some((pts, v, rig)) => bench_set(c, "mohawk_2226x32", &pts, v, &rig),
        None => eprintln!("skipping the mohawk: ../shared/data/grooms is absent"),
    }
    let (pts, v, rig) = synthetic();
    bench_set(c, "synthetic_10000x32", &pts, v, &rig);
}

criterion_group!(benches, simulation);
criterion_main!(benches);
