//! Time against error for patches: how far a run with few constraint sweeps
//! lands from a converged run, and how much its edges stretch.
//!
//! The scene: a `rows x cols` flag, 2 cm between particles, starting
//! horizontal with its top row pinned; the pinned row circles at 1 Hz with a
//! 10 cm radius while the flag falls and swings past a 10 cm sphere below
//! it. Defaults of [`SimParams`] except `iterations`.

use super::grid::Patch;
use super::step::step;
use crate::{SimParams, Sphere};
use glam::Vec3;

/// Iterations of the reference run that [`convergence`] compares against.
pub const REFERENCE_ITERATIONS: u32 = 256;

/// Error of one setting after the scene's steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchQuality {
    pub iterations: u32,
    /// RMS distance (m) of the particles from the 256-iteration run.
    pub rms_distance: f32,
    /// Largest distance (m) of a particle from the 256-iteration run.
    pub max_distance: f32,
    /// Largest relative stretch `|x_a - x_b| / rest - 1` of a structural
    /// edge at the end of the run (negative: compressed only).
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

/// Runs the scene for `steps` steps (of 1/60 s) with `iterations` sweeps and
/// with [`REFERENCE_ITERATIONS`], and compares them. `rows`, `cols` >= 2.
pub fn convergence(rows: usize, cols: usize, iterations: u32, steps: usize) -> PatchQuality {
    let (points, pinned) = flag_scene(rows, cols);
    let run = |iterations: u32| -> Patch {
        let mut patch = Patch::new(&points, rows, cols, &pinned).expect("valid scene");
        let params = SimParams {
            iterations,
            ..Default::default()
        };
        let rig = [Sphere {
            center: Vec3::new(0.5 * 0.02 * cols as f32, 0.8, 0.0),
            radius: 0.1,
        }];
        let mut skin = points.clone();
        for s in 0..steps {
            let a = std::f32::consts::TAU * s as f32 * params.dt;
            let off = Vec3::new(0.1 * a.cos() - 0.1, 0.0, 0.1 * a.sin());
            for (k, p) in skin.iter_mut().enumerate() {
                *p = points[k] + off;
            }
            patch.set_skinned(&skin).expect("finite skin");
            step(&mut patch, &params, &rig);
        }
        patch
    };
    let (low, reference) = (run(iterations), run(REFERENCE_ITERATIONS));
    let (a, b) = (low.positions(), reference.positions());
    let d: Vec<f32> = a.iter().zip(&b).map(|(x, y)| x.distance(*y)).collect();
    let rms = (d.iter().map(|x| x * x).sum::<f32>() / d.len() as f32).sqrt();
    PatchQuality {
        iterations,
        rms_distance: rms,
        max_distance: d.iter().copied().fold(0.0, f32::max),
        max_stretch: max_edge_stretch(&low),
    }
}

/// Largest `|x_a - x_b| / rest - 1` over the structural edges of `patch`.
pub fn max_edge_stretch(patch: &Patch) -> f32 {
    let x = patch.positions();
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
