//! Physics: the strand step against the analytic hanging chain
//! ([`crate::quality::chain`]), which a converged run of the step itself
//! cannot judge (it would share a gain of energy or a wrong period).
//!
//! 31 links of 1 cm pinned at the top, g = 9.81 m/s^2, started at rest in
//! mode 1 or 2 of the chain's tension matrix with the tip 2 % of the length
//! off vertical, undamped (`damping` 1), no collisions, 12 s. Kernels:
//!
//! - `physics chain mode 1 period`: `|T / T_1 - 1|` from the tip's zero
//!   crossings (1 where the tip did not cross zero three times);
//! - `physics chain mode 1 amplitude`: `max(1 - kept, peak - 1, 0)`, kept the
//!   largest tip offset over the last period of the 12 s, peak the largest
//!   over the run, both over the start offset: what the step lost, or what
//!   it gained;
//! - `physics chain mode 2 period`: as mode 1.
//!
//! Settings: the solver's knobs that change the physics at dt = 1/60 s,
//! substeps `n = dt / max_substep` in {2, 4, 8, 16} x `stiff_mode_damping`
//! `a` in {0, 0.05, 0.15} (default 4 and 0.05), plus dt = 1/30 s at the
//! default `max_substep` (8 substeps of 1/240 s). Rows that diverge (the
//! kernels' README: h = 1/120 s zig-zags at the root) are measured as they
//! come out of the step, whose guard restores non-finite lanes.
//!
//! Time: ns per vertex-step (a step = all its substeps), the median step of
//! the mode 1 run on 64 identical chains (8 SIMD blocks, 2,048 vertices
//! counting the pinned tops), SIMD and scalar; the run is repeated (three
//! times in a full report) and the spread is the range of those medians.
//! The mode is read from strand 0.

use super::{Options, Path, Row, Timing};
use crate::quality::chain::{self, ChainRun, LINKS};
use coif::kernels::SimParams;

/// Substeps per step of 1/60 s measured (`max_substep = dt / n`).
pub const SUBSTEPS: [u32; 4] = [2, 4, 8, 16];
/// `stiff_mode_damping` values measured.
pub const STIFF_MODE_DAMPING: [f32; 3] = [0.0, 0.05, 0.15];
/// Identical chains stepped together (8 SIMD blocks).
pub const CHAINS: usize = 64;
/// Simulated seconds per run.
pub const SECONDS: f64 = 12.0;

/// One setting of the family: its name, parameters and whether it is the
/// default.
fn settings(options: Options) -> Vec<(String, SimParams, bool)> {
    let defaults = SimParams::default();
    let undamped = SimParams {
        damping: 1.0,
        ..Default::default()
    };
    let (substeps, blends): (&[u32], &[f32]) = if options.quick {
        (&[2, 4], &[0.05])
    } else {
        (&SUBSTEPS, &STIFF_MODE_DAMPING)
    };
    let mut out = Vec::new();
    for &n in substeps {
        for &a in blends {
            let params = SimParams {
                max_substep: undamped.dt / n as f32,
                stiff_mode_damping: a,
                ..undamped.clone()
            };
            let is_default =
                params.substeps() == defaults.substeps() && a == defaults.stiff_mode_damping;
            out.push((format!("substeps={n} a={a}"), params, is_default));
        }
    }
    let slow = SimParams {
        dt: 1.0 / 30.0,
        ..undamped
    };
    out.push((
        format!(
            "dt=1/30 substeps={} a={}",
            slow.substeps(),
            slow.stiff_mode_damping
        ),
        slow,
        false,
    ));
    out
}

/// The `physics chain ...` rows, SIMD and scalar.
pub fn rows(options: Options) -> Vec<Row> {
    let reps = if options.quick { 1 } else { 3 };
    let per_step = (CHAINS * (LINKS + 1)) as f64;
    let mut rows = Vec::new();
    for (setting, params, is_default) in settings(options) {
        let mode1: Vec<ChainRun> = (0..reps)
            .map(|_| chain::run(&params, 1, SECONDS, CHAINS, chain::SIMD))
            .collect();
        let scalar: Vec<ChainRun> = (0..reps)
            .map(|_| chain::run(&params, 1, SECONDS, CHAINS, chain::SCALAR))
            .collect();
        let mode2 = chain::run(&params, 2, SECONDS, CHAINS, chain::SIMD);
        let ns = |runs: &[ChainRun]| {
            Timing::from_samples(
                runs.iter()
                    .map(|r| r.step_seconds * 1e9 / per_step)
                    .collect(),
            )
        };
        let errors = [
            (
                "physics chain mode 1 period",
                "|period error| against mode 1 of K (fraction)",
                mode1[0].period_error(),
            ),
            (
                "physics chain mode 1 amplitude",
                "amplitude lost over 12 s or gained (fraction)",
                mode1[0].amplitude_error(),
            ),
            (
                "physics chain mode 2 period",
                "|period error| against mode 2 of K (fraction)",
                mode2.period_error(),
            ),
        ];
        for (kernel, error_metric, error) in errors {
            for (path, time) in [(Path::Simd, ns(&mode1)), (Path::Scalar, ns(&scalar))] {
                rows.push(Row {
                    kernel: kernel.into(),
                    setting: setting.clone(),
                    path,
                    element: "vertex-step",
                    time,
                    error_metric,
                    error,
                    is_default,
                });
            }
        }
        eprintln!(
            "physics {setting}: mode 1 period {:+.4} %, kept {:.1} %, peak {:.1} %, restored {}; mode 2 period {:+.4} %, kept {:.1} %",
            mode1[0].period.map_or(f64::NAN, |p| (p / mode1[0].expected_period - 1.0) * 100.0),
            mode1[0].kept * 100.0,
            mode1[0].peak * 100.0,
            mode1[0].restored,
            mode2.period.map_or(f64::NAN, |p| (p / mode2.expected_period - 1.0) * 100.0),
            mode2.kept * 100.0,
        );
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_cover_the_knobs_with_one_default() {
        let full = settings(Options { quick: false });
        assert_eq!(full.len(), SUBSTEPS.len() * STIFF_MODE_DAMPING.len() + 1);
        assert_eq!(full.iter().filter(|s| s.2).count(), 1);
        let default = full.iter().find(|s| s.2).unwrap();
        assert_eq!(default.0, "substeps=4 a=0.05");
        for (name, p, _) in &full {
            assert_eq!(p.damping, 1.0, "{name}: undamped");
            assert!(p.validate().is_ok(), "{name}");
            let n: u32 = name
                .split("substeps=")
                .nth(1)
                .and_then(|s| s.split(' ').next())
                .and_then(|s| s.parse().ok())
                .unwrap();
            assert_eq!(p.substeps(), n, "{name}");
        }
        assert!(full.last().unwrap().0.starts_with("dt=1/30 substeps=8"));
    }
}
