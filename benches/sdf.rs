//! The mesh signed distance field (`coif::kernels::Sdf`): build time of the
//! shared Sintel bust at 4 mm cells (skipped when `../shared` is absent)
//! and of an icosphere of the same size from `coif_testkit::meshes` (5,120 triangles, 20 cm
//! across), and lookups per point, the SIMD lane lookup (eight points per
//! call) against the scalar twin, in cache: 4,096 points near the surface
//! of the icosphere's 1 cm field (about 27,000 nodes, 110 KB) and of the
//! bust's 4 mm field (3 MB).
//!
//! `cargo bench --bench sdf` (add `-- --quick` for a fast pass).

use coif::kernels::{Sdf, Vec3Lanes, LANES};
use coif_testkit::meshes::{icosphere, Mesh};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;
use std::time::Duration;

/// 4,096 points within 2 cm of the mesh's vertices (a deterministic hash).
fn near_points(positions: &[Vec3]) -> Vec<Vec3> {
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..4096)
        .map(|_| {
            let v = positions[(rnd() * positions.len() as f32) as usize % positions.len()];
            v + (Vec3::new(rnd(), rnd(), rnd()) - Vec3::splat(0.5)) * 0.04
        })
        .collect()
}

fn meshes() -> Vec<(&'static str, Mesh)> {
    let mut m = vec![("icosphere5120", icosphere(4, 0.1))];
    if let Some(bust) = coif_testkit::sintel_bust() {
        m.push(("sintel_bust", bust));
    }
    m
}

fn build(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    let mut group = c.benchmark_group("sdf/build_4mm");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4));
    for (name, (p, t)) in meshes() {
        let sdf = Sdf::from_mesh(&p, &t, 0.004).unwrap();
        eprintln!(
            "{name}: {} triangles, {:?} = {} nodes, {:.1} MB",
            t.len(),
            sdf.dims(),
            sdf.node_count(),
            sdf.node_count() as f64 * 4e-6
        );
        group.bench_function(name, |b| {
            b.iter(|| Sdf::from_mesh(black_box(&p), black_box(&t), 0.004).unwrap())
        });
    }
    group.finish();
}

fn lookup(c: &mut Criterion) {
    let mut group = c.benchmark_group("sdf/lookup");
    group
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    for ((name, (p, t)), cell) in meshes().into_iter().zip([0.01, 0.004]) {
        let sdf = Sdf::from_mesh(&p, &t, cell).unwrap();
        let pts = near_points(&p);
        let blocks: Vec<Vec3Lanes> = pts
            .chunks_exact(LANES)
            .map(|c| {
                let mut v = Vec3Lanes::ZERO;
                for (l, p) in c.iter().enumerate() {
                    v.set_lane(l, *p);
                }
                v
            })
            .collect();
        group.throughput(Throughput::Elements(pts.len() as u64));
        group.bench_function(format!("{name}_{}mm/scalar", cell * 1e3), |b| {
            b.iter(|| {
                for &q in &pts {
                    black_box(sdf.sample_mesh(black_box(q)));
                }
            })
        });
        group.bench_function(format!("{name}_{}mm/simd", cell * 1e3), |b| {
            b.iter(|| {
                for &q in &blocks {
                    black_box(sdf.sample_mesh_simd(black_box(q)));
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, build, lookup);
criterion_main!(benches);
