//! Simulation: iterations and pearls against error, via
//! [`crate::quality::simulation`]: 256 strands of 32 vertices on a sphere
//! head, scenes `settling` (180 steps of 1/60 s) and `whipping` (head on a
//! 10 cm circle at 3 Hz, 120 steps).
//!
//! Time per vertex-step is the median over the run's steps; the run is
//! repeated (three times in a full report) and the spread is the range of
//! those medians. Three errors per scene, each its own kernel in the
//! report: RMS vertex distance (metres) at the end to the converged run
//! (256 iterations, 3 pearls), the largest stretch seen, and the deepest
//! penetration of the head seen (what pearls are for).

use super::{Options, Path, Row, Timing};
use crate::kernels::SimParams;
use crate::quality::simulation::{converged, measure_setting, Row as SettingRow, Scene};

/// Iterations and pearls measured (full run).
pub const ITERATIONS: [u32; 5] = [1, 2, 4, 8, 16];
pub const PEARLS: [u32; 3] = [0, 1, 2];

/// The three errors reported per scene: (kernel suffix, metric, value).
fn errors(r: &SettingRow) -> [(&'static str, &'static str, f64); 3] {
    [
        (
            "",
            "RMS distance to converged run (m)",
            r.rms_distance_to_converged as f64,
        ),
        (
            " stretch",
            "largest stretch seen (fraction)",
            r.max_stretch as f64,
        ),
        (
            " penetration",
            "deepest penetration seen (m)",
            r.max_penetration as f64,
        ),
    ]
}

pub fn rows(options: Options) -> Vec<Row> {
    let (iterations, pearls, reps): (&[u32], &[u32], usize) = if options.quick {
        (&[1, 4], &[1], 1)
    } else {
        (&ITERATIONS, &PEARLS, 3)
    };
    let defaults = SimParams::default();
    let mut rows = Vec::new();
    for scene in [Scene::Settling, Scene::Whipping] {
        let reference = converged(scene);
        for &it in iterations {
            for &p in pearls {
                let runs: Vec<SettingRow> = (0..reps)
                    .map(|_| measure_setting(scene, it, p, &reference))
                    .collect();
                let is_default = it == defaults.iterations && p == defaults.pearls_per_segment;
                let simd =
                    Timing::from_samples(runs.iter().map(|r| r.simd_ns_per_vertex_step).collect());
                let scalar = Timing::from_samples(
                    runs.iter().map(|r| r.scalar_ns_per_vertex_step).collect(),
                );
                for (suffix, error_metric, error) in errors(&runs[0]) {
                    for (path, time) in [(Path::Simd, simd), (Path::Scalar, scalar)] {
                        rows.push(Row {
                            kernel: format!("simulation {}{suffix}", scene.name()),
                            setting: format!("iterations={it} pearls={p}"),
                            path,
                            element: "vertex-step",
                            time,
                            error_metric,
                            error,
                            is_default,
                        });
                    }
                }
            }
        }
    }
    rows
}
