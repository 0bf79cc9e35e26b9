//! The grid of the hair: splat, smoothing, fields (module doc, steps 1-2).

use super::{MAX_HAIR_GRID_NODES, ROOT_RAMP};
use crate::lanes::{groups, F32Group, Vec3Lanes, GROUP_LANES, LANES, V3};
use crate::Strands;
use coif_base::lanes::{block_of_group, F32Lanes, GROUPS_PER_BLOCK};
use coif_base::tasks::{for_each_chunk_mut, Executor, Serial};
use glam::{UVec3, Vec3};
use std::ops::Range;
use wide::i32x8 as I32Group;

/// Jacobi sweeps of the pressure solve per step (module doc, step 2):
/// measured on the draped head against pushing down the excess's own
/// gradient (`kernels/README.md`, "Hair against hair").
pub const JACOBI_SWEEPS: usize = 10;

/// Empty nodes kept round the hair's box on every side (the central
/// differences reach one node past the splat's).
const PAD: u32 = 2;

/// The most parts the splat is cut into (one per thread up to this):
/// each part past the first costs a grid of its own (20 bytes per node
/// of the buffers' capacity) and its nodes' merge.
pub const MAX_SPLAT_PARTS: usize = 4;

/// Bits of headroom kept in every node's 32-bit sum: with each term at
/// most `2^weight_bits` and at most `N` terms per node (one per vertex
/// lane), `weight_bits = SUM_BITS - ceil(log2 N)` keeps every sum below
/// `2^30`, whatever the hair does (every vertex in one cell included).
const SUM_BITS: i32 = 30;

/// The slowest speed bound the momentum's scale follows (m/s, a power of
/// two): below it the scale stops growing.
const MIN_SPEED_BITS: i32 = -20;

/// One part of the splat: the sums of its run of lane groups, in fixed
/// point, the cells it reached and the nodes that took weight. Part 0's
/// sums become the grid's.
#[derive(Clone, Debug, Default)]
struct SplatPart {
    /// Per node: `[sum s, sum s vx, sum s vy, sum s vz]` in fixed point
    /// (`HairGrid::weight_unit`, `velocity_unit`); zero at every node but
    /// the ones its last splat listed in `nodes` (part 0: the grid's
    /// `touched`).
    acc: Vec<[i32; 4]>,
    /// The cells (by their lowest node) this part reached, in the order
    /// it first reached them.
    cells: Vec<u32>,
    /// The nodes of those cells that took weight, cell by cell, corner
    /// order within a cell.
    nodes: Vec<u32>,
    /// Per node: the splat's `stamp` when its cell (the node as a cell's
    /// lowest corner) was listed in `cells`, and when the node was listed
    /// in `nodes` (no clearing between steps).
    cell_mark: Vec<u32>,
    node_mark: Vec<u32>,
}

impl SplatPart {
    fn new(capacity: usize) -> Self {
        SplatPart {
            acc: vec![[0; 4]; capacity],
            cells: Vec::with_capacity(capacity),
            nodes: Vec::with_capacity(capacity),
            cell_mark: vec![0; capacity],
            node_mark: vec![0; capacity],
        }
    }
}

/// The grid of one step and the target density, sized once.
#[derive(Clone, Debug, Default)]
pub(crate) struct HairGrid {
    /// The splat's parts; the first holds the step's sums after the merge.
    parts: Vec<SplatPart>,
    /// Per node: `[dp/dx, dp/dy, dp/dz (per cell), vx, vy, vz, rho /
    /// rho_0, 0]` with `p` the pressure, valid at the touched nodes.
    pub(crate) field: Vec<[f32; 8]>,
    /// The nodes this step's splat gave weight: part 0's, then each other
    /// part's new ones. Nothing depends on this order: every node's
    /// pressure sweep and field reads its neighbours alone.
    touched: Vec<u32>,
    /// This splat's number (marks equal to it are this step's).
    stamp: u32,
    /// One unit of a node's weight sum in weight (`2^-weight_bits`), and
    /// the velocity of a node whose momentum and weight sums are equal
    /// (`2^(weight_bits - momentum_bits)`, m/s).
    weight_unit: f32,
    velocity_unit: f32,
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

/// What every part of one splat shares: the grid's placement, the fixed
/// point's scales and the step's vertices.
struct SplatSetup<'a> {
    s: &'a Strands,
    pos: &'a [Vec3Lanes],
    prev: &'a [Vec3Lanes],
    origin: Vec3,
    cell: f32,
    dt: f32,
    dims: UVec3,
    stamp: u32,
    /// `2^weight_bits` and `2^momentum_bits`.
    weight_scale: f32,
    momentum_scale: f32,
    /// Every velocity component is clamped to `[-speed_bound, speed_bound]`
    /// (m/s, `2^(weight_bits - momentum_bits)`), so that no term exceeds
    /// `2^weight_bits`.
    speed_bound: f32,
    /// The largest hair share (1 where every share is 0): weights are
    /// shares over it, at most 1.
    share_max: f32,
}

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
        self.splat(s, &pose, &pose, 1.0, cell, &Serial);
        self.pose = pose;
        let unit = self.weight_unit / (self.cell * self.cell * self.cell);
        let acc = &self.parts[0].acc;
        let densest = self
            .touched
            .iter()
            .map(|&i| acc[i as usize][0] as f32)
            .fold(0.0f32, f32::max)
            * unit;
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
    /// previous ones `prev` (local frame, one step of `dt` apart), the
    /// splat's parts run as tasks of `executor`.
    pub(crate) fn build(
        &mut self,
        s: &Strands,
        pos: &[Vec3Lanes],
        prev: &[Vec3Lanes],
        dt: f32,
        cell: f32,
        executor: &dyn Executor,
    ) {
        let target = self.target(s, cell);
        self.splat(s, pos, prev, dt, cell, executor);
        if !self.live {
            return;
        }
        // Weight per unit of a node's sum, over the target's weight per node.
        let inv_target = self.weight_unit / (target * self.cell * self.cell * self.cell);
        let (nx, ny) = (self.dims.x as usize, self.dims.y as usize);
        let acc = &self.parts[0].acc;
        let (sy, sz) = (nx, nx * ny);
        // The excess `e` per touched node, in their order.
        self.excess.clear();
        self.excess.extend(
            self.touched
                .iter()
                .map(|&t| (acc[t as usize][0] as f32 * inv_target - 1.0).max(0.0)),
        );
        // The pressure: `JACOBI_SWEEPS` Jacobi sweeps of `-lap(p) = e` (grid
        // units) over the hair's nodes, `p = 0` where there is no hair,
        // from zero; two buffers, each node from its neighbours alone: the
        // same bytes in any order.
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
        let velocity_unit = self.velocity_unit;
        for &t in &self.touched {
            let i = t as usize;
            // Touched nodes lie at least PAD - 1 nodes inside the box, so
            // every neighbour exists.
            let g = [
                0.5 * (q(i + 1) - q(i - 1)),
                0.5 * (q(i + sy) - q(i - sy)),
                0.5 * (q(i + sz) - q(i - sz)),
            ];
            let a = acc[i].map(|x| x as f32);
            let per = velocity_unit / a[0];
            let v = [a[1] * per, a[2] * per, a[3] * per];
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
    /// than the buffers hold), the fixed point's scales, and the trilinear
    /// (cloud-in-cell) splat of weight and momentum: the lane groups cut
    /// into parts (one per thread of `executor`, at most
    /// [`MAX_SPLAT_PARTS`]), each part's sums in its own grid as a task,
    /// then the other parts' nodes added into part 0's. The sums are
    /// integers, so they are the same bytes in any grouping: with any
    /// number of parts and threads.
    fn splat(
        &mut self,
        s: &Strands,
        pos: &[Vec3Lanes],
        prev: &[Vec3Lanes],
        dt: f32,
        cell: f32,
        executor: &dyn Executor,
    ) {
        if self.parts.is_empty() {
            self.parts.push(SplatPart::default());
        }
        // (Each part clears its last splat's nodes in its task, so a grid
        // that is not live keeps its lists until the next one that is.)
        if self.stamp == u32::MAX {
            for p in &mut self.parts {
                p.cell_mark.fill(0);
                p.node_mark.fill(0);
            }
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
        // coordinate within reach, and their largest velocity component
        // over the step (finite ones), a block at a time (min and max are
        // exact: the same box in any order; a lane out of reach, NaN
        // included, is not selected, so the fast min and max serve).
        let reach = F32Lanes::splat(MAX_GRID_REACH);
        let (mut lo8, mut hi8) = (
            Vec3Lanes::splat(Vec3::splat(f32::INFINITY)),
            Vec3Lanes::splat(Vec3::splat(f32::NEG_INFINITY)),
        );
        let mut moved8 = F32Lanes::ZERO;
        for (b, &active) in s.active.iter().enumerate().take(s.blocks) {
            let r = b * s.verts..(b + 1) * s.verts;
            for (x, xp) in pos[r.clone()].iter().zip(&prev[r]) {
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
                let d = *x - *xp;
                let d = d.x.abs().fast_max(d.y.abs()).fast_max(d.z.abs());
                // NaN and infinity fail `< reach`: not selected.
                moved8 = F32Lanes::select(ok & d.simd_lt(reach), moved8.fast_max(d), moved8);
            }
        }
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let mut moved = 0.0f32;
        for l in 0..LANES {
            lo = lo.min(lo8.lane(l));
            hi = hi.max(hi8.lane(l));
            moved = moved.max(moved8.as_array()[l]);
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
            self.parts[0] = SplatPart::new(self.capacity);
            self.field = vec![[0.0; 8]; self.capacity];
            self.pressure = vec![0.0; self.capacity];
            self.pressure_next = vec![0.0; self.capacity];
            self.touched = Vec::with_capacity(self.capacity);
            self.excess = Vec::with_capacity(self.capacity);
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
        // The fixed point: at most N terms per node (one per vertex lane),
        // each at most 2^weight_bits, so every sum stays below 2^30. The
        // momentum's terms are weight times a velocity component clamped
        // to 2^speed_bits (the step's largest, at most MAX_GRID_SPEED), at
        // 2^(weight_bits - speed_bits): no larger than the weight's bound,
        // and as fine as the step's speeds allow.
        let lanes_total = (s.blocks * LANES * s.verts).max(2);
        let weight_bits = SUM_BITS - (usize::BITS - (lanes_total - 1).leading_zeros()) as i32;
        // (NaN, from a zero or NaN dt, takes the widest.)
        let fastest = (moved / dt).min(MAX_GRID_SPEED);
        let fastest = if fastest.is_nan() {
            MAX_GRID_SPEED
        } else {
            fastest
        };
        let mut speed_bits = MIN_SPEED_BITS;
        while speed_bits < 7 && pow2(speed_bits) < fastest {
            speed_bits += 1;
        }
        self.weight_unit = pow2(-weight_bits);
        self.velocity_unit = pow2(speed_bits);
        let share_max = s
            .hair_share
            .iter()
            .take(s.blocks)
            .map(|h| h.as_array().iter().copied().fold(0.0f32, f32::max))
            .fold(0.0f32, f32::max);
        let setup = SplatSetup {
            s,
            pos,
            prev,
            origin: self.origin,
            cell,
            dt,
            dims,
            stamp: self.stamp,
            weight_scale: pow2(weight_bits),
            momentum_scale: pow2(weight_bits - speed_bits),
            speed_bound: pow2(speed_bits),
            share_max: if share_max > 0.0 { share_max } else { 1.0 },
        };
        let groups = s.blocks * GROUPS_PER_BLOCK;
        let parts = executor
            .threads()
            .clamp(1, MAX_SPLAT_PARTS)
            .min(groups.max(1));
        // A thread count seen for the first time sizes its parts (once).
        while self.parts.len() < parts {
            self.parts.push(SplatPart::new(self.capacity));
        }
        let run = |k: usize| groups * k / parts..groups * (k + 1) / parts;
        // Part 0 clears the grid's last nodes (its own and the other parts'
        // it took in), every other part its own.
        let (last, parts_all) = (&self.touched[..], &mut self.parts[..parts]);
        if parts == 1 {
            splat_part(&mut parts_all[0], &setup, run(0), Some(last));
        } else {
            for_each_chunk_mut(executor, parts_all, 1, &|k, part| {
                if let Some(part) = part.first_mut() {
                    splat_part(part, &setup, run(k), (k == 0).then_some(last));
                }
            });
        }
        // The other parts' nodes into part 0: their sums added (integers:
        // the same sums in any grouping), the nodes new to part 0 listed.
        let stamp = self.stamp;
        if let Some((first, rest)) = self.parts.split_first_mut() {
            for part in &rest[..parts - 1] {
                for &n in &part.nodes {
                    let i = n as usize;
                    let add = part.acc[i];
                    for (x, a) in first.acc[i].iter_mut().zip(add) {
                        *x = x.wrapping_add(a);
                    }
                    if first.node_mark[i] != stamp {
                        first.node_mark[i] = stamp;
                        first.nodes.push(n);
                    }
                }
            }
            // Part 0's list is the step's; the last step's goes to part 0,
            // which clears it at its next splat.
            std::mem::swap(&mut self.touched, &mut first.nodes);
        }
    }
}

/// `2^k` as an `f32` (exact for `-126 <= k <= 127`).
fn pow2(k: i32) -> f32 {
    2.0f32.powi(k)
}

/// One part of the splat: the lane groups `run` (block `g / G`, group
/// `g % G` of it, `G` groups per block) in order, vertex by vertex, into
/// `part`'s grid, listing the cells it reaches. Eight lanes at a time:
/// weights, velocities and the eight corner weights in one `f32x8` each,
/// then per lane, per row of two nodes of its cell, the eight terms
/// (`[1, v, 1, v]` scaled to fixed point, times the row's corner weights)
/// rounded to the nearest integer and added.
///
/// Not inlined: called through the executor's closure, the compiler
/// otherwise left the transposes unoptimised (measured: twice the
/// instructions).
#[inline(never)]
fn splat_part(part: &mut SplatPart, k: &SplatSetup<'_>, run: Range<usize>, last: Option<&[u32]>) {
    let s = k.s;
    let dims = k.dims;
    let (nx, ny) = (dims.x as usize, dims.y as usize);
    let reach8 = F32Group::splat(MAX_GRID_REACH);
    let inv_cell = F32Group::splat(1.0 / k.cell);
    let inv_dt = F32Group::splat(1.0 / k.dt);
    let zero = F32Group::ZERO;
    let one = F32Group::ONE;
    let bound = F32Group::splat(k.speed_bound);
    let (weight_scale, momentum_scale) = (
        F32Group::splat(k.weight_scale),
        F32Group::splat(k.momentum_scale),
    );
    let share_max = F32Group::splat(k.share_max);
    let max_i = (dims - UVec3::splat(2)).as_vec3();
    let origin = V3::<F32Group>::splat(k.origin);
    let stamp = k.stamp;
    let (nxy, span) = (nx * ny, nx * ny + nx + 2);
    let SplatPart {
        acc,
        cells,
        nodes,
        cell_mark,
        node_mark,
    } = part;
    // Only listed nodes hold weight (part 0's last list is the grid's):
    // the corners of listed cells that took none were added zero (a
    // corner's momentum terms are no larger than its weight term, so they
    // round to zero with it).
    for &i in last.unwrap_or(nodes) {
        if let Some(a) = acc.get_mut(i as usize) {
            *a = [0; 4];
        }
    }
    nodes.clear();
    cells.clear();
    let group = |x: Vec3Lanes, g: usize| V3::new(groups(x.x)[g], groups(x.y)[g], groups(x.z)[g]);
    for (b, g) in run.map(block_of_group) {
        let lanes = s
            .lanes_in_block(b)
            .saturating_sub(g * GROUP_LANES)
            .min(GROUP_LANES);
        if lanes == 0 {
            continue;
        }
        let base = b * s.verts;
        // A share over the largest: at most 1 (a correctly rounded
        // quotient of a <= b is at most 1).
        let hair_share = groups(s.hair_share[b])[g] / share_max;
        for v in 0..s.verts {
            let (x, xp) = (group(k.pos[base + v], g), group(k.prev[base + v], g));
            let rest_arc = groups(s.rest_arc[base + v])[g];
            let inside =
                x.x.abs().simd_lt(reach8) & x.y.abs().simd_lt(reach8) & x.z.abs().simd_lt(reach8);
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
            let clamp = |c: F32Group| F32Group::select(finite, c.max(-bound).min(bound), zero);
            let vel = V3::new(clamp(vel.x), clamp(vel.y), clamp(vel.z));
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
            // and `[1, v, 1, v]` in fixed point (powers of two: exact).
            let corner = F32Group::transpose(std::array::from_fn(|c| {
                weight
                    * if c & 1 == 1 { fx } else { gx }
                    * if (c >> 1) & 1 == 1 { fy } else { gy }
                    * if (c >> 2) & 1 == 1 { fz } else { gz }
            }));
            let (vx, vy, vz) = (
                vel.x * momentum_scale,
                vel.y * momentum_scale,
                vel.z * momentum_scale,
            );
            let unit = F32Group::transpose([weight_scale, vx, vy, vz, weight_scale, vx, vy, vz]);
            let (node, weight) = (node.to_array(), weight.to_array());
            for l in 0..lanes {
                if weight[l] <= 0.0 {
                    continue;
                }
                // One 32-byte row of two nodes at a time, to all eight
                // corners (a corner of zero weight adds zero), in corner
                // order, x fastest: the cell's four rows.
                let cell_node = node[l] as u32 as usize;
                let Some(block) = acc.get_mut(cell_node..cell_node + span) else {
                    continue;
                };
                if cell_mark[cell_node] != stamp {
                    cell_mark[cell_node] = stamp;
                    cells.push(cell_node as u32);
                }
                for (row, at) in [0, nx, nxy, nxy + nx].into_iter().enumerate() {
                    let Ok(pair): Result<&mut [i32; 8], _> =
                        block[at..at + 2].as_flattened_mut().try_into()
                    else {
                        continue;
                    };
                    let terms = fixed_terms(unit[l], row_weights(corner[l], row));
                    *pair = (I32Group::new(*pair) + terms).to_array();
                }
            }
        }
    }
    // The nodes of its cells that took weight.
    for &c in cells.iter() {
        for at in [0, 1, nx, nx + 1, nxy, nxy + 1, nxy + nx, nxy + nx + 1] {
            let i = c as usize + at;
            if acc[i][0] > 0 && node_mark[i] != stamp {
                node_mark[i] = stamp;
                nodes.push(i as u32);
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

/// `round(unit * w)` lane by lane, to the nearest integer (ties to even):
/// one multiply and one conversion. The splat's terms are finite and at
/// most `2^30` (`SUM_BITS`), so the conversion's out-of-range and NaN
/// cases (which `wide`'s `round_int` spends four more instructions on)
/// never arise; were they to, the lane would read `i32::MIN`, still no UB.
#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
#[inline(always)]
fn fixed_terms(unit: F32Group, w: F32Group) -> I32Group {
    use std::arch::x86_64::{__m256, _mm256_cvtps_epi32};
    let product: __m256 = wide::bytemuck::cast(unit * w);
    // SAFETY: AVX2 is enabled (cfg above); the conversion reads only its
    // register operand.
    wide::bytemuck::cast(unsafe { _mm256_cvtps_epi32(product) })
}

/// `wide`'s rounding where AVX2 is not enabled (the same integers for the
/// splat's terms, which are finite and in range).
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
#[inline(always)]
fn fixed_terms(unit: F32Group, w: F32Group) -> I32Group {
    (unit * w).round_int()
}

#[cfg(test)]
mod tests {
    use super::*;
    use coif_testkit::executors::Backwards;

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
        g.build(&s, &s.pos, &prev, 0.1, 0.01, &Serial);
        assert!(g.live);
        let n = (g.dims.x * g.dims.y * g.dims.z) as usize;
        let acc = &g.parts[0].acc[..n];
        let total = acc.iter().map(|a| a[0] as f64).sum::<f64>() * g.weight_unit as f64;
        let expected: f64 = (0..41)
            .map(|i| (0.005 * i as f64 / ROOT_RAMP as f64).clamp(0.0, 1.0))
            .sum();
        assert!((total - expected).abs() < 1e-4, "{total} {expected}");
        let momentum_unit = g.weight_unit as f64 * g.velocity_unit as f64;
        let py = acc.iter().map(|a| a[2] as f64).sum::<f64>() * momentum_unit;
        assert!((py - expected).abs() < 1e-4, "{py}");
        // The hair's velocity is (0, 1, 0) wherever there is hair.
        for &i in &g.touched {
            let (a, f) = (
                acc[i as usize][0] as f32 * g.weight_unit,
                g.field[i as usize],
            );
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
    fn fixed_terms_round_to_the_nearest_integer_ties_to_even() {
        let unit = F32Group::new([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 2.0, 1024.0]);
        let w = F32Group::new([0.5, 1.5, 2.5, -0.5, -1.5, 0.49999997, 0.75, 0.25]);
        assert_eq!(fixed_terms(unit, w).to_array(), [0, 2, 2, 0, -2, 0, 2, 256]);
        let big = F32Group::splat((1u32 << 30) as f32);
        assert_eq!(fixed_terms(big, F32Group::ONE).to_array(), [1 << 30; 8]);
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
        g.build(&s, &s.pos, &s.pos, 1.0 / 60.0, 0.01, &Serial);
        let cap = g.capacity;
        let mut far = s.pos.clone();
        for p in &mut far {
            let q = p.lane(1) + Vec3::Y * 5.0e3;
            p.set_lane(1, q);
        }
        g.build(&s, &far, &far, 1.0 / 60.0, 0.01, &Serial);
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
        g.build(&s, &far, &far, 1.0 / 60.0, 0.01, &Serial);
        assert_eq!(g.cell, 0.01);
        // A NaN strand is left out.
        far[3].set_lane(0, Vec3::NAN);
        g.build(&s, &far, &far, 1.0 / 60.0, 0.01, &Serial);
        assert!(g.live && g.cell.is_finite());
    }

    /// 61 strands of 13 vertices over a 12 cm patch, waving, and their
    /// positions a step of `dt` earlier: every strand moving its own way
    /// (up to about 3 m/s), one vertex in ten fast (about 150 m/s, so
    /// clamped), so that nodes take terms of many strands and signs.
    fn waving(dt: f32) -> (Strands, Vec<Vec3Lanes>) {
        let mut pts = Vec::new();
        for k in 0..61 {
            let (u, w) = ((k % 8) as f32 * 0.015, (k / 8) as f32 * 0.015);
            for v in 0..13 {
                let t = v as f32 * 0.01;
                pts.push(Vec3::new(
                    u + 0.02 * (t * 40.0 + k as f32).sin(),
                    -t,
                    w + 0.3 * t * t,
                ));
            }
        }
        let s = Strands::from_polylines(&pts, 13).unwrap();
        let mut prev = s.pos.clone();
        for (i, p) in prev.iter_mut().enumerate() {
            for l in 0..LANES {
                let k = (i * LANES + l) as f32;
                let speed = if i % 10 == 3 { 150.0 } else { 3.0 };
                let vel = Vec3::new((k * 0.7).sin(), (k * 1.3).cos(), (k * 0.3).sin()) * speed;
                p.set_lane(l, p.lane(l) - vel * dt);
            }
        }
        (s, prev)
    }

    /// The placement's bits, the node sums, the touched nodes, their fields.
    type GridBits = (Vec<u32>, Vec<[i32; 4]>, Vec<u32>, Vec<[u32; 8]>);

    /// Everything a step reads of the grid, as bits: the placement, the
    /// node sums, the touched nodes (as a set) and their fields.
    fn grid_bits(g: &HairGrid) -> GridBits {
        let n = (g.dims.x * g.dims.y * g.dims.z) as usize;
        let mut touched = g.touched.clone();
        touched.sort_unstable();
        let fields = touched
            .iter()
            .map(|&i| g.field[i as usize].map(f32::to_bits))
            .collect();
        let place = [
            g.origin.x,
            g.origin.y,
            g.origin.z,
            g.cell,
            g.weight_unit,
            g.velocity_unit,
        ]
        .map(f32::to_bits)
        .into_iter()
        .chain(g.dims.to_array())
        .collect();
        (place, g.parts[0].acc[..n].to_vec(), touched, fields)
    }

    #[test]
    fn the_sums_are_the_same_bytes_in_any_parts_and_order() {
        let dt = 1.0 / 60.0;
        let (s, prev) = waving(dt);
        let build = |executor: &dyn Executor| {
            let mut g = HairGrid::default();
            // Two steps: the second clears the first's nodes and merges again.
            g.build(&s, &prev, &s.pos, dt, 0.004, executor);
            g.build(&s, &s.pos, &prev, dt, 0.004, executor);
            assert!(g.live && !g.touched.is_empty());
            g
        };
        let one = build(&Serial);
        // Some node takes terms from several parts, or the test is empty.
        assert!(one.touched.len() > 100);
        let want = grid_bits(&one);
        for parts in [2, 3, 4, 7] {
            let g = build(&Backwards(parts));
            assert_eq!(g.parts.len(), parts.min(MAX_SPLAT_PARTS));
            assert!(grid_bits(&g) == want, "{parts} parts");
            // Every part holds weight only at the nodes it listed (which
            // its next splat clears).
            for p in &g.parts[1..] {
                let listed: std::collections::HashSet<u32> = p.nodes.iter().copied().collect();
                assert!(p
                    .acc
                    .iter()
                    .enumerate()
                    .all(|(i, a)| *a == [0; 4] || listed.contains(&(i as u32))));
            }
        }
        for threads in [2, 3] {
            let workers = coif_base::tasks::Workers::new(threads).expect("threads");
            assert!(grid_bits(&build(&workers)) == want, "{threads} threads");
        }
        // One grid whose part count changes from step to step: a part
        // left out keeps its last sums, and clears them when next used.
        let mut g = HairGrid::default();
        for (executor, step) in [
            (&Backwards(3) as &dyn Executor, 0),
            (&Serial, 1),
            (&Backwards(4), 0),
            (&Backwards(2), 1),
        ] {
            let (a, b) = if step == 0 {
                (&prev, &s.pos)
            } else {
                (&s.pos, &prev)
            };
            g.build(&s, a, b, dt, 0.004, executor);
        }
        assert!(grid_bits(&g) == want, "changing parts");
    }

    #[test]
    fn the_fixed_point_sums_are_within_half_a_unit_per_term_of_the_exact_splat() {
        let dt = 1.0 / 60.0;
        let (s, prev) = waving(dt);
        let mut g = HairGrid::default();
        g.build(&s, &s.pos, &prev, dt, 0.004, &Backwards(3));
        // The exact sums, in f64 from the same placement: per node the
        // weight, the momentum (velocities clamped as the splat clamps
        // them), the count of terms, and per term the sums of |momentum|
        // and of the largest velocity component.
        let (o, c, d) = (g.origin.as_dvec3(), g.cell as f64, g.dims);
        let n = (d.x * d.y * d.z) as usize;
        let mut exact = vec![([0.0f64; 4], 0u32, [0.0f64; 2]); n];
        for b in 0..s.blocks {
            for v in 0..s.verts {
                for l in 0..s.lanes_in_block(b) {
                    let i = b * s.verts + v;
                    let (x, xp) = (s.pos[i].lane(l).as_dvec3(), prev[i].lane(l).as_dvec3());
                    let w = (s.rest_arc[i].as_array()[l] as f64 / ROOT_RAMP as f64).clamp(0.0, 1.0);
                    if w <= 0.0 {
                        continue;
                    }
                    let vel = (x - xp) / dt as f64;
                    let vel = vel * (MAX_GRID_SPEED as f64 / vel.length()).min(1.0);
                    let u = (x - o) / c;
                    let cell = u.floor();
                    let f = u - cell;
                    for k in 0..8u32 {
                        let pick = |bit: u32, f: f64| if k >> bit & 1 == 1 { f } else { 1.0 - f };
                        let cw = w * pick(0, f.x) * pick(1, f.y) * pick(2, f.z);
                        let at = cell.as_uvec3() + UVec3::new(k & 1, k >> 1 & 1, k >> 2);
                        let e = &mut exact[((at.z * d.y + at.y) * d.x + at.x) as usize];
                        e.0[0] += cw;
                        for a in 0..3 {
                            e.0[a + 1] += cw * vel[a];
                        }
                        e.1 += 1;
                        e.2[0] += cw * vel.abs().max_element();
                        e.2[1] += vel.abs().max_element();
                    }
                }
            }
        }
        // Per term: half a unit of rounding to the fixed point, plus what
        // the f32 inputs carry (a corner weight about 1e-5 absolute from
        // its fractions, times the velocity for the momentum; the speed
        // clamp's approximate reciprocal about 3e-4 of the momentum): the
        // tolerance per node, and the worst share of it.
        let units = [
            g.weight_unit as f64,
            g.weight_unit as f64 * g.velocity_unit as f64,
        ];
        let mut worst = 0.0f64;
        let mut nodes = 0;
        for (a, (e, terms, size)) in g.parts[0].acc[..n].iter().zip(&exact) {
            for ch in 0..4 {
                let m = (ch > 0) as usize;
                let err = (a[ch] as f64 * units[m] - e[ch]).abs();
                let inputs = if m == 0 {
                    1e-5 * *terms as f64
                } else {
                    1e-5 * size[1] + 3e-4 * size[0]
                };
                worst = worst.max(err / (0.5 * units[m] * *terms as f64 + inputs).max(1e-30));
            }
            nodes += (*terms > 0) as usize;
        }
        assert!(nodes > 100);
        assert!(worst <= 1.0, "{worst} of the tolerance");
        // The momentum's scale follows the fastest vertex: clamped to
        // 100 m/s, a bound of 128.
        assert_eq!(g.velocity_unit, 128.0);
    }

    #[test]
    fn every_vertex_in_one_cell_at_full_speed_keeps_the_sums_in_range() {
        // 4,096 strands of 32 vertices: 131,072 terms on a few nodes.
        let pts: Vec<Vec3> = (0..4096 * 32)
            .map(|i| Vec3::new(0.001 * (i / 32) as f32, -0.01 * (i % 32) as f32, 0.0))
            .collect();
        let s = Strands::from_polylines(&pts, 32).unwrap();
        let here = Vec3::new(0.0123, -0.0456, 0.0789);
        let pos = vec![Vec3Lanes::splat(here); s.pos.len()];
        let prev = vec![Vec3Lanes::splat(here - Vec3::new(0.0, 0.0, 500.0) / 60.0); s.pos.len()];
        let mut g = HairGrid::default();
        g.build(&s, &pos, &prev, 1.0 / 60.0, 0.01, &Backwards(2));
        assert!(g.live);
        let expected: f64 = (0..32)
            .map(|v| (0.01 * v as f64 / ROOT_RAMP as f64).clamp(0.0, 1.0))
            .sum::<f64>()
            * 4096.0;
        let acc = &g.parts[0].acc;
        let total = g
            .touched
            .iter()
            .map(|&i| acc[i as usize][0] as f64)
            .sum::<f64>()
            * g.weight_unit as f64;
        assert!(
            (total - expected).abs() < 1e-3 * expected,
            "{total} {expected}"
        );
        // The hair's velocity is the clamped one, along +z, at every node
        // (to the reciprocal estimate's relative error, 1.5 x 2^-12, which
        // differs between processors: an Intel Xeon gave 100.016).
        for &i in &g.touched {
            let f = g.field[i as usize];
            assert!(
                (f[5] - MAX_GRID_SPEED).abs() < 4e-4 * MAX_GRID_SPEED && f[3].abs() < 1e-3,
                "{f:?}"
            );
        }
    }
}
