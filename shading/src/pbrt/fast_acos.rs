//! A polynomial arccosine shared by the scalar and SIMD table lookups, so
//! both compute the same table coordinates with the same operations.
//!
//! Abramowitz & Stegun 4.4.46: for 0 <= x <= 1,
//! `acos x = sqrt(1 - x) (a0 + a1 x + ... + a7 x^7)` with absolute error at
//! most 2e-8 (in exact arithmetic; in `f32` the error is a few 1e-7 rad),
//! and `acos(-x) = pi - acos x`.

use coif_base::lanes::F32Lanes;
use std::f32::consts::PI;

/// The published coefficients (a0 is A&S's value, not exactly pi/2).
#[allow(clippy::approx_constant)]
const A: [f32; 8] = [
    1.570_796_3,
    -0.214_598_8,
    0.088_978_99,
    -0.050_174_303,
    0.030_891_88,
    -0.017_088_126,
    0.006_670_09,
    -0.001_262_491_1,
];

/// Arccosine of `x` clamped to [-1, 1]; NaN stays NaN.
#[inline]
pub fn acos(x: f32) -> f32 {
    // Clamped so that NaN stays NaN (`f32::min` would replace it).
    let ax = if x.abs() > 1.0 { 1.0 } else { x.abs() };
    let mut p = A[7];
    for &c in A[..7].iter().rev() {
        p = p.mul_add(ax, c);
    }
    let r = (1.0 - ax).sqrt() * p;
    if x < 0.0 {
        PI - r
    } else {
        r
    }
}

/// Eight arccosines, the same operations lane by lane as [`acos`].
#[inline]
pub fn acos_simd(x: F32Lanes) -> F32Lanes {
    // minps(1, |x|): 1 above 1, and NaN stays NaN (as the scalar's test).
    let ax = F32Lanes::ONE.fast_min(x.abs());
    let mut p = F32Lanes::splat(A[7]);
    for &c in A[..7].iter().rev() {
        p = p.mul_add(ax, F32Lanes::splat(c));
    }
    let r = (F32Lanes::ONE - ax).sqrt() * p;
    // One blend (the mask is all ones or all zeros per lane).
    x.simd_lt(F32Lanes::ZERO).select(F32Lanes::splat(PI) - r, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_to_std_acos_and_simd_matches_scalar() {
        let mut worst = 0.0f32;
        for k in 0..=4000 {
            let x = -1.0 + k as f32 / 2000.0;
            worst = worst.max((acos(x) - x.acos()).abs());
            let v = acos_simd(F32Lanes::splat(x)).to_array();
            assert_eq!(v[3].to_bits(), acos(x).to_bits(), "x = {x}");
        }
        assert!(worst < 1e-6, "{worst}");
        assert!(acos(f32::NAN).is_nan());
        assert!(acos_simd(F32Lanes::splat(f32::NAN)).to_array()[0].is_nan());
    }
}
