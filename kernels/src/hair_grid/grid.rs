//! The grid of the hair: splat, smoothing, fields (module doc, steps 1-2).

use super::{MAX_HAIR_GRID_NODES, ROOT_RAMP};
use crate::lanes::{groups, F32Group, Vec3Lanes, GROUP_LANES, LANES, V3};
use crate::Strands;
use coif_base::lanes::F32Lanes;
use glam::{UVec3, Vec3};

/// Jacobi sweeps of the pressure solve per step (module doc, step 2):
/// measured on the draped head against pushing down the excess's own
/// gradient (`kernels/README.md`, "Hair against hair").
pub const JACOBI_SWEEPS: usize = 10;

/// Empty nodes kept round the hair's box on every side (the central
/// differences reach one node past the splat's).
const PAD: u32 = 2;

/// The grid of one step and the target density, sized once.
#[derive(Clone, Debug, Default)]
pub(crate) struct HairGrid {
    /// Per node: `[sum s, sum s vx, sum s vy, sum s vz]`; zero at every
    /// node but this step's `touched` ones.
    acc: Vec<[f32; 4]>,
    /// Per node: `[dp/dx, dp/dy, dp/dz (per cell), vx, vy, vz, rho /
    /// rho_0, 0]` with `p` the pressure, valid at the touched nodes.
    pub(crate) field: Vec<[f32; 8]>,
    /// The nodes this step's splat gave weight, cell by cell in the order
    /// the splat first reached each cell, corner order within a cell.
    touched: Vec<u32>,
    /// The cells (by their lowest node) this step's splat reached, in the
    /// order it first reached them.
    cells: Vec<u32>,
    /// Per node: the splat's `stamp` when its cell (the node as a cell's
    /// lowest corner) was listed in `cells`, and when the node was listed
    /// in `touched` (no clearing between steps).
    cell_mark: Vec<u32>,
    node_mark: Vec<u32>,
    /// This splat's number (marks equal to it are this step's).
    stamp: u32,
    /// The pressure at every node and its next sweep; zero between steps.
    pressure: Vec<f32>,
    pressure_next: Vec<f32>,
    /// The excess `max(rho / rho_0 - 1, 0)` of each `touched` node.
    excess: Vec<f32>,
    /// Nodes the buffers hold (set at the first build, never grown).
    capacity: usize,
    /// This step's grid, in the strands' local frame.
    pub(crate) origin: Vec3,
    pub(crate) cell: f32,
    pub(crate) dims: UVec3,
    /// Whether this step's grid holds any hair.
    pub(crate) live: bool,
    /// Target density, weight per m^3 (`None` until the first build).
    target: Option<f32>,
    /// The groomed pose gridded for the target, kept so that a target
    /// computed again (after `Strands::set_hair_shares`) allocates nothing.
    pose: Vec<Vec3Lanes>,
}

/// Farther than this from the strands' origin (metres), a vertex is out
/// of the grid: a strand thrown away by a bad state (which the step's
/// guard then restores) does not stretch the grid over every other one.
const MAX_GRID_REACH: f32 = 1.0e4;
/// The fastest a vertex's velocity counts in the grid (m/s): one strand
/// gone wild does not drag the hair around it.
const MAX_GRID_SPEED: f32 = 100.0;

impl HairGrid {
    /// Forgets the target (the strands' shares changed): the next build
    /// computes it again.
    pub(crate) fn forget_target(&mut self) {
        self.target = None;
    }

    /// The target density (weight per m^3): the densest node of the
    /// groomed pose (roots plus rest offsets under the rest rotation),
    /// gridded at `cell` as the step grids the hair; computed once.
    pub(crate) fn target(&mut self, s: &Strands, cell: f32) -> f32 {
        if let Some(t) = self.target {
            return t;
        }
        let mut pose = std::mem::take(&mut self.pose);
        pose.clear();
        pose.resize(s.blocks * s.verts, Vec3Lanes::ZERO);
        for b in 0..s.blocks {
            for v in 0..s.verts {
                let root = s.roots[b];
                let off = s.rest_offset[b * s.verts + v];
                let mut p = Vec3Lanes::ZERO;
                for l in 0..LANES {
                    p.set_lane(l, root.lane(l) + s.rest_rotation * off.lane(l));
                }
                pose[b * s.verts + v] = p;
            }
        }
        // The same grid as a step's, with zero velocity.
        self.splat(s, &pose, &pose, 1.0, cell);
        self.pose = pose;
        let inv_volume = 1.0 / (self.cell * self.cell * self.cell);
        let densest = self
            .touched
            .iter()
            .map(|&i| self.acc[i as usize][0])
            .fold(0.0f32, f32::max)
            * inv_volume;
        // No hair away from the roots: any density is excess-free.
        let t = if densest > 0.0 {
            densest
        } else {
            f32::INFINITY
        };
        self.target = Some(t);
        self.live = false;
        t
    }

    /// Steps 1-2 of the module doc for this step's positions `pos` and
    /// previous ones `prev` (local frame, one step of `dt` apart).
    pub(crate) fn build(
        &mut self,
        s: &Strands,
        pos: &[Vec3Lanes],
        prev: &[Vec3Lanes],
        dt: f32,
        cell: f32,
    ) {
        let target = self.target(s, cell);
        self.splat(s, pos, prev, dt, cell);
        if !self.live {
            return;
        }
        let inv_target = 1.0 / (target * self.cell * self.cell * self.cell);
        let (nx, ny, nz) = (
            self.dims.x as usize,
            self.dims.y as usize,
            self.dims.z as usize,
        );
        let acc = &self.acc;
        let (sy, sz) = (nx, nx * ny);
        let _ = nz;
        // The excess `e` per touched node, in their order.
        self.excess.clear();
        self.excess.extend(
            self.touched
                .iter()
                .map(|&t| (acc[t as usize][0] * inv_target - 1.0).max(0.0)),
        );
        // The pressure: `JACOBI_SWEEPS` Jacobi sweeps of `-lap(p) = e` (grid
        // units) over the hair's nodes, `p = 0` where there is no hair,
        // from zero; two buffers, node order fixed: the same bytes always.
        // With no excess anywhere every sweep gives zero: none is run.
        let sweeps = if self.excess.iter().any(|&e| e > 0.0) {
            JACOBI_SWEEPS
        } else {
            0
        };
        for _ in 0..sweeps {
            let (p, next) = (&self.pressure[..], &mut self.pressure_next[..]);
            for (&t, &e) in self.touched.iter().zip(&self.excess) {
                let i = t as usize;
                let around =
                    (p[i + 1] + p[i - 1]) + (p[i + sy] + p[i - sy]) + (p[i + sz] + p[i - sz]);
                next[i] = (around + e) * (1.0 / 6.0);
            }
            std::mem::swap(&mut self.pressure, &mut self.pressure_next);
        }
        let q = |i: usize| self.pressure[i];
        for &t in &self.touched {
            let i = t as usize;
            // Touched nodes lie at least PAD - 1 nodes inside the box, so
            // every neighbour exists.
            let g = [
                0.5 * (q(i + 1) - q(i - 1)),
                0.5 * (q(i + sy) - q(i - sy)),
                0.5 * (q(i + sz) - q(i - sz)),
            ];
            let a = acc[i];
            let v = [a[1] / a[0], a[2] / a[0], a[3] / a[0]];
            let relative = a[0] * inv_target;
            self.field[i] = [g[0], g[1], g[2], v[0], v[1], v[2], relative, 0.0];
        }
        // Zero again for the next step's sweeps (they read untouched
        // neighbours as zero).
        for &t in &self.touched {
            self.pressure[t as usize] = 0.0;
            self.pressure_next[t as usize] = 0.0;
        }
    }

    /// Step 1: the last step's nodes cleared, the grid's box from the
    /// finite vertices, the cell (coarser when the box needs more nodes
    /// than the buffers hold), and the trilinear (cloud-in-cell) splat of
    /// weight and momentum in block, vertex and lane order.
    fn splat(&mut self, s: &Strands, pos: &[Vec3Lanes], prev: &[Vec3Lanes], dt: f32, cell: f32) {
        // Only listed nodes hold weight; the corners of listed cells that
        // the splat gave none were written with zero weight and are zero.
        for &i in &self.touched {
            self.acc[i as usize] = [0.0; 4];
        }
        self.touched.clear();
        self.cells.clear();
        if self.stamp == u32::MAX {
            self.cell_mark.fill(0);
            self.node_mark.fill(0);
            self.stamp = 0;
        }
        self.stamp += 1;
        // A cell that is not a finite positive length (the step takes
        // `SimParams` unvalidated) grids nothing: 0 never grew coarser, and
        // NaN or infinity put every vertex on node 0.
        if !(cell.is_finite() && cell > 0.0) {
            self.live = false;
            return;
        }
        // The box of the strands' lanes (not the padding) with every
        // coordinate within reach, a block at a time (min and max are
        // exact: the same box in any order; a lane out of reach, NaN
        // included, is not selected, so the fast min and max serve).
        let reach = F32Lanes::splat(MAX_GRID_REACH);
        let (mut lo8, mut hi8) = (
            Vec3Lanes::splat(Vec3::splat(f32::INFINITY)),
            Vec3Lanes::splat(Vec3::splat(f32::NEG_INFINITY)),
        );
        for (b, &active) in s.active.iter().enumerate().take(s.blocks) {
            for x in &pos[b * s.verts..(b + 1) * s.verts] {
                let ok = active
                    & x.x.abs().simd_lt(reach)
                    & x.y.abs().simd_lt(reach)
                    & x.z.abs().simd_lt(reach);
                lo8 = Vec3Lanes::new(
                    F32Lanes::select(ok, lo8.x.fast_min(x.x), lo8.x),
                    F32Lanes::select(ok, lo8.y.fast_min(x.y), lo8.y),
                    F32Lanes::select(ok, lo8.z.fast_min(x.z), lo8.z),
                );
                hi8 = Vec3Lanes::new(
                    F32Lanes::select(ok, hi8.x.fast_max(x.x), hi8.x),
                    F32Lanes::select(ok, hi8.y.fast_max(x.y), hi8.y),
                    F32Lanes::select(ok, hi8.z.fast_max(x.z), hi8.z),
                );
            }
        }
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for l in 0..LANES {
            lo = lo.min(lo8.lane(l));
            hi = hi.max(hi8.lane(l));
        }
        self.live = lo.x <= hi.x;
        if !self.live {
            return;
        }
        let extent = hi - lo;
        let mut cell = cell;
        let nodes = |cell: f32| -> f64 {
            (0..3)
                .map(|a| ((extent[a] / cell).ceil() as f64 + 1.0 + 2.0 * PAD as f64).max(1.0))
                .product()
        };
        if self.capacity == 0 {
            // Sized once: room for the box twice as large along each axis,
            // and for eight nodes per vertex.
            let want = (nodes(cell) * 8.0).clamp(32.0 * 32.0 * 32.0, MAX_HAIR_GRID_NODES as f64);
            self.capacity = want as usize;
            self.acc = vec![[0.0; 4]; self.capacity];
            self.field = vec![[0.0; 8]; self.capacity];
            self.pressure = vec![0.0; self.capacity];
            self.pressure_next = vec![0.0; self.capacity];
            self.touched = Vec::with_capacity(self.capacity);
            self.excess = Vec::with_capacity(self.capacity);
            self.cells = Vec::with_capacity(self.capacity);
            self.cell_mark = vec![0; self.capacity];
            self.node_mark = vec![0; self.capacity];
        }
        // (A NaN count is never small enough: the loop ends at an infinite cell.)
        while nodes(cell).is_nan() || nodes(cell) > self.capacity as f64 {
            cell *= 1.25;
            if !cell.is_finite() {
                self.live = false;
                return;
            }
        }
        let dims = UVec3::new(
            ((extent.x / cell).ceil() as u32) + 1 + 2 * PAD,
            ((extent.y / cell).ceil() as u32) + 1 + 2 * PAD,
            ((extent.z / cell).ceil() as u32) + 1 + 2 * PAD,
        );
        self.dims = dims;
        self.cell = cell;
        self.origin = lo - Vec3::splat(PAD as f32 * cell);
        let (nx, ny) = (dims.x as usize, dims.y as usize);
        // Eight lanes at a time (a 16-lane block as two groups of eight,
        // so that the sums into a node come in the same order at either
        // width): weights, velocities and the eight corner weights in one
        // `f32x8` each, then the writes lane by lane, corner by corner.
        let reach8 = F32Group::splat(MAX_GRID_REACH);
        let inv_cell = F32Group::splat(1.0 / cell);
        let inv_dt = F32Group::splat(1.0 / dt);
        let zero = F32Group::ZERO;
        let one = F32Group::ONE;
        let max_i = (dims - UVec3::splat(2)).as_vec3();
        let origin = V3::<F32Group>::splat(self.origin);
        let stamp = self.stamp;
        let (nxy, span) = (nx * ny, nx * ny + nx + 2);
        let acc = &mut self.acc[..];
        let (cells, cell_mark) = (&mut self.cells, &mut self.cell_mark[..]);
        let group =
            |x: Vec3Lanes, k: usize| V3::new(groups(x.x)[k], groups(x.y)[k], groups(x.z)[k]);
        for (b, k) in (0..s.blocks).flat_map(|b| (0..LANES / GROUP_LANES).map(move |k| (b, k))) {
            let lanes = s
                .lanes_in_block(b)
                .saturating_sub(k * GROUP_LANES)
                .min(GROUP_LANES);
            if lanes == 0 {
                continue;
            }
            let base = b * s.verts;
            let hair_share = groups(s.hair_share[b])[k];
            for v in 0..s.verts {
                let (x, xp) = (group(pos[base + v], k), group(prev[base + v], k));
                let (reach, rest_arc) = (reach8, groups(s.rest_arc[base + v])[k]);
                let inside =
                    x.x.abs().simd_lt(reach) & x.y.abs().simd_lt(reach) & x.z.abs().simd_lt(reach);
                let weight = (rest_arc * F32Group::splat(1.0 / ROOT_RAMP))
                    .max(zero)
                    .min(one);
                let weight = F32Group::select(inside, weight * hair_share, zero);
                if weight.simd_gt(zero).to_bitmask() == 0 {
                    continue;
                }
                let vel = (x - xp) * inv_dt;
                let speed2 = vel.dot(vel);
                let scale = (F32Group::splat(MAX_GRID_SPEED)
                    * speed2.max(F32Group::splat(1e-30)).sqrt().recip())
                .min(one);
                let vel = vel * scale;
                let finite = vel.x.is_finite() & vel.y.is_finite() & vel.z.is_finite();
                let vel = V3::new(
                    F32Group::select(finite, vel.x, zero),
                    F32Group::select(finite, vel.y, zero),
                    F32Group::select(finite, vel.z, zero),
                );
                let u = (x - origin) * inv_cell;
                let axis = |u: F32Group, m: f32| {
                    let i = u.floor().max(zero).min(F32Group::splat(m));
                    (i, (u - i).max(zero).min(one))
                };
                let (ix, fx) = axis(u.x, max_i.x);
                let (iy, fy) = axis(u.y, max_i.y);
                let (iz, fz) = axis(u.z, max_i.z);
                // Whole numbers below 2^24 (at most MAX_HAIR_GRID_NODES):
                // exact in f32 and in the integer conversion.
                let node = iz
                    .mul_add(
                        F32Group::splat((nx * ny) as f32),
                        iy.mul_add(F32Group::splat(nx as f32), ix),
                    )
                    .trunc_int();
                let (gx, gy, gz) = (one - fx, one - fy, one - fz);
                // Per lane (after the transposes): the eight corner weights,
                // and `[1, v, 1, v]`.
                let corner = F32Group::transpose(std::array::from_fn(|c| {
                    weight
                        * if c & 1 == 1 { fx } else { gx }
                        * if (c >> 1) & 1 == 1 { fy } else { gy }
                        * if (c >> 2) & 1 == 1 { fz } else { gz }
                }));
                let unit =
                    F32Group::transpose([one, vel.x, vel.y, vel.z, one, vel.x, vel.y, vel.z]);
                let (node, weight) = (node.to_array(), weight.to_array());
                for l in 0..lanes {
                    if weight[l] <= 0.0 {
                        continue;
                    }
                    // One 32-byte multiply-add per row of two nodes, to all
                    // eight corners (a corner of zero weight adds zero), in
                    // corner order, x fastest: the cell's four rows. Each
                    // float is the same fused multiply-add as one 16-byte
                    // multiply-add per node.
                    let cell_node = node[l] as u32 as usize;
                    let Some(block) = acc.get_mut(cell_node..cell_node + span) else {
                        continue;
                    };
                    if cell_mark[cell_node] != stamp {
                        cell_mark[cell_node] = stamp;
                        cells.push(cell_node as u32);
                    }
                    for (row, at) in [0, nx, nxy, nxy + nx].into_iter().enumerate() {
                        let Ok(pair): Result<&mut [f32; 8], _> =
                            block[at..at + 2].as_flattened_mut().try_into()
                        else {
                            continue;
                        };
                        let w = row_weights(corner[l], row);
                        *pair = unit[l].mul_add(w, F32Group::new(*pair)).to_array();
                    }
                }
            }
        }
        // The nodes that took weight, cell by cell: the pressure solve
        // and the fields run over them (the same set whatever the order).
        let node_mark = &mut self.node_mark[..];
        for &c in cells.iter() {
            let c = c as usize;
            for at in [0, 1, nx, nx + 1, nxy, nxy + 1, nxy + nx, nxy + nx + 1] {
                let i = c + at;
                if acc[i][0] > 0.0 && node_mark[i] != stamp {
                    node_mark[i] = stamp;
                    self.touched.push(i as u32);
                }
            }
        }
    }
}

/// `[w_2r x4, w_2r+1 x4]` from a lane's eight corner weights `w`: the
/// weights of the cell's row `r` of two nodes, four floats each.
#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
#[inline(always)]
fn row_weights(w: F32Group, row: usize) -> F32Group {
    use std::arch::x86_64::{__m256, __m256i, _mm256_permutevar8x32_ps};
    let (a, b) = (2 * row as i32, 2 * row as i32 + 1);
    let index: __m256i = wide::bytemuck::cast(wide::i32x8::new([a, a, a, a, b, b, b, b]));
    let w: __m256 = wide::bytemuck::cast(w);
    // SAFETY: AVX2 is enabled (cfg above); the permute reads only its two
    // register operands.
    wide::bytemuck::cast(unsafe { _mm256_permutevar8x32_ps(w, index) })
}

/// Plain moves where AVX2 is not enabled.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
#[inline(always)]
fn row_weights(w: F32Group, row: usize) -> F32Group {
    let w = w.to_array();
    let (a, b) = (w[2 * row], w[2 * row + 1]);
    F32Group::new([a, a, a, a, b, b, b, b])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One straight strand along +x, 41 vertices 5 mm apart.
    fn line() -> Strands {
        let pts: Vec<Vec3> = (0..41).map(|i| Vec3::X * (0.005 * i as f32)).collect();
        Strands::from_polylines(&pts, 41).unwrap()
    }

    #[test]
    fn the_splat_keeps_the_weight_and_the_momentum() {
        let s = line();
        let mut g = HairGrid::default();
        // Everything moves at (0, 1, 0) m/s over a step of 0.1 s.
        let prev: Vec<Vec3Lanes> = s
            .pos
            .iter()
            .map(|p| *p - Vec3Lanes::splat(Vec3::Y * 0.1))
            .collect();
        g.build(&s, &s.pos, &prev, 0.1, 0.01);
        assert!(g.live);
        let n = (g.dims.x * g.dims.y * g.dims.z) as usize;
        let total: f32 = g.acc[..n].iter().map(|a| a[0]).sum();
        let expected: f32 = (0..41)
            .map(|i| (0.005 * i as f32 / ROOT_RAMP).clamp(0.0, 1.0))
            .sum();
        assert!((total - expected).abs() < 1e-3, "{total} {expected}");
        let py: f32 = g.acc[..n].iter().map(|a| a[2]).sum();
        assert!((py - expected).abs() < 1e-3, "{py}");
        // The hair's velocity is (0, 1, 0) wherever there is hair.
        for &i in &g.touched {
            let (a, f) = (g.acc[i as usize][0], g.field[i as usize]);
            if a > 1e-3 {
                assert!((f[4] - 1.0).abs() < 1e-4 && f[3].abs() < 1e-4, "{f:?}");
            }
        }
        // The groomed pose is the target: no excess anywhere.
        assert!(g
            .touched
            .iter()
            .all(|&i| g.field[i as usize][..3] == [0.0; 3]));
    }

    #[test]
    fn a_rows_weights_repeat_its_two_corners_four_times() {
        let w = F32Group::new([0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5]);
        for row in 0..4 {
            let (a, b) = (w.as_array()[2 * row], w.as_array()[2 * row + 1]);
            assert_eq!(row_weights(w, row).to_array(), [a, a, a, a, b, b, b, b]);
        }
    }

    #[test]
    fn a_far_strand_coarsens_the_grid_without_allocating() {
        let pts: Vec<Vec3> = (0..16)
            .map(|i| Vec3::X * (0.005 * (i % 8) as f32) + Vec3::Y * if i < 8 { 0.0 } else { 1.0 })
            .collect();
        let s = Strands::from_polylines(&pts, 8).unwrap();
        let mut g = HairGrid::default();
        g.build(&s, &s.pos, &s.pos, 1.0 / 60.0, 0.01);
        let cap = g.capacity;
        let mut far = s.pos.clone();
        for p in &mut far {
            let q = p.lane(1) + Vec3::Y * 5.0e3;
            p.set_lane(1, q);
        }
        g.build(&s, &far, &far, 1.0 / 60.0, 0.01);
        assert_eq!(g.capacity, cap);
        assert!(
            (g.dims.x * g.dims.y * g.dims.z) as usize <= cap && g.cell > 0.1,
            "{}",
            g.cell
        );
        // Beyond the grid's reach, a strand is left out: the cell is back.
        for p in &mut far {
            let q = p.lane(1) + Vec3::Y * 1.0e6;
            p.set_lane(1, q);
        }
        g.build(&s, &far, &far, 1.0 / 60.0, 0.01);
        assert_eq!(g.cell, 0.01);
        // A NaN strand is left out.
        far[3].set_lane(0, Vec3::NAN);
        g.build(&s, &far, &far, 1.0 / 60.0, 0.01);
        assert!(g.live && g.cell.is_finite());
    }
}
