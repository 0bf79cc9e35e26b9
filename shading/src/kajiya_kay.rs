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
//! Scheuermann's strips are. Then t' . wo = (c_o + shift s_o) / sqrt(1 + shift^2)
//! and t' . wi = (c_i + shift (wi . wo - c_i c_o) / s_o) / sqrt(1 + shift^2).
//!
//! Inputs need not be unit length (the cosines are divided by the lengths);
//! a zero-length vector gives zero for that sample; a non-finite component
//! (or a squared length overflowing f32) gives NaN for that sample.
//! The result is diffuse + specular, without light colour or cosine factor.

use crate::{RgbBuffer, ShadingSamples};
use coif_kernels::{Vec3x8, LANES};
use glam::Vec3;
use wide::f32x8;

/// One specular highlight: colour K_s, exponent p and tangent shift.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Highlight {
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
    pub primary: Highlight,
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

/// Smallest squared length treated as a direction.
const MIN_LENGTH_SQUARED: f32 = 1e-30;
/// Below this sin theta_o the normal (wo projected) is undefined: no shift.
const MIN_SIN_O: f32 = 1e-6;
/// Base floor of the power so that ln stays finite: x^p = exp(p ln max(x, 1e-30)).
const MIN_BASE: f32 = 1e-30;
/// Highlights below e^-60 (~1e-26) are flushed to zero: exp of a very negative
/// argument lands in the subnormal range, where every later multiply takes a
/// microcode assist (measured: 20x slower batches with random directions).
const MIN_LOG_LOBE: f32 = -60.0;

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
        let rt = lt2.sqrt();
        let (ri, ro) = (li2.sqrt(), lo2.sqrt());
        let c_i = (wi.dot(t) / (ri * rt)).clamp(-1.0, 1.0);
        let c_o = (wo.dot(t) / (ro * rt)).clamp(-1.0, 1.0);
        let c_io = (wi.dot(wo) / (ri * ro)).clamp(-1.0, 1.0);
        let s_i = (1.0 - c_i * c_i).max(0.0).sqrt();
        let s_o = (1.0 - c_o * c_o).max(0.0).sqrt();
        // wi . n, with n the view direction projected into the normal plane.
        let wi_n = if s_o > MIN_SIN_O {
            (c_io - c_i * c_o) / s_o
        } else {
            0.0
        };
        let lobe = |h: &Highlight| {
            let k = 1.0 / (1.0 + h.shift * h.shift).sqrt();
            let ci = ((c_i + h.shift * wi_n) * k).clamp(-1.0, 1.0);
            let co = ((c_o + h.shift * s_o) * k).clamp(-1.0, 1.0);
            let si = (1.0 - ci * ci).max(0.0).sqrt();
            let so = (1.0 - co * co).max(0.0).sqrt();
            let base = (si * so - ci * co).max(MIN_BASE);
            let x = h.exponent.max(0.0) * base.ln();
            if x < MIN_LOG_LOBE {
                0.0
            } else {
                x.exp()
            }
        };
        self.diffuse * s_i
            + self.primary.color * lobe(&self.primary)
            + self.secondary.color * lobe(&self.secondary)
    }

    /// Eight samples; the same steps as [`KajiyaKay::shade`].
    #[inline(always)]
    pub fn shade8(&self, t: Vec3x8, wi: Vec3x8, wo: Vec3x8) -> Vec3x8 {
        let one = f32x8::ONE;
        let zero = f32x8::ZERO;
        let (lt2, li2, lo2) = (t.dot(t), wi.dot(wi), wo.dot(wo));
        let non_finite = !(lt2 + li2 + lo2).is_finite();
        let tiny = f32x8::splat(MIN_LENGTH_SQUARED);
        let zero_len = lt2.simd_lt(tiny) | li2.simd_lt(tiny) | lo2.simd_lt(tiny);
        let rt = lt2.sqrt();
        let (ri, ro) = (li2.sqrt(), lo2.sqrt());
        let clamp1 = |x: f32x8| x.max(-one).min(one);
        let c_i = clamp1(wi.dot(t) / (ri * rt));
        let c_o = clamp1(wo.dot(t) / (ro * rt));
        let c_io = clamp1(wi.dot(wo) / (ri * ro));
        let s_i = (one - c_i * c_i).max(zero).sqrt();
        let s_o = (one - c_o * c_o).max(zero).sqrt();
        let wi_n = s_o
            .simd_gt(f32x8::splat(MIN_SIN_O))
            .select((c_io - c_i * c_o) / s_o, zero);
        let lobe = |h: &Highlight| {
            let k = f32x8::splat(1.0 / (1.0 + h.shift * h.shift).sqrt());
            let shift = f32x8::splat(h.shift);
            let ci = clamp1((c_i + shift * wi_n) * k);
            let co = clamp1((c_o + shift * s_o) * k);
            let si = (one - ci * ci).max(zero).sqrt();
            let so = (one - co * co).max(zero).sqrt();
            let base = (si * so - ci * co).max(f32x8::splat(MIN_BASE));
            let x = f32x8::splat(h.exponent.max(0.0)) * base.ln();
            let tiny = x.simd_lt(f32x8::splat(MIN_LOG_LOBE));
            tiny.select(zero, x.max(f32x8::splat(MIN_LOG_LOBE)).exp())
        };
        let (l1, l2) = (lobe(&self.primary), lobe(&self.secondary));
        let (d, a, b) = (self.diffuse, self.primary.color, self.secondary.color);
        let channel = |d: f32, a: f32, b: f32| {
            f32x8::splat(d) * s_i + f32x8::splat(a) * l1 + f32x8::splat(b) * l2
        };
        let out = Vec3x8::new(
            channel(d.x, a.x, b.x),
            channel(d.y, a.y, b.y),
            channel(d.z, a.z, b.z),
        );
        let out = Vec3x8::select(zero_len, Vec3x8::ZERO, out);
        Vec3x8::select(non_finite, Vec3x8::splat(Vec3::NAN), out)
    }

    /// SIMD batch: every sample of `samples` into `out` (resized to
    /// `samples.len()`; no allocation once it has the capacity).
    pub fn shade_batch(&self, samples: &ShadingSamples, out: &mut RgbBuffer) {
        let n = samples.len();
        out.resize(n);
        let mut start = 0;
        while start < n {
            let (t, wi, wo) = samples.load_block(start);
            out.store_block(start, self.shade8(t, wi, wo));
            start += LANES;
        }
    }

    /// Scalar batch: [`KajiyaKay::shade`] per sample (the SIMD path's reference).
    pub fn shade_batch_scalar(&self, samples: &ShadingSamples, out: &mut RgbBuffer) {
        out.resize(samples.len());
        for i in 0..samples.len() {
            let (t, wi, wo) = samples.get(i);
            out.set(i, self.shade(t, wi, wo));
        }
    }
}
