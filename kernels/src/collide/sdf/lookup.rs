//! The per-point lookup: trilinear value and gradient, one lane or eight.
//!
//! With `u = (p - origin) / cell` the point in grid units, clamped to the
//! grid box as `uc`, `i = min(floor(uc), n - 2)` the cell and
//! `f = uc - i` the fraction, the value is the trilinear interpolant of the
//! cell's eight corners `c_xyz`,
//! `v = lerp_z(lerp_y(lerp_x(c000, c100), lerp_x(c010, c110)), ...)`
//! with `lerp(a, b, t) = (b - a) t + a` (one fused multiply-add), and the
//! gradient is that interpolant's exact derivative divided by the cell:
//! `dv/dfx` is the bilinear (y, z) interpolant of the x differences
//! `c1yz - c0yz`, and likewise for y and z.
//!
//! Outside the box the point is clamped and `o = u - uc` (grid units) is
//! its offset from the box; the value is the trilinear value at the clamped
//! point plus `|o| cell`, an upper bound of the true distance (the triangle
//! inequality), positive because the box keeps a margin of empty cells
//! round the mesh; the gradient adds the unit vector `o / |o|`, pointing
//! away from the box. `|o|` is computed as `m |o / m|` with `m` the largest
//! component, so points up to about `1e35` cells away neither overflow nor
//! lose the direction.
//!
//! The scalar ([`f32`]) and SIMD ([`f32x8`]) paths run the same generic body
//! ([`sample`]); only the corner loads differ (eight AVX2 gathers, or plain
//! loads), so they agree bit for bit. A NaN coordinate clamps to the box
//! (`maxps` returns its second operand on NaN) and gives a NaN or a finite
//! value in its own lane; indices are clamped as integers again before any
//! load, so no lane can read outside the grid.

use super::{Grid, Sdf};
use crate::lanes::{Lane, V3};
use wide::{f32x8, i32x8};

/// Offsets of a cell's eight corners from its lowest node, x fastest.
#[inline(always)]
fn corner_offsets(g: &Grid) -> [i32; 8] {
    let (sx, sy) = (g.dims.x as i32, (g.dims.x * g.dims.y) as i32);
    [0, 1, sx, sx + 1, sy, sy + 1, sy + sx, sy + sx + 1]
}

/// Signed distance and its gradient (d/dp of the trilinear interpolant, mesh
/// frame, not normalised) at points given in the MESH frame, one lane or
/// eight. The strand step calls this per vertex per substep; it allocates
/// nothing.
pub(crate) trait SdfLane: Lane {
    /// `floor(self)` (exact in both widths).
    fn floor(self) -> Self;
    /// The eight corner values of the cells whose lowest node is `base`
    /// (an integer-valued float index, already in range), x fastest.
    fn corners(g: &Grid, base: Self) -> [Self; 8];
    /// Signed distance and gradient at `p_mesh` (the generic [`sample`]).
    #[inline(always)]
    fn sample(sdf: &Sdf, p_mesh: V3<Self>) -> (Self, V3<Self>) {
        sample(&sdf.grid, p_mesh)
    }
}

impl SdfLane for f32 {
    #[inline(always)]
    fn floor(self) -> f32 {
        f32::floor(self)
    }
    #[inline(always)]
    fn corners(g: &Grid, base: f32) -> [f32; 8] {
        let b = (base as i32).clamp(0, g.max_base);
        corner_offsets(g).map(|o| g.values[(b + o) as usize])
    }
}

impl SdfLane for f32x8 {
    #[inline(always)]
    fn floor(self) -> f32x8 {
        f32x8::floor(self)
    }
    #[inline(always)]
    fn corners(g: &Grid, base: f32x8) -> [f32x8; 8] {
        let b = base
            .trunc_int()
            .max(i32x8::splat(0))
            .min(i32x8::splat(g.max_base));
        corner_offsets(g).map(|o| gather(&g.values, b + i32x8::splat(o)))
    }
}

/// `values[idx[l]]` per lane; every index is in `0..values.len()` (the
/// caller clamps the base so that base plus any corner offset is).
#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
#[inline(always)]
fn gather(values: &[f32], idx: i32x8) -> f32x8 {
    use std::arch::x86_64::{__m256i, _mm256_i32gather_ps, _mm256_loadu_si256, _mm256_storeu_ps};
    let lanes = idx.to_array();
    debug_assert!(lanes.iter().all(|&i| i >= 0 && (i as usize) < values.len()));
    let mut out = [0.0f32; 8];
    // SAFETY: AVX2 is enabled (cfg above). Every lane index is in
    // `0..values.len()` (clamped by the caller, checked in debug builds), so
    // the gather reads only inside `values`; `lanes` and `out` are 8-element
    // arrays, matching the unaligned 256-bit load and store.
    unsafe {
        let vi = _mm256_loadu_si256(lanes.as_ptr() as *const __m256i);
        let v = _mm256_i32gather_ps::<4>(values.as_ptr(), vi);
        _mm256_storeu_ps(out.as_mut_ptr(), v);
    }
    f32x8::new(out)
}

/// Plain loads where AVX2 is not enabled.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
#[inline(always)]
fn gather(values: &[f32], idx: i32x8) -> f32x8 {
    f32x8::new(idx.to_array().map(|i| values[i as usize]))
}

/// `(b - a) t + a`, fused.
#[inline(always)]
fn lerp<T: Lane>(a: T, b: T, t: T) -> T {
    (b - a).mul_add(t, a)
}

/// Signed distance and gradient (mesh frame, per metre, not normalised) at
/// `p` in the mesh frame: the module's formulas, one body for both widths.
#[inline(always)]
pub(crate) fn sample<T: SdfLane>(g: &Grid, p: V3<T>) -> (T, V3<T>) {
    let inv = T::splat(g.inv_cell);
    let zero = T::splat(0.0);
    let u = V3::new(
        (p.x - T::splat(g.origin.x)) * inv,
        (p.y - T::splat(g.origin.y)) * inv,
        (p.z - T::splat(g.origin.z)) * inv,
    );
    // Clamp to the box; a NaN becomes 0 (max returns its second operand).
    let uc = V3::new(
        u.x.max(zero).min(T::splat(g.max_u.x)),
        u.y.max(zero).min(T::splat(g.max_u.y)),
        u.z.max(zero).min(T::splat(g.max_u.z)),
    );
    let i = V3::new(
        uc.x.floor().min(T::splat(g.max_i.x)),
        uc.y.floor().min(T::splat(g.max_i.y)),
        uc.z.floor().min(T::splat(g.max_i.z)),
    );
    let f = uc - i;
    let base =
        i.z.mul_add(T::splat(g.stride_z), i.y.mul_add(T::splat(g.stride_y), i.x));
    let [c000, c100, c010, c110, c001, c101, c011, c111] = T::corners(g, base);

    // Trilinear value.
    let c00 = lerp(c000, c100, f.x);
    let c10 = lerp(c010, c110, f.x);
    let c01 = lerp(c001, c101, f.x);
    let c11 = lerp(c011, c111, f.x);
    let c0 = lerp(c00, c10, f.y);
    let c1 = lerp(c01, c11, f.y);
    let inside = lerp(c0, c1, f.z);
    // Its derivative in grid units.
    let gx = lerp(
        lerp(c100 - c000, c110 - c010, f.y),
        lerp(c101 - c001, c111 - c011, f.y),
        f.z,
    );
    let gy = lerp(c10 - c00, c11 - c01, f.z);
    let gz = c1 - c0;

    // Outside the box: + |o| cell, and the outward unit direction.
    let o = u - uc;
    let m = o.x.abs().max(o.y.abs()).max(o.z.abs());
    let out = m.gt(T::splat(1e-6));
    let one = T::splat(1.0);
    let s = o * T::select(out, m, one).recip();
    let s2 = T::select(out, s.length_squared(), one);
    let il = s2.inv_sqrt();
    let dir = V3::select(out, s * il, V3::zero());
    let away = T::select(out, m * (s2 * il) * T::splat(g.cell), zero);
    let value = inside + away;
    let grad = V3::new(gx, gy, gz) * inv + dir;
    (value, grad)
}
