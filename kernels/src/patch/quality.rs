//! Time against error for patches: how far a run with few constraint sweeps
//! lands from a converged run, and how much its edges stretch.
//!
//! The scene: a `rows x cols` flag, 2 cm between particles, starting
//! horizontal with its top row pinned; the pinned row circles at 1 Hz with a
//! 10 cm radius while the flag falls and swings past a 10 cm sphere below
//! it. Defaults of [`SimParams`] except `iterations`.

use super::grid::Patch;
use super::step::step;
use crate::{Error, SimParams, Sphere};
use glam::Vec3;

/// Iterations of the reference run that [`convergence`] compares against.
pub const REFERENCE_ITERATIONS: u32 = 256;

/// Error of one setting, over the measured steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchQuality {
    /// Constraint sweeps per step of the measured setting.
    pub iterations: u32,
    /// RMS over particles and steps of the distance (m) between one step
    /// with `iterations` sweeps and one with 256 from the same state.
    pub rms_distance: f32,
    /// Largest such distance (m).
    pub max_distance: f32,
    /// Largest relative stretch `|x_a - x_b| / rest - 1` of a structural
    /// edge after an `iterations` step (negative: compressed only).
    pub max_stretch: f32,
}

/// The quality scene's rest grid (horizontal, in the x-z plane) and its
/// pinned top row.
pub fn flag_scene(rows: usize, cols: usize) -> (Vec<Vec3>, Vec<bool>) {
    let spacing = 0.02;
    let points = (0..rows * cols)
        .map(|k| {
            Vec3::new(
                (k % cols) as f32 * spacing,
                1.0,
                (k / cols) as f32 * spacing,
            )
        })
        .collect();
    let pinned = (0..rows * cols).map(|k| k < cols).collect();
    (points, pinned)
}

/// Per-step solver error of `iterations` sweeps: the scene is advanced with
/// [`REFERENCE_ITERATIONS`] sweeps; at each of the `steps` steps after a
/// 30-step warm-up, a copy of the state takes one step with `iterations`
/// sweeps and is compared with the reference's step from the same state
/// (so the flag's chaotic swing does not enter the error). Steps of 1/60 s.
/// Errors as [`Patch::new`] for a grid it refuses (`rows`, `cols` must be
/// >= 2, `cols` <= 256).
///
/// # Errors
///
/// As [`Patch::new`] for a grid it refuses.
pub fn convergence(
    rows: usize,
    cols: usize,
    iterations: u32,
    steps: usize,
) -> Result<PatchQuality, Error> {
    let (points, pinned) = flag_scene(rows, cols);
    let mut reference = Patch::new(&points, rows, cols, &pinned)?;
    let exact = SimParams {
        iterations: REFERENCE_ITERATIONS,
        ..Default::default()
    };
    let trial = SimParams {
        iterations,
        ..exact.clone()
    };
    let rig = [Sphere {
        center: Vec3::new(0.5 * 0.02 * cols as f32, 0.8, 0.0),
        radius: 0.1,
    }];
    let mut skin = points.clone();
    let (mut sum2, mut count, mut worst, mut stretch) = (0.0f64, 0usize, 0.0f32, f32::NEG_INFINITY);
    let mut low = reference.clone();
    for s in 0..30 + steps {
        let a = std::f32::consts::TAU * s as f32 * exact.dt;
        let off = Vec3::new(0.1 * a.cos() - 0.1, 0.0, 0.1 * a.sin());
        for (k, p) in skin.iter_mut().enumerate() {
            *p = points[k] + off;
        }
        reference.set_skinned(&skin)?;
        if s >= 30 {
            low.clone_from(&reference);
            step(&mut low, &trial, &rig);
        }
        step(&mut reference, &exact, &rig);
        if s >= 30 {
            for (x, y) in low
                .positions_local()
                .iter()
                .zip(reference.positions_local())
            {
                let d = x.distance(y);
                sum2 += (d * d) as f64;
                worst = worst.max(d);
                count += 1;
            }
            stretch = stretch.max(max_edge_stretch(&low));
        }
    }
    Ok(PatchQuality {
        iterations,
        rms_distance: (sum2 / count.max(1) as f64).sqrt() as f32,
        max_distance: worst,
        max_stretch: stretch,
    })
}

/// Largest `|x_a - x_b| / rest - 1` over the structural edges of `patch`.
pub fn max_edge_stretch(patch: &Patch) -> f32 {
    let x = patch.positions_local();
    let (rows, cols) = (patch.rows(), patch.cols());
    let mut worst = f32::NEG_INFINITY;
    for k in 0..rows * cols {
        for j in [k + 1, k + cols] {
            if let Some(rest) = patch.rest_edge(k, j) {
                if rest > 0.0 {
                    worst = worst.max(x[k].distance(x[j]) / rest - 1.0);
                }
            }
        }
    }
    worst
}
