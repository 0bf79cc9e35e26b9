//! The simulation's quality knobs (iterations, pearls) against error.
//!
//! Two scenes on a grown sphere head: **settling** (hair grown straight out
//! falls and drapes for 3 s) and **whipping** (the head and roots swing on a
//! 10 cm circle at 3 Hz, about 1.9 m/s, for 2 s). For every setting the run
//! records the time per step (SIMD and scalar), the largest stretch and
//! penetration seen at any step, and the distance at the end to a converged
//! run (256 iterations, 3 pearls) of the same scene.

use crate::kernels::{self, measure, scalar, SimParams, Sphere, Strands};
use crate::scene::{grow_on_sphere, GrowOptions};
use glam::Vec3;
use std::time::Instant;

/// A test scene of the study.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scene {
    /// Hair grown straight out of the head falls and settles (180 steps).
    Settling,
    /// Head and roots swing on a 10 cm circle at 3 Hz (120 steps).
    Whipping,
}

impl Scene {
    pub fn name(self) -> &'static str {
        match self {
            Scene::Settling => "settling",
            Scene::Whipping => "whipping",
        }
    }

    fn steps(self) -> usize {
        match self {
            Scene::Settling => 180,
            Scene::Whipping => 120,
        }
    }

    /// Offset of the head and roots at step `i`.
    fn offset(self, i: usize, dt: f32) -> Vec3 {
        match self {
            Scene::Settling => Vec3::ZERO,
            Scene::Whipping => {
                let a = std::f32::consts::TAU * 3.0 * i as f32 * dt;
                Vec3::new(0.1 * a.cos() - 0.1, 0.1 * a.sin(), 0.0)
            }
        }
    }
}

/// One measured setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub scene: Scene,
    pub iterations: u32,
    pub pearls: u32,
    /// Median nanoseconds per vertex-step, SIMD path.
    pub simd_ns_per_vertex_step: f64,
    /// Median nanoseconds per vertex-step, scalar reference.
    pub scalar_ns_per_vertex_step: f64,
    /// Largest polyline stretch seen (fraction).
    pub max_stretch: f32,
    /// Deepest penetration seen (metres).
    pub max_penetration: f32,
    /// Largest vertex distance to the converged run at the end (metres).
    /// Dominated by the few strands on the crown that slide off the
    /// frictionless head to the other side: a chaotic choice.
    pub max_distance_to_converged: f32,
    /// Root-mean-square vertex distance to the converged run (metres).
    pub rms_distance_to_converged: f32,
}

/// Strand count and vertex count of the study's groom.
pub const STUDY_STRANDS: usize = 256;
pub const STUDY_VERTS: usize = 32;

fn setup() -> (Vec<Vec3>, Sphere) {
    let g = grow_on_sphere(&GrowOptions {
        strand_count: STUDY_STRANDS,
        verts_per_strand: STUDY_VERTS,
        curl: 0.3,
        ..Default::default()
    });
    (g.points, g.head)
}

type StepFn = fn(&mut Strands, &SimParams, &[Sphere]);

/// Runs a scene; returns the final state, per-step times (s), and the worst
/// stretch and penetration seen.
fn run(scene: Scene, params: &SimParams, stepper: StepFn) -> (Strands, Vec<f64>, f32, f32) {
    let (points, head) = setup();
    let mut s = Strands::from_polylines(&points, STUDY_VERTS).expect("grown scene is valid");
    let mut roots: Vec<Vec3> = points.iter().step_by(STUDY_VERTS).copied().collect();
    let base = roots.clone();
    let mut rig = [head.clone()];
    let (mut times, mut stretch, mut depth) = (Vec::with_capacity(scene.steps()), 0.0f32, 0.0f32);
    for i in 0..scene.steps() {
        let off = scene.offset(i, params.dt);
        for (r, b) in roots.iter_mut().zip(&base) {
            *r = *b + off;
        }
        rig[0].center = head.center + off;
        s.set_roots(&roots).expect("finite roots");
        let t0 = Instant::now();
        stepper(&mut s, params, &rig);
        times.push(t0.elapsed().as_secs_f64());
        let m = kernels::measure(&s, &rig);
        stretch = stretch.max(m.max_stretch);
        depth = depth.max(m.max_penetration);
    }
    (s, times, stretch, depth)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Measures one setting of one scene against a converged final state.
pub fn measure_setting(scene: Scene, iterations: u32, pearls: u32, converged: &Strands) -> Row {
    let params = SimParams {
        iterations,
        pearls_per_segment: pearls,
        ..Default::default()
    };
    let per_step = (STUDY_STRANDS * STUDY_VERTS) as f64;
    let (state, simd_times, max_stretch, max_penetration) = run(scene, &params, kernels::step);
    let (_, scalar_times, _, _) = run(scene, &params, scalar::step);
    let dist = measure::distances(&state, converged);
    Row {
        scene,
        iterations,
        pearls,
        simd_ns_per_vertex_step: median(simd_times) * 1e9 / per_step,
        scalar_ns_per_vertex_step: median(scalar_times) * 1e9 / per_step,
        max_stretch,
        max_penetration,
        max_distance_to_converged: dist.0,
        rms_distance_to_converged: dist.1,
    }
}

/// The converged reference of a scene: 256 iterations, 3 pearls.
pub fn converged(scene: Scene) -> Strands {
    let params = SimParams {
        iterations: 256,
        pearls_per_segment: 3,
        ..Default::default()
    };
    run(scene, &params, kernels::step).0
}

/// The full study: both scenes, iterations 1..32, pearls 0..3.
pub fn study(iterations: &[u32], pearls: &[u32]) -> Vec<Row> {
    let mut rows = Vec::new();
    for scene in [Scene::Settling, Scene::Whipping] {
        let reference = converged(scene);
        for &it in iterations {
            for &p in pearls {
                rows.push(measure_setting(scene, it, p, &reference));
            }
        }
    }
    rows
}

/// The study's default knob values.
pub const ITERATIONS: [u32; 6] = [1, 2, 4, 8, 16, 32];
pub const PEARLS: [u32; 4] = [0, 1, 2, 3];

/// Rows as CSV with a header line.
pub fn to_csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "scene,iterations,pearls,simd_ns_per_vertex_step,scalar_ns_per_vertex_step,max_stretch,max_penetration_m,max_distance_to_converged_m,rms_distance_to_converged_m\n",
    );
    for r in rows {
        out += &format!(
            "{},{},{},{:.3},{:.3},{:.5},{:.6},{:.6},{:.6}\n",
            r.scene.name(),
            r.iterations,
            r.pearls,
            r.simd_ns_per_vertex_step,
            r.scalar_ns_per_vertex_step,
            r.max_stretch,
            r.max_penetration,
            r.max_distance_to_converged,
            r.rms_distance_to_converged
        );
    }
    out
}
