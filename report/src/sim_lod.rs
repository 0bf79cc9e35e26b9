//! Simulation LOD: what skipping simulation costs in accuracy.
//!
//! The built-in head (guides combed back and draped for 7 s) runs one step
//! of 1/60 s per frame: 1 s still, the turn and nod of
//! `coif::frame::motion::turn_and_nod` (3 s), then still (2 s in a quick
//! run, 6 s in a full one). Two kernels:
//!
//! - `simulation LOD sleeping`: `SimParams::sleep_speed` in 0 (never; the
//!   reference), 0.002, 0.005, 0.01, 0.02 (default), 0.05 m/s; ns per
//!   vertex-step (all guides); RMS vertex distance to never sleeping over
//!   all frames. The setting names the share of strand-steps advanced.
//! - `simulation LOD guides`: the simulation level of
//!   `coif::frame::sim_lod::SimLod` simulating about every k-th guide
//!   (k = 1, 2, 4, 8; the others follow), sleeping off; ns per vertex-step
//!   of every guide (followers included: the output); RMS distance to
//!   simulating every guide over all frames.
//!
//! Time is the median over repeated runs of the whole sequence.

use super::{Options, Path, Row, Timing};
use coif::frame::crowd::settled_head;
use coif::frame::motion::turn_and_nod;
use coif::frame::sim_lod::{SimLod, STRIDES};
use coif::frame::HairScene;
use coif::kernels::{self as kernels, scalar, SimParams, Sphere, Strands};
use glam::{Affine3A, Mat3, Quat, Vec3};
use std::time::Instant;

/// Sleep speeds measured (m/s); 0 is the reference.
pub const SLEEP_SPEEDS: [f32; 6] = [0.0, 0.002, 0.005, 0.01, 0.02, 0.05];

/// The scene: rest guides, settled guides, points per guide, rig, pivot.
struct Scene {
    hair: HairScene,
    settled: Vec<Vec3>,
    frames: usize,
}

fn scene(options: Options) -> Scene {
    let (hair, settled) = settled_head(if options.quick { 256 } else { 1024 }, 32)
        .expect("the built-in head grows and drapes");
    Scene {
        hair,
        settled,
        frames: if options.quick { 240 } else { 600 },
    }
}

/// Head pose and rig at frame `f`: 1 s still, 3 s of motion, then still.
fn pose(s: &Scene, f: usize) -> (Affine3A, Vec<Sphere>) {
    let t = f as f32 / 60.0 - 1.0;
    let pose = turn_and_nod(t.max(0.0), s.hair.pivot);
    let rig = s
        .hair
        .rig
        .iter()
        .map(|r| Sphere {
            center: pose.transform_point3(r.center),
            radius: r.radius,
        })
        .collect();
    (pose, rig)
}

/// One run of plain strands at `sleep_speed`: (ns per vertex-step, the
/// positions of every frame, strand-steps advanced).
fn run_sleep(s: &Scene, sleep_speed: f32, path: Path) -> (f64, Vec<Vec<Vec3>>, usize) {
    let stepper = stepper(path);
    let verts = s.hair.verts_per_strand;
    let params = SimParams {
        sleep_speed,
        ..Default::default()
    };
    let mut strands = Strands::from_polylines(&s.hair.guides, verts).expect("valid");
    strands.set_state(&s.settled, &s.settled).expect("valid");
    let (mut ns, mut frames, mut advanced) = (0.0f64, Vec::new(), 0usize);
    for f in 0..s.frames {
        let (pose, rig) = pose(s, f);
        let roots: Vec<Vec3> = s
            .settled
            .iter()
            .step_by(verts)
            .map(|p| pose.transform_point3(*p))
            .collect();
        let t0 = Instant::now();
        let _ = strands.set_roots(&roots);
        let _ = strands.set_rest_rotation(Quat::from_mat3(&Mat3::from(pose.matrix3)));
        stepper(&mut strands, &params, &rig);
        ns += t0.elapsed().as_nanos() as f64;
        advanced += strands.awake_strands();
        frames.push(strands.positions());
    }
    (ns / (s.frames * s.settled.len()) as f64, frames, advanced)
}

/// One run of the simulation LOD at `level`, sleeping off.
fn run_level(s: &Scene, level: usize, path: Path) -> (f64, Vec<Vec<Vec3>>) {
    let stepper = stepper(path);
    let params = SimParams {
        sleep_speed: 0.0,
        ..Default::default()
    };
    let mut lod = SimLod::new(
        &s.hair.guides,
        &s.settled,
        s.hair.verts_per_strand,
        &STRIDES,
    )
    .expect("valid");
    lod.set_level(level, &s.hair.rig, params.pearl_radius);
    let (mut ns, mut frames) = (0.0f64, Vec::new());
    for f in 0..s.frames {
        let (pose, rig) = pose(s, f);
        let t0 = Instant::now();
        lod.step_with(stepper, &params, pose, &rig);
        ns += t0.elapsed().as_nanos() as f64;
        frames.push(lod.positions().to_vec());
    }
    (ns / (s.frames * s.settled.len()) as f64, frames)
}

/// A SIMD and a scalar row of one setting: `times` per path (ns per
/// vertex-step of each run), the same error.
fn push_both(
    rows: &mut Vec<Row>,
    (kernel, setting): (&str, String),
    times: [Vec<f64>; 2],
    (error_metric, error): (&'static str, f64),
    is_default: bool,
) {
    for (path, ns) in [Path::Simd, Path::Scalar].into_iter().zip(times) {
        rows.push(Row {
            kernel: kernel.into(),
            setting: setting.clone(),
            path,
            element: "vertex-step",
            time: Timing::from_samples(ns),
            error_metric,
            error,
            is_default,
        });
    }
}

/// The strand step of `path`.
fn stepper(path: Path) -> fn(&mut Strands, &SimParams, &[Sphere]) {
    match path {
        Path::Simd => kernels::step,
        Path::Scalar => scalar::step,
    }
}

/// RMS vertex distance over every frame.
fn rms(a: &[Vec<Vec3>], b: &[Vec<Vec3>]) -> f64 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (fa, fb) in a.iter().zip(b) {
        for (x, y) in fa.iter().zip(fb) {
            sum += x.distance_squared(*y) as f64;
            n += 1;
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

/// The `simulation LOD sleeping` and `simulation LOD guides` rows, SIMD
/// and scalar (the error is the SIMD run's; the scalar step agrees with it
/// bit for bit).
pub fn rows(options: Options) -> Vec<Row> {
    let reps = if options.quick { 1 } else { 3 };
    let s = scene(options);
    let strand_steps = s.frames * s.settled.len() / s.hair.verts_per_strand;
    let mut rows = Vec::new();
    let mut reference = Vec::new();
    let default_sleep = SimParams::default().sleep_speed;
    for &speed in &SLEEP_SPEEDS {
        let runs: Vec<_> = (0..reps)
            .map(|_| run_sleep(&s, speed, Path::Simd))
            .collect();
        if speed == 0.0 {
            reference = runs[0].1.clone();
        }
        let advanced = runs[0].2 as f64 / strand_steps as f64;
        let error = rms(&runs[0].1, &reference);
        let scalar: Vec<f64> = (0..reps)
            .map(|_| run_sleep(&s, speed, Path::Scalar).0)
            .collect();
        push_both(
            &mut rows,
            (
                "simulation LOD sleeping",
                format!("sleep_speed={speed} ({:.0} % stepped)", 100.0 * advanced),
            ),
            [runs.iter().map(|r| r.0).collect(), scalar],
            ("RMS distance to never sleeping over all frames (m)", error),
            speed == default_sleep,
        );
    }
    let mut full = Vec::new();
    for (level, &stride) in STRIDES.iter().enumerate() {
        let runs: Vec<_> = (0..reps)
            .map(|_| run_level(&s, level, Path::Simd))
            .collect();
        if level == 0 {
            full = runs[0].1.clone();
        }
        let error = rms(&runs[0].1, &full);
        let scalar: Vec<f64> = (0..reps)
            .map(|_| run_level(&s, level, Path::Scalar).0)
            .collect();
        push_both(
            &mut rows,
            ("simulation LOD guides", format!("stride={stride}")),
            [runs.iter().map(|r| r.0).collect(), scalar],
            (
                "RMS distance to every guide simulated over all frames (m)",
                error,
            ),
            level == 0,
        );
    }
    rows
}
