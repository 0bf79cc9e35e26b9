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
//! round the mesh; the gradient is that value's derivative: the trilinear
//! gradient at the clamped point without its components along the clamped
//! axes, plus the unit vector `o / |o|` pointing away from the box. `|o|` is computed as `m |o / m|` with `m` the largest
//! component, so points up to about `1e35` cells away neither overflow nor
//! lose the direction.
//!
//! The scalar ([`f32`]) and SIMD ([`F32Lanes`]) paths run the same generic body
//! ([`sample`]); only the corner loads differ (eight AVX2 gathers, or plain
//! loads), so they agree bit for bit. A NaN coordinate clamps to the box
//! (`maxps` returns its second operand on NaN) and gives a NaN or a finite
//! value in its own lane; indices are clamped as integers again before any
//! load, so no lane can read outside the grid.

use super::{Grid, Sdf};
use crate::lanes::{Lane, V3};
use coif_base::lanes::{F32Lanes, I32Lanes, LANES};

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
    /// `table[idx]` per lane (`idx` an integer-valued float index, clamped
    /// into the table).
    fn fetch(table: &[f32], idx: Self) -> Self;
    /// Signed distance and gradient at `p_mesh` (the generic [`sample`]).
    #[inline(always)]
    fn sample(sdf: &Sdf, p_mesh: V3<Self>) -> (Self, V3<Self>) {
        sample(&sdf.grid, p_mesh, true)
    }
    /// [`SdfLane::sample`] for a skin of thickness `skin` (the strand
    /// step's pushes): exact wherever the value is below `skin`. When every
    /// node on the grid box's faces clears `skin` ([`Grid::outside_floor`]),
    /// a point outside the box can never be within it (its value is a
    /// face's interpolant plus its distance to the box), so outside lanes
    /// get the value and gradient at their clamped point (a lower bound of
    /// the exact value, still at least `skin`) and the outside formula is
    /// skipped.
    #[inline(always)]
    fn sample_for_skin(sdf: &Sdf, p_mesh: V3<Self>, skin: f32) -> (Self, V3<Self>) {
        // A NaN skin takes the exact formula.
        let clears = skin < sdf.grid.outside_floor;
        sample(&sdf.grid, p_mesh, !clears)
    }
    /// The far map's entry for the block of each lane's point (mesh
    /// frame): `+1 / L` where the block is far, `-1 / L` where not, `L` the
    /// slope bound of the block grown by one block (`build::far_map`). A
    /// point outside the grid box reads the block of its projection onto the
    /// box (the block index is clamped, and the grid is a whole number of
    /// blocks); a NaN point reads some block.
    #[inline(always)]
    fn block_entry(sdf: &Sdf, p_mesh: V3<Self>) -> Self {
        let g = &sdf.grid;
        let inv = Self::splat(g.far_inv);
        let zero = Self::splat(0.0);
        let axis = |c: Self, o: f32, max: f32| {
            ((c - Self::splat(o)) * inv)
                .floor()
                .max(zero)
                .min(Self::splat(max))
        };
        let x = axis(p_mesh.x, g.origin.x, g.far_max.x);
        let y = axis(p_mesh.y, g.origin.y, g.far_max.y);
        let z = axis(p_mesh.z, g.origin.z, g.far_max.z);
        let idx = z.mul_add(
            Self::splat(g.far_stride_z),
            y.mul_add(Self::splat(g.far_stride_y), x),
        );
        Self::fetch(&g.far, idx)
    }
    /// Lanes whose point (mesh frame) lies in a block of the far map (from
    /// its [`SdfLane::block_entry`]): more than `far_clearance` outside the
    /// surface, so no skin thinner than that reaches it. A NaN point is
    /// never far.
    #[inline(always)]
    fn far(entry: Self, p_mesh: V3<Self>) -> Self::Mask {
        entry.gt(Self::splat(0.0)) & p_mesh.finite()
    }
    /// The squared radius of a ball round `p_mesh` (mesh frame) no point
    /// of which the skin reaches: `d` is a lower bound of the field at
    /// `p_mesh` (its lookup, or the far clearance), `margin` how far above
    /// the skin that is (`d + off - pearl_radius`, `off` +inf for a pinned
    /// vertex), `entry` the point's [`SdfLane::block_entry`]. -1 (no ball)
    /// where the margin is not positive or not a number.
    ///
    /// With `L = 1 / |entry|`, the radius is
    /// `min((margin - slack_d) / L - slack_p, cap)`:
    /// - `L` bounds the field's slope within the block of `p_mesh` grown by
    ///   one block (`slope.rs`), and a move shorter than a block width from
    ///   a point of the block stays in it (after clamping to the box too:
    ///   the clamp only shortens moves, and the point's block is its
    ///   projection's). So `cap` is just under a block width
    ///   (`FAR_BLOCK cell (1 - 1e-3)`: a point whose block index rounded to
    ///   the neighbour's lies at most an ulp outside that block);
    /// - `slack_d = 1e-6 m + 1e-5 |d|` covers the rounding of the lookup's
    ///   arithmetic at both points (a few ulps of the values; the outside
    ///   distance's square root estimate, a few 1e-7 relative);
    /// - `slack_p = 1e-6 m + 4e-7 |p_mesh - origin|_1` covers the rounding
    ///   of both points to grid units (at most about `1.2e-7 |p - origin|`
    ///   per axis each), which moves where the interpolant is evaluated.
    ///
    /// So for a point `q` with `|q - p_mesh| < radius` the looked-up value
    /// is at least `d - margin + (slack_d - rounding) > pearl_radius - off`:
    /// the test `d + off < reach` (`reach <= pearl_radius`) fails in every
    /// lane, and the lookup would leave the vertex as it is.
    #[inline(always)]
    fn clear_radius2(sdf: &Sdf, p_mesh: V3<Self>, d: Self, margin: Self, entry: Self) -> Self {
        let g = &sdf.grid;
        let slack_d = d.abs().mul_add(Self::splat(1.0e-5), Self::splat(1.0e-6));
        let from = (p_mesh.x - Self::splat(g.origin.x)).abs()
            + (p_mesh.y - Self::splat(g.origin.y)).abs()
            + (p_mesh.z - Self::splat(g.origin.z)).abs();
        let slack_p = from.mul_add(Self::splat(4.0e-7), Self::splat(1.0e-6));
        let r = (margin - slack_d).mul_add(entry.abs(), -slack_p);
        // `min` returns its second operand on NaN: a NaN radius stays NaN.
        let r = Self::splat(g.ball_cap).min(r);
        Self::select(r.gt(Self::splat(0.0)), r * r, Self::splat(-1.0))
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
        g.corners.map(|o| g.values[(b + o) as usize])
    }
    #[inline(always)]
    fn fetch(table: &[f32], idx: f32) -> f32 {
        let last = table.len().saturating_sub(1) as i32;
        table
            .get((idx as i32).clamp(0, last) as usize)
            .copied()
            .unwrap_or(0.0)
    }
}

impl SdfLane for F32Lanes {
    #[inline(always)]
    fn floor(self) -> F32Lanes {
        F32Lanes::floor(self)
    }
    #[inline(always)]
    fn corners(g: &Grid, base: F32Lanes) -> [F32Lanes; 8] {
        let b = base
            .trunc_int()
            .max(I32Lanes::splat(0))
            .min(I32Lanes::splat(g.max_base));
        g.corners.map(|o| gather(&g.values, b + I32Lanes::splat(o)))
    }
    #[inline(always)]
    fn fetch(table: &[f32], idx: F32Lanes) -> F32Lanes {
        if table.is_empty() {
            return F32Lanes::ZERO;
        }
        let last = table.len() as i32 - 1;
        let i = idx
            .trunc_int()
            .max(I32Lanes::splat(0))
            .min(I32Lanes::splat(last));
        gather(table, i)
    }
}

/// `values[idx[l]]` per lane; every index is in `0..values.len()` (the
/// caller clamps the base so that base plus any corner offset is). One AVX2
/// gather per eight lanes (two in a 16-lane build: AVX-512's 16-lane gather
/// is not used, as no machine at hand could test it).
#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
#[inline(always)]
fn gather(values: &[f32], idx: I32Lanes) -> F32Lanes {
    use std::arch::x86_64::{__m256i, _mm256_i32gather_ps, _mm256_loadu_si256, _mm256_storeu_ps};
    let lanes = idx.to_array();
    debug_assert!(lanes.iter().all(|&i| i >= 0 && (i as usize) < values.len()));
    let mut out = [0.0f32; LANES];
    for (group, dst) in lanes.chunks_exact(8).zip(out.chunks_exact_mut(8)) {
        // SAFETY: AVX2 is enabled (cfg above). Every lane index is in
        // `0..values.len()` (clamped by the caller, checked in debug
        // builds), so the gather reads only inside `values`; `group` and
        // `dst` are 8-element chunks, matching the unaligned 256-bit load
        // and store.
        unsafe {
            let vi = _mm256_loadu_si256(group.as_ptr() as *const __m256i);
            let v = _mm256_i32gather_ps::<4>(values.as_ptr(), vi);
            _mm256_storeu_ps(dst.as_mut_ptr(), v);
        }
    }
    F32Lanes::new(out)
}

/// Plain loads where AVX2 is not enabled.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
#[inline(always)]
fn gather(values: &[f32], idx: I32Lanes) -> F32Lanes {
    F32Lanes::new(idx.to_array().map(|i| values[i as usize]))
}

/// `(b - a) t + a`, fused.
#[inline(always)]
fn lerp<T: Lane>(a: T, b: T, t: T) -> T {
    (b - a).mul_add(t, a)
}

/// Signed distance and gradient (mesh frame, per metre, not normalised) at
/// `p` in the mesh frame: the module's formulas, one body for both widths.
///
/// `outside`: the outside formula for lanes outside the box; without it they
/// get the clamped point's value and gradient (`SdfLane::sample_for_skin`).
#[inline(always)]
pub(crate) fn sample<T: SdfLane>(g: &Grid, p: V3<T>, outside: bool) -> (T, V3<T>) {
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

    let g_in = V3::new(gx, gy, gz) * inv;
    if !outside {
        return (inside, g_in);
    }

    // Outside the box: + |o| cell, and the outward unit direction. Skipped
    // when no lane is outside (the usual case); the selects below make the
    // inside lanes the same bits either way.
    let o = u - uc;
    let m = o.x.abs().max(o.y.abs()).max(o.z.abs());
    let out = m.gt(T::splat(1e-6));
    if !T::any(out) {
        return (inside, g_in);
    }
    let one = T::splat(1.0);
    let s = o * T::select(out, m, one).recip();
    let s2 = T::select(out, s.length_squared(), one);
    let il = s2.inv_sqrt();
    let away = m * (s2 * il) * T::splat(g.cell);
    let value = T::select(out, inside + away, inside);
    // The trilinear term does not change along a clamped axis.
    let g_out = V3::new(
        T::select(o.x.abs().gt(zero), zero, gx),
        T::select(o.y.abs().gt(zero), zero, gy),
        T::select(o.z.abs().gt(zero), zero, gz),
    ) * inv
        + s * il;
    (value, V3::select(out, g_out, g_in))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::Vec3Lanes;
    use glam::Vec3;

    /// A closed UV sphere of radius 0.1 and its field at 1 cm.
    fn sphere_sdf() -> Sdf {
        let (rings, segs) = (10u32, 20u32);
        let mut p = vec![Vec3::Y * 0.1, -Vec3::Y * 0.1];
        for i in 1..rings {
            let th = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..segs {
                let ph = std::f32::consts::TAU * j as f32 / segs as f32;
                p.push(Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()) * 0.1);
            }
        }
        let v = |i: u32, j: u32| 2 + (i - 1) * segs + j % segs;
        let mut t = vec![];
        for j in 0..segs {
            t.push([0, v(1, j + 1), v(1, j)]);
            t.push([1, v(rings - 1, j), v(rings - 1, j + 1)]);
            for i in 1..rings - 1 {
                t.push([v(i, j), v(i, j + 1), v(i + 1, j)]);
                t.push([v(i, j + 1), v(i + 1, j + 1), v(i + 1, j)]);
            }
        }
        Sdf::from_mesh(&p, &t, 0.01).unwrap()
    }

    /// Numbers in [0, 1) from a xorshift generator seeded by `s`.
    fn unit_numbers(mut s: u64) -> impl FnMut() -> f32 {
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    /// Points inside the box, outside it (up to 1e30 m), exactly on its
    /// faces, edges and corners, and non-finite ones, eight to a block: each
    /// lane of the SIMD lookup equals the scalar twin bit for bit (a NaN
    /// equals any NaN).
    #[test]
    fn simd_equals_scalar_bit_for_bit() {
        let sdf = sphere_sdf();
        let (lo, hi) = sdf.bounds();
        assert!(sdf.distance(Vec3::ZERO) < -0.08);
        let mut rnd = unit_numbers(0x9E37_79B9_7F4A_7C15);
        let mut points = vec![];
        for k in 0..6000 {
            let t = Vec3::new(rnd(), rnd(), rnd());
            let p = match k % 6 {
                0 | 1 => lo + (hi - lo) * t,
                2 => lo + (hi - lo) * (t * 3.0 - Vec3::ONE),
                3 => (t - Vec3::splat(0.5)) * 10f32.powf(rnd() * 60.0 - 30.0),
                4 => {
                    // On the box: snap one to three coordinates to a face.
                    let mut p = lo + (hi - lo) * t;
                    for a in 0..3 {
                        if rnd() < 0.5 {
                            p[a] = if rnd() < 0.5 { lo[a] } else { hi[a] };
                        }
                    }
                    p
                }
                _ => {
                    let mut p = lo + (hi - lo) * t;
                    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e38, -1e38];
                    p[(rnd() * 3.0) as usize % 3] = bad[(rnd() * 5.0) as usize % 5];
                    p
                }
            };
            points.push(p);
        }
        for block in points.chunks_exact(8) {
            let mut v = Vec3Lanes::ZERO;
            for (l, p) in block.iter().enumerate() {
                v.set_lane(l, *p);
            }
            let (d8, g8) = <F32Lanes as SdfLane>::sample(&sdf, v);
            for (l, p) in block.iter().enumerate() {
                let (d1, g1) = <f32 as SdfLane>::sample(&sdf, V3::from_vec3(*p));
                let g = g8.lane(l);
                assert!(same(d8.as_array()[l], d1), "{p}: {} {d1}", d8.as_array()[l]);
                assert!(
                    same(g.x, g1.x) && same(g.y, g1.y) && same(g.z, g1.z),
                    "{p}: {g} {g1:?}"
                );
                if p.is_finite() && p.abs().max_element() < 1e30 {
                    assert!(d1.is_finite(), "{p}: {d1}");
                }
            }
        }
    }

    /// The lookup for a skin: the outside floor lies below every value
    /// outside the box (and above the skins the step uses); points inside
    /// the box, on its faces and outside it get the exact lookup's bits
    /// wherever that is below the skin, and a value still at least the
    /// skin (at most the exact one) elsewhere; a skin beyond the floor
    /// gets the exact lookup everywhere.
    #[test]
    fn the_lookup_for_a_skin_is_exact_within_it() {
        let sdf = sphere_sdf();
        let (lo, hi) = sdf.bounds();
        let floor = sdf.grid.outside_floor;
        // The box's margin is at least MARGIN_CELLS cells from the surface.
        let margin = super::super::MARGIN_CELLS as f32 * sdf.cell();
        assert!(floor > 0.99 * margin && floor < 0.2, "{floor}");
        let mut rnd = unit_numbers(0x2545_F491_4F6C_DD1D);
        let (mut outside, mut within) = (0, 0);
        for k in 0..40_000 {
            let t = Vec3::new(rnd(), rnd(), rnd());
            let mut p = lo + (hi - lo) * (t * 1.4 - Vec3::splat(0.2));
            if k % 4 == 0 {
                p[k % 3] = if rnd() < 0.5 { lo[k % 3] } else { hi[k % 3] };
            }
            let v = V3::from_vec3(p);
            let (d, g) = <f32 as SdfLane>::sample(&sdf, v);
            if p.cmplt(lo).any() || p.cmpgt(hi).any() {
                outside += 1;
                assert!(d >= floor, "{p}: {d} below the floor {floor}");
            }
            for skin in [0.0, 0.002, 0.01] {
                let (ds, gs) = <f32 as SdfLane>::sample_for_skin(&sdf, v, skin);
                if d < skin {
                    within += 1;
                    assert!(same(d, ds) && g.to_vec3() == gs.to_vec3(), "{p}");
                } else {
                    assert!(ds >= skin && ds <= d, "{p}: {ds} against {d}");
                }
            }
            let (ds, _) = <f32 as SdfLane>::sample_for_skin(&sdf, v, floor + 0.01);
            assert!(same(d, ds), "{p}: a thick skin takes the exact lookup");
        }
        assert!(outside > 10_000 && within > 1_000, "{outside} {within}");
    }

    /// The gradient is the derivative of the value: central differences
    /// inside cells, and the outward direction outside the box.
    #[test]
    fn gradient_is_the_derivative_of_the_value() {
        let sdf = sphere_sdf();
        let (lo, hi) = sdf.bounds();
        let f = |p: Vec3| <f32 as SdfLane>::sample(&sdf, V3::from_vec3(p));
        let h = 1e-4;
        for k in 0..500 {
            let t = Vec3::new(
                (k as f32 * 0.618).fract(),
                (k as f32 * 0.414).fract(),
                (k as f32 * 0.732).fract(),
            );
            let p = lo + (hi - lo) * t;
            let c = sdf.cell();
            // Skip points within h of a cell face (the derivative jumps).
            let u = (p - lo) / c;
            if (u - u.round()).abs().min_element() < 2.0 * h / c {
                continue;
            }
            let (_, g) = f(p);
            for a in 0..3 {
                let mut e = Vec3::ZERO;
                e[a] = h;
                let fd = (f(p + e).0 - f(p - e).0) / (2.0 * h);
                assert!(
                    (fd - g.to_vec3()[a]).abs() < 2e-2,
                    "{p} axis {a}: {fd} {g:?}"
                );
            }
        }
        // Outside, straight above the top face: the value grows at rate
        // about 1 and the gradient points up.
        let top = Vec3::new(0.0, hi.y, 0.0);
        let (d0, _) = f(top);
        let (d1, g1) = f(top + Vec3::Y * 0.5);
        assert!((d1 - d0 - 0.5).abs() < 1e-5, "{d0} {d1}");
        assert!((g1.y - 1.0).abs() < 1e-5 && g1.x.abs() < 0.1, "{g1:?}");
        // Beyond an edge, diagonally: along the diagonal.
        let (_, g2) = f(hi + Vec3::new(1.0, 1.0, 0.0) - Vec3::Z * 0.5 * (hi.z - lo.z));
        assert!(
            (g2.x - g2.y).abs() < 1e-5 && (g2.x - 0.5f32.sqrt()).abs() < 1e-4,
            "{g2:?}"
        );
    }
}
