//! `2^-q` for `q >= 0`, the same operations in the scalar and SIMD twins
//! (so dual scattering's two paths agree to the bit), ten operations per
//! eight lanes where `wide`'s `exp` also handles overflow and subnormals.
//! Callers fold `log2 e` into their arguments (the tables store `-log2 a_f`,
//! the Gaussians' widths are scaled by it).
//!
//! `q` is clamped to at most 125 (results below 2^-125, 2.4e-38, are
//! about that), `m = round(q)` (to nearest, ties to even), `f = m - q` in
//! [-1/2, 1/2], `2^f` by a degree-4 polynomial with constant term 1 fitted
//! for the smallest maximum relative error on [-1/2, 1/2] (2.9e-6 in `f32`
//! (tested), far below what dual scattering approximates; `2^0` is exactly
//! 1), and `2^-m` applied by subtracting `m` from the exponent bits (the
//! polynomial is at least 2^-1/2, so the result stays a normal number).
//!
//! NaN in gives NaN out (the clamp keeps it: `min(125, NaN)` as `minps`
//! takes it is NaN, and NaN's exponent bits minus 0 are NaN's).

use coif_base::lanes::{F32Lanes, I32Lanes};
use wide::bytemuck::cast;

/// Largest `q`.
const MAX_Q: f32 = 125.0;
/// `2^f ~ 1 + f (C[0] + f (C[1] + f (C[2] + f C[3])))` on [-1/2, 1/2].
const C: [f32; 4] = [0.693_124_2, 0.240_241, 0.055_906_43, 0.009_582_855];

/// `2^-q` for `q >= 0` (see the module docs; a negative `q` down to -125
/// also gives `2^-q`).
#[inline(always)]
pub(crate) fn exp2_neg(q: f32) -> f32 {
    // minps(MAX_Q, q): NaN stays NaN (`f32::min` would replace it).
    let q = if MAX_Q < q { MAX_Q } else { q };
    let m = q.round_ties_even();
    let f = m - q;
    let p = C[3].mul_add(f, C[2]);
    let p = p.mul_add(f, C[1]);
    let p = p.mul_add(f, C[0]);
    let p = p.mul_add(f, 1.0);
    // `m as i32` is 0 for NaN, as cvttps2dq's 0x80000000 shifted by 23.
    f32::from_bits(p.to_bits().wrapping_sub(((m as i32) << 23) as u32))
}

/// [`exp2_neg`] in eight lanes.
#[inline(always)]
pub(crate) fn exp2_neg_simd(q: F32Lanes) -> F32Lanes {
    let q = F32Lanes::splat(MAX_Q).fast_min(q);
    let m = q.round_ties_even();
    let f = m - q;
    let p = F32Lanes::splat(C[3]).mul_add(f, F32Lanes::splat(C[2]));
    let p = p.mul_add(f, F32Lanes::splat(C[1]));
    let p = p.mul_add(f, F32Lanes::splat(C[0]));
    let p = p.mul_add(f, F32Lanes::ONE);
    let bits: I32Lanes = cast(p);
    cast(bits - (m.fast_trunc_int() << 23))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_to_libm_and_simd_is_the_scalar_to_the_bit() {
        let mut worst = 0.0f64;
        let mut q = 0.0f32;
        while q < 130.0 {
            let offsets = [0.0, 0.013, 0.031, 0.05, 0.07, 0.09, 0.11, 0.5];
            let qs: [f32; coif_base::LANES] = std::array::from_fn(|l| q + offsets[l % 8]);
            let v = exp2_neg_simd(F32Lanes::new(qs)).to_array();
            for (l, &ql) in qs.iter().enumerate() {
                let s = exp2_neg(ql);
                assert_eq!(v[l].to_bits(), s.to_bits(), "q = {ql}");
                let exact = (-(ql.min(MAX_Q) as f64)).exp2();
                worst = worst.max(((s as f64) - exact).abs() / exact);
            }
            q += 0.0037;
        }
        assert!(worst < 3e-6, "relative error {worst}");
        assert_eq!(exp2_neg(0.0), 1.0);
        assert_eq!(exp2_neg(-0.0), 1.0);
        assert_eq!(exp2_neg(1.0), 0.5);
        assert!(exp2_neg(f32::INFINITY) < 3e-38);
        assert!(exp2_neg(f32::NAN).is_nan());
        assert!(exp2_neg_simd(F32Lanes::splat(f32::NAN)).to_array()[0].is_nan());
        // 1 - 2^-q never goes negative.
        assert!(exp2_neg(1e-7) <= 1.0);
    }
}
