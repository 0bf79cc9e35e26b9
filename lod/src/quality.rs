//! Error measurements for time-against-error reports: chord error of the
//! refinement level, and fit error against control count and smoothing.
//! Reference values come from direct (closed-form) curve evaluation.

use crate::bspline::{evaluate, refine};
use crate::fit::fit;
use crate::Error;
use coif_kernels::rng::SplitMix64;
use glam::Vec3;

/// Sub-samples per refined segment when measuring chord error.
pub const CHORD_SAMPLES_PER_SEGMENT: usize = 32;

/// Measured chord error of `refine(control, N)`: the largest distance
/// between the curve `C(u)` and the refined polyline's linear interpolation
/// at the same parameter, over [`CHORD_SAMPLES_PER_SEGMENT`] samples per
/// segment. This is what [`crate::level::chord_error_bound`] bounds. 0 for
/// fewer than two control points.
pub fn chord_error(control: &[Vec3], segments_per_span: usize) -> f32 {
    if control.len() < 2 {
        return 0.0;
    }
    let n = segments_per_span.max(1);
    let mut poly = Vec::new();
    refine(control, n, &mut poly);
    let mut worst = 0.0f32;
    for (s, w) in poly.windows(2).enumerate() {
        for m in 1..CHORD_SAMPLES_PER_SEGMENT {
            let f = m as f32 / CHORD_SAMPLES_PER_SEGMENT as f32;
            let u = (s as f32 + f) / n as f32;
            let err = (evaluate(control, u) - w[0].lerp(w[1], f)).length();
            worst = worst.max(err);
        }
    }
    worst
}

/// Root-mean-square and largest distance between a fitted curve and the
/// points it is compared with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitError {
    pub rms: f32,
    pub max: f32,
}

/// Fits `n_control` controls with `smoothing` to `samples` (see
/// [`crate::fit`]) and measures the fitted curve, at the samples' uniform
/// parameters, against `truth` (same length as `samples`; pass `samples`
/// itself for the residual, or the noise-free points to measure how much
/// noise the fit removed).
pub fn fit_error(
    truth: &[Vec3],
    samples: &[Vec3],
    n_control: usize,
    smoothing: f32,
) -> Result<FitError, Error> {
    if truth.len() != samples.len() {
        return Err(Error::CountMismatch {
            expected: samples.len(),
            got: truth.len(),
        });
    }
    let ctrl = fit(samples, n_control, smoothing)?;
    let p = samples.len();
    let (mut sum, mut max) = (0.0f64, 0.0f32);
    for (i, t) in truth.iter().enumerate() {
        let u = if p > 1 {
            i as f32 * (n_control - 1) as f32 / (p - 1) as f32
        } else {
            0.0
        };
        let d = (evaluate(&ctrl, u) - *t).length();
        sum += (d as f64) * (d as f64);
        max = max.max(d);
    }
    Ok(FitError {
        rms: (sum / p.max(1) as f64).sqrt() as f32,
        max,
    })
}

/// `n` points of a helix around +Y (a curly strand): radius `radius`,
/// `turns` turns over height `height`, starting at `(radius, 0, 0)`.
pub fn helix(n: usize, radius: f32, height: f32, turns: f32) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let s = if n > 1 {
                i as f32 / (n - 1) as f32
            } else {
                0.0
            };
            let a = std::f32::consts::TAU * turns * s;
            Vec3::new(radius * a.cos(), -height * s, radius * a.sin())
        })
        .collect()
}

/// `points` plus independent noise uniform in `[-amplitude, amplitude]` per
/// coordinate, reproducibly from `seed`.
pub fn with_noise(points: &[Vec3], amplitude: f32, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    points
        .iter()
        .map(|p| {
            *p + Vec3::new(
                rng.range(-amplitude, amplitude),
                rng.range(-amplitude, amplitude),
                rng.range(-amplitude, amplitude),
            )
        })
        .collect()
}
