//! pbrt-v3's approximations of the modified Bessel function of the first
//! kind, order zero (pbrt-v3 `src/materials/hair.cpp`, `I0` and `LogI0`).
//!
//! These are approximations whose error matters at the 1e-2 level for some
//! configurations, so they are reproduced exactly,
//! operation by operation, in `f32` as pbrt's `Float` build computes them.

/// I0(x) by the first ten terms of its series,
/// `I0(x) = sum_{i=0}^{9} x^(2i) / (4^i (i!)^2)`.
///
/// Like pbrt-v3 the denominator `4^i (i!)^2` is formed exactly in 64-bit
/// integers and then converted to `f32`.
#[inline]
pub fn i0(x: f32) -> f32 {
    let mut val = 0.0f32;
    let mut x2i = 1.0f32;
    let mut ifact: i64 = 1;
    let mut i4: i64 = 1;
    for i in 0..10i64 {
        if i > 1 {
            ifact *= i;
        }
        val += x2i / ((i4 * (ifact * ifact)) as f32);
        x2i *= x * x;
        i4 *= 4;
    }
    val
}

/// ln I0(x): for x > 12 the asymptotic form
/// `x + 0.5 (-ln(2 pi) + ln(1/x) + 1/(8x))`, else `ln(i0(x))`.
///
/// pbrt-v3 writes the factor 0.5 as a `double` literal, so the final
/// `x + 0.5 * (...)` is evaluated in `f64` and rounded back to `f32`.
#[inline]
pub fn log_i0(x: f32) -> f32 {
    if x > 12.0 {
        let inner = -(2.0 * std::f32::consts::PI).ln() + (1.0 / x).ln() + 1.0 / (8.0 * x);
        (x as f64 + 0.5 * inner as f64) as f32
    } else {
        i0(x).ln()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// I0 by its series summed to convergence in f64.
    fn i0_reference(x: f64) -> f64 {
        let mut term = 1.0;
        let mut sum = 1.0;
        for k in 1..1000 {
            term *= (x * x / 4.0) / (k as f64 * k as f64);
            sum += term;
        }
        sum
    }

    #[test]
    fn ten_term_series_is_accurate_for_moderate_arguments() {
        // I0(1) = 1.2660658777520082 (Abramowitz & Stegun table 9.8).
        assert!((i0(1.0) - 1.266_066).abs() < 1e-6);
        for x in [0.0f32, 0.5, 2.0, 5.0] {
            let r = i0_reference(x as f64) as f32;
            assert!((i0(x) - r).abs() <= 1e-5 * r, "x = {x}");
        }
    }

    #[test]
    fn ten_terms_truncate_for_large_arguments() {
        // At x = 12 the truncated series is measurably below I0: the point
        // of reproducing pbrt's approximation rather than the true function.
        let r = i0_reference(12.0);
        assert!((i0(12.0) as f64) < 0.99 * r);
    }

    #[test]
    fn log_form_matches_asymptotic_expansion_above_12() {
        for x in [13.0f32, 50.0, 100.0] {
            let exact = i0_reference(x as f64).ln();
            assert!(((log_i0(x) as f64) - exact).abs() < 1e-3 * exact, "x = {x}");
        }
    }
}
