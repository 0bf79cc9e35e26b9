//! Timing of a batch: median and spread over repeated runs.

use std::time::Instant;

/// Nanoseconds per element over repeated runs of a batch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Median run.
    pub median: f64,
    /// Fastest run.
    pub min: f64,
    /// Slowest run.
    pub max: f64,
}

impl Timing {
    /// From per-run nanoseconds per element (not empty).
    pub fn from_samples(mut ns: Vec<f64>) -> Timing {
        assert!(!ns.is_empty(), "at least one timed run");
        ns.sort_by(f64::total_cmp);
        Timing {
            median: ns[ns.len() / 2],
            min: ns[0],
            max: ns[ns.len() - 1],
        }
    }

    /// `max - min`.
    pub fn spread(&self) -> f64 {
        self.max - self.min
    }
}

/// Runs `batch` once to warm up, then `reps` times (at least 1), and
/// returns nanoseconds per element (`elements` per batch).
pub fn time_batch(reps: usize, elements: usize, mut batch: impl FnMut()) -> Timing {
    batch();
    let per = elements.max(1) as f64;
    let ns = (0..reps.max(1))
        .map(|_| {
            let t0 = Instant::now();
            batch();
            t0.elapsed().as_nanos() as f64 / per
        })
        .collect();
    Timing::from_samples(ns)
}
