//! The simulation's quality knobs (projections, pearls, substeps) against
//! error.
//!
//! Two scenes on a grown sphere head: **settling** (hair grown straight out
//! falls and drapes for 3 s) and **whipping** (the head and roots swing on a
//! 10 cm circle at 3 Hz, about 1.9 m/s, for 2 s). Every frame is one step
//! of the default `dt` = 1/60 s. For every setting the run records the time
//! per step (SIMD and scalar), the largest stretch and penetration seen at
//! the end of any frame, and the distance to a converged run of the same
//! scene.
//!
//! Two studies:
//! - **iterations x pearls** ([`measure_setting`]): `iterations` is the
//!   projections of the length constraints per substep (Newton iterations of
//!   the chain's tridiagonal solve), at the default substeps, against
//!   [`converged`] (256 projections, 3 pearls), compared at the end;
//! - **substeps** ([`measure_substeps`]): the solver's own substep knob,
//!   `max_substep = dt / n`, so that each step of `dt` runs `n` substeps
//!   (`SimParams::substeps`; default 4), against [`converged_substeps`] (32
//!   substeps of 8 projections, 3 pearls) at the end of every frame
//!   ([`Row::rms_distance_over_frames`]). How well that reference is
//!   resolved is measured by `examples/substeps_reference.rs` (against 64
//!   substeps, the most a step runs): about 5 mm for settling but 10 cm for
//!   whipping, whose flailing hair is chaotic, so differences between
//!   settings below that are noise.
//!
//! `dt` is the same in every setting, and the step spreads its damping over
//! its substeps (`d^(1/n)` per substep: the velocity kept per step does not
//! depend on `n`), so the settings differ in how finely they resolve the
//! same physics. Contact friction acts at every push-out, once per substep
//! (twice on the last): that is the solver's own behaviour and part of what
//! the knob changes.

use coif::geometry::scene::{grow_on_sphere, GrowOptions};
use coif::kernels::{self as kernels, measure, scalar, SimParams, Sphere, Strands};
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
    /// The scene's name in rows and CSV: `settling` or `whipping`.
    pub fn name(self) -> &'static str {
        match self {
            Scene::Settling => "settling",
            Scene::Whipping => "whipping",
        }
    }

    /// Length of the scene in seconds.
    fn duration(self) -> f32 {
        match self {
            Scene::Settling => 3.0,
            Scene::Whipping => 2.0,
        }
    }

    /// Offset of the head and roots at time `t` (seconds).
    fn offset(self, t: f32) -> Vec3 {
        match self {
            Scene::Settling => Vec3::ZERO,
            Scene::Whipping => {
                let a = std::f32::consts::TAU * 3.0 * t;
                Vec3::new(0.1 * a.cos() - 0.1, 0.1 * a.sin(), 0.0)
            }
        }
    }
}

/// One measured setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The scene run.
    pub scene: Scene,
    /// Projections of the length constraints per substep.
    pub iterations: u32,
    /// Pearls per segment: collision points between a segment's end
    /// vertices (Nguyen and Donnelly 2005, the Nalu demo).
    pub pearls: u32,
    /// Substeps per step of `dt` (`SimParams::substeps`).
    pub substeps: u32,
    /// Median nanoseconds per vertex-step, SIMD path (the median step's
    /// time, all its substeps, over the vertices).
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
    /// Root-mean-square vertex distance to the converged run at the end
    /// (metres).
    pub rms_distance_to_converged: f32,
    /// Root-mean-square vertex distance to the converged run at the same
    /// frame times, over every frame (metres).
    pub rms_distance_over_frames: f32,
}

/// Substeps per step the default parameters run (4 of 1/240 s at dt = 1/60 s).
pub fn default_substeps() -> u32 {
    SimParams::default().substeps()
}

/// Substeps per step measured by the study.
pub const SUBSTEPS: [u32; 4] = [2, 4, 8, 16];

/// Parameters for `substeps` substeps per step of the default `dt`
/// (`max_substep = dt / substeps`), the rest from `base`.
pub fn with_substeps(base: &SimParams, substeps: u32) -> SimParams {
    SimParams {
        max_substep: base.dt / substeps.max(1) as f32,
        ..base.clone()
    }
}

/// Strands of the study's groom.
pub const STUDY_STRANDS: usize = 256;
/// Vertices per strand of the study's groom.
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

/// A run of a scene to measure against: the vertex positions (world) at
/// the end of every frame, and the final state.
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// World positions of every vertex at the end of each frame.
    pub frames: Vec<Vec<Vec3>>,
    /// The strands after the last frame.
    pub last: Strands,
}

/// What [`run`] saw.
struct RunResult {
    last: Strands,
    /// Seconds per step (all its substeps).
    step_times: Vec<f64>,
    max_stretch: f32,
    max_penetration: f32,
    /// Positions at the end of every frame, if asked for.
    frames: Vec<Vec<Vec3>>,
    /// RMS vertex distance to the given trajectory over every frame.
    rms_over_frames: f32,
}

/// Runs a scene in frames of one step of `params.dt`; every step sees the
/// head where it is at the start of that step. Measures the worst stretch
/// and penetration at the end of every frame, records the positions of
/// every frame if `record`, and compares them with `reference`'s frames at
/// the same times if given (NaN otherwise).
fn run(
    scene: Scene,
    params: &SimParams,
    stepper: StepFn,
    record: bool,
    reference: Option<&Trajectory>,
) -> RunResult {
    let (points, head) = setup();
    let mut s = Strands::from_polylines(&points, STUDY_VERTS).expect("grown scene is valid");
    let mut roots: Vec<Vec3> = points.iter().step_by(STUDY_VERTS).copied().collect();
    let base = roots.clone();
    let mut rig = [head.clone()];
    let frame_count = (scene.duration() / params.dt).round() as usize;
    let (mut times, mut stretch, mut depth) = (Vec::with_capacity(frame_count), 0.0f32, 0.0f32);
    let mut frames = Vec::new();
    let (mut sum_sq, mut count) = (0.0f64, 0usize);
    for f in 0..frame_count {
        let off = scene.offset(f as f32 * params.dt);
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
        if record || reference.is_some() {
            let now = s.positions();
            if let Some(then) = reference.and_then(|r| r.frames.get(f)) {
                for (a, b) in now.iter().zip(then) {
                    sum_sq += a.distance_squared(*b) as f64;
                    count += 1;
                }
            }
            if record {
                frames.push(now);
            }
        }
    }
    RunResult {
        last: s,
        step_times: times,
        max_stretch: stretch,
        max_penetration: depth,
        frames,
        rms_over_frames: if count > 0 {
            (sum_sq / count as f64).sqrt() as f32
        } else {
            f32::NAN
        },
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Measures one setting of the iterations x pearls study (`iterations`
/// projections per substep, `pearls` per segment, the default substeps)
/// against a converged run.
pub fn measure_setting(scene: Scene, iterations: u32, pearls: u32, converged: &Trajectory) -> Row {
    let params = SimParams {
        iterations,
        pearls_per_segment: pearls,
        ..Default::default()
    };
    measure_params(scene, &params, converged)
}

/// Measures `substeps` substeps per step of the default `dt` (default
/// projections and pearls, see [`with_substeps`]) against
/// [`converged_substeps`].
pub fn measure_substeps(scene: Scene, substeps: u32, converged: &Trajectory) -> Row {
    measure_params(
        scene,
        &with_substeps(&SimParams::default(), substeps),
        converged,
    )
}

/// Runs `params` on both paths and measures the SIMD run against
/// `converged` (at the end and over every frame).
pub fn measure_params(scene: Scene, params: &SimParams, converged: &Trajectory) -> Row {
    let per_step = (STUDY_STRANDS * STUDY_VERTS) as f64;
    let simd = run(scene, params, kernels::step, false, Some(converged));
    let scalar = run(scene, params, scalar::step, false, None);
    let dist = measure::distances(&simd.last, &converged.last);
    Row {
        scene,
        iterations: params.iterations,
        pearls: params.pearls_per_segment,
        substeps: params.substeps(),
        simd_ns_per_vertex_step: median(simd.step_times) * 1e9 / per_step,
        scalar_ns_per_vertex_step: median(scalar.step_times) * 1e9 / per_step,
        max_stretch: simd.max_stretch,
        max_penetration: simd.max_penetration,
        max_distance_to_converged: dist.0,
        rms_distance_to_converged: dist.1,
        rms_distance_over_frames: simd.rms_over_frames,
    }
}

fn trajectory(r: RunResult) -> Trajectory {
    Trajectory {
        frames: r.frames,
        last: r.last,
    }
}

/// The converged reference of the iterations x pearls study: 256
/// projections per substep, 3 pearls, the default substeps.
pub fn converged(scene: Scene) -> Trajectory {
    let params = SimParams {
        iterations: 256,
        pearls_per_segment: 3,
        ..Default::default()
    };
    trajectory(run(scene, &params, kernels::step, true, None))
}

/// Substeps per step of [`converged_substeps`].
pub const REFERENCE_SUBSTEPS: u32 = 32;
/// Projections per substep of [`converged_substeps`].
pub const REFERENCE_ITERATIONS: u32 = 8;

/// The converged reference of the substeps study: [`REFERENCE_SUBSTEPS`]
/// substeps of [`REFERENCE_ITERATIONS`] projections per step of the
/// default `dt`, 3 pearls.
pub fn converged_substeps(scene: Scene) -> Trajectory {
    converged_substeps_with(scene, REFERENCE_SUBSTEPS, REFERENCE_ITERATIONS)
}

/// [`converged_substeps`] with another number of substeps (at most
/// `coif::kernels::MAX_SUBSTEPS` = 64 take effect) and projections.
pub fn converged_substeps_with(scene: Scene, substeps: u32, iterations: u32) -> Trajectory {
    let base = SimParams {
        iterations,
        pearls_per_segment: 3,
        ..Default::default()
    };
    trajectory(run(
        scene,
        &with_substeps(&base, substeps),
        kernels::step,
        true,
        None,
    ))
}

/// RMS vertex distance between two runs of a scene at the same frame
/// times, over every frame both recorded (metres; NaN if none).
pub fn trajectory_distance(a: &Trajectory, b: &Trajectory) -> f32 {
    let (mut sum_sq, mut count) = (0.0f64, 0usize);
    for (fa, fb) in a.frames.iter().zip(&b.frames) {
        for (p, q) in fa.iter().zip(fb) {
            sum_sq += p.distance_squared(*q) as f64;
            count += 1;
        }
    }
    if count > 0 {
        (sum_sq / count as f64).sqrt() as f32
    } else {
        f32::NAN
    }
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

/// The study's iteration counts (with [`PEARLS`]).
pub const ITERATIONS: [u32; 6] = [1, 2, 4, 8, 16, 32];
/// The study's pearl counts (with [`ITERATIONS`]).
pub const PEARLS: [u32; 4] = [0, 1, 2, 3];

/// Rows as CSV with a header line.
pub fn to_csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "scene,iterations,pearls,substeps,simd_ns_per_vertex_step,scalar_ns_per_vertex_step,max_stretch,max_penetration_m,max_distance_to_converged_m,rms_distance_to_converged_m,rms_distance_over_frames_m\n",
    );
    for r in rows {
        out += &format!(
            "{},{},{},{},{:.3},{:.3},{:.5},{:.6},{:.6},{:.6},{:.6}\n",
            r.scene.name(),
            r.iterations,
            r.pearls,
            r.substeps,
            r.simd_ns_per_vertex_step,
            r.scalar_ns_per_vertex_step,
            r.max_stretch,
            r.max_penetration,
            r.max_distance_to_converged,
            r.rms_distance_to_converged,
            r.rms_distance_over_frames
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn substeps_are_the_solvers_own_knob() {
        assert_eq!(default_substeps(), 4);
        let base = SimParams::default();
        for n in SUBSTEPS.into_iter().chain([REFERENCE_SUBSTEPS]) {
            let p = with_substeps(&base, n);
            assert_eq!(p.substeps(), n);
            assert_eq!(p.dt, base.dt, "the frame is one step of the same dt");
            assert_eq!(p.damping, base.damping, "damping is per step of dt");
            assert!(p.validate().is_ok());
        }
        assert_eq!(with_substeps(&base, default_substeps()).substeps(), 4);
    }
}
