//! Fits: P-spline control count and smoothing (lambda) against fit error.
//! A P-spline is a least-squares B-spline fit with a difference penalty
//! of weight lambda on adjacent control points (Eilers and Marx 1996).
//!
//! 256 noisy curls (64 samples of a 1.5 cm radius, 2-turn, 25 cm helix
//! with +-1 mm uniform noise per axis, as in lod/README.md). Times
//! [`coif::lod::Fitter::fit_into`] per strand (one factored system, every
//! strand solved; scalar only: faer's Cholesky, no SIMD twin). Error: RMS
//! over 16 strands of [`coif::lod::quality::fit_error`]'s rms distance of
//! the fitted curve from the noise-free curl (metres).

use super::timing::time_batch;
use super::{Options, Path, Row};
use coif::lod::quality::{fit_error, helix, with_noise};
use coif::lod::Fitter;
use glam::Vec3;

/// Control points per strand measured.
pub const CONTROLS: [usize; 5] = [6, 8, 12, 16, 24];
/// Smoothing weights (lambda of the difference penalty) measured.
pub const LAMBDAS: [f32; 3] = [0.0, 0.1, 1.0];
/// The setting of the lod benches and README: 12 controls, lambda 0.1.
pub const DEFAULT: (usize, f32) = (12, 0.1);

const SAMPLES: usize = 64;

/// The `fits` rows: every controls x lambda setting, scalar only.
pub fn rows(options: Options) -> Vec<Row> {
    let strands = if options.quick { 32 } else { 256 };
    let truth = helix(SAMPLES, 0.015, 0.25, 2.0);
    let noisy: Vec<Vec<Vec3>> = (0..strands)
        .map(|s| with_noise(&truth, 0.001, 1000 + s as u64))
        .collect();
    let flat: Vec<Vec3> = noisy.iter().flatten().copied().collect();
    let (controls, lambdas): (&[usize], &[f32]) = if options.quick {
        (&[8, 12], &[0.1])
    } else {
        (&CONTROLS, &LAMBDAS)
    };
    let mut rows = Vec::new();
    for &n in controls {
        for &lambda in lambdas {
            let mut fitter = Fitter::new(SAMPLES, n, lambda).expect("valid fit shape");
            let mut out = vec![Vec3::ZERO; strands * n];
            let time = time_batch(options.reps(), strands, || {
                fitter.fit_into(&flat, &mut out).expect("whole strands");
                std::hint::black_box(&out);
            });
            let checked = noisy.len().min(16);
            let sum_sq: f64 = noisy[..checked]
                .iter()
                .map(|s| {
                    let e = fit_error(&truth, s, n, lambda).expect("valid fit");
                    (e.rms as f64).powi(2)
                })
                .sum();
            rows.push(Row {
                kernel: "fits".into(),
                setting: format!("controls={n} lambda={lambda}"),
                path: Path::Scalar,
                element: "strand",
                time,
                error_metric: "RMS distance to noise-free curl (m)",
                error: (sum_sq / checked as f64).sqrt(),
                is_default: (n, lambda) == DEFAULT,
            });
        }
    }
    rows
}
