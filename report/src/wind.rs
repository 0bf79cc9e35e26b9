//! Wind and drag: the strand step against two closed forms that do not
//! depend on the solver.
//!
//! The step's air model (`SimParams::wind`, `SimParams::drag`; the kernels'
//! README, "Wind and drag") is linear drag: air moving at `w` pulls a
//! vertex moving at `v` with acceleration `c (w - v)`, `c` = `drag` in 1/s.
//! Two exact consequences:
//!
//! - **Equilibrium** (kernel `wind equilibrium`): in a steady wind every
//!   mass of a chain of equal masses feels the same constant acceleration
//!   `a = g + c w` once it is at rest, so the chain hangs straight along `a`
//!   from its pin, as a chain hangs straight along `g` in still air (the
//!   tension in every link then balances the weight below it along the
//!   link; any bend would leave a sideways force on the mass at the bend).
//!   One strand of 32 vertices on 1 cm links, pinned at the root, starts
//!   hanging straight down and settles for `max(10 s, 5 c L / |a|)` (the
//!   second term: five time constants `c L / |a|` of the slow creep of an
//!   overdamped chain of length `L`; 10 s is longer for every case here)
//!   at the default `damping`; error = the angle in degrees between
//!   `tip - root` and `a`, the worst over three winds per setting:
//!   `(2, 0, 0)`, `(3, 0.5, 4)` and `(8, 0, 0)` m/s (at drag 4/s the last is
//!   3.4 g, where `SimParams::substeps` shortens the substep by itself).
//! - **Decay** (kernel `wind decay`): the small swings of a pinned chain
//!   obey `M u'' + c M u' + (g / l) K u = 0` (`K` the tension matrix of
//!   [`crate::quality::chain`]); uniform drag is proportional to the mass
//!   matrix, so every mode keeps its shape and swings as
//!   `theta'' + c theta' + omega_k^2 theta = 0`, which decays as
//!   `exp(-c t / 2)` (the damped oscillator; e.g. Goldstein, Classical
//!   Mechanics, ch. 6, or any text on the damped harmonic oscillator).
//!   The chain of [`crate::quality::chain`] (31 links of 1 cm) starts at
//!   rest in mode 1 with its tip 3 degrees off vertical, `damping` = 1 (no
//!   other loss), no wind; the peaks of the tip's swing (each refined by the
//!   parabola through its three samples) are fitted with a line in
//!   `log |peak|` against time by least squares, and the error is
//!   `|rate - c / 2| / (c / 2)` (1 where fewer than three peaks were
//!   found). The run lasts `10 / c` seconds (at least 2.5 s, at most 10 s:
//!   five e-foldings); peaks below 1 % of the start are left out.
//!
//! What else moves the result: the one-projection solve at long substeps
//! (1/120 s zig-zags at the root, the kernels' README), and the blend
//! `stiff_mode_damping` (default 0.05), which takes about
//! `a omega^2 h` per second from a mode of frequency `omega` at substep `h`
//! on top of the drag (0.009/s for mode 1 at 1/240 s, 1.9 % of c/2 at
//! c = 1): counted as error, since the closed form has none.
//!
//! First full run (`docs/report/summary.md`): at 1/240 s the strand hangs
//! within 0.003 degrees of `g + c w` and the swing decays at c/2 within
//! 1.9 % (c = 1, the blend's share) and 0.4 % (c = 4); at 1/120 s the decay
//! is 60-87 % off (the root zig-zags) and the angle 0.2-0.35 degrees. The
//! angle grows again at 1/480 and 1/960 s (0.02-0.05 degrees), as rounding
//! of the move `a h^2` per substep in f32 would (1e-5 m at 1/960 s on
//! positions of 0.3 m); not tracked down further.
//!
//! Settings: `max_substep` 1/120, 1/240 (the default), 1/480, 1/960 s at
//! dt = 1/60 s, x drag 1 and 4 per second; the setting names the substeps
//! the step ran (more than `dt / max_substep` where the wind is beyond 2 g,
//! see `SimParams::substeps`). Rows at the default `max_substep` are marked
//! default (drag has no default but off). Time: ns per vertex-step (a step
//! = all its substeps) on [`STRANDS`] identical strands (4 SIMD blocks,
//! strand 0 read), the median step of each run; the spread is the range
//! of those medians over the three winds' runs (equilibrium) or three
//! repeated runs (decay; one in a quick run). SIMD and scalar: the scalar
//! step gives the same bits, so the error is the SIMD run's.
//!
//! A quick run measures `max_substep` 1/240 and 1/480 at drag 4 and the
//! strongest wind alone.

use super::{Options, Path, Row, Timing};
use crate::quality::chain::{self, LINK, LINKS};
use coif::kernels::{self as kernels, scalar, SimParams, Strands};
use glam::{DVec3, Vec3};
use std::time::Instant;

/// `max_substep` values measured, as the denominator of 1/n seconds.
pub const MAX_SUBSTEP: [u32; 4] = [120, 240, 480, 960];
/// Drag values measured (1/s).
pub const DRAG: [f32; 2] = [1.0, 4.0];
/// Steady winds of the equilibrium study (m/s).
pub const WINDS: [Vec3; 3] = [
    Vec3::new(2.0, 0.0, 0.0),
    Vec3::new(3.0, 0.5, 4.0),
    Vec3::new(8.0, 0.0, 0.0),
];
/// Identical strands stepped together (4 SIMD blocks); strand 0 is read.
pub const STRANDS: usize = 32;
/// Start angle of the decay run (degrees off vertical, tip against root).
pub const START_DEGREES: f64 = 3.0;

/// The step of a path.
fn stepper(path: Path) -> fn(&mut Strands, &SimParams, &[kernels::Sphere]) {
    match path {
        Path::Simd => kernels::step,
        Path::Scalar => scalar::step,
    }
}

/// Parameters of one setting: `max_substep = 1 / rate` s, drag `c`, no
/// sleeping (a settling strand must not stop early), the rest default.
fn params(rate: u32, drag: f32) -> SimParams {
    SimParams {
        max_substep: 1.0 / rate as f32,
        drag,
        sleep_speed: 0.0,
        ..Default::default()
    }
}

/// Runs `STRANDS` copies of `points` (one strand) for `steps` steps;
/// calls `read` with strand 0's positions after every step and returns
/// the median seconds per step.
fn run(
    points: &[Vec3],
    params: &SimParams,
    steps: usize,
    path: Path,
    mut read: impl FnMut(&Strands),
) -> f64 {
    let all: Vec<Vec3> = (0..STRANDS).flat_map(|_| points.iter().copied()).collect();
    let mut s = Strands::from_polylines(&all, points.len()).expect("a valid strand");
    let step = stepper(path);
    let mut times = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t0 = Instant::now();
        step(&mut s, params, &[]);
        times.push(t0.elapsed().as_secs_f64());
        read(&s);
    }
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// The steady acceleration `g + c w` of a setting in a wind.
pub fn steady_acceleration(params: &SimParams) -> DVec3 {
    (params.gravity + params.wind * params.drag).as_dvec3()
}

/// Seconds the equilibrium run settles: `max(10, 5 c L / |a|)`.
pub fn settle_seconds(params: &SimParams) -> f64 {
    let length = LINKS as f64 * LINK;
    let a = steady_acceleration(params).length();
    (5.0 * params.drag as f64 * length / a).max(10.0)
}

/// Angle in degrees between `u` and `v` (by atan2, exact near 0).
pub fn angle_degrees(u: DVec3, v: DVec3) -> f64 {
    u.cross(v).length().atan2(u.dot(v)).to_degrees()
}

/// One equilibrium run: (angle in degrees between tip - root and
/// `g + c w` at the end, median seconds per step).
pub fn equilibrium(params: &SimParams, path: Path) -> (f64, f64) {
    let points: Vec<Vec3> = (0..=LINKS)
        .map(|v| Vec3::new(0.0, -(v as f32) * LINK as f32, 0.0))
        .collect();
    let steps = (settle_seconds(params) / params.dt as f64).ceil() as usize;
    let mut last = DVec3::NAN;
    let seconds = run(&points, params, steps, path, |s| {
        let (root, tip) = (s.vertex(0, 0), s.vertex(0, LINKS));
        if let (Some(root), Some(tip)) = (root, tip) {
            last = (tip - root).as_dvec3();
        }
    });
    let angle = angle_degrees(last, steady_acceleration(params));
    (if angle.is_finite() { angle } else { 180.0 }, seconds)
}

/// Decay rate (1/s) of the peaks of `x` sampled every `dt`: each local
/// extreme of `|x|` refined by the parabola through its three samples,
/// those above `floor` fitted by least squares in `log |peak|` against
/// time. None with fewer than three such peaks or a non-finite sample.
pub fn decay_rate(x: &[f64], dt: f64, floor: f64) -> Option<f64> {
    if x.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut peaks = Vec::new();
    for i in 1..x.len().saturating_sub(1) {
        let (a, b, c) = (x[i - 1], x[i], x[i + 1]);
        let same_side = a.signum() == b.signum() && b.signum() == c.signum();
        if same_side && b.abs() >= a.abs() && b.abs() > c.abs() {
            // Vertex of the parabola through (-1, a), (0, b), (1, c).
            let curve = a - 2.0 * b + c;
            let (offset, value) = if curve != 0.0 {
                let o = 0.5 * (a - c) / curve;
                (o, b - 0.25 * (a - c) * o)
            } else {
                (0.0, b)
            };
            if value.abs() > floor {
                peaks.push(((i as f64 + offset) * dt, value.abs().ln()));
            }
        }
    }
    if peaks.len() < 3 {
        return None;
    }
    let n = peaks.len() as f64;
    let (mt, my) = peaks
        .iter()
        .fold((0.0, 0.0), |(st, sy), (t, y)| (st + t / n, sy + y / n));
    let (sxy, sxx) = peaks.iter().fold((0.0, 0.0), |(sxy, sxx), (t, y)| {
        (sxy + (t - mt) * (y - my), sxx + (t - mt) * (t - mt))
    });
    Some(-sxy / sxx)
}

/// Seconds of the decay run at drag `c`: `10 / c` within [2.5, 10].
pub fn decay_seconds(drag: f32) -> f64 {
    (10.0 / drag as f64).clamp(2.5, 10.0)
}

/// One decay run at `params` (damping is set to 1 and the wind to zero
/// here): (the fitted rate, the relative error against `c / 2`, median
/// seconds per step).
pub fn decay(params: &SimParams, path: Path) -> (Option<f64>, f64, f64) {
    let params = SimParams {
        damping: 1.0,
        wind: Vec3::ZERO,
        ..params.clone()
    };
    let length = LINKS as f64 * LINK;
    let a0 = length * START_DEGREES.to_radians().sin();
    let points = chain::chain_in_mode(1, a0);
    let dt = params.dt as f64;
    let steps = (decay_seconds(params.drag) / dt).round() as usize;
    let mut tips = vec![points[LINKS].x as f64];
    let seconds = run(&points, &params, steps, path, |s| {
        tips.push(s.vertex(0, LINKS).map_or(f64::NAN, |p| p.x as f64));
    });
    let expected = params.drag as f64 / 2.0;
    let rate = decay_rate(&tips, dt, 0.01 * a0);
    let error = rate.map_or(1.0, |r| (r - expected).abs() / expected);
    (rate, error, seconds)
}

/// The settings of a run: (max_substep denominators, drags).
fn settings(options: Options) -> (&'static [u32], &'static [f32]) {
    if options.quick {
        (&[240, 480], &[4.0])
    } else {
        (&MAX_SUBSTEP, &DRAG)
    }
}

/// The `wind equilibrium` and `wind decay` rows, SIMD and scalar.
pub fn rows(options: Options) -> Vec<Row> {
    let (rates, drags) = settings(options);
    let winds: &[Vec3] = if options.quick { &WINDS[2..] } else { &WINDS };
    let reps = if options.quick { 1 } else { 3 };
    let default_substep = SimParams::default().max_substep;
    let per_step = (STRANDS * (LINKS + 1)) as f64;
    let ns = |seconds: Vec<f64>| {
        Timing::from_samples(seconds.into_iter().map(|s| s * 1e9 / per_step).collect())
    };
    let mut rows = Vec::new();
    for &drag in drags {
        for &rate in rates {
            let base = params(rate, drag);
            let is_default = base.max_substep == default_substep;
            let mut worst = 0.0f64;
            let mut times = [Vec::new(), Vec::new()];
            let (mut fewest, mut most) = (u32::MAX, 0);
            for &wind in winds {
                let p = SimParams {
                    wind,
                    ..base.clone()
                };
                fewest = fewest.min(p.substeps());
                most = most.max(p.substeps());
                let (angle, simd) = equilibrium(&p, Path::Simd);
                let (_, scalar) = equilibrium(&p, Path::Scalar);
                eprintln!(
                    "wind 1/{rate} drag={drag} wind={wind}: {} substeps, {angle:.4} degrees off g + c w",
                    p.substeps()
                );
                worst = worst.max(angle);
                times[0].push(simd);
                times[1].push(scalar);
            }
            let substeps = if fewest == most {
                format!("{fewest}")
            } else {
                format!("{fewest}-{most}")
            };
            let setting = format!("max_substep=1/{rate} drag={drag} ({substeps} substeps)");
            let [simd, scalar] = times;
            push_both(
                &mut rows,
                "wind equilibrium",
                &setting,
                [ns(simd), ns(scalar)],
                (
                    "worst angle between tip - root and g + c w after settling (degrees)",
                    worst,
                ),
                is_default,
            );

            let runs: Vec<_> = (0..reps).map(|_| decay(&base, Path::Simd)).collect();
            let scalar: Vec<f64> = (0..reps).map(|_| decay(&base, Path::Scalar).2).collect();
            let (rate_fit, error, _) = runs[0];
            eprintln!(
                "wind decay 1/{rate} drag={drag}: rate {:.5}/s against {:.5}/s, error {:.3} %",
                rate_fit.unwrap_or(f64::NAN),
                drag / 2.0,
                error * 100.0
            );
            push_both(
                &mut rows,
                "wind decay",
                &format!(
                    "max_substep=1/{rate} drag={drag} ({} substeps)",
                    base.substeps()
                ),
                [ns(runs.iter().map(|r| r.2).collect()), ns(scalar)],
                (
                    "|decay rate of the swing - c/2| / (c/2) in mode 1 of the chain (fraction)",
                    error,
                ),
                is_default,
            );
        }
    }
    rows
}

/// A SIMD and a scalar row of one setting with the same error.
fn push_both(
    rows: &mut Vec<Row>,
    kernel: &str,
    setting: &str,
    times: [Timing; 2],
    (error_metric, error): (&'static str, f64),
    is_default: bool,
) {
    for (path, time) in [Path::Simd, Path::Scalar].into_iter().zip(times) {
        rows.push(Row {
            kernel: kernel.into(),
            setting: setting.into(),
            path,
            element: "vertex-step",
            time,
            error_metric,
            error,
            is_default,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decay_rate_of_a_damped_cosine() {
        let (dt, rate, omega) = (1.0 / 60.0, 0.5, 6.7);
        let x: Vec<f64> = (0..600)
            .map(|i| {
                let t = i as f64 * dt;
                0.016 * (-rate * t).exp() * (omega * t).cos()
            })
            .collect();
        let fitted = decay_rate(&x, dt, 1e-4).expect("peaks");
        assert!((fitted / rate - 1.0).abs() < 2e-3, "{fitted}");
        assert_eq!(decay_rate(&[1.0, 2.0, 1.0], dt, 0.0), None);
    }

    #[test]
    fn angles_and_settling() {
        let a = angle_degrees(DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 0.0));
        assert!((a - 45.0).abs() < 1e-12);
        assert_eq!(angle_degrees(DVec3::Y, DVec3::Y * 3.0), 0.0);
        // Every case here settles for 10 s: 5 c L / |a| is below it.
        for &drag in &DRAG {
            for wind in WINDS {
                let p = SimParams {
                    wind,
                    ..params(240, drag)
                };
                assert_eq!(settle_seconds(&p), 10.0);
            }
        }
        assert_eq!(params(240, 1.0).substeps(), 4);
        assert_eq!(params(960, 1.0).substeps(), 16);
    }
}
