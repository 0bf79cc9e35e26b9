//! The hanging chain against its closed form: the small oscillations of a
//! chain of equal masses on equal links, pinned at the top (Daniel
//! Bernoulli 1733; the discrete chain's normal modes from its tension
//! matrix, e.g. Goldstein, Classical Mechanics, ch. 6).
//!
//! A chain of `N` links of length `l` and `N` masses below the pin swings
//! horizontally by `u'' = -(g / l) K u`, with `K` symmetric tridiagonal,
//! `K_kk = T_k + T_(k+1)`, `K_(k,k+1) = -T_(k+1)`, `T_k = N - k + 1` (link
//! `k` carries the weight of the `N - k + 1` masses below it; `T_(N+1) = 0`).
//! Mode `k` swings at `omega_k = sqrt((g / l) lambda_k)`, `lambda_k` the
//! `k`-th smallest eigenvalue of `K`, with the eigenvector as its shape. As
//! `N` grows, `omega_k -> (j_0k / 2) sqrt(g / L)`, `L = N l`, `j_0k` the
//! zeros of the Bessel function `J_0` (2.4048, 5.5201, ...).
//!
//! The eigen solve here is the report's own, on purpose a different method
//! from the Jacobi rotations of the kernels' analytic test, so that the
//! two references share no code: eigenvalues by bisection on Sturm
//! sequences (Givens 1954; Wilkinson, The Algebraic Eigenvalue Problem,
//! 1965, ch. 5), eigenvectors by inverse iteration with the tridiagonal
//! (Thomas) solve, both in f64.
//!
//! [`run`] drops a set of identical chains started at rest in one mode
//! (the tip a given share of the length off vertical) into the strand
//! step, no collisions, and measures the period from the tip's zero
//! crossings and the amplitude kept, from strand 0, timing every step.

use coif::kernels::{self as kernels, scalar, SimParams, Strands};
use glam::Vec3;
use std::time::Instant;

/// Gravity of the chain study (m/s^2).
pub const G: f64 = 9.81;
/// Links of the chain (vertices: one more, the pinned top).
pub const LINKS: usize = 31;
/// Length of one link (m).
pub const LINK: f64 = 0.01;
/// Start offset of the tip as a share of the chain's length.
pub const TIP_SHARE: f64 = 0.02;

/// The tension matrix `K` of a chain of `links` links as its diagonal and
/// off-diagonal (`off[i] = K_(i,i+1)`, `links - 1` entries).
pub fn tension_matrix(links: usize) -> (Vec<f64>, Vec<f64>) {
    let t = |k: usize| {
        if k > links {
            0.0
        } else {
            (links - k + 1) as f64
        }
    };
    let diag = (1..=links).map(|k| t(k) + t(k + 1)).collect();
    let off = (1..links).map(|k| -t(k + 1)).collect();
    (diag, off)
}

/// Eigenvalues of the symmetric tridiagonal matrix (`diag`, `off`) below
/// `x`: the sign changes of its Sturm sequence (the count of negative
/// pivots of the LDL^T factorisation of `K - x I`).
fn count_below(diag: &[f64], off: &[f64], x: f64) -> usize {
    let mut count = 0;
    let mut q = 1.0f64;
    for i in 0..diag.len() {
        let b2 = if i == 0 { 0.0 } else { off[i - 1] * off[i - 1] };
        q = diag[i] - x - if i == 0 { 0.0 } else { b2 / q };
        if q == 0.0 {
            q = -f64::EPSILON * (diag[i].abs() + x.abs() + 1.0);
        }
        if q < 0.0 {
            count += 1;
        }
    }
    count
}

/// The `k`-th smallest eigenvalue (0-based) of the symmetric tridiagonal
/// matrix (`diag`, `off`), by bisection on the Sturm count inside the
/// Gershgorin interval, to f64 resolution.
pub fn eigenvalue(diag: &[f64], off: &[f64], k: usize) -> f64 {
    let n = diag.len();
    let radius = |i: usize| {
        (if i > 0 { off[i - 1].abs() } else { 0.0 }) + (if i + 1 < n { off[i].abs() } else { 0.0 })
    };
    let mut lo = (0..n).map(|i| diag[i] - radius(i)).fold(f64::MAX, f64::min);
    let mut hi = (0..n).map(|i| diag[i] + radius(i)).fold(f64::MIN, f64::max);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if count_below(diag, off, mid) > k {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Solves `(T - shift I) x = b` for the symmetric tridiagonal `T`
/// (`diag`, `off`) by the Thomas algorithm (a zero pivot is nudged).
fn solve_shifted(diag: &[f64], off: &[f64], shift: f64, b: &[f64]) -> Vec<f64> {
    let n = diag.len();
    let mut c = vec![0.0; n];
    let mut d = vec![0.0; n];
    for i in 0..n {
        let lower = if i > 0 { off[i - 1] } else { 0.0 };
        let mut pivot = diag[i] - shift - if i > 0 { lower * c[i - 1] } else { 0.0 };
        if pivot.abs() < 1e-300 {
            pivot = 1e-300;
        }
        c[i] = if i + 1 < n { off[i] / pivot } else { 0.0 };
        d[i] = (b[i] - if i > 0 { lower * d[i - 1] } else { 0.0 }) / pivot;
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = d[i] - if i + 1 < n { c[i] * x[i + 1] } else { 0.0 };
    }
    x
}

/// The unit eigenvector of the symmetric tridiagonal (`diag`, `off`) for
/// its eigenvalue `lambda`, by inverse iteration (a shift just off
/// `lambda`, three solves from a vector of ones), signed so that its last
/// entry is positive.
pub fn eigenvector(diag: &[f64], off: &[f64], lambda: f64) -> Vec<f64> {
    let shift = lambda * (1.0 + 1e-10) + 1e-12;
    let mut x = vec![1.0; diag.len()];
    for _ in 0..3 {
        x = solve_shifted(diag, off, shift, &x);
        let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        x.iter_mut().for_each(|v| *v /= norm);
    }
    if x.last().is_some_and(|&v| v < 0.0) {
        x.iter_mut().for_each(|v| *v = -*v);
    }
    x
}

/// Angular frequency (rad/s) of mode `mode` (1-based) of the chain of
/// [`LINKS`] links of [`LINK`]: `sqrt((g / l) lambda_mode)`.
pub fn omega(mode: usize) -> f64 {
    let (diag, off) = tension_matrix(LINKS);
    (G / LINK * eigenvalue(&diag, &off, mode - 1)).sqrt()
}

/// Period (s) of mode `mode` (1-based): `2 pi / omega`.
pub fn period(mode: usize) -> f64 {
    std::f64::consts::TAU / omega(mode)
}

/// The chain hanging from the origin along -y in mode `mode` (1-based), the
/// tip `tip` metres off vertical in +x: the eigenvector's horizontal
/// displacements, built link by link at exact lengths. [`LINKS`] + 1 points.
pub fn chain_in_mode(mode: usize, tip: f64) -> Vec<Vec3> {
    let (diag, off) = tension_matrix(LINKS);
    let u = eigenvector(&diag, &off, eigenvalue(&diag, &off, mode - 1));
    let scale = tip / u[LINKS - 1];
    let mut p = vec![[0.0f64; 2]];
    let mut prev_u = 0.0;
    for &ur in &u {
        let s = ((ur - prev_u) * scale / LINK).clamp(-1.0, 1.0);
        prev_u = ur;
        let last = p[p.len() - 1];
        p.push([last[0] + LINK * s, last[1] - LINK * (1.0 - s * s).sqrt()]);
    }
    p.iter()
        .map(|q| Vec3::new(q[0] as f32, q[1] as f32, 0.0))
        .collect()
}

/// Period (s) from the zero crossings of the samples `x` taken every `dt`
/// (linear interpolation between samples); None with fewer than three
/// crossings or a non-finite sample.
pub fn period_from_crossings(x: &[f64], dt: f64) -> Option<f64> {
    if x.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut crossings = vec![];
    for i in 1..x.len() {
        if x[i - 1] != 0.0 && x[i - 1].signum() != x[i].signum() {
            let f = x[i - 1] / (x[i - 1] - x[i]);
            crossings.push((i as f64 - 1.0 + f) * dt);
        }
    }
    (crossings.len() >= 3).then(|| {
        2.0 * (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
    })
}

/// What one run of the chain gave (strand 0).
#[derive(Clone, Debug, PartialEq)]
pub struct ChainRun {
    /// The mode started (1-based).
    pub mode: usize,
    /// The mode's period from `K` (s).
    pub expected_period: f64,
    /// The period from the tip's zero crossings (s); None if the tip
    /// crossed zero fewer than three times or went non-finite.
    pub period: Option<f64>,
    /// Largest |tip x| over the last expected period, over the start offset.
    pub kept: f64,
    /// Largest |tip x| over the whole run, over the start offset.
    pub peak: f64,
    /// Chains the step restored to their rest pose (non-finite lanes).
    pub restored: u64,
    /// Median seconds per step of the whole set of chains.
    pub step_seconds: f64,
}

impl ChainRun {
    /// `|period / expected - 1|`; 1 where no period was measured (the tip
    /// did not swing through zero three times).
    pub fn period_error(&self) -> f64 {
        self.period
            .map_or(1.0, |p| (p / self.expected_period - 1.0).abs())
    }

    /// `max(1 - kept, peak - 1, 0)`: the amplitude lost by the end, or the
    /// growth above the start at any time, whichever is larger.
    pub fn amplitude_error(&self) -> f64 {
        (1.0 - self.kept).max(self.peak - 1.0).max(0.0)
    }
}

/// Which step a run drives.
pub type StepFn = fn(&mut Strands, &SimParams, &[kernels::Sphere]);

/// The SIMD step ([`kernels::step`]).
pub const SIMD: StepFn = kernels::step;
/// The scalar reference step ([`scalar::step`]).
pub const SCALAR: StepFn = scalar::step;

/// Runs `chains` identical chains (32 vertices, [`LINKS`] links of
/// [`LINK`]) started at rest in mode `mode` with the tip [`TIP_SHARE`] of
/// the length off vertical, for `seconds` at `params` (no collisions),
/// through `stepper`; reads strand 0's tip after every step and times
/// every step.
pub fn run(
    params: &SimParams,
    mode: usize,
    seconds: f64,
    chains: usize,
    stepper: StepFn,
) -> ChainRun {
    let a0 = TIP_SHARE * LINKS as f64 * LINK;
    let one = chain_in_mode(mode, a0);
    let points: Vec<Vec3> = (0..chains.max(1))
        .flat_map(|_| one.iter().copied())
        .collect();
    let mut s = Strands::from_polylines(&points, LINKS + 1).expect("the chain is valid");
    let dt = params.dt as f64;
    let steps = (seconds / dt).round() as usize;
    let mut tips = Vec::with_capacity(steps + 1);
    tips.push(one[LINKS].x as f64);
    let mut times = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t0 = Instant::now();
        stepper(&mut s, params, &[]);
        times.push(t0.elapsed().as_secs_f64());
        tips.push(s.vertex(0, LINKS).map_or(f64::NAN, |p| p.x as f64));
    }
    times.sort_by(f64::total_cmp);
    let expected_period = period(mode);
    let last = ((expected_period / dt).ceil() as usize).clamp(1, tips.len());
    // A NaN sample counts as infinitely far (f64::max would skip it).
    let peak = |t: &[f64]| {
        t.iter().fold(0.0f64, |m, x| {
            if x.is_finite() {
                m.max(x.abs())
            } else {
                f64::INFINITY
            }
        }) / a0
    };
    ChainRun {
        mode,
        expected_period,
        period: period_from_crossings(&tips, dt),
        kept: peak(&tips[tips.len() - last..]),
        peak: peak(&tips),
        restored: s.restored_strands(),
        step_seconds: times.get(times.len() / 2).copied().unwrap_or(f64::NAN),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periods_match_the_continuous_chain() {
        // omega_k -> (j_0k / 2) sqrt(g / L) as the links shrink; 31 links
        // are within a few per cent of it (the kernels' analytic test finds
        // the same with Jacobi rotations).
        let big_l = LINKS as f64 * LINK;
        for (mode, j0) in [(1, 2.4048), (2, 5.5201)] {
            let continuous = std::f64::consts::TAU / (j0 / 2.0 * (G / big_l).sqrt());
            let t = period(mode);
            assert!(
                (t / continuous - 1.0).abs() < 0.03,
                "mode {mode}: {t} s vs continuous {continuous} s"
            );
        }
        // The discrete chain's mode 1 period to four digits (as the
        // kernels' analytic test states it).
        assert!((period(1) - 0.9363).abs() < 5e-4, "{}", period(1));
    }

    #[test]
    fn eigenpairs_solve_k() {
        let (diag, off) = tension_matrix(LINKS);
        let n = diag.len();
        let mut last = 0.0;
        for k in 0..4 {
            let lambda = eigenvalue(&diag, &off, k);
            assert!(lambda > last, "ascending, positive");
            last = lambda;
            let u = eigenvector(&diag, &off, lambda);
            let mut residual = 0.0f64;
            for i in 0..n {
                let mut ku = diag[i] * u[i];
                if i > 0 {
                    ku += off[i - 1] * u[i - 1];
                }
                if i + 1 < n {
                    ku += off[i] * u[i + 1];
                }
                residual = residual.max((ku - lambda * u[i]).abs());
            }
            assert!(residual < 1e-9 * lambda.max(1.0), "mode {k}: {residual}");
            // Mode k + 1 changes sign k times along the chain.
            let changes = u
                .windows(2)
                .filter(|w| w[0].signum() != w[1].signum())
                .count();
            assert_eq!(changes, k, "mode {}", k + 1);
        }
    }

    #[test]
    fn chain_in_mode_has_exact_links_and_the_tip_offset() {
        let p = chain_in_mode(2, 0.0062);
        assert_eq!(p.len(), LINKS + 1);
        for w in p.windows(2) {
            assert!(((w[1] - w[0]).length() as f64 - LINK).abs() < 1e-6);
        }
        assert!((p[LINKS].x as f64 - 0.0062).abs() < 1e-6);
    }

    #[test]
    fn period_from_crossings_of_a_sine() {
        let dt = 0.01;
        let x: Vec<f64> = (0..1000).map(|i| (i as f64 * dt * 2.0).cos()).collect();
        let t = period_from_crossings(&x, dt).unwrap();
        assert!((t / std::f64::consts::PI - 1.0).abs() < 1e-4, "{t}");
        assert_eq!(period_from_crossings(&[1.0, 2.0, 1.0], dt), None);
        assert_eq!(
            period_from_crossings(&[1.0, f64::NAN, -1.0, 1.0, -1.0], dt),
            None
        );
    }
}
