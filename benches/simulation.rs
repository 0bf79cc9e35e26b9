//! Simulation step, SIMD against scalar, on the TressFX mohawk (2,226 x 32)
//! and a synthetic 10,000 x 32 head, over projections per substep
//! (`iterations`) {1, 2} at the default 4 substeps of 1/240 s, pearls {0, 1}
//! and rigs of {1, 16, 256} spheres (head, neck, and the rest of a body rig
//! a body length away: the broad phase keeps the 254 far ones out of the
//! narrow phase), plus the default with local shape springs on
//! (`shape1`). Throughput is in vertex-steps per second. Sleeping is off
//! (`sleep_speed` 0) throughout: these are the costs of awake hair.
//!
//! The `step/threads` group runs the 10,000 x 32 head (16 spheres, one
//! pearl, local shape on) on `Serial` and on rayon pools of 1 and 2
//! threads (`step_with`), after printing Amdahl's serial fraction of the
//! step measured on one thread (the speed-up and the projections in the
//! `docs/threads.md`).
//!
//! The `step/world` group runs the mohawk at the defaults (16 spheres) in
//! the scenes of the world's cost goals: 16 spheres with friction and
//! without, 16 capsules of the same radii (2 radii long) in place of the
//! spheres, the spheres in wind and drag, in gusts, and with one 4 mm field
//! of the shared Sintel bust (its head on the head sphere, the median root
//! on its surface), SIMD and
//! scalar (`kernels/examples/step_cost.rs` runs the same scenes one at a
//! time, for callgrind).
//!
//! `cargo bench --bench simulation` (add `-- --quick` for a fast pass;
//! `cargo bench --bench simulation -- step/threads` for the threads group,
//! `-- step/world` for the world's scenes).

use coif::geometry::scene::{
    body_rig, grow_on_sphere, rig_with_distractors, scalp_spheres, GrowOptions,
};
use coif::groom::tfx;
mod common;

use coif::kernels::tasks::Executor;
use coif::kernels::{self, scalar, Capsule, Colliders, Sdf, SimParams, Sphere, Strands};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;
use std::time::{Duration, Instant};

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
            // Every block awake: the cost of stepping hair, not of
            // skipping it (a draped set falls asleep; `benches/crowd.rs`
            // measures sleeping).
            sleep_speed: 0.0,
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

/// Runs the tasks on the calling thread in order, timing each one.
struct Timed {
    tasks: std::sync::Mutex<Vec<f64>>,
}

// SAFETY: every index once, in order, before `run` returns.
unsafe impl Executor for Timed {
    fn threads(&self) -> usize {
        1
    }
    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let mut times = self.tasks.lock().unwrap();
        times.clear();
        for i in 0..count {
            let t0 = Instant::now();
            task(i);
            times.push(t0.elapsed().as_secs_f64());
        }
    }
}

/// Amdahl's serial fraction of one step, measured on one thread: per
/// repetition the step's time, each task's time, and the rest (set-up,
/// rig to local, handing out the tasks, the sums) as the serial part; the
/// least over 40 repetitions of each (the load only adds). Prints the
/// fraction and the speed-ups it allows on p threads: Amdahl's
/// `1 / (f + (1 - f) / p)` and a greedy schedule of the measured tasks in
/// index order (what a work-stealing pool does), which adds the imbalance
/// of whole tasks.
fn amdahl(s: &Strands, params: &SimParams, rig: &[Sphere]) {
    let timed = Timed {
        tasks: Default::default(),
    };
    let (mut serial, mut tasks) = (f64::INFINITY, Vec::<f64>::new());
    let mut total = f64::INFINITY;
    for _ in 0..40 {
        let mut s = s.clone();
        let t0 = Instant::now();
        kernels::step_with(&mut s, params, rig, &timed);
        let t = t0.elapsed().as_secs_f64();
        let times = timed.tasks.lock().unwrap();
        serial = serial.min(t - times.iter().sum::<f64>());
        total = total.min(t);
        if tasks.is_empty() {
            tasks = times.clone();
        }
        for (m, x) in tasks.iter_mut().zip(times.iter()) {
            *m = m.min(*x);
        }
    }
    let work: f64 = tasks.iter().sum();
    let f = serial / (serial + work);
    println!(
        "step/threads/amdahl: 10,000 x 32, {} tasks, step {:.2} ms (least of 40), tasks {:.2} ms, serial part {:.1} us: f = {:.2e}",
        tasks.len(),
        total * 1e3,
        work * 1e3,
        serial * 1e6,
        f
    );
    for p in [2usize, 4, 8, 16] {
        let mut free = vec![0.0f64; p];
        for t in &tasks {
            let w = free.iter_mut().min_by(|a, b| a.total_cmp(b)).unwrap();
            *w += t;
        }
        let makespan = free.iter().copied().fold(0.0, f64::max);
        println!(
            "step/threads/amdahl: p = {p:2}: Amdahl {:.2}x, greedy schedule of the measured tasks {:.2}x",
            1.0 / (f + (1.0 - f) / p as f64),
            (serial + work) / (serial + makespan)
        );
    }
}

/// On-CPU time of every thread of this process so far, in ns (Linux:
/// `/proc/self/task/*/schedstat`; None elsewhere). Unlike wall time, the
/// load of other processes hardly changes it.
fn cpu_ns() -> Option<u64> {
    let mut total = 0;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let stat = std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok()?;
        total += stat.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(total)
}

/// CPU time per step summed over every thread, per executor: what running
/// on more threads adds to the work (handing out tasks, waking and
/// stealing, caches), measurable on a loaded machine where the wall-clock
/// speed-up is not.
fn cpu_per_step(s: &Strands, params: &SimParams, rig: &[Sphere], executors: &[common::Named]) {
    for (name, exec) in executors {
        let mut s = s.clone();
        kernels::step_with(&mut s, params, rig, exec.as_ref());
        let Some(c0) = cpu_ns() else { return };
        for _ in 0..20 {
            kernels::step_with(&mut s, params, rig, exec.as_ref());
        }
        let Some(c1) = cpu_ns() else { return };
        println!(
            "step/threads/cpu: {name}: {:.2} ms of CPU per step, all threads (20 steps)",
            (c1 - c0) as f64 / 20e6
        );
    }
}

/// `step_with` on 10,000 x 32 at 1 and 2 threads (rayon; rayon off: the
/// serial executor only).
fn threads(c: &mut Criterion) {
    eprintln!(
        "coif benches: {} lanes per SIMD block",
        coif::kernels::LANES
    );
    let (pts, verts, make_rig) = synthetic();
    let rig = make_rig(16);
    let params = SimParams {
        pearls_per_segment: 1,
        local_shape_stiffness: 1.0,
        // Every block awake (see `bench_set`).
        sleep_speed: 0.0,
        ..Default::default()
    };
    let mut settled = Strands::from_polylines(&pts, verts).unwrap();
    for _ in 0..30 {
        kernels::step(&mut settled, &params, &rig);
    }
    amdahl(&settled, &params, &rig);
    let mut group = c.benchmark_group("step/threads");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(pts.len() as u64));
    let executors = common::executors();
    cpu_per_step(&settled, &params, &rig, &executors);
    for (name, exec) in &executors {
        let mut s = settled.clone();
        group.bench_function(BenchmarkId::new("synthetic_10000x32", name), |b| {
            b.iter(|| kernels::step_with(black_box(&mut s), &params, &rig, exec.as_ref()))
        });
    }
    group.finish();
}

/// The world's scenes on the mohawk (see the module doc).
fn world(c: &mut Criterion) {
    let Some((pts, v, make_rig)) = mohawk() else {
        eprintln!("skipping step/world: ../shared/data/grooms is absent");
        return;
    };
    let spheres = make_rig(16);
    let capsules: Vec<Capsule> = spheres
        .iter()
        .map(|s| Capsule {
            a: s.center - Vec3::X * s.radius,
            b: s.center + Vec3::X * s.radius,
            radius: s.radius,
        })
        .collect();
    let roots: Vec<Vec3> = pts.iter().step_by(v).copied().collect();
    let bust = coif_testkit::sintel_bust().map(|(p, t)| {
        let mut f = Sdf::from_mesh(&p, &t, 0.004).expect("the bust's field");
        // Its head on the head sphere, then moved along y until the median
        // root lies on its surface (as `kernels/examples/step_cost.rs`).
        let mut at = spheres[0].center - Vec3::new(0.0, 0.37, 0.0);
        for _ in 0..4 {
            f.set_transform(glam::Affine3A::from_translation(at))
                .expect("a translation");
            let mut d: Vec<f32> = roots.iter().map(|r| f.distance(*r)).collect();
            d.sort_by(f32::total_cmp);
            at.y += d[d.len() / 2];
        }
        f.set_transform(glam::Affine3A::from_translation(at))
            .expect("a translation");
        f
    });
    let base = SimParams {
        sleep_speed: 0.0,
        ..Default::default()
    };
    let windy = SimParams {
        wind: Vec3::new(2.0, 0.0, 1.0),
        drag: 1.0,
        ..base.clone()
    };
    let frictionless = SimParams {
        friction: 0.0,
        static_friction: 0.0,
        ..base.clone()
    };
    let gusty = SimParams {
        turbulence: 1.0,
        ..windy.clone()
    };
    let none: [Sdf; 0] = [];
    let fields = bust.as_slice();
    let scenes: Vec<(&str, SimParams, Colliders<'_>)> = vec![
        ("spheres16", base.clone(), Colliders::spheres(&spheres)),
        (
            "spheres16_frictionless",
            frictionless,
            Colliders::spheres(&spheres),
        ),
        (
            "capsules16",
            base.clone(),
            Colliders {
                capsules: &capsules,
                ..Default::default()
            },
        ),
        ("spheres16_wind", windy, Colliders::spheres(&spheres)),
        ("spheres16_gusts", gusty, Colliders::spheres(&spheres)),
        (
            "spheres16_field",
            base.clone(),
            Colliders {
                spheres: &spheres,
                sdfs: if fields.is_empty() { &none } else { fields },
                ..Default::default()
            },
        ),
    ];
    let mut group = c.benchmark_group("step/world");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    group.throughput(Throughput::Elements(pts.len() as u64));
    for (name, params, colliders) in &scenes {
        let mut settled = Strands::from_polylines(&pts, v).unwrap();
        for _ in 0..30 {
            kernels::step_colliders(&mut settled, params, colliders);
        }
        let mut s = settled.clone();
        group.bench_function(BenchmarkId::new("simd", name), |b| {
            b.iter(|| kernels::step_colliders(black_box(&mut s), params, colliders))
        });
        let mut s = settled.clone();
        group.bench_function(BenchmarkId::new("scalar", name), |b| {
            b.iter(|| scalar::step_colliders(black_box(&mut s), params, colliders))
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

criterion_group!(benches, threads, world, simulation);
criterion_main!(benches);
