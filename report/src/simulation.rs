//! Simulation: projections (of the length constraints per substep, the
//! Newton iterations of the chain's tridiagonal solve), pearls (extra
//! collision points per segment, Nguyen and Donnelly 2005) and substeps
//! against error, via [`crate::quality::simulation`]: 256 strands of 32
//! vertices on a sphere head, scenes `settling` (3 s) and `whipping` (head
//! on a 10 cm circle at 3 Hz, 2 s), one step of dt = 1/60 s per frame.
//!
//! - Kernels `simulation <scene>`: iterations (projections per substep) x
//!   pearls at the default 4 substeps; time per vertex-step; reference 256
//!   projections, 3 pearls, compared at the end.
//! - Kernels `simulation <scene> substeps`: the solver's own substep knob,
//!   `max_substep = dt / n` for n in 2, 4, 8, 16 substeps per step
//!   (default 4; default projections and pearls); time per vertex-step (a
//!   step = all its substeps), so the settings compare; reference 32
//!   substeps of 8 projections, 3 pearls, compared at the end of every
//!   frame (RMS over all frames).
//!
//! Time is the median over the run's steps; the run is repeated (three
//! times in a full report) and the spread is the range of those medians.
//! Three errors per scene and study, each its own kernel in the report: RMS
//! vertex distance (metres) to the converged run, the largest
//! stretch seen, and the deepest penetration of the head seen (what pearls
//! are for).

use super::{Options, Path, Row, Timing};
use crate::quality::simulation::{
    converged, converged_substeps, converged_substeps_with, default_substeps, measure_setting,
    measure_substeps, Row as SettingRow, Scene, REFERENCE_SUBSTEPS, SUBSTEPS,
};
use coif::kernels::SimParams;

/// Iterations and pearls measured (full run).
pub const ITERATIONS: [u32; 5] = [1, 2, 4, 8, 16];
/// Pearls per segment measured (full run).
pub const PEARLS: [u32; 3] = [0, 1, 2];

/// The three errors reported per scene: (kernel suffix, metric, value).
/// The distance is taken at the end (`per_frame` false: the iterations x
/// pearls study) or at every frame's end (`per_frame`: the substeps study).
/// Time is per vertex-step in both.
fn errors(r: &SettingRow, per_frame: bool) -> [(&'static str, &'static str, f64); 3] {
    let distance = if per_frame {
        (
            "RMS distance to converged run over all frames (m)",
            r.rms_distance_over_frames as f64,
        )
    } else {
        (
            "RMS distance to converged run (m)",
            r.rms_distance_to_converged as f64,
        )
    };
    [
        ("", distance.0, distance.1),
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

/// One row per error and path for `runs` of one setting.
fn push_rows(
    rows: &mut Vec<Row>,
    kernel: &str,
    setting: String,
    runs: &[SettingRow],
    per_frame: bool,
    is_default: bool,
) {
    let ns = |r: &SettingRow, path: Path| match path {
        Path::Simd => r.simd_ns_per_vertex_step,
        Path::Scalar => r.scalar_ns_per_vertex_step,
    };
    for (suffix, error_metric, error) in errors(&runs[0], per_frame) {
        for path in [Path::Simd, Path::Scalar] {
            rows.push(Row {
                kernel: format!("{kernel}{suffix}"),
                setting: setting.clone(),
                path,
                element: "vertex-step",
                time: Timing::from_samples(runs.iter().map(|r| ns(r, path)).collect()),
                error_metric,
                error,
                is_default,
            });
        }
    }
}

/// The `simulation <scene>` and `simulation <scene> substeps` rows, each
/// with its ` stretch` and ` penetration` kernels, SIMD and scalar.
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
                push_rows(
                    &mut rows,
                    &format!("simulation {}", scene.name()),
                    format!("iterations={it} pearls={p}"),
                    &runs,
                    false,
                    is_default,
                );
            }
        }
    }
    rows.extend(substeps_rows(options));
    rows
}

/// The substeps study (kernels `simulation <scene> substeps ...`). Quick
/// runs measure 4 and 16 substeps against a cheaper reference (32
/// substeps of 2 projections).
fn substeps_rows(options: Options) -> Vec<Row> {
    let (substeps, reps): (&[u32], usize) = if options.quick {
        (&[4, 16], 1)
    } else {
        (&SUBSTEPS, 3)
    };
    let mut rows = Vec::new();
    for scene in [Scene::Settling, Scene::Whipping] {
        let reference = if options.quick {
            converged_substeps_with(scene, REFERENCE_SUBSTEPS, 2)
        } else {
            converged_substeps(scene)
        };
        for &n in substeps {
            let runs: Vec<SettingRow> = (0..reps)
                .map(|_| measure_substeps(scene, n, &reference))
                .collect();
            push_rows(
                &mut rows,
                &format!("simulation {} substeps", scene.name()),
                format!("substeps={n}"),
                &runs,
                true,
                n == default_substeps(),
            );
        }
    }
    rows
}
