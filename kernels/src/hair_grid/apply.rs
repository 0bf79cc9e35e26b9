//! Step 3 of the module doc: each vertex reads the grid's fields and moves
//! (volume) and changes its velocity (friction); one generic body for the
//! SIMD path (strands in lanes) and its scalar twin.
//!
//! The fields are read trilinearly: with `u = (x - origin) / cell` clamped
//! to the grid, `i = min(floor(u), dims - 2)` and `f = u - i`, the value is
//! `sum_c w_c F_c` over the cell's eight corners, `w_c` the products of `f`
//! and `1 - f`, accumulated in corner order (x fastest), the same in both
//! widths.

use super::grid::HairGrid;
use crate::lanes::{Lane, V3};
use coif_base::lanes::{from_groups, F32Group, F32Lanes, GROUP_LANES, LANES};

/// The volume push per step, in cells per unit of the excess's gradient
/// (per cell), and its cap in cells.
pub const PUSH: f32 = 0.75;

/// What [`apply_block`] needs of the parameters, per step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GridSetup {
    pub volume: f32,
    pub friction: f32,
    pub dt: f32,
    /// The wind's pull `drag * wind` (m/s^2; zero in still air) and its
    /// unit direction.
    pub pull: glam::Vec3,
    pub wind_dir: glam::Vec3,
    /// `(sleep_speed dt)^2`: a vertex the grid moves less than this
    /// (squared, in position or previous position: a velocity change under
    /// `sleep_speed`) does not count as moved, so it wakes no sleeping
    /// block.
    pub wake_move2: f32,
}

/// How far upwind (cells) a vertex looks for the hair that shields it.
pub const UPWIND_CELLS: f32 = 1.0;
/// The share of the wind's pull that hair at its groomed density (or
/// denser) upwind takes away.
pub const WIND_SHIELD: f32 = 0.9;

/// The per-lane reads of the grid: `floor`, and the trilinear sum of the
/// seven fields over a cell's eight corners, one lane or a block's.
pub(crate) trait GridLane: Lane {
    fn floor(self) -> Self;
    /// `sum_c weights[c] F(base + offsets[c])`, accumulated in corner order
    /// by fused multiply-adds (`base` an integer-valued float, every node
    /// in range).
    fn trilinear(
        field: &[[f32; 8]],
        base: Self,
        offsets: [usize; 8],
        weights: [Self; 8],
    ) -> [Self; 7];
}

impl GridLane for f32 {
    #[inline(always)]
    fn floor(self) -> f32 {
        f32::floor(self)
    }
    #[inline(always)]
    fn trilinear(
        field: &[[f32; 8]],
        base: f32,
        offsets: [usize; 8],
        weights: [f32; 8],
    ) -> [f32; 7] {
        // One bounds check for the whole cell, as the SIMD path's per lane.
        let mut out = [0.0f32; 7];
        let at = base as u32 as usize;
        let Some(cell) = field.get(at..at + offsets[7] + 1) else {
            return out;
        };
        for (&off, w) in offsets.iter().zip(weights) {
            let n = cell[off];
            for k in 0..7 {
                out[k] = w.mul_add(n[k], out[k]);
            }
        }
        out
    }
}

impl GridLane for F32Lanes {
    #[inline(always)]
    fn floor(self) -> F32Lanes {
        F32Lanes::floor(self)
    }
    #[inline(always)]
    fn trilinear(
        field: &[[f32; 8]],
        base: F32Lanes,
        offsets: [usize; 8],
        weights: [F32Lanes; 8],
    ) -> [F32Lanes; 7] {
        // A node is eight floats, one register: each lane sums its eight
        // nodes' rows (the same multiply-adds in the same order as the
        // scalar twin, field by field), then one transpose. The corners
        // are the cell's four rows of two nodes (x fastest), one bounds
        // check per lane for the whole cell (`offsets[7] + 1` nodes from
        // its lowest); `base` is a whole number below 2^24.
        // In groups of eight lanes (one 8 x 8 transpose each; two groups
        // in a 16-lane build), the same per lane at either width.
        let base = base.trunc_int().to_array();
        let weights = weights.map(|w| w.to_array());
        let span = offsets[7] + 1;
        let mut groups = [[F32Group::ZERO; 8]; LANES / GROUP_LANES];
        for (k, fields) in groups.iter_mut().enumerate() {
            let mut rows = [F32Group::ZERO; 8];
            for (j, sum) in rows.iter_mut().enumerate() {
                let l = k * GROUP_LANES + j;
                let at = base[l] as u32 as usize;
                let Some(cell) = field.get(at..at + span) else {
                    continue;
                };
                for row in 0..4 {
                    let (c0, c1) = (2 * row, 2 * row + 1);
                    let pair = &cell[offsets[c0]..offsets[c0] + 2];
                    *sum = F32Group::splat(weights[c0][l]).mul_add(F32Group::new(pair[0]), *sum);
                    *sum = F32Group::splat(weights[c1][l]).mul_add(F32Group::new(pair[1]), *sum);
                }
            }
            *fields = F32Group::transpose(rows);
        }
        std::array::from_fn(|k| from_groups(groups.map(|g| g[k])))
    }
}

/// The seven fields at `p` (local frame), trilinearly.
#[inline(always)]
fn sample<T: GridLane>(g: &HairGrid, p: V3<T>) -> [T; 7] {
    let inv = T::splat(1.0 / g.cell);
    let zero = T::splat(0.0);
    let max_u = (g.dims - glam::UVec3::ONE).as_vec3();
    let max_i = (g.dims - glam::UVec3::splat(2)).as_vec3();
    let axis = |c: T, o: f32, mu: f32, mi: f32| {
        let u = ((c - T::splat(o)) * inv).max(zero).min(T::splat(mu));
        let i = u.floor().min(T::splat(mi));
        (i, u - i)
    };
    let (ix, fx) = axis(p.x, g.origin.x, max_u.x, max_i.x);
    let (iy, fy) = axis(p.y, g.origin.y, max_u.y, max_i.y);
    let (iz, fz) = axis(p.z, g.origin.z, max_u.z, max_i.z);
    let (nx, nxy) = (g.dims.x as usize, (g.dims.x * g.dims.y) as usize);
    let base = iz.mul_add(T::splat(nxy as f32), iy.mul_add(T::splat(nx as f32), ix));
    let one = T::splat(1.0);
    let (gx, gy, gz) = (one - fx, one - fy, one - fz);
    let offsets: [usize; 8] =
        std::array::from_fn(|c| (c & 1) + ((c >> 1) & 1) * nx + ((c >> 2) & 1) * nxy);
    let weights: [T; 8] = std::array::from_fn(|c| {
        let wx = if c & 1 == 1 { fx } else { gx };
        let wy = if (c >> 1) & 1 == 1 { fy } else { gy };
        let wz = if (c >> 2) & 1 == 1 { fz } else { gz };
        wx * wy * wz
    });
    T::trilinear(&g.field, base, offsets, weights)
}

/// Volume and friction for one block's free vertices (`w > 0`), weighted
/// by the root ramp of their rest arc `arc` (module doc, step 3). Returns
/// the lanes it moved by more than `sqrt(wake_move2)` (position or
/// previous position, `sleep_speed dt`): pressure or friction from awake
/// hair wakes a sleeping block when it would move it faster than the
/// speed below which hair sleeps. (With `1e-6` m instead, one strand
/// trembling on Sintel's bust at 1-4 cm/s kept its neighbours awake
/// through the grid's friction, and they theirs: 56-64 of her 228 guides
/// slept after 10 s at rest, 220 with this.)
pub(crate) fn apply_block<T: GridLane>(
    g: &HairGrid,
    pos: &mut [V3<T>],
    prev: &mut [V3<T>],
    w: &[T],
    arc: &[T],
    k: &GridSetup,
) -> T::Mask {
    let mut moved = !T::all_lanes();
    if !g.live {
        return moved;
    }
    let zero = T::splat(0.0);
    let quarter = T::splat(PUSH * g.cell);
    let volume = T::splat(k.volume * PUSH * g.cell);
    let friction = T::splat(k.friction);
    let inv_ramp = T::splat(1.0 / super::ROOT_RAMP);
    let tiny = T::splat(1.0e-12);
    let wake = T::splat(k.wake_move2.max(1.0e-12));
    let shielded = k.pull.length_squared() > 0.0 && k.pull.is_finite();
    let upwind = V3::splat(k.wind_dir * (UPWIND_CELLS * g.cell));
    let pull_dt = V3::splat(k.pull * k.dt);
    let shield_share = T::splat(WIND_SHIELD);
    for ((x, xp), (&w, &a)) in pos.iter_mut().zip(prev.iter_mut()).zip(w.iter().zip(arc)) {
        let free = w.gt(zero);
        if !T::any(free) {
            continue;
        }
        let ramp = (a * inv_ramp).max(zero).min(T::splat(1.0));
        let f = sample(g, *x);
        // Volume: down the excess's gradient, at most a quarter cell.
        let mut d = V3::new(f[0], f[1], f[2]) * -volume;
        let d2 = d.dot(d);
        let cap = (quarter * d2.max(tiny).inv_sqrt()).min(T::splat(1.0));
        d = d * (cap * ramp);
        // Friction: the velocity toward the hair's.
        let vel = (*x - *xp) * T::splat(1.0 / k.dt);
        let mut dv = (V3::new(f[3], f[4], f[5]) - vel) * (friction * ramp);
        // Wind shielded by the hair upwind: the pull's share taken away.
        if shielded {
            let up = sample(g, *x - upwind)[6];
            let shield = up.max(zero).min(T::splat(1.0)) * (shield_share * ramp);
            dv = dv - pull_dt * shield;
        }
        // Volume as a velocity: along the push `n`, the vertex leaves the
        // denser hair at least at the push's speed `|d| / dt` (a contact
        // that separates: its normal velocity is raised, never lowered),
        // and the solver's substeps carry it there with its strand.
        let dl2 = d.dot(d);
        let pushed = dl2.gt(tiny);
        let inv_l = dl2.max(tiny).inv_sqrt();
        let n = d * inv_l;
        let speed = dl2 * inv_l * T::splat(1.0 / k.dt);
        let vn = (vel + dv).dot(n);
        let raise = (speed - vn).max(zero);
        dv = V3::select(pushed, dv + n * raise, dv);
        let new_x = *x;
        let new_prev = *xp - dv * T::splat(k.dt);
        let change = d.dot(d).max((new_prev - *xp).dot(new_prev - *xp));
        moved = moved | (free & change.gt(wake));
        *x = V3::select(free, new_x, *x);
        *xp = V3::select(free, new_prev, *xp);
    }
    moved
}
