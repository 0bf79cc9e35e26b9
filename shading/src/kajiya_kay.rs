//! Kajiya-Kay (1989) hair shading with Scheuermann's (2004) two shifted
//! highlights, per sample (scalar) and in `wide` SIMD batches.
//!
//! With unit tangent t, light direction wi and view direction wo (both
//! pointing away from the fibre), c_i = t . wi, c_o = t . wo, s = sqrt(1 - c^2):
//!
//! - diffuse  K_d s_i  (the Lambertian term integrated around the cylinder,
//!   Kajiya & Kay 1989, eq. 8 up to a constant);
//! - specular K_s (s_i s_o - c_i c_o)^p, the cosine of the angle between wo and
//!   the cone of mirror directions, largest where t . wo = -t . wi (eq. 9).
//!
//! Scheuermann ("Practical real-time hair rendering and shading", SIGGRAPH
//! 2004 sketch) evaluates two specular terms, each with its own colour and
//! exponent, on tangents shifted along the normal, t' = normalize(t + shift n),
//! which moves the primary highlight toward the tip and the secondary
//! (coloured, TRT-like) one toward the root. coif's samples carry no normal:
//! n is the view direction projected into the normal plane,
//! n = normalize(wo - c_o t), the normal of a camera-facing hair ribbon as
//! Scheuermann's strips are. With the tilt tau = atan(shift),
//! t' = t cos tau + n sin tau, so t' . wo = c_o cos tau + s_o sin tau, its sine
//! is |s_o cos tau - c_o sin tau| (wo lies in the plane of t and n), and
//! t' . wi = c_i cos tau + sin tau (wi . wo - c_i c_o) / s_o.
//!
//! Inputs must be unit vectors (the hot path does not renormalise: a
//! non-unit input gives a finite, clamped but meaningless value); a
//! zero-length vector gives zero for that sample; a non-finite component (or
//! a squared length overflowing f32) gives NaN for that sample.
//! The result is diffuse + specular, without light colour or cosine factor.
//!
//! [`KajiyaKay::shade`] (one sample) and [`KajiyaKay::shade_simd`] (eight
//! lanes) run the same steps in the same order; [`KajiyaKay::shade_batch`]
//! (SIMD) and [`scalar::shade_batch`] shade a whole [`ShadingSamples`].
//! Steps: 1. degenerate inputs (zero length, non-finite); 2. the cosines and
//! sines c_i, c_o, s_i, s_o and wi . n; 3. per highlight, the tilted cone
//! term `x^p = 2^(p log2 x)` (short series below); 4. diffuse plus both
//! highlights.

pub mod scalar;

use crate::{RgbBuffer, ShadingSamples};
use coif_base::lanes::{F32Lanes, I32Lanes};
use coif_base::Vec3Lanes;
use glam::Vec3;
use wide::bytemuck::cast;

/// One specular highlight: colour K_s, exponent p and tangent shift.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Highlight {
    /// Specular colour `K_s` of the highlight.
    pub color: Vec3,
    /// Phong-like exponent p (clamped to >= 0 when used).
    pub exponent: f32,
    /// Shift of the tangent along the normal (0 = Kajiya-Kay's own lobe;
    /// Scheuermann uses small opposite shifts, e.g. +-0.1, for the two).
    pub shift: f32,
}

/// Kajiya-Kay diffuse plus two (possibly shifted) specular highlights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KajiyaKay {
    /// K_d per RGB channel.
    pub diffuse: Vec3,
    /// The primary (white, R-like) highlight, shifted toward the tip.
    pub primary: Highlight,
    /// The secondary (coloured, TRT-like) highlight, shifted toward the root.
    pub secondary: Highlight,
}

impl Default for KajiyaKay {
    /// Scheuermann-style brown hair: a white primary highlight shifted toward
    /// the tip and a broader coloured secondary one shifted toward the root.
    fn default() -> Self {
        KajiyaKay {
            diffuse: Vec3::new(0.30, 0.18, 0.10),
            primary: Highlight {
                color: Vec3::splat(0.4),
                exponent: 80.0,
                shift: 0.1,
            },
            secondary: Highlight {
                color: Vec3::new(0.35, 0.22, 0.12),
                exponent: 20.0,
                shift: -0.1,
            },
        }
    }
}

/// (cos tau, sin tau) of the tangent tilt tau = atan(shift): the shifted
/// tangent normalize(t + shift n) is t cos tau + n sin tau.
#[inline(always)]
fn tilt(shift: f32) -> (f32, f32) {
    let k = 1.0 / (1.0 + shift * shift).sqrt();
    (k, shift * k)
}

/// Smallest squared length treated as a direction.
const MIN_LENGTH_SQUARED: f32 = 1e-30;
/// Below this sin theta_o the normal (wo projected) is undefined: no shift.
const MIN_SIN_O: f32 = 1e-6;
/// Base floor of the power so that log2 stays finite: x^p = 2^(p log2 max(x, 1e-30)).
const MIN_BASE: f32 = 1e-30;
/// Highlights below 2^-90 (~8e-28) are flushed to zero: 2^y for very
/// negative y lands in the subnormal range, where every later multiply takes
/// a microcode assist.
const MIN_LOG2_LOBE: f32 = -90.0;

impl KajiyaKay {
    /// Plain Kajiya-Kay: one unshifted highlight.
    pub fn plain(diffuse: Vec3, specular: Vec3, exponent: f32) -> Self {
        KajiyaKay {
            diffuse,
            primary: Highlight {
                color: specular,
                exponent,
                shift: 0.0,
            },
            secondary: Highlight {
                color: Vec3::ZERO,
                exponent: 1.0,
                shift: 0.0,
            },
        }
    }

    /// One sample (the scalar reference).
    pub fn shade(&self, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let (lt2, li2, lo2) = (t.dot(t), wi.dot(wi), wo.dot(wo));
        if !(lt2 + li2 + lo2).is_finite() {
            return Vec3::NAN;
        }
        if lt2 < MIN_LENGTH_SQUARED || li2 < MIN_LENGTH_SQUARED || lo2 < MIN_LENGTH_SQUARED {
            return Vec3::ZERO;
        }
        let c_i = wi.dot(t).clamp(-1.0, 1.0);
        let c_o = wo.dot(t).clamp(-1.0, 1.0);
        let c_io = wi.dot(wo);
        let s_i = (1.0 - c_i * c_i).max(0.0).sqrt();
        let s_o = (1.0 - c_o * c_o).max(0.0).sqrt();
        // wi . n, with n the view direction projected into the normal plane.
        let wi_n = if s_o > MIN_SIN_O {
            (c_io - c_i * c_o) / s_o
        } else {
            0.0
        };
        let lobe = |h: &Highlight| {
            let (cos_tilt, sin_tilt) = tilt(h.shift);
            // wo lies in the plane of t and n, so its angle to the tilted
            // tangent is its angle to t minus the tilt: no square root.
            let co = c_o * cos_tilt + s_o * sin_tilt;
            let so = (s_o * cos_tilt - c_o * sin_tilt).abs();
            let ci = (c_i * cos_tilt + wi_n * sin_tilt).clamp(-1.0, 1.0);
            let si = (1.0 - ci * ci).max(0.0).sqrt();
            let base = (si * so - ci * co).max(MIN_BASE);
            let x = h.exponent.max(0.0) * log2(base);
            if x < MIN_LOG2_LOBE {
                0.0
            } else {
                exp2(x)
            }
        };
        self.diffuse * s_i
            + self.primary.color * lobe(&self.primary)
            + self.secondary.color * lobe(&self.secondary)
    }

    /// Eight samples; the same steps as [`KajiyaKay::shade`].
    #[inline(always)]
    pub fn shade_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes {
        // `fast_max` / `fast_min` (one instruction each; wide's `max` / `min`
        // add a NaN fix-up): equal to the scalar's `max` / `min` on finite
        // lanes, and a lane with a non-finite input is replaced by NaN at
        // the end whatever it computed.
        let one = F32Lanes::ONE;
        let zero = F32Lanes::ZERO;
        let (lt2, li2, lo2) = (t.dot(t), wi.dot(wi), wo.dot(wo));
        let non_finite = !(lt2 + li2 + lo2).is_finite();
        let tiny = F32Lanes::splat(MIN_LENGTH_SQUARED);
        let zero_len = lt2.simd_lt(tiny) | li2.simd_lt(tiny) | lo2.simd_lt(tiny);
        let clamp1 = |x: F32Lanes| x.fast_max(-one).fast_min(one);
        let c_i = clamp1(wi.dot(t));
        let c_o = clamp1(wo.dot(t));
        let c_io = wi.dot(wo);
        let s_i = (one - c_i * c_i).fast_max(zero).sqrt();
        let s_o = (one - c_o * c_o).fast_max(zero).sqrt();
        let wi_n = s_o
            .simd_gt(F32Lanes::splat(MIN_SIN_O))
            .select((c_io - c_i * c_o) / s_o, zero);
        let lobe = |h: &Highlight| {
            let (cos_tilt, sin_tilt) = tilt(h.shift);
            let (ct, st) = (F32Lanes::splat(cos_tilt), F32Lanes::splat(sin_tilt));
            let co = c_o * ct + s_o * st;
            let so = (s_o * ct - c_o * st).abs();
            let ci = clamp1(c_i * ct + wi_n * st);
            let si = (one - ci * ci).fast_max(zero).sqrt();
            let base = (si * so - ci * co).fast_max(F32Lanes::splat(MIN_BASE));
            let x = F32Lanes::splat(h.exponent.max(0.0)) * log2_simd(base);
            let tiny = x.simd_lt(F32Lanes::splat(MIN_LOG2_LOBE));
            tiny.select(zero, exp2_simd(x.fast_max(F32Lanes::splat(MIN_LOG2_LOBE))))
        };
        let (l1, l2) = (lobe(&self.primary), lobe(&self.secondary));
        let (d, a, b) = (self.diffuse, self.primary.color, self.secondary.color);
        let channel = |d: f32, a: f32, b: f32| {
            F32Lanes::splat(d) * s_i + F32Lanes::splat(a) * l1 + F32Lanes::splat(b) * l2
        };
        let out = Vec3Lanes::new(
            channel(d.x, a.x, b.x),
            channel(d.y, a.y, b.y),
            channel(d.z, a.z, b.z),
        );
        let out = Vec3Lanes::select(zero_len, Vec3Lanes::ZERO, out);
        Vec3Lanes::select(non_finite, Vec3Lanes::splat(Vec3::NAN), out)
    }

    /// SIMD batch: every sample of `samples` into `out` (resized to
    /// `samples.len()`; no allocation once it has the capacity).
    pub fn shade_batch(&self, samples: &ShadingSamples, out: &mut RgbBuffer) {
        crate::batch::shade_blocks(
            samples,
            out,
            #[inline(always)]
            |t, wi, wo| self.shade_simd(t, wi, wo),
        );
    }
}

// The power x^p = 2^(p log2 x) is the hot spot of Kajiya-Kay (two per
// sample). libm's and wide's general ln/exp handle every special case; here
// x is in [1e-30, 1] and p log2 x in [-90, 0], so two short series do:
//
// log2 x = e + (2 / ln 2) atanh(z), z = (m - 1) / (m + 1), with x = m 2^e and
//   m in [sqrt(1/2), sqrt(2)), so |z| <= 0.1716; atanh z = z + z^3/3 + ... + z^9/9
//   (truncation error below 4e-10).
// 2^y = 2^n 2^f, n = round(y), f in [-1/2, 1/2]; 2^f = e^(f ln 2) by its
//   Taylor series to degree 6 (truncation error below 1.3e-7 relative).
//
// The scalar and SIMD twins below run the same operations in the same order.

const TWO_OVER_LN2: f32 = 2.0 * std::f32::consts::LOG2_E;
const ATANH: [f32; 4] = [1.0 / 3.0, 1.0 / 5.0, 1.0 / 7.0, 1.0 / 9.0];
const LN2: f32 = std::f32::consts::LN_2;
const EXP: [f32; 6] = [
    1.0,
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
];

/// log2 of a positive normal float (scalar twin of `log2_simd`).
#[inline(always)]
fn log2(x: f32) -> f32 {
    let bits = x.to_bits() as i32;
    // Split x = m 2^e with m in [sqrt(1/2), sqrt(2)): offset the exponent by
    // the bits of sqrt(1/2) so the split falls at sqrt(2).
    let offset = bits - 0x3f35_04f3;
    let e = offset >> 23;
    let m = f32::from_bits((bits - (e << 23)) as u32);
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    let poly = ((ATANH[3] * z2 + ATANH[2]) * z2 + ATANH[1]) * z2 + ATANH[0];
    let atanh = (poly * z2) * z + z;
    e as f32 + TWO_OVER_LN2 * atanh
}

/// 2^y for y in [-126, 0] (scalar twin of `exp2_simd`).
#[inline(always)]
fn exp2(y: f32) -> f32 {
    let n = y.round();
    let f = (y - n) * LN2;
    let p = ((((EXP[5] * f + EXP[4]) * f + EXP[3]) * f + EXP[2]) * f + EXP[1]) * f + EXP[0];
    let e = f * p + 1.0;
    e * f32::from_bits((((n as i32) + 127) << 23) as u32)
}

#[inline(always)]
fn log2_simd(x: F32Lanes) -> F32Lanes {
    let bits: I32Lanes = cast(x);
    let offset = bits - I32Lanes::splat(0x3f35_04f3);
    let e: I32Lanes = offset >> 23;
    let m: F32Lanes = cast(bits - (e << 23));
    let one = F32Lanes::ONE;
    let z = (m - one) / (m + one);
    let z2 = z * z;
    let c = |k: usize| F32Lanes::splat(ATANH[k]);
    let poly = ((c(3) * z2 + c(2)) * z2 + c(1)) * z2 + c(0);
    let atanh = (poly * z2) * z + z;
    e.round_float() + F32Lanes::splat(TWO_OVER_LN2) * atanh
}

#[inline(always)]
fn exp2_simd(y: F32Lanes) -> F32Lanes {
    let n = y.round();
    let f = (y - n) * F32Lanes::splat(LN2);
    let c = |k: usize| F32Lanes::splat(EXP[k]);
    let p = ((((c(5) * f + c(4)) * f + c(3)) * f + c(2)) * f + c(1)) * f + c(0);
    let e = f * p + F32Lanes::ONE;
    let scale: F32Lanes = cast((n.round_int() + I32Lanes::splat(127)) << 23);
    e * scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_series_match_libm() {
        let mut x = 1e-30f32;
        while x <= 1.0 {
            let l = log2(x);
            assert!((l - x.log2()).abs() < 2e-6 * x.log2().abs().max(1.0), "{x}");
            let l8 = log2_simd(F32Lanes::splat(x)).to_array()[3];
            assert_eq!(l, l8, "{x}");
            x *= 1.37;
        }
        let mut y = -90.0f32;
        while y <= 0.0 {
            let e = exp2(y);
            assert!((e / y.exp2() - 1.0).abs() < 1e-6, "{y}");
            assert_eq!(e, exp2_simd(F32Lanes::splat(y)).to_array()[5], "{y}");
            y += 0.173;
        }
    }
}
