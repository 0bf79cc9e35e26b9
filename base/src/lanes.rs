//! Lane math: three SIMD registers holding one 3-vector per strand lane.
//!
//! Strands live in SIMD lanes: lane `l` of block `b` is strand
//! `b * LANES + l`, so every operation here works on [`LANES`] strands at
//! once with no gathers or shuffles.
//!
//! # The width is a build-time choice
//!
//! | build | [`LANES`] | [`F32Lanes`] |
//! |---|---|---|
//! | default (x86-64-v3: AVX2 + FMA) | 8 | `wide::f32x8`, one 256-bit register |
//! | `target_feature = "avx512f"` (x86-64-v4, `target-cpu=native` on Zen 4/5 or a Xeon) | 16 | `wide::f32x16`, one 512-bit register |
//! | cargo feature `lanes16` on any target | 16 | `wide::f32x16`, two 256-bit halves where AVX-512 is absent |
//!
//! A strand's result does not depend on the width: every kernel is
//! lane-wise IEEE arithmetic (`+ - * /`, fused multiply-add, compare,
//! select) or a hardware estimate that reads the same table at every width
//! ([`recip_simd`] and [`inv_sqrt_simd`] take `vrcpps` / `vrsqrtps` on
//! 256-bit halves even on AVX-512, whose 14-bit `vrcp14ps` would round
//! differently), and the few places that sum floats across strands (the
//! shadow map's deposits, for one) visit them in groups of eight
//! ([`GROUP_LANES`]) whatever the width. The tests build the same scenes at
//! both widths and compare their bytes.

use glam::Vec3;

#[cfg(not(any(feature = "lanes16", target_feature = "avx512f")))]
mod width {
    /// Eight `f32` lanes (AVX2).
    pub type F32Lanes = wide::f32x8;
    /// Eight `i32` lanes.
    pub type I32Lanes = wide::i32x8;
    /// Strands per SIMD block.
    pub const LANES: usize = 8;
}

#[cfg(any(feature = "lanes16", target_feature = "avx512f"))]
mod width {
    /// Sixteen `f32` lanes (AVX-512, or two AVX2 halves).
    pub type F32Lanes = wide::f32x16;
    /// Sixteen `i32` lanes.
    pub type I32Lanes = wide::i32x16;
    /// Strands per SIMD block.
    pub const LANES: usize = 16;
}

/// `f32` in every lane of a block: `wide::f32x8`, or `wide::f32x16` in a
/// 16-lane build (see the module docs).
pub use width::F32Lanes;
/// `i32` in every lane of a block (indices, truncated coordinates).
pub use width::I32Lanes;
/// Strands (or samples) per SIMD block: 8, or 16 where the build targets
/// `avx512f` or the `lanes16` feature is on.
pub use width::LANES;

/// The strands a cross-strand sum visits together, whatever [`LANES`] is:
/// kernels that add many strands into one cell or total (the hair grid's
/// splat) walk a block as `LANES / GROUP_LANES` groups of eight, vertex by
/// vertex within each group, so the additions happen in the same order at
/// both widths.
pub const GROUP_LANES: usize = 8;

/// Groups of [`GROUP_LANES`] lanes in one block: 1 in an 8-lane build, 2
/// in a 16-lane one. Passes whose work comes in eight-strand groups (the
/// frame's interpolation groups, a shadow map's deposits) fill a block with
/// this many groups, so no lane is padding at either width.
pub const GROUPS_PER_BLOCK: usize = LANES / GROUP_LANES;

/// Group `u` of eight lanes, counted over consecutive blocks: `(block,
/// group within it)`, `(u / GROUPS_PER_BLOCK, u % GROUPS_PER_BLOCK)`.
#[inline(always)]
#[allow(clippy::modulo_one)] // GROUPS_PER_BLOCK is 1 in an 8-lane build
pub fn block_of_group(u: usize) -> (usize, usize) {
    (u / GROUPS_PER_BLOCK, u % GROUPS_PER_BLOCK)
}

/// Eight `f32` lanes, [`F32Lanes`]'s 256-bit halves: the width the
/// hardware estimates ([`recip_simd`], [`inv_sqrt_simd`]) and the
/// eight-strand groups are computed at.
pub type F32Group = wide::f32x8;

/// Splits a block's lanes into its [`GROUP_LANES`]-wide groups, lane order
/// kept (one group in an 8-lane build, two in a 16-lane one).
#[inline(always)]
pub fn groups(x: F32Lanes) -> [F32Group; LANES / GROUP_LANES] {
    wide::bytemuck::cast(x)
}

/// Joins [`groups`] back into a block's lanes.
#[inline(always)]
pub fn from_groups(g: [F32Group; LANES / GROUP_LANES]) -> F32Lanes {
    wide::bytemuck::cast(g)
}

/// Three coordinates per lane: `V3<f32>` is one 3-vector, `V3<F32Lanes>`
/// ([`Vec3Lanes`]) eight of them in structure-of-arrays form, so a kernel
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

/// [`LANES`] 3-vectors in structure-of-arrays form, one per lane.
pub type Vec3Lanes = V3<F32Lanes>;

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

impl Vec3Lanes {
    /// Zero in every lane.
    pub const ZERO: Vec3Lanes = Vec3Lanes {
        x: F32Lanes::ZERO,
        y: F32Lanes::ZERO,
        z: F32Lanes::ZERO,
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
    pub fn normalize_or(self, fallback: Vec3Lanes) -> Vec3Lanes {
        let len = self.length_squared().sqrt();
        let ok = len.simd_gt(F32Lanes::splat(1e-20));
        let inv = F32Lanes::ONE / len.max(F32Lanes::splat(1e-20));
        Vec3Lanes::select(ok, self * inv, fallback)
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

/// One lane (`f32`) or a register of them (`wide::f32x8`, `wide::f32x16`; a
/// block is [`F32Lanes`]): the arithmetic a kernel's scalar and
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
    /// A lane mask: `bool` for one lane, an all-bits register for many.
    type Mask: Copy
        + std::ops::BitAnd<Output = Self::Mask>
        + std::ops::BitOr<Output = Self::Mask>
        + std::ops::Not<Output = Self::Mask>;
    /// The same value in every lane.
    fn splat(v: f32) -> Self;
    /// `self * a + b`, fused.
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// `1 / sqrt(self)`: [`inv_sqrt`] / [`inv_sqrt_simd`] (estimate + one
    /// Newton step, about 2^-22 relative). `self` > 0 and finite.
    fn inv_sqrt(self) -> Self;
    /// `1 / self`: [`recip`] / [`recip_simd`] (estimate + one Newton step).
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

/// Eight planes of a block (one field of every lane per plane) as one row
/// of eight floats per lane: an 8 x 8 transpose per group of eight lanes.
#[inline(always)]
pub fn planes_to_rows(planes: [F32Lanes; 8]) -> [F32Group; LANES] {
    let split = planes.map(groups);
    let mut rows = [F32Group::ZERO; LANES];
    for (k, out) in rows.chunks_exact_mut(GROUP_LANES).enumerate() {
        out.copy_from_slice(&F32Group::transpose(split.map(|g| g[k])));
    }
    rows
}

/// The inverse of [`planes_to_rows`]: one row of eight floats per lane (a
/// record of eight fields) as eight planes of the block, an 8 x 8
/// transpose per group of eight lanes.
#[inline(always)]
pub fn rows_to_planes(rows: [F32Group; LANES]) -> [F32Lanes; 8] {
    let mut split = [[F32Group::ZERO; GROUPS_PER_BLOCK]; 8];
    for (k, group) in rows.chunks_exact(GROUP_LANES).enumerate() {
        let planes = F32Group::transpose(group.try_into().expect("eight rows"));
        for (plane, p) in split.iter_mut().zip(planes) {
            plane[k] = p;
        }
    }
    split.map(from_groups)
}

/// [`Lane`] for a `wide` register type, with its hardware estimates of
/// `1 / x` and `1 / sqrt(x)` (each refined by one Newton step here).
macro_rules! simd_lane {
    ($t:ty, $rcp_estimate:path, $rsqrt_estimate:path) => {
        impl Lane for $t {
            type Mask = $t;
            #[inline(always)]
            fn splat(v: f32) -> $t {
                <$t>::splat(v)
            }
            #[inline(always)]
            fn mul_add(self, a: $t, b: $t) -> $t {
                <$t>::mul_add(self, a, b)
            }
            #[inline(always)]
            fn inv_sqrt(self) -> $t {
                let y = $rsqrt_estimate(self);
                y * (<$t>::splat(1.5) - <$t>::splat(0.5) * self * (y * y))
            }
            #[inline(always)]
            fn recip(self) -> $t {
                let y = $rcp_estimate(self);
                y * (<$t>::splat(2.0) - self * y)
            }
            #[inline(always)]
            fn max(self, o: $t) -> $t {
                self.fast_max(o)
            }
            #[inline(always)]
            fn min(self, o: $t) -> $t {
                self.fast_min(o)
            }
            #[inline(always)]
            fn abs(self) -> $t {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn gt(self, o: $t) -> $t {
                self.simd_gt(o)
            }
            #[inline(always)]
            fn lt(self, o: $t) -> $t {
                self.simd_lt(o)
            }
            #[inline(always)]
            fn select(m: $t, a: $t, b: $t) -> $t {
                m.select(a, b)
            }
            #[inline(always)]
            fn any(m: $t) -> bool {
                m.any()
            }
            #[inline(always)]
            fn finite(self) -> $t {
                self.is_finite()
            }
            #[inline(always)]
            fn all_lanes() -> $t {
                <$t>::ZERO.simd_eq(<$t>::ZERO)
            }
        }
    };
}

simd_lane!(wide::f32x8, wide::f32x8::recip, wide::f32x8::recip_sqrt);
simd_lane!(wide::f32x16, rcp_estimate_x16, rsqrt_estimate_x16);

/// `vrcpps` on each 256-bit half, also on AVX-512 (whose own 14-bit
/// estimate, or wide's exact division there, would round differently from
/// the eight-lane build and the scalar twin's `rcpss`).
#[inline(always)]
fn rcp_estimate_x16(x: wide::f32x16) -> wide::f32x16 {
    let halves: [wide::f32x8; 2] = wide::bytemuck::cast(x);
    wide::bytemuck::cast(halves.map(wide::f32x8::recip))
}

/// `vrsqrtps` on each 256-bit half (as [`rcp_estimate_x16`]).
#[inline(always)]
fn rsqrt_estimate_x16(x: wide::f32x16) -> wide::f32x16 {
    let halves: [wide::f32x8; 2] = wide::bytemuck::cast(x);
    wide::bytemuck::cast(halves.map(wide::f32x8::recip_sqrt))
}

/// `1 / x` to about 2^-22 relative error without the divider: the hardware
/// estimate (`vrcpps`, 12 bits) and one Newton-Raphson step
/// `y' = y (2 - x y)`. [`recip`] computes the same value bit for bit, one
/// lane at a time. `x` must be nonzero and finite.
#[inline(always)]
pub fn recip_simd(x: F32Lanes) -> F32Lanes {
    <F32Lanes as Lane>::recip(x)
}

/// The scalar twin of [`recip_simd`]: `rcpss` reads the same table as
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
pub fn inv_sqrt_simd(x: F32Lanes) -> F32Lanes {
    <F32Lanes as Lane>::inv_sqrt(x)
}

/// The scalar twin of [`inv_sqrt_simd`]: the same estimate (`rsqrtss` reads the
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
    F32Group::splat(x).recip().as_array()[0]
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
fn rsqrt_estimate(x: f32) -> f32 {
    // Elsewhere wide's estimate is not reproducible lane by lane; the two
    // paths then agree to the Newton step's accuracy, not bit for bit.
    F32Group::splat(x).recip_sqrt().as_array()[0]
}

/// The lane mask (all bits set) of lanes `0..n`: the lanes of a block that
/// hold one of its `n` strands or samples (`n >= LANES` sets them all).
#[inline]
pub fn lanes_below(n: usize) -> F32Lanes {
    F32Lanes::new(std::array::from_fn(|l| if l < n { 1.0 } else { 0.0 })).simd_gt(F32Lanes::ZERO)
}

/// The lane mask (all bits set) of the lanes whose bit is set in `bits`
/// (bit `l` for lane `l`; bits from [`LANES`] up are ignored).
#[inline]
pub fn lanes_of_bits(bits: u32) -> F32Lanes {
    wide::bytemuck::cast(I32Lanes::new(std::array::from_fn(|l| {
        -(((bits >> l) & 1) as i32)
    })))
}

/// Loads lanes from a slice of up to [`LANES`] values, padding with `pad`.
#[inline]
pub fn load_padded(values: &[f32], pad: f32) -> F32Lanes {
    let mut a = [pad; LANES];
    let n = values.len().min(LANES);
    a[..n].copy_from_slice(&values[..n]);
    F32Lanes::new(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_round_trip_and_math() {
        let mut v = Vec3Lanes::ZERO;
        for l in 0..LANES {
            v.set_lane(l, Vec3::new(l as f32, 2.0 * l as f32, -1.0));
        }
        for l in 0..LANES {
            let s = v.lane(l);
            assert_eq!(s, Vec3::new(l as f32, 2.0 * l as f32, -1.0));
            assert_eq!(v.dot(v).as_array()[l], s.dot(s));
            assert_eq!(v.cross(Vec3Lanes::splat(Vec3::X)).lane(l), s.cross(Vec3::X));
        }
        let n = v.normalize_or(Vec3Lanes::splat(Vec3::Y));
        for l in 0..LANES {
            assert!((n.lane(l).length() - 1.0).abs() < 1e-6);
        }
        let z = Vec3Lanes::ZERO.normalize_or(Vec3Lanes::splat(Vec3::Y));
        assert_eq!(z.lane(3), Vec3::Y);
        let padded = load_padded(&[1.0, 2.0], 9.0).to_array();
        assert_eq!(padded[..2], [1.0, 2.0]);
        assert!(padded[2..].iter().all(|&p| p == 9.0));
        assert_eq!(padded.len(), LANES);
    }

    #[test]
    fn inv_sqrt_twins_agree_and_are_accurate() {
        let mut x = 1e-6f32;
        while x < 1e6 {
            let one = inv_sqrt(x);
            let eight = inv_sqrt_simd(F32Lanes::splat(x)).to_array();
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
                let eight = recip_simd(F32Lanes::splat(x)).to_array();
                assert!(eight.iter().all(|e| e.to_bits() == one.to_bits()), "{x}");
                assert!((one * x - 1.0).abs() < 1e-6, "{x}");
            }
            m *= 1.37;
        }
    }

    #[test]
    fn planes_to_rows_transposes_every_lane() {
        let planes: [F32Lanes; 8] =
            std::array::from_fn(|p| F32Lanes::new(std::array::from_fn(|l| (100 * l + p) as f32)));
        for (l, row) in planes_to_rows(planes).iter().enumerate() {
            assert_eq!(
                row.to_array(),
                std::array::from_fn(|p| (100 * l + p) as f32)
            );
        }
    }

    #[test]
    fn groups_keep_lane_order() {
        let x = F32Lanes::new(std::array::from_fn(|l| l as f32));
        let g = groups(x);
        for (k, group) in g.iter().enumerate() {
            for (l, v) in group.to_array().iter().enumerate() {
                assert_eq!(*v, (k * GROUP_LANES + l) as f32);
            }
        }
        assert_eq!(from_groups(g).to_array(), x.to_array());
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
            let eight = body(F32Lanes::splat(x), F32Lanes::splat(y)).to_array();
            assert!(eight.iter().all(|e| e.to_bits() == one.to_bits()));
        }
        assert!(!<F32Lanes as Lane>::any(!<F32Lanes as Lane>::all_lanes()));
        assert!(<f32 as Lane>::any(f32::NAN.finite() | true));
    }

    #[test]
    fn lane_trait_is_the_same_arithmetic_in_both_widths() {
        fn poly<L: Lane>(x: L) -> L {
            L::splat(0.5).mul_add(x, L::splat(2.0)) * x - x / L::splat(4.0)
        }
        for x in [-3.0f32, -0.25, 0.0, 1.5, 7.0] {
            assert_eq!(poly(x), poly(F32Lanes::splat(x)).to_array()[2]);
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
