//! The azimuthal scattering function N_p of Chiang et al. 2016 ("A practical
//! and controllable hair and fur model for production path tracing", CGF
//! 35(2)), as pbrt-v3 writes it (`Phi`, `Logistic`, `TrimmedLogistic`, `Np`).

use std::f32::consts::PI;

/// Exit azimuth of the path with `p` internal segments (Chiang 2016 eq. 9):
/// `Phi(p, gamma_o, gamma_t) = 2 p gamma_t - 2 gamma_o + p pi`.
#[inline]
pub fn phi(p: i32, gamma_o: f32, gamma_t: f32) -> f32 {
    (2 * p) as f32 * gamma_t - 2.0 * gamma_o + p as f32 * PI
}

/// The logistic distribution of scale `s`, `e^(-|x|/s) / (s (1 + e^(-|x|/s))^2)`.
#[inline]
pub fn logistic(x: f32, s: f32) -> f32 {
    let x = x.abs();
    let e = (-x / s).exp();
    e / (s * ((1.0 + e) * (1.0 + e)))
}

/// Its cumulative distribution `1 / (1 + e^(-x/s))`.
#[inline]
pub fn logistic_cdf(x: f32, s: f32) -> f32 {
    1.0 / (1.0 + (-x / s).exp())
}

/// The logistic renormalised to `[a, b]`.
#[inline]
pub fn trimmed_logistic(x: f32, s: f32, a: f32, b: f32) -> f32 {
    logistic(x, s) / (logistic_cdf(b, s) - logistic_cdf(a, s))
}

/// `N_p(phi) = trimmed_logistic(phi - Phi(p), s, -pi, pi)` with the
/// difference wrapped into `[-pi, pi]` by whole turns, as pbrt-v3 does
/// (two bounded loops: `phi` is a difference of two `atan2` values and
/// `Phi` is bounded, so at most a few turns are removed; NaN passes through).
#[inline]
pub fn np(phi_rel: f32, p: i32, s: f32, gamma_o: f32, gamma_t: f32) -> f32 {
    let dphi = wrap(phi_rel - phi(p, gamma_o, gamma_t));
    trimmed_logistic(dphi, s, -PI, PI)
}

/// Wraps into `[-pi, pi]` by subtracting or adding `2 pi` (pbrt-v3's loops).
/// Bounded to 16 turns each way so that a huge input can never hang.
#[inline]
pub fn wrap(mut dphi: f32) -> f32 {
    let mut turns = 0;
    while dphi > PI && turns < 16 {
        dphi -= 2.0 * PI;
        turns += 1;
    }
    while dphi < -PI && turns < 32 {
        dphi += 2.0 * PI;
        turns += 1;
    }
    dphi
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trimmed_logistic_integrates_to_one_over_the_circle() {
        for s in [0.05f32, 0.2, 0.6, 1.5] {
            let n = 20_000;
            let dx = 2.0 * PI as f64 / n as f64;
            let sum: f64 = (0..n)
                .map(|k| -PI as f64 + (k as f64 + 0.5) * dx)
                .map(|x| trimmed_logistic(x as f32, s, -PI, PI) as f64 * dx)
                .sum();
            assert!((sum - 1.0).abs() < 1e-3, "s = {s}: {sum}");
        }
    }

    #[test]
    fn wrap_brings_differences_into_range() {
        assert!((wrap(3.0 * PI + 0.25) - (PI + 0.25 - 2.0 * PI)).abs() < 1e-5);
        assert!((wrap(-2.5 * PI) - (-0.5 * PI)).abs() < 1e-5);
        assert_eq!(wrap(0.5), 0.5);
        assert!(wrap(f32::NAN).is_nan());
        assert!(wrap(f32::INFINITY).is_infinite(), "huge input terminates");
    }
}
