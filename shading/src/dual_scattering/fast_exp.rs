//! `e^x` for `x <= 0`, the same operations in the scalar and SIMD twins
//! (so dual scattering's two paths agree to the bit), about 20 operations
//! per eight lanes where `wide`'s `exp` also handles overflow and
//! subnormals.
//!
//! `e^x = 2^y`, `y = x log2 e` clamped to [-126, 0] (results below 2^-126,
//! 1.2e-38, are that), `y = n + f` with `n = floor(y + 1/2)`, `f` in [-1/2, 1/2),
//! `2^f = e^(f ln 2)` by its Taylor series to degree 5 (truncation error
//! below 4e-6 relative (tested), far below what dual scattering approximates),
//! times `2^n` built in the exponent bits.

use wide::bytemuck::cast;
use wide::{f32x8, i32x8};

const LN2: f32 = std::f32::consts::LN_2;
const LOG2_E: f32 = std::f32::consts::LOG2_E;
const C: [f32; 5] = [1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0];

/// `e^x` for `x <= 0` (positive `x` gives 1; NaN gives a finite value:
/// callers mask it).
#[inline(always)]
// max then min, not clamp: the SIMD twin's order (and clamp panics on NaN
// bounds, keeps a NaN input where max/min replace it).
#[allow(clippy::manual_clamp)]
pub(crate) fn exp_neg(x: f32) -> f32 {
    let y = (x * LOG2_E).max(-126.0).min(0.0);
    let n = (y + 0.5).floor();
    let f = (y - n) * LN2;
    let p = (((C[4] * f + C[3]) * f + C[2]) * f + C[1]) * f + C[0];
    let e = f * p + 1.0;
    e * f32::from_bits((((n as i32) + 127) << 23) as u32)
}

/// [`exp_neg`] in eight lanes.
#[inline(always)]
pub(crate) fn exp_neg_x8(x: f32x8) -> f32x8 {
    // fast_max / fast_min with a constant second operand: the same result
    // as max / min (and the scalar's), NaN included, in one instruction.
    let y = (x * f32x8::splat(LOG2_E))
        .fast_max(f32x8::splat(-126.0))
        .fast_min(f32x8::ZERO);
    let n = (y + f32x8::splat(0.5)).floor();
    let f = (y - n) * f32x8::splat(LN2);
    let c = |k: usize| f32x8::splat(C[k]);
    let p = (((c(4) * f + c(3)) * f + c(2)) * f + c(1)) * f + c(0);
    let e = f * p + f32x8::ONE;
    let scale: f32x8 = cast((n.trunc_int() + i32x8::splat(127)) << 23);
    e * scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_to_libm_and_simd_is_the_scalar_to_the_bit() {
        let mut worst = 0.0f64;
        let mut x = 0.0f32;
        while x > -87.0 {
            let xs = [
                x,
                x - 0.013,
                x - 0.031,
                x - 0.05,
                x - 0.07,
                x - 0.09,
                x - 0.11,
                x - 0.13,
            ];
            let v = exp_neg_x8(f32x8::new(xs)).to_array();
            for (l, &xl) in xs.iter().enumerate() {
                let s = exp_neg(xl);
                assert_eq!(v[l].to_bits(), s.to_bits(), "x = {xl}");
                let exact = (xl as f64).exp();
                worst = worst.max(((s as f64) - exact).abs() / exact);
            }
            x -= 0.37;
        }
        assert!(worst < 5e-6, "relative error {worst}");
        assert_eq!(exp_neg(0.0), 1.0);
        assert_eq!(exp_neg(3.0), 1.0);
        assert!(exp_neg(-1000.0) < 1.2e-38);
    }
}
