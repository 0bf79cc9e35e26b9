//! The mesh signed distance field (`coif::kernels::Sdf`): build time of the
//! shared Sintel bust at 4 mm cells (skipped when `../shared` is absent)
//! and of an icosphere of the same size made here (5,120 triangles, 20 cm
//! across), and lookups per point, the SIMD lane lookup (eight points per
//! call) against the scalar twin, in cache: 4,096 points near the surface
//! of the icosphere's 1 cm field (about 27,000 nodes, 110 KB) and of the
//! bust's 4 mm field (3 MB).
//!
//! `cargo bench --bench sdf` (add `-- --quick` for a fast pass).

use coif::kernels::{Sdf, Vec3x8};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;
use std::time::Duration;

/// Positions and triangles.
type Mesh = (Vec<Vec3>, Vec<[u32; 3]>);

/// An icosphere of radius `r`: the icosahedron subdivided `n` times.
fn icosphere(n: u32, r: f32) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut p: Vec<Vec3> = [
        (-1., t, 0.),
        (1., t, 0.),
        (-1., -t, 0.),
        (1., -t, 0.),
        (0., -1., t),
        (0., 1., t),
        (0., -1., -t),
        (0., 1., -t),
        (t, 0., -1.),
        (t, 0., 1.),
        (-t, 0., -1.),
        (-t, 0., 1.),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..n {
        let mut mid = std::collections::HashMap::new();
        let mut g = vec![];
        for [a, b, c] in f {
            let mut m = |i: u32, j: u32| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    p.push(((p[i as usize] + p[j as usize]) * 0.5).normalize());
                    p.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            g.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = g;
    }
    (p.into_iter().map(|v| v * r).collect(), f)
}

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
        let blocks: Vec<Vec3x8> = pts
            .chunks_exact(8)
            .map(|c| {
                let mut v = Vec3x8::ZERO;
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
                    black_box(sdf.sample_mesh_x8(black_box(q)));
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, build, lookup);
criterion_main!(benches);
