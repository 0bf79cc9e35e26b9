//! Fused lane helpers the strand step and its contacts share, written over
//! [`Lane`] so that the SIMD path and its scalar twin round alike (every
//! product-sum a fused multiply-add, in a fixed order).

use crate::constraints::MIN_LENGTH;
use crate::lanes::{Lane, V3};
use glam::Mat3;

/// `a s + c`, fused (`Lane::mul_add`).
#[inline(always)]
pub(crate) fn madd<T: Lane>(a: V3<T>, s: T, c: V3<T>) -> V3<T> {
    V3::new(
        a.x.mul_add(s, c.x),
        a.y.mul_add(s, c.y),
        a.z.mul_add(s, c.z),
    )
}

/// `a . b + c` as `x x' + (y y' + (z z' + c))`, fused.
#[inline(always)]
pub(crate) fn dot_add<T: Lane>(a: V3<T>, b: V3<T>, c: T) -> T {
    a.x.mul_add(b.x, a.y.mul_add(b.y, a.z.mul_add(b.z, c)))
}

/// `a . b` as `x x' + (y y' + z z')`, fused.
#[inline(always)]
pub(crate) fn dot<T: Lane>(a: V3<T>, b: V3<T>) -> T {
    a.x.mul_add(b.x, a.y.mul_add(b.y, a.z * b.z))
}

/// `m * v` as `x_axis v.x + y_axis v.y + z_axis v.z`.
#[inline(always)]
pub(crate) fn rotate<T: Lane>(m: &Mat3, v: V3<T>) -> V3<T> {
    V3::splat(m.x_axis) * v.x + V3::splat(m.y_axis) * v.y + V3::splat(m.z_axis) * v.z
}

/// `|d|` and `d / |d|`, lengths clamped to [`MIN_LENGTH`].
#[inline(always)]
pub(crate) fn length_dir<T: Lane>(d: V3<T>) -> (T, V3<T>) {
    let d2 = dot(d, d).max(T::splat(MIN_LENGTH * MIN_LENGTH));
    let r = d2.inv_sqrt();
    (d2 * r, d * r)
}

/// 0 where `free`, +inf elsewhere.
#[inline(always)]
pub(crate) fn offset_unless<T: Lane>(free: T::Mask) -> T {
    T::select(free, T::splat(0.0), T::splat(f32::INFINITY))
}
