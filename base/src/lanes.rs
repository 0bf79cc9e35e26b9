//! Lane math: three `f32x8` registers holding one 3-vector per strand lane.
//!
//! Strands live in SIMD lanes: lane `l` of block `b` is
//! strand `b * LANES + l`, so every operation here works on eight strands at
//! once with no gathers or shuffles.

use glam::Vec3;
use wide::f32x8;

/// Strands (or samples) per SIMD block: the width of [`f32x8`].
pub const LANES: usize = 8;

/// Three coordinates per lane: `V3<f32>` is one 3-vector, `V3<f32x8>`
/// ([`Vec3x8`]) eight of them in structure-of-arrays form, so a kernel
/// written over [`Lane`] serves the scalar twin and the SIMD path alike.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct V3<T> {
    /// The x coordinates, one per lane.
    pub x: T,
    /// The y coordinates, one per lane.
    pub y: T,
    /// The z coordinates, one per lane.
    pub z: T,
}

/// Eight 3-vectors in structure-of-arrays form, one per lane.
pub type Vec3x8 = V3<f32x8>;

impl<T: Lane> V3<T> {
    #[inline(always)]
    /// From the three coordinate registers.
    pub fn new(x: T, y: T, z: T) -> Self {
        V3 { x, y, z }
    }

    /// The same vector in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        V3 {
            x: T::splat(v.x),
            y: T::splat(v.y),
            z: T::splat(v.z),
        }
    }

    /// Zero in every lane.
    #[inline(always)]
    pub fn zero() -> Self {
        V3::new(T::splat(0.0), T::splat(0.0), T::splat(0.0))
    }

    /// `x*x + y*y + z*z`, evaluated left to right (the scalar twins use the
    /// same order, so results agree bit for bit).
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    /// `|v|^2` per lane.
    pub fn length_squared(self) -> T {
        self.dot(self)
    }

    #[inline(always)]
    /// The cross product per lane.
    pub fn cross(self, o: Self) -> Self {
        V3 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    /// Lane-wise `if mask { a } else { b }` (mask from a comparison).
    #[inline(always)]
    pub fn select(mask: T::Mask, a: Self, b: Self) -> Self {
        V3 {
            x: T::select(mask, a.x, b.x),
            y: T::select(mask, a.y, b.y),
            z: T::select(mask, a.z, b.z),
        }
    }

    /// Lanes whose three coordinates are finite.
    #[inline(always)]
    pub fn finite(self) -> T::Mask {
        self.x.finite() & self.y.finite() & self.z.finite()
    }
}

impl Vec3x8 {
    /// Zero in every lane.
    pub const ZERO: Vec3x8 = Vec3x8 {
        x: f32x8::ZERO,
        y: f32x8::ZERO,
        z: f32x8::ZERO,
    };

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

    /// Unit vector, or `fallback` in lanes whose length is not above `1e-20`.
    #[inline(always)]
    pub fn normalize_or(self, fallback: Vec3x8) -> Vec3x8 {
        let len = self.length_squared().sqrt();
        let ok = len.simd_gt(f32x8::splat(1e-20));
        let inv = f32x8::ONE / len.max(f32x8::splat(1e-20));
        Vec3x8::select(ok, self * inv, fallback)
    }
}

impl V3<f32> {
    /// As a `glam::Vec3`.
    #[inline(always)]
    pub fn to_vec3(self) -> Vec3 {
        Vec3::new(self.x, self.y, self.z)
    }

    /// From a `glam::Vec3`.
    #[inline(always)]
    pub fn from_vec3(v: Vec3) -> Self {
        V3::new(v.x, v.y, v.z)
    }
}

impl<T: Lane> std::ops::Add for V3<T> {
    type Output = V3<T>;
    #[inline(always)]
    fn add(self, o: V3<T>) -> V3<T> {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl<T: Lane> std::ops::Sub for V3<T> {
    type Output = V3<T>;
    #[inline(always)]
    fn sub(self, o: V3<T>) -> V3<T> {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl<T: Lane> std::ops::Mul<T> for V3<T> {
    type Output = V3<T>;
    #[inline(always)]
    fn mul(self, s: T) -> V3<T> {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl<T: Lane> std::ops::Neg for V3<T> {
    type Output = V3<T>;
    #[inline(always)]
    fn neg(self) -> V3<T> {
        V3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

/// One lane (`f32`) or eight (`f32x8`): the arithmetic a kernel's scalar and
/// SIMD twins share, so that one generic body serves both and both round
/// the same way (`mul_add` is fused in both when the target has FMA, as
/// coif's build sets it). Every operation is IEEE (`+ - * /`, compare,
/// select) or a hardware estimate refined by one Newton step that reads the
/// same table in both widths ([`Lane::inv_sqrt`], [`Lane::recip`]), so on
/// x86-64 with AVX a body written over `Lane` gives the same bits per lane.
pub trait Lane:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::Neg<Output = Self>
{
    /// A lane mask: `bool` for one lane, an all-bits `f32x8` for eight.
    type Mask: Copy
        + std::ops::BitAnd<Output = Self::Mask>
        + std::ops::BitOr<Output = Self::Mask>
        + std::ops::Not<Output = Self::Mask>;
    /// The same value in every lane.
    fn splat(v: f32) -> Self;
    /// `self * a + b`, fused.
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// `1 / sqrt(self)`: [`inv_sqrt`] / [`inv_sqrt_x8`] (estimate + one
    /// Newton step, about 2^-22 relative). `self` > 0 and finite.
    fn inv_sqrt(self) -> Self;
    /// `1 / self`: [`recip`] / [`recip_x8`] (estimate + one Newton step).
    fn recip(self) -> Self;
    /// `if self > o { self } else { o }` (`maxps`: a NaN in either gives `o`).
    fn max(self, o: Self) -> Self;
    /// `if self < o { self } else { o }` (`minps`: a NaN in either gives `o`).
    fn min(self, o: Self) -> Self;
    /// `|self|`.
    fn abs(self) -> Self;
    /// Lanes where `self > o`.
    fn gt(self, o: Self) -> Self::Mask;
    /// Lanes where `self < o`.
    fn lt(self, o: Self) -> Self::Mask;
    /// Lane-wise `if m { a } else { b }`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// True if any lane of `m` is set.
    fn any(m: Self::Mask) -> bool;
    /// Lanes whose value is finite.
    fn finite(self) -> Self::Mask;
    /// A mask with every lane set.
    fn all_lanes() -> Self::Mask;
}

impl Lane for f32 {
    type Mask = bool;
    #[inline(always)]
    fn splat(v: f32) -> f32 {
        v
    }
    #[inline(always)]
    fn mul_add(self, a: f32, b: f32) -> f32 {
        f32::mul_add(self, a, b)
    }
    #[inline(always)]
    fn inv_sqrt(self) -> f32 {
        inv_sqrt(self)
    }
    #[inline(always)]
    fn recip(self) -> f32 {
        recip(self)
    }
    #[inline(always)]
    fn max(self, o: f32) -> f32 {
        if self > o {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    fn min(self, o: f32) -> f32 {
        if self < o {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    fn abs(self) -> f32 {
        f32::abs(self)
    }
    #[inline(always)]
    fn gt(self, o: f32) -> bool {
        self > o
    }
    #[inline(always)]
    fn lt(self, o: f32) -> bool {
        self < o
    }
    #[inline(always)]
    fn select(m: bool, a: f32, b: f32) -> f32 {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn any(m: bool) -> bool {
        m
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline(always)]
    fn all_lanes() -> bool {
        true
    }
}

impl Lane for f32x8 {
    type Mask = f32x8;
    #[inline(always)]
    fn splat(v: f32) -> f32x8 {
        f32x8::splat(v)
    }
    #[inline(always)]
    fn mul_add(self, a: f32x8, b: f32x8) -> f32x8 {
        f32x8::mul_add(self, a, b)
    }
    #[inline(always)]
    fn inv_sqrt(self) -> f32x8 {
        inv_sqrt_x8(self)
    }
    #[inline(always)]
    fn recip(self) -> f32x8 {
        recip_x8(self)
    }
    #[inline(always)]
    fn max(self, o: f32x8) -> f32x8 {
        self.fast_max(o)
    }
    #[inline(always)]
    fn min(self, o: f32x8) -> f32x8 {
        self.fast_min(o)
    }
    #[inline(always)]
    fn abs(self) -> f32x8 {
        f32x8::abs(self)
    }
    #[inline(always)]
    fn gt(self, o: f32x8) -> f32x8 {
        self.simd_gt(o)
    }
    #[inline(always)]
    fn lt(self, o: f32x8) -> f32x8 {
        self.simd_lt(o)
    }
    #[inline(always)]
    fn select(m: f32x8, a: f32x8, b: f32x8) -> f32x8 {
        m.select(a, b)
    }
    #[inline(always)]
    fn any(m: f32x8) -> bool {
        m.any()
    }
    #[inline(always)]
    fn finite(self) -> f32x8 {
        self.is_finite()
    }
    #[inline(always)]
    fn all_lanes() -> f32x8 {
        f32x8::ZERO.simd_eq(f32x8::ZERO)
    }
}

/// `1 / x` to about 2^-22 relative error without the divider: the hardware
/// estimate (`vrcpps`, 12 bits) and one Newton-Raphson step
/// `y' = y (2 - x y)`. [`recip`] computes the same value bit for bit, one
/// lane at a time. `x` must be nonzero and finite.
#[inline(always)]
pub fn recip_x8(x: f32x8) -> f32x8 {
    let y = f32x8::recip(x);
    y * (f32x8::splat(2.0) - x * y)
}

/// The scalar twin of [`recip_x8`]: `rcpss` reads the same table as
/// `vrcpps`, then the same Newton step in the same order.
#[inline(always)]
pub fn recip(x: f32) -> f32 {
    let y = rcp_estimate(x);
    y * (2.0 - x * y)
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

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[inline(always)]
fn rcp_estimate(x: f32) -> f32 {
    use std::arch::x86_64::{_mm_cvtss_f32, _mm_rcp_ss, _mm_set_ss};
    // SAFETY: as in `rsqrt_estimate`.
    unsafe { _mm_cvtss_f32(_mm_rcp_ss(_mm_set_ss(x))) }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
fn rcp_estimate(x: f32) -> f32 {
    f32x8::splat(x).recip().as_array()[0]
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
fn rsqrt_estimate(x: f32) -> f32 {
    // Elsewhere wide's estimate is not reproducible lane by lane; the two
    // paths then agree to the Newton step's accuracy, not bit for bit.
    f32x8::splat(x).recip_sqrt().as_array()[0]
}

/// The lane mask (all bits set) of lanes `0..n`: the lanes of a block that
/// hold one of its `n` strands or samples (`n >= LANES` sets them all).
#[inline]
pub fn lanes_below(n: usize) -> f32x8 {
    f32x8::new(std::array::from_fn(|l| if l < n { 1.0 } else { 0.0 })).simd_gt(f32x8::ZERO)
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
    fn recip_twins_agree_bit_for_bit_and_are_accurate() {
        let mut m = 1e-6f32;
        while m < 1e6 {
            for x in [m, -m] {
                let one = recip(x);
                let eight = recip_x8(f32x8::splat(x)).to_array();
                assert!(eight.iter().all(|e| e.to_bits() == one.to_bits()), "{x}");
                assert!((one * x - 1.0).abs() < 1e-6, "{x}");
            }
            m *= 1.37;
        }
    }

    #[test]
    fn generic_lane_ops_match_in_both_widths() {
        fn body<L: Lane>(x: L, y: L) -> L {
            let m = x.gt(y) | (-x).lt(L::splat(0.25));
            let s = L::select(m, x.max(y), x.min(y).abs());
            let v = V3::new(x, y, s);
            (v.dot(v) + L::splat(1.0)).inv_sqrt() * (x * x + L::splat(0.5)).recip()
        }
        for (x, y) in [(1.5f32, -2.0f32), (-3.0, 0.1), (0.2, 0.3), (7.0, 7.0)] {
            let one = body(x, y);
            let eight = body(f32x8::splat(x), f32x8::splat(y)).to_array();
            assert!(eight.iter().all(|e| e.to_bits() == one.to_bits()));
        }
        assert!(!<f32x8 as Lane>::any(!<f32x8 as Lane>::all_lanes()));
        assert!(<f32 as Lane>::any(f32::NAN.finite() | true));
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

    #[test]
    fn lanes_below_masks_the_first_n_lanes() {
        for n in 0..=LANES + 1 {
            let m = lanes_below(n).to_bitmask();
            assert_eq!(m, (1u32 << n.min(LANES)) - 1, "{n}");
        }
    }
}
