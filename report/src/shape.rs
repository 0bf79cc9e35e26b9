//! Styled hair in motion: the local shape springs
//! (`SimParams::local_shape_stiffness`, `kernels/src/shape.rs`) with the
//! sag-free rest state (`Strands::solve_sag_free`) on Sintel's groom and
//! bust, against the groom itself and the hair carried rigidly by the
//! head (`coif::frame::style`).
//!
//! Scene: Sintel's 228 guides of 32 points on her bust's 4 mm field, the
//! default `SimParams` but the stiffness, one step of 1/60 s per frame:
//! 3 s at rest from the groom, then a 40-degree head turn in 0.5 s held
//! for 2.5 s. Three kernels carry the three measures as their error
//! column (lower is better in each):
//!
//! - `shape rest drift`: the 95th percentile distance of free vertices
//!   from the groom after the rest (m; goal <= 3 mm from 0.7 to 1);
//! - `shape kinks`: the largest share of interior vertices turning 30
//!   degrees or more beyond their groomed angle, at rest or in the turn
//!   (goal <= 1 % from 0.5 to 1);
//! - `shape return`: the tips' RMS distance from the rigidly carried hair
//!   2.5 s after the turn (m; goal <= 3 mm at 0.7).
//!
//! The setting names the stiffness, the sag-free solve (on, or `as
//! built` for the groom stepped without it) and the swing: the tips'
//! largest RMS distance from the rigidly carried hair in the turn (goal
//! at least 10 mm at 0.7, softer swinging no less). Time: ns per vertex-step of
//! the step on that scene (one thread, `coif::kernels::step_colliders`
//! and `scalar::step_colliders`), the median step of the run; the spread
//! is the range of those medians over the runs (three in a full report,
//! one in a quick run). The scalar step computes the same bytes (the
//! kernels' tests), so the errors are the SIMD run's.
//!
//! A quick run measures stiffness 0.7 with the solve and 1 without.

use super::{Options, Path, Row, Timing};
use coif::frame::style::{StyleRun, StyleScene};
use coif::kernels::{scalar, step_colliders, SimParams};

/// Stiffnesses measured with the sag-free solve (full run).
pub const STIFFNESS: [f32; 6] = [1.0, 0.9, 0.7, 0.6, 0.5, 0.3];
/// Stiffnesses measured on the groom as built, without the solve (the
/// library before the springs had a rest state of their own).
pub const AS_BUILT: [f32; 2] = [1.0, 0.7];
/// The default scene's stiffness (`demo`, `coif-bevy`).
pub const SCENE_DEFAULT: f32 = coif::frame::style::SCENE_STIFFNESS;

/// One run of the scene at stiffness `k`, with the solve or not, on `path`.
pub fn run(scene: &StyleScene, k: f32, sag_free: bool, path: Path) -> StyleRun {
    let params = SimParams {
        local_shape_stiffness: k,
        ..SimParams::default()
    };
    let prepare =
        |s: &mut coif::kernels::Strands, p: &SimParams, c: &coif::kernels::Colliders<'_>| {
            if sag_free {
                s.solve_sag_free(p, c)?;
            }
            Ok(())
        };
    let result = match path {
        Path::Simd => scene.run_stepped(&params, step_colliders, prepare),
        Path::Scalar => scene.run_stepped(&params, scalar::step_colliders, prepare),
    };
    result.expect("Sintel's scene runs")
}

/// The family's rows.
pub fn rows(options: Options) -> Vec<Row> {
    let scene = StyleScene::sintel().expect("Sintel's scene");
    let vertex_steps = scene.guides.len() as f64;
    let runs = if options.quick { 1 } else { 3 };
    let settings: Vec<(f32, bool)> = if options.quick {
        vec![(0.7, true), (1.0, false)]
    } else {
        STIFFNESS
            .iter()
            .map(|&k| (k, true))
            .chain(AS_BUILT.iter().map(|&k| (k, false)))
            .collect()
    };
    let mut rows = Vec::new();
    for (k, sag_free) in settings {
        let first = run(&scene, k, sag_free, Path::Simd);
        for path in [Path::Simd, Path::Scalar] {
            let mut times: Vec<f64> = (0..runs)
                .map(|i| {
                    if i == 0 && path == Path::Simd {
                        first.step_seconds
                    } else {
                        run(&scene, k, sag_free, path).step_seconds
                    }
                })
                .map(|s| s * 1e9 / vertex_steps)
                .collect();
            times.sort_by(f64::total_cmp);
            let time = Timing {
                median: times[times.len() / 2],
                min: times[0],
                max: times[times.len() - 1],
            };
            let setting = format!(
                "local_shape={k} {} swing={:.1}mm",
                if sag_free { "sag-free" } else { "as built" },
                first.swing * 1e3
            );
            let is_default = sag_free && k == SCENE_DEFAULT;
            let kinks = first.kinked_at_rest.max(first.kinked_in_turn) as f64;
            for (kernel, metric, error) in [
                (
                    "shape rest drift",
                    "95th percentile distance from the groom after 3 s at rest (m)",
                    first.rest_drift_p95 as f64,
                ),
                (
                    "shape kinks",
                    "largest share of interior vertices turning >= 30 deg beyond the groom",
                    kinks,
                ),
                (
                    "shape return",
                    "RMS of the tips from the rigidly carried hair 2.5 s after the turn (m)",
                    first.returned as f64,
                ),
            ] {
                rows.push(Row {
                    kernel: kernel.to_string(),
                    setting: setting.clone(),
                    path,
                    element: "vertex-step",
                    time,
                    error_metric: metric,
                    error,
                    is_default,
                });
            }
        }
    }
    rows
}
