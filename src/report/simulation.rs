//! Simulation: iterations and pearls against the distance to a converged
//! run, via [`crate::quality::simulation`] (the settling scene: 256
//! strands of 32 vertices on a sphere head, 180 steps of 1/60 s).
//!
//! Time per vertex-step is the median over the run's steps; the run is
//! repeated (three times in a full report) and the spread is the range of those
//! medians. Error: RMS vertex distance (metres) at the end to the
//! converged run (256 iterations, 3 pearls).

use super::{Options, Path, Row, Timing};
use crate::kernels::SimParams;
use crate::quality::simulation::{converged, measure_setting, Scene};

/// Iterations and pearls measured (full run).
pub const ITERATIONS: [u32; 5] = [1, 2, 4, 8, 16];
pub const PEARLS: [u32; 3] = [0, 1, 2];

pub fn rows(options: Options) -> Vec<Row> {
    let (iterations, pearls, reps): (&[u32], &[u32], usize) = if options.quick {
        (&[1, 4], &[1], 1)
    } else {
        (&ITERATIONS, &PEARLS, 3)
    };
    let defaults = SimParams::default();
    let scene = Scene::Settling;
    let reference = converged(scene);
    let mut rows = Vec::new();
    for &it in iterations {
        for &p in pearls {
            let runs: Vec<_> = (0..reps)
                .map(|_| measure_setting(scene, it, p, &reference))
                .collect();
            let error = runs[0].rms_distance_to_converged as f64;
            let is_default = it == defaults.iterations && p == defaults.pearls_per_segment;
            for (path, ns) in [
                (
                    Path::Simd,
                    runs.iter()
                        .map(|r| r.simd_ns_per_vertex_step)
                        .collect::<Vec<_>>(),
                ),
                (
                    Path::Scalar,
                    runs.iter().map(|r| r.scalar_ns_per_vertex_step).collect(),
                ),
            ] {
                rows.push(Row {
                    kernel: "simulation".into(),
                    setting: format!("iterations={it} pearls={p}"),
                    path,
                    element: "vertex-step",
                    time: Timing::from_samples(ns),
                    error_metric: "RMS distance to converged run (m)",
                    error,
                    is_default,
                });
            }
        }
    }
    rows
}
