//! Lane math: three `f32x8` registers holding one 3-vector per strand lane.
//!
//! Strands live in SIMD lanes: lane `l` of block `b` is
//! strand `b * LANES + l`, so every operation here works on eight strands at
//! once with no gathers or shuffles.

use glam::Vec3;
use wide::f32x8;

/// Strands (or samples) per SIMD block: the width of [`f32x8`].
pub const LANES: usize = 8;

/// Eight 3-vectors in structure-of-arrays form, one per lane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec3x8 {
    /// The x coordinates, one per lane.
    pub x: f32x8,
    /// The y coordinates, one per lane.
    pub y: f32x8,
    /// The z coordinates, one per lane.
    pub z: f32x8,
}

impl Vec3x8 {
    /// Zero in every lane.
    pub const ZERO: Vec3x8 = Vec3x8 {
        x: f32x8::ZERO,
        y: f32x8::ZERO,
        z: f32x8::ZERO,
    };

    #[inline(always)]
    /// From the three coordinate registers.
    pub fn new(x: f32x8, y: f32x8, z: f32x8) -> Self {
        Vec3x8 { x, y, z }
    }

    /// The same vector in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        Vec3x8 {
            x: f32x8::splat(v.x),
            y: f32x8::splat(v.y),
            z: f32x8::splat(v.z),
        }
    }

    /// Lane `l` as a `Vec3`.
    #[inline]
    pub fn lane(&self, l: usize) -> Vec3 {
        Vec3::new(
            self.x.as_array()[l],
            self.y.as_array()[l],
            self.z.as_array()[l],
        )
    }

    /// Sets lane `l`.
    #[inline]
    pub fn set_lane(&mut self, l: usize, v: Vec3) {
        self.x.as_mut_array()[l] = v.x;
        self.y.as_mut_array()[l] = v.y;
        self.z.as_mut_array()[l] = v.z;
    }

    /// `x*x + y*y + z*z`, evaluated left to right (the scalar twins use the
    /// same order, so results agree bit for bit).
    #[inline(always)]
    pub fn dot(self, o: Vec3x8) -> f32x8 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    /// `|v|^2` per lane.
    pub fn length_squared(self) -> f32x8 {
        self.dot(self)
    }

    #[inline(always)]
    /// The cross product per lane.
    pub fn cross(self, o: Vec3x8) -> Vec3x8 {
        Vec3x8 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    /// Lane-wise `if mask { a } else { b }` (mask from a comparison).
    #[inline(always)]
    pub fn select(mask: f32x8, a: Vec3x8, b: Vec3x8) -> Vec3x8 {
        Vec3x8 {
            x: mask.select(a.x, b.x),
            y: mask.select(a.y, b.y),
            z: mask.select(a.z, b.z),
        }
    }

    /// Unit vector, or `fallback` in lanes whose length is not above `1e-20`.
    #[inline(always)]
    pub fn normalize_or(self, fallback: Vec3x8) -> Vec3x8 {
        let len = self.length_squared().sqrt();
        let ok = len.simd_gt(f32x8::splat(1e-20));
        let inv = f32x8::ONE / len.max(f32x8::splat(1e-20));
        Vec3x8::select(ok, self * inv, fallback)
    }
}

impl std::ops::Add for Vec3x8 {
    type Output = Vec3x8;
    #[inline(always)]
    fn add(self, o: Vec3x8) -> Vec3x8 {
        Vec3x8 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl std::ops::Sub for Vec3x8 {
    type Output = Vec3x8;
    #[inline(always)]
    fn sub(self, o: Vec3x8) -> Vec3x8 {
        Vec3x8 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl std::ops::Mul<f32x8> for Vec3x8 {
    type Output = Vec3x8;
    #[inline(always)]
    fn mul(self, s: f32x8) -> Vec3x8 {
        Vec3x8 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl std::ops::Neg for Vec3x8 {
    type Output = Vec3x8;
    #[inline(always)]
    fn neg(self) -> Vec3x8 {
        Vec3x8 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

/// One lane (`f32`) or eight (`f32x8`): the arithmetic a kernel's scalar and
/// SIMD twins share, so that one generic body serves both and both round
/// the same way (`mul_add` is fused in both when the target has FMA, as
/// coif's build sets it).
pub trait Lane:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
{
    /// The same value in every lane.
    fn splat(v: f32) -> Self;
    /// `self * a + b`, fused.
    fn mul_add(self, a: Self, b: Self) -> Self;
}

impl Lane for f32 {
    #[inline(always)]
    fn splat(v: f32) -> f32 {
        v
    }
    #[inline(always)]
    fn mul_add(self, a: f32, b: f32) -> f32 {
        f32::mul_add(self, a, b)
    }
}

impl Lane for f32x8 {
    #[inline(always)]
    fn splat(v: f32) -> f32x8 {
        f32x8::splat(v)
    }
    #[inline(always)]
    fn mul_add(self, a: f32x8, b: f32x8) -> f32x8 {
        f32x8::mul_add(self, a, b)
    }
}

/// `1 / sqrt(x)` to about 2^-22 relative error without the divider: the
/// hardware estimate (`vrsqrtps`, 12 bits) and one Newton-Raphson step,
/// `y' = y (1.5 - 0.5 x y^2)`. [`inv_sqrt`] computes the same value,
/// bit for bit, one lane at a time. `x` must be positive and finite.
#[inline(always)]
pub fn inv_sqrt_x8(x: f32x8) -> f32x8 {
    let y = x.recip_sqrt();
    y * (f32x8::splat(1.5) - f32x8::splat(0.5) * x * (y * y))
}

/// The scalar twin of [`inv_sqrt_x8`]: the same estimate (`rsqrtss` reads the
/// same table as `vrsqrtps`) and the same Newton step in the same order.
#[inline(always)]
pub fn inv_sqrt(x: f32) -> f32 {
    let y = rsqrt_estimate(x);
    y * (1.5 - 0.5 * x * (y * y))
}

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[inline(always)]
fn rsqrt_estimate(x: f32) -> f32 {
    use std::arch::x86_64::{_mm_cvtss_f32, _mm_rsqrt_ss, _mm_set_ss};
    // SAFETY: SSE is part of the x86_64 baseline, and AVX (checked by the cfg
    // above) implies it; the intrinsics only read and write registers.
    unsafe { _mm_cvtss_f32(_mm_rsqrt_ss(_mm_set_ss(x))) }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
fn rsqrt_estimate(x: f32) -> f32 {
    // Elsewhere wide's estimate is not reproducible lane by lane; the two
    // paths then agree to the Newton step's accuracy, not bit for bit.
    f32x8::splat(x).recip_sqrt().as_array()[0]
}

/// Loads lanes from a slice of up to [`LANES`] values, padding with `pad`.
#[inline]
pub fn load_padded(values: &[f32], pad: f32) -> f32x8 {
    let mut a = [pad; LANES];
    let n = values.len().min(LANES);
    a[..n].copy_from_slice(&values[..n]);
    f32x8::new(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_round_trip_and_math() {
        let mut v = Vec3x8::ZERO;
        for l in 0..LANES {
            v.set_lane(l, Vec3::new(l as f32, 2.0 * l as f32, -1.0));
        }
        for l in 0..LANES {
            let s = v.lane(l);
            assert_eq!(s, Vec3::new(l as f32, 2.0 * l as f32, -1.0));
            assert_eq!(v.dot(v).as_array()[l], s.dot(s));
            assert_eq!(v.cross(Vec3x8::splat(Vec3::X)).lane(l), s.cross(Vec3::X));
        }
        let n = v.normalize_or(Vec3x8::splat(Vec3::Y));
        for l in 0..LANES {
            assert!((n.lane(l).length() - 1.0).abs() < 1e-6);
        }
        let z = Vec3x8::ZERO.normalize_or(Vec3x8::splat(Vec3::Y));
        assert_eq!(z.lane(3), Vec3::Y);
        assert_eq!(
            load_padded(&[1.0, 2.0], 9.0).to_array(),
            [1.0, 2.0, 9.0, 9.0, 9.0, 9.0, 9.0, 9.0]
        );
    }

    #[test]
    fn inv_sqrt_twins_agree_and_are_accurate() {
        let mut x = 1e-6f32;
        while x < 1e6 {
            let one = inv_sqrt(x);
            let eight = inv_sqrt_x8(f32x8::splat(x)).to_array();
            assert!(eight.iter().all(|e| (e - one).abs() <= 1e-6 * one), "{x}");
            assert!((one * x.sqrt() - 1.0).abs() < 1e-6, "{x}");
            x *= 1.7;
        }
    }

    #[test]
    fn lane_trait_is_the_same_arithmetic_in_both_widths() {
        fn poly<L: Lane>(x: L) -> L {
            L::splat(0.5).mul_add(x, L::splat(2.0)) * x - x / L::splat(4.0)
        }
        for x in [-3.0f32, -0.25, 0.0, 1.5, 7.0] {
            assert_eq!(poly(x), poly(f32x8::splat(x)).to_array()[2]);
        }
    }
}
