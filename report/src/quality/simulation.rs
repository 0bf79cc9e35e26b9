//! The simulation's quality knobs (iterations, pearls, substeps) against
//! error.
//!
//! Two scenes on a grown sphere head: **settling** (hair grown straight out
//! falls and drapes for 3 s) and **whipping** (the head and roots swing on a
//! 10 cm circle at 3 Hz, about 1.9 m/s, for 2 s). For every setting the run
//! records the time per frame (SIMD and scalar), the largest stretch and
//! penetration seen at the end of any frame, and the distance at the end to
//! a converged run of the same scene.
//!
//! Two studies:
//! - **iterations x pearls** ([`measure_setting`]): one step of the default
//!   `dt` = 1/60 s per frame, against [`converged`] (256 iterations, 3 pearls);
//! - **substeps** ([`measure_substeps`]): frames of [`FRAME_TIME`] = 1/30 s
//!   (the `coif` binary's default 30 fps, which the pipeline's fixed
//!   `dt` = 1/60 s turns into 2 substeps per frame) advanced with `n` steps of
//!   `dt = FRAME_TIME / n`, against [`converged_substeps`] (16 substeps of
//!   32 iterations, 3 pearls) at the end of every frame
//!   ([`Row::rms_distance_over_frames`]). How well that reference is resolved
//!   is measured by `examples/substeps_reference.rs` (against 32 substeps):
//!   about 4 mm for settling but 8 cm for whipping, whose flailing hair is
//!   chaotic, so differences between settings below that are noise.
//!
//! `SimParams::damping` and `friction` are per step (`x + d (x - x_prev)`;
//! the share of tangential velocity removed per push-out), so more substeps
//! would damp more per second. [`per_second_equivalent`] rescales both so
//! that the velocity kept per second is the same as with the default
//! `dt` = 1/60 s: `d' = d^(dt'/dt)`, `1 - mu' = (1 - mu)^(dt'/dt)`. Every
//! substeps setting (and its reference) runs with those, so the settings
//! differ only in how finely they resolve the same physics.

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
    /// Constraint iterations per step.
    pub iterations: u32,
    /// Pearls per segment: collision points between a segment's end
    /// vertices (Nguyen and Donnelly 2005, the Nalu demo).
    pub pearls: u32,
    /// Simulation steps per frame.
    pub substeps: u32,
    /// Median nanoseconds per vertex-step, SIMD path (the median frame's
    /// time over the vertices and substeps).
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

impl Row {
    /// Median nanoseconds per vertex-frame (all substeps of a frame), SIMD.
    pub fn simd_ns_per_vertex_frame(&self) -> f64 {
        self.simd_ns_per_vertex_step * self.substeps as f64
    }

    /// Median nanoseconds per vertex-frame (all substeps of a frame), scalar.
    pub fn scalar_ns_per_vertex_frame(&self) -> f64 {
        self.scalar_ns_per_vertex_step * self.substeps as f64
    }
}

/// Frame time of the substeps study: 1/30 s, the `coif` binary's default
/// frame rate.
pub const FRAME_TIME: f32 = 1.0 / 30.0;

/// Substeps per frame the frame pipeline runs at [`FRAME_TIME`] with its
/// default fixed step (`SimParams::default().dt` = 1/60 s): 2.
pub fn default_substeps() -> u32 {
    (FRAME_TIME / SimParams::default().dt).round() as u32
}

/// Substeps measured by the study.
pub const SUBSTEPS: [u32; 4] = [1, 2, 4, 8];

/// `params` for a step of `dt` seconds with the same damping and contact
/// friction per second as `params` at its own `params.dt`:
/// `d' = d^(dt / params.dt)` and `1 - mu' = (1 - mu)^(dt / params.dt)`
/// (both act once per step, see [`SimParams`]). At `dt == params.dt` it
/// returns `params` unchanged.
pub fn per_second_equivalent(params: &SimParams, dt: f32) -> SimParams {
    let ratio = dt / params.dt;
    if ratio == 1.0 {
        return params.clone();
    }
    SimParams {
        dt,
        damping: params.damping.powf(ratio),
        friction: 1.0 - (1.0 - params.friction).powf(ratio),
        ..params.clone()
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
    /// Seconds per frame (all its substeps).
    frame_times: Vec<f64>,
    max_stretch: f32,
    max_penetration: f32,
    /// Positions at the end of every frame, if asked for.
    frames: Vec<Vec<Vec3>>,
    /// RMS vertex distance to the given trajectory over every frame.
    rms_over_frames: f32,
}

/// Runs a scene in frames of `frame_time` seconds, each of `substeps`
/// steps of `params` (whose `dt` must be `frame_time / substeps`); every
/// step sees the head where it is at the start of that step. Measures the
/// worst stretch and penetration at the end of every frame, records the
/// positions of every frame if `record`, and compares them with
/// `reference`'s frames at the same times if given (NaN otherwise).
fn run(
    scene: Scene,
    params: &SimParams,
    frame_time: f32,
    substeps: u32,
    stepper: StepFn,
    record: bool,
    reference: Option<&Trajectory>,
) -> RunResult {
    let (points, head) = setup();
    let mut s = Strands::from_polylines(&points, STUDY_VERTS).expect("grown scene is valid");
    let mut roots: Vec<Vec3> = points.iter().step_by(STUDY_VERTS).copied().collect();
    let base = roots.clone();
    let mut rig = [head.clone()];
    let frame_count = (scene.duration() / frame_time).round() as usize;
    let (mut times, mut stretch, mut depth) = (Vec::with_capacity(frame_count), 0.0f32, 0.0f32);
    let mut frames = Vec::new();
    let (mut sum_sq, mut count) = (0.0f64, 0usize);
    for f in 0..frame_count {
        let mut elapsed = 0.0;
        for k in 0..substeps as usize {
            let step_index = f * substeps as usize + k;
            let off = scene.offset(step_index as f32 * params.dt);
            for (r, b) in roots.iter_mut().zip(&base) {
                *r = *b + off;
            }
            rig[0].center = head.center + off;
            s.set_roots(&roots).expect("finite roots");
            let t0 = Instant::now();
            stepper(&mut s, params, &rig);
            elapsed += t0.elapsed().as_secs_f64();
        }
        times.push(elapsed);
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
        frame_times: times,
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

/// Measures one setting of one scene against a converged run.
pub fn measure_setting(scene: Scene, iterations: u32, pearls: u32, converged: &Trajectory) -> Row {
    let params = SimParams {
        iterations,
        pearls_per_segment: pearls,
        ..Default::default()
    };
    measure_frames(scene, &params, params.dt, 1, converged)
}

/// Measures `substeps` steps per frame of [`FRAME_TIME`] (default
/// iterations and pearls, damping and friction per second kept, see
/// [`per_second_equivalent`]) against [`converged_substeps`].
pub fn measure_substeps(scene: Scene, substeps: u32, converged: &Trajectory) -> Row {
    let substeps = substeps.max(1);
    let params = per_second_equivalent(&SimParams::default(), FRAME_TIME / substeps as f32);
    measure_frames(scene, &params, FRAME_TIME, substeps, converged)
}

fn measure_frames(
    scene: Scene,
    params: &SimParams,
    frame_time: f32,
    substeps: u32,
    converged: &Trajectory,
) -> Row {
    let per_step = (STUDY_STRANDS * STUDY_VERTS) as f64 * substeps as f64;
    let simd = run(
        scene,
        params,
        frame_time,
        substeps,
        kernels::step,
        false,
        Some(converged),
    );
    let scalar = run(
        scene,
        params,
        frame_time,
        substeps,
        scalar::step,
        false,
        None,
    );
    let dist = measure::distances(&simd.last, &converged.last);
    Row {
        scene,
        iterations: params.iterations,
        pearls: params.pearls_per_segment,
        substeps,
        simd_ns_per_vertex_step: median(simd.frame_times) * 1e9 / per_step,
        scalar_ns_per_vertex_step: median(scalar.frame_times) * 1e9 / per_step,
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

/// The converged reference of a scene: 256 iterations, 3 pearls.
pub fn converged(scene: Scene) -> Trajectory {
    let params = SimParams {
        iterations: 256,
        pearls_per_segment: 3,
        ..Default::default()
    };
    trajectory(run(scene, &params, params.dt, 1, kernels::step, true, None))
}

/// Substeps per frame of [`converged_substeps`].
pub const REFERENCE_SUBSTEPS: u32 = 16;

/// The converged reference of the substeps study: frames of [`FRAME_TIME`]
/// in [`REFERENCE_SUBSTEPS`] steps of 32 iterations and 3 pearls (damping
/// and friction per second as in the default, see [`per_second_equivalent`]).
pub fn converged_substeps(scene: Scene) -> Trajectory {
    converged_substeps_with(scene, REFERENCE_SUBSTEPS, 32)
}

/// [`converged_substeps`] with another number of substeps and iterations
/// (a cheaper reference for quick runs).
pub fn converged_substeps_with(scene: Scene, substeps: u32, iterations: u32) -> Trajectory {
    let substeps = substeps.max(1);
    let base = SimParams {
        iterations,
        pearls_per_segment: 3,
        ..Default::default()
    };
    let params = per_second_equivalent(&base, FRAME_TIME / substeps as f32);
    trajectory(run(
        scene,
        &params,
        FRAME_TIME,
        substeps,
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
    fn per_second_equivalent_keeps_the_velocity_kept_per_second() {
        let base = SimParams::default();
        assert_eq!(per_second_equivalent(&base, base.dt), base);
        let quarter = per_second_equivalent(&base, base.dt / 4.0);
        assert_eq!(quarter.dt, base.dt / 4.0);
        // Four steps of the quarter keep what one step of the base keeps.
        assert!((quarter.damping.powi(4) - base.damping).abs() < 1e-6);
        assert!(((1.0 - quarter.friction).powi(4) - (1.0 - base.friction)).abs() < 1e-6);
        assert!(quarter.damping > base.damping && quarter.friction < base.friction);
        assert_eq!(quarter.iterations, base.iterations);
        assert_eq!(default_substeps(), 2);
    }
}
