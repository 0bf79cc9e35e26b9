//! Cloth patches (fins, ribbons): constraint sweeps (position-based length
//! constraints, Jakobsen 2001, with Provot 1995's strain limit) against the
//! per-step solver error, via [`coif::kernels::patch::quality::convergence`] (a 16 x 32
//! flag with its pinned row circling past a sphere; RMS distance, metres,
//! of one step with few sweeps from one with 256 from the same state), and
//! as its own kernel (`patch stretch`) the largest structural edge stretch
//! after those steps (the strain limits hold it near `max_stretch`).
//!
//! Times [`coif::kernels::patch::step`] (SIMD) and
//! [`coif::kernels::patch::scalar::step`] on the same flag, per
//! particle-step.

use super::timing::time_batch;
use super::{Options, Path, Row};
use coif::kernels::patch::{self, quality, Patch};
use coif::kernels::{SimParams, Sphere};
use glam::Vec3;

/// Constraint sweeps per step measured.
pub const ITERATIONS: [u32; 5] = [1, 2, 4, 8, 16];
const ROWS: usize = 16;
const COLS: usize = 32;
/// Steps per timed batch.
const STEPS: usize = 10;

/// The `patch` and `patch stretch` rows: every sweep count, SIMD and scalar.
pub fn rows(options: Options) -> Vec<Row> {
    let (iterations, error_steps): (&[u32], usize) = if options.quick {
        (&[1, 4], 5)
    } else {
        (&ITERATIONS, 60)
    };
    let (points, pinned) = quality::flag_scene(ROWS, COLS);
    let start = Patch::new(&points, ROWS, COLS, &pinned).expect("valid flag");
    let rig = [Sphere {
        center: Vec3::new(0.5 * 0.02 * COLS as f32, 0.8, 0.0),
        radius: 0.1,
    }];
    let default_iterations = SimParams::default().iterations;
    let mut rows = Vec::new();
    for &it in iterations {
        let params = SimParams {
            iterations: it,
            ..Default::default()
        };
        let q = quality::convergence(ROWS, COLS, it, error_steps).expect("valid flag");
        let elements = STEPS * ROWS * COLS;
        let mut flag = start.clone();
        let simd = time_batch(options.reps(), elements, || {
            for _ in 0..STEPS {
                patch::step(&mut flag, &params, &rig);
            }
        });
        let mut flag = start.clone();
        let scalar = time_batch(options.reps(), elements, || {
            for _ in 0..STEPS {
                patch::scalar::step(&mut flag, &params, &rig);
            }
        });
        let errors = [
            (
                "patch",
                "RMS per-step distance to 256 sweeps (m)",
                q.rms_distance,
            ),
            (
                "patch stretch",
                "largest structural edge stretch after a step",
                q.max_stretch,
            ),
        ];
        for (kernel, metric, error) in errors {
            for (path, time) in [(Path::Simd, simd), (Path::Scalar, scalar)] {
                rows.push(Row {
                    kernel: kernel.into(),
                    setting: format!("iterations={it}"),
                    path,
                    element: "particle-step",
                    time,
                    error_metric: metric,
                    error: error as f64,
                    is_default: it == default_iterations,
                });
            }
        }
    }
    rows
}
