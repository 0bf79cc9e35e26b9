//! `Patch`: one cloth grid in SIMD lanes (columns in lanes, see `mod.rs`).

use super::pairs::{mass_share, partner, PairSet};
use crate::collide::broad_phase::Candidate;
use crate::lanes::{Vec3Lanes, LANES};
use crate::Error;
use coif_base::lanes::F32Lanes;
use glam::{DVec3, Vec3};

/// Local coordinates beyond this distance from the origin trigger a rebase
/// in [`Patch::set_skinned`] (as for strands).
const REBASE_DISTANCE: f64 = 64.0;

/// Most columns of a patch: the broad phase tags column blocks in a 32-bit
/// mask (32 blocks of eight columns; the same limit at 16 lanes, where it
/// takes 16 blocks).
pub const MAX_PATCH_COLUMNS: usize = 256;

/// One grid of `rows x cols` cloth particles, simulated in SIMD lanes and
/// blended with the engine's skinned positions.
///
/// Every public slice is a **row-major** world-space grid: particle `(r, c)`
/// is element `r * cols + c`. Positions are kept relative to an `f64` local
/// origin ([`Patch::origin`]) so that a patch far from the world origin keeps
/// sub-millimetre precision.
#[derive(Clone, Debug)]
pub struct Patch {
    pub(crate) rows: usize,
    pub(crate) cols: usize,
    pub(crate) blocks: usize,
    pub(crate) origin: DVec3,
    /// Current positions relative to `origin`, index `b * rows + r`, lane `c % 8`.
    pub(crate) pos: Vec<Vec3Lanes>,
    /// Positions one step ago (Verlet's implicit velocity).
    pub(crate) prev: Vec<Vec3Lanes>,
    /// Skinned positions relative to `origin` (padding lanes repeat the
    /// block's last real column).
    pub(crate) skin: Vec<Vec3Lanes>,
    /// The skinned positions as given, row-major world space (for the blend).
    pub(crate) skin_world: Vec<Vec3>,
    /// Inverse mass: 0 = pinned to the skin (and padding lanes).
    pub(crate) inv_mass: Vec<F32Lanes>,
    /// Largest distance from the skinned position (INFINITY = no limit).
    pub(crate) max_distance: Vec<F32Lanes>,
    /// Long range attachment: per row-major particle, the pinned particle
    /// nearest along the grid (`usize::MAX`: none, or pinned itself).
    pub(crate) anchor: Vec<usize>,
    /// Rest distance along the grid to the anchor (INFINITY: no anchor).
    pub(crate) tether_len: Vec<F32Lanes>,
    /// All bits set where a free particle's shortest path to its anchor
    /// leaves through the particle directly above (row r - 1): the column
    /// strain limit pulls it toward that parent.
    pub(crate) parent_up: Vec<F32Lanes>,
    /// The anchor's skinned position relative to `origin`, per particle.
    pub(crate) anchor_skin: Vec<Vec3Lanes>,
    /// Blend weight per particle, row-major (0 = skin, 1 = simulation).
    pub(crate) weight: Vec<f32>,
    /// Vertical edge r -> r + 1: rest length and mass shares of both ends.
    pub(crate) vert_rest: Vec<F32Lanes>,
    pub(crate) vert_share: Vec<[F32Lanes; 2]>,
    /// Vertical bending edge r -> r + 2.
    pub(crate) vbend_rest: Vec<F32Lanes>,
    pub(crate) vbend_share: Vec<[F32Lanes; 2]>,
    /// Per row, the column its strain limit starts from: the pinned particle
    /// nearest the middle column, or the middle column when the row has none.
    pub(crate) row_root: Vec<usize>,
    /// Horizontal edges (stride 1) per colour.
    pub(crate) horiz: [PairSet; 2],
    /// Horizontal bending edges (stride 2) per colour.
    pub(crate) hbend: [PairSet; 2],
    /// Shear edges per colour, seen from the upper particle (partner in row
    /// r + 1) and from the lower one (partner in row r - 1).
    pub(crate) shear_down: [PairSet; 2],
    pub(crate) shear_up: [PairSet; 2],
    /// Per column block: all bits set in lanes holding a real column.
    pub(crate) active: Vec<F32Lanes>,
    /// Longest rest edge (structural or shear): the broad phase's slack.
    pub(crate) max_rest_edge: f32,
    /// Stiffness in [0, 1] of the shear edges (0 = off).
    pub(crate) shear_stiffness: f32,
    /// Times the patch was restored to its skin after blowing up.
    pub(crate) restored: u64,
    pub(crate) scratch: PatchScratch,
}

/// Per-step buffers, sized at construction (no per-frame allocation unless
/// the rig grows).
#[derive(Clone, Debug, Default)]
pub(crate) struct PatchScratch {
    pub spheres_local: Vec<[f32; 4]>,
    pub candidates: Vec<Candidate>,
    pub boxes: Vec<crate::collide::broad_phase::Aabb>,
    /// Partner positions of one row, one entry per column block (two rows
    /// for shear passes).
    pub partner_a: Vec<Vec3Lanes>,
    pub partner_b: Vec<Vec3Lanes>,
    /// Shear corrections permuted to the lower row.
    pub partner_c: Vec<Vec3Lanes>,
}

impl Patch {
    /// Builds a patch from its rest grid (`rows * cols` world-space points,
    /// row-major) and a pinned flag per particle (pinned particles follow
    /// the skin exactly). Needs at least 2 rows and 2 columns, at most
    /// [`MAX_PATCH_COLUMNS`] columns. Rest lengths come from `grid`; the
    /// skin starts at `grid`, blend weights at 1, max distances at infinity,
    /// shear stiffness at 0 (off; see [`Patch::set_shear_stiffness`]).
    ///
    /// # Errors
    ///
    /// [`Error::TooFewVertices`] on fewer than 2 rows or columns,
    /// [`Error::InvalidParameter`] on more than [`MAX_PATCH_COLUMNS`] columns,
    /// [`Error::CountMismatch`] unless `grid` and `pinned` hold `rows * cols`
    /// entries, [`Error::NonFinite`] on a non-finite point.
    pub fn new(grid: &[Vec3], rows: usize, cols: usize, pinned: &[bool]) -> Result<Patch, Error> {
        validate_grid(grid, rows, cols, pinned)?;
        let rest = RestGrid {
            grid,
            rows,
            cols,
            pinned,
        };
        let mut p = Patch::zeroed(&rest);
        for c in 0..p.blocks * LANES {
            for r in 0..rows {
                p.fill_particle(&rest, r, c);
                p.fill_vertical_edges(&rest, r, c);
                p.fill_pair_edges(&rest, r, c);
            }
        }
        p.fill_tethers(&rest);
        p.update_anchor_skin();
        Ok(p)
    }

    /// A patch for `rest` with every per-particle array sized and at its
    /// neutral value (zero; INFINITY for max distances and tethers; weight 1),
    /// the local origin at the grid's mean, the rows' root columns, the
    /// column blocks' active masks and the scratch buffers.
    fn zeroed(rest: &RestGrid) -> Patch {
        let (rows, cols, grid) = (rest.rows, rest.cols, rest.grid);
        let n = rows * cols;
        let blocks = cols.div_ceil(LANES);
        let slots = blocks * rows;
        Patch {
            rows,
            cols,
            blocks,
            origin: grid.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / n as f64,
            pos: vec![Vec3Lanes::ZERO; slots],
            prev: vec![Vec3Lanes::ZERO; slots],
            skin: vec![Vec3Lanes::ZERO; slots],
            skin_world: grid.to_vec(),
            inv_mass: vec![F32Lanes::ZERO; slots],
            max_distance: vec![F32Lanes::splat(f32::INFINITY); slots],
            anchor: vec![usize::MAX; n],
            tether_len: vec![F32Lanes::splat(f32::INFINITY); slots],
            anchor_skin: vec![Vec3Lanes::ZERO; slots],
            parent_up: vec![F32Lanes::ZERO; slots],
            weight: vec![1.0; n],
            row_root: (0..rows).map(|r| rest.row_root(r)).collect(),
            vert_rest: vec![F32Lanes::ZERO; slots],
            vert_share: vec![[F32Lanes::ZERO; 2]; slots],
            vbend_rest: vec![F32Lanes::ZERO; slots],
            vbend_share: vec![[F32Lanes::ZERO; 2]; slots],
            horiz: [PairSet::zeros(slots), PairSet::zeros(slots)],
            hbend: [PairSet::zeros(slots), PairSet::zeros(slots)],
            shear_down: [PairSet::zeros(slots), PairSet::zeros(slots)],
            shear_up: [PairSet::zeros(slots), PairSet::zeros(slots)],
            active: (0..blocks)
                .map(|b| {
                    let lane_index = F32Lanes::new(std::array::from_fn(|l| (b * LANES + l) as f32));
                    lane_index.simd_lt(F32Lanes::splat(cols as f32))
                })
                .collect(),
            max_rest_edge: 0.0,
            shear_stiffness: 0.0,
            restored: 0,
            scratch: PatchScratch {
                partner_a: vec![Vec3Lanes::ZERO; blocks],
                partner_b: vec![Vec3Lanes::ZERO; blocks],
                partner_c: vec![Vec3Lanes::ZERO; blocks],
                boxes: Vec::with_capacity(blocks),
                ..Default::default()
            },
        }
    }

    /// Padded particle `(r, c)`: position, previous position and skin (its
    /// rest point, local), and inverse mass.
    fn fill_particle(&mut self, rest: &RestGrid, r: usize, c: usize) {
        let (i, l) = ((c / LANES) * self.rows + r, c % LANES);
        let x = (rest.at(r, c).as_dvec3() - self.origin).as_vec3();
        self.pos[i].set_lane(l, x);
        self.prev[i].set_lane(l, x);
        self.skin[i].set_lane(l, x);
        set(&mut self.inv_mass[i], l, rest.w(r, c));
    }

    /// The lane-parallel edges below padded particle `(r, c)`: the vertical
    /// edge to `r + 1` and the vertical bending edge to `r + 2` (rest length
    /// and both mass shares).
    fn fill_vertical_edges(&mut self, rest: &RestGrid, r: usize, c: usize) {
        let (i, l) = ((c / LANES) * self.rows + r, c % LANES);
        if c >= rest.cols {
            return;
        }
        let w = rest.w(r, c);
        for (step, lengths, shares) in [
            (1, &mut self.vert_rest, &mut self.vert_share),
            (2, &mut self.vbend_rest, &mut self.vbend_share),
        ] {
            if r + step < rest.rows {
                let d = (rest.at(r + step, c) - rest.at(r, c)).length();
                set(&mut lengths[i], l, d);
                let wj = rest.w(r + step, c);
                set(&mut shares[i][0], l, mass_share(w, wj));
                set(&mut shares[i][1], l, mass_share(wj, w));
                if step == 1 {
                    self.max_rest_edge = self.max_rest_edge.max(d);
                }
            }
        }
    }

    /// The lane-pair edges of padded particle `(r, c)` in both colours:
    /// horizontal (stride 1), horizontal bending (stride 2) and the two shear
    /// directions (partner in row `r + 1`, and in row `r - 1`); rest length,
    /// this particle's mass share and the partner's inverse mass.
    fn fill_pair_edges(&mut self, rest: &RestGrid, r: usize, c: usize) {
        let (i, l) = ((c / LANES) * self.rows + r, c % LANES);
        let lanes = self.blocks * LANES;
        let (rows, cols) = (rest.rows, rest.cols);
        let w = rest.w(r, c);
        for colour in 0..2 {
            // (set, stride, row offset).
            let kinds: [(&mut PairSet, usize, isize); 4] = [
                (&mut self.horiz[colour], 1, 0),
                (&mut self.hbend[colour], 2, 0),
                (&mut self.shear_down[colour], 1, 1),
                (&mut self.shear_up[colour], 1, -1),
            ];
            for (pairs, stride, dr) in kinds {
                let rr = r as isize + dr;
                let Some(pc) = partner(c, stride, colour, lanes) else {
                    continue;
                };
                if c >= cols || pc >= cols || rr < 0 || rr >= rows as isize {
                    continue;
                }
                let rr = rr as usize;
                let d = (rest.at(rr, pc) - rest.at(r, c)).length();
                let wj = rest.w(rr, pc);
                set(&mut pairs.rest[i], l, d);
                set(&mut pairs.share[i], l, mass_share(w, wj));
                set(&mut pairs.partner_w[i], l, wj);
                if stride == 1 {
                    self.max_rest_edge = self.max_rest_edge.max(d);
                }
            }
        }
    }

    /// Long range attachments: each particle's anchor, tether length and
    /// whether its path to the pins leaves through the particle above.
    fn fill_tethers(&mut self, rest: &RestGrid) {
        let mut up = vec![false; rest.rows * rest.cols];
        let lengths = tether_lengths(
            rest.grid,
            rest.rows,
            rest.cols,
            rest.pinned,
            &mut self.anchor,
            &mut up,
        );
        for (k, len) in lengths.into_iter().enumerate() {
            let (i, l) = self.slot(k);
            set(&mut self.tether_len[i], l, len);
            if up[k] {
                set(&mut self.parent_up[i], l, f32::from_bits(!0));
            }
        }
    }

    /// Rows of the grid.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Columns of the grid.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// `rows * cols`.
    pub fn particle_count(&self) -> usize {
        self.rows * self.cols
    }

    /// World position of the local origin that positions are relative to.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Times the patch blew up (a non-finite coordinate, or one beyond
    /// 10^6 m) and was restored to its skinned positions.
    pub fn restored_count(&self) -> u64 {
        self.restored
    }

    /// Sets the blend weights (row-major, one per particle, each in [0, 1]):
    /// 0 = the output follows the skin, 1 = fully simulated.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] unless there is one weight per particle,
    /// [`Error::InvalidParameter`] on a weight outside [0, 1] (or NaN); nothing
    /// changes then.
    pub fn set_weights(&mut self, weights: &[f32]) -> Result<(), Error> {
        self.check_len(weights.len())?;
        if let Some(index) = weights.iter().position(|w| !(0.0..=1.0).contains(w)) {
            return Err(Error::InvalidParameter {
                name: "weight",
                value: weights[index],
                expected: "0 <= weight <= 1",
            });
        }
        self.weight.copy_from_slice(weights);
        Ok(())
    }

    /// Sets the largest distance (metres, row-major, one per particle, `>= 0`,
    /// `f32::INFINITY` = no limit) a simulated particle may move from its
    /// skinned position. Enforced inside the step, so it feeds back into the
    /// motion (PhysX and Unity cloth's "max distance").
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] unless there is one distance per particle,
    /// [`Error::InvalidParameter`] on a negative or NaN distance; nothing changes
    /// then.
    pub fn set_max_distances(&mut self, max_distance: &[f32]) -> Result<(), Error> {
        self.check_len(max_distance.len())?;
        if let Some(index) = max_distance.iter().position(|d| d.is_nan() || *d < 0.0) {
            return Err(Error::InvalidParameter {
                name: "max_distance",
                value: max_distance[index],
                expected: "max_distance >= 0 (infinity = no limit)",
            });
        }
        for (k, &d) in max_distance.iter().enumerate() {
            let (i, l) = self.slot(k);
            set(&mut self.max_distance[i], l, d);
        }
        Ok(())
    }

    /// Sets the stiffness in [0, 1] of the shear (diagonal) edges; 0 (the
    /// default) turns them off. Shear edges make the grid rigid in its own
    /// plane; under strong in-plane loads (a 10 g whip) Gauss-Seidel then
    /// converges slowly and rows stretch (measured in `PATCH.md`), so they
    /// are opt-in. Bending edges (skip-one, both directions) use
    /// [`crate::SimParams::bend_stiffness`] as for strands.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] outside [0, 1] (or NaN).
    pub fn set_shear_stiffness(&mut self, stiffness: f32) -> Result<(), Error> {
        if !(0.0..=1.0).contains(&stiffness) {
            return Err(Error::InvalidParameter {
                name: "shear_stiffness",
                value: stiffness,
                expected: "0 <= shear_stiffness <= 1",
            });
        }
        self.shear_stiffness = stiffness;
        Ok(())
    }

    /// Gives this frame's skinned positions (world space, row-major). Pinned
    /// particles move there at the next step; the others are drawn toward
    /// them by the max distance and the blend. Rejects a wrong count or a
    /// non-finite point, keeping the previous skin. Rebases the local origin
    /// when the skin has moved far from it.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] unless there is one point per particle,
    /// [`Error::NonFinite`] on a non-finite point; the previous skin is kept.
    pub fn set_skinned(&mut self, skinned: &[Vec3]) -> Result<(), Error> {
        self.check_len(skinned.len())?;
        if let Some(index) = skinned.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFinite { index });
        }
        let first = skinned[0].as_dvec3();
        if (first - self.origin).length() > REBASE_DISTANCE {
            let shift = (self.origin - first).as_vec3();
            let s = Vec3Lanes::splat(shift);
            for p in self.pos.iter_mut().chain(self.prev.iter_mut()) {
                *p = *p + s;
            }
            self.origin = first;
        }
        self.skin_world.copy_from_slice(skinned);
        let o = self.origin;
        for r in 0..self.rows {
            for c in 0..self.blocks * LANES {
                let x = (skinned[r * self.cols + c.min(self.cols - 1)].as_dvec3() - o).as_vec3();
                self.skin[(c / LANES) * self.rows + r].set_lane(c % LANES, x);
            }
        }
        self.update_anchor_skin();
        Ok(())
    }

    /// Copies each anchor's skinned position into its particles' lanes.
    fn update_anchor_skin(&mut self) {
        for k in 0..self.particle_count() {
            if let Some(&a) = self.anchor.get(k).filter(|&&a| a != usize::MAX) {
                let (ia, la) = self.slot(a);
                let (i, l) = self.slot(k);
                let x = self.skin[ia].lane(la);
                self.anchor_skin[i].set_lane(l, x);
            }
        }
    }

    /// Moves every particle (and its previous position) onto the skin: a
    /// teleport without velocity, or a reset.
    pub fn reset_to_skin(&mut self) {
        self.pos.copy_from_slice(&self.skin);
        self.prev.copy_from_slice(&self.skin);
    }

    /// Writes the simulated world positions, row-major, into the first
    /// `rows * cols` entries of `out` (the rest of a longer `out` is left as
    /// it was). Returns the number of points written. Allocates nothing.
    ///
    /// # Errors
    ///
    /// [`Error::BufferTooSmall`] (and nothing written) if `out` holds fewer
    /// than `rows * cols` points.
    pub fn write_positions(&self, out: &mut [Vec3]) -> Result<usize, Error> {
        let needed = self.particle_count();
        if out.len() < needed {
            return Err(Error::BufferTooSmall {
                needed,
                got: out.len(),
            });
        }
        self.fill_positions(&mut out[..needed]);
        Ok(needed)
    }

    /// World positions of the first `out.len()` particles into `out`.
    fn fill_positions(&self, out: &mut [Vec3]) {
        let o = self.origin;
        for (k, slot) in out.iter_mut().enumerate().take(self.particle_count()) {
            let (i, l) = self.slot(k);
            *slot = (o + self.pos[i].lane(l).as_dvec3()).as_vec3();
        }
    }

    /// Simulated world positions, row-major (allocates; for tests and tools).
    pub fn positions(&self) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; self.particle_count()];
        self.fill_positions(&mut out);
        out
    }

    /// Simulated positions relative to [`Patch::origin`], row-major.
    pub fn positions_local(&self) -> Vec<Vec3> {
        (0..self.particle_count())
            .map(|k| {
                let (i, l) = self.slot(k);
                self.pos[i].lane(l)
            })
            .collect()
    }

    /// Rest distance between row-major particles `a` and `b` if they share a
    /// structural edge (same row, neighbouring columns, or same column,
    /// neighbouring rows).
    pub fn rest_edge(&self, a: usize, b: usize) -> Option<f32> {
        let n = self.particle_count();
        if a >= n || b >= n {
            return None;
        }
        let (lo, hi) = (a.min(b), a.max(b));
        let (r, c) = (lo / self.cols, lo % self.cols);
        let (i, l) = self.slot(lo);
        if hi == lo + 1 && c + 1 < self.cols {
            let colour = c % 2;
            Some(self.horiz[colour].rest[i].as_array()[l])
        } else if hi == lo + self.cols && r + 1 < self.rows {
            Some(self.vert_rest[i].as_array()[l])
        } else {
            None
        }
    }

    /// Storage slot (index, lane) of row-major particle `k`.
    #[inline]
    pub(crate) fn slot(&self, k: usize) -> (usize, usize) {
        let (r, c) = (k / self.cols, k % self.cols);
        ((c / LANES) * self.rows + r, c % LANES)
    }

    fn check_len(&self, got: usize) -> Result<(), Error> {
        if got == self.particle_count() {
            Ok(())
        } else {
            Err(Error::CountMismatch {
                what: "values (one per particle)",
                expected: self.particle_count(),
                got,
            })
        }
    }
}

/// The input checks of [`Patch::new`].
fn validate_grid(grid: &[Vec3], rows: usize, cols: usize, pinned: &[bool]) -> Result<(), Error> {
    if rows < 2 || cols < 2 {
        return Err(Error::TooFewVertices {
            verts_per_strand: rows.min(cols),
        });
    }
    if cols > MAX_PATCH_COLUMNS {
        return Err(Error::InvalidParameter {
            name: "cols",
            value: cols as f32,
            expected: "at most 256 columns",
        });
    }
    // An overflowing rows * cols matches no slice (instead of wrapping).
    let n = rows.checked_mul(cols);
    for len in [grid.len(), pinned.len()] {
        if Some(len) != n {
            return Err(Error::CountMismatch {
                what: "points and pin flags (rows times columns)",
                expected: n.unwrap_or(usize::MAX),
                got: len,
            });
        }
    }
    if let Some(index) = grid.iter().position(|p| !p.is_finite()) {
        return Err(Error::NonFinite { index });
    }
    Ok(())
}

/// A validated rest grid (row-major) with its pins, read by padded column:
/// a padding column `c >= cols` copies the last real column and is pinned.
struct RestGrid<'a> {
    grid: &'a [Vec3],
    rows: usize,
    cols: usize,
    pinned: &'a [bool],
}

impl RestGrid<'_> {
    /// Rest point of padded particle `(r, c)`.
    fn at(&self, r: usize, c: usize) -> Vec3 {
        self.grid[r * self.cols + c.min(self.cols - 1)]
    }

    /// Inverse mass of padded particle `(r, c)`: 1 if real and free, else 0.
    fn w(&self, r: usize, c: usize) -> f32 {
        if c < self.cols && !self.pinned[r * self.cols + c] {
            1.0
        } else {
            0.0
        }
    }

    /// The column row `r`'s strain limit starts from: the pinned particle
    /// nearest the middle column, or the middle column when the row has none.
    fn row_root(&self, r: usize) -> usize {
        let middle = self.cols / 2;
        (0..self.cols)
            .filter(|&c| self.pinned[r * self.cols + c])
            .min_by_key(|&c| c.abs_diff(middle))
            .unwrap_or(middle)
    }
}

/// Shortest rest distances along the grid's structural and diagonal edges
/// from every particle to the nearest pinned one (Dijkstra 1959), writing
/// that pinned particle into `anchor`; INFINITY where no pinned particle is
/// connected, and for pinned particles themselves (they need no tether).
/// `parent_up[k]` is set where the path from free particle `k` leaves
/// through the particle directly above it.
fn tether_lengths(
    grid: &[Vec3],
    rows: usize,
    cols: usize,
    pinned: &[bool],
    anchor: &mut [usize],
    parent_up: &mut [bool],
) -> Vec<f32> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let n = rows * cols;
    let mut dist = vec![f32::INFINITY; n];
    // Non-negative finite f32s order like their bit patterns.
    let mut heap = BinaryHeap::new();
    for k in (0..n).filter(|&k| pinned[k]) {
        dist[k] = 0.0;
        anchor[k] = k;
        heap.push(Reverse((0u32, k)));
    }
    while let Some(Reverse((bits, k))) = heap.pop() {
        if f32::from_bits(bits) > dist[k] {
            continue;
        }
        let (r, c) = ((k / cols) as isize, (k % cols) as isize);
        for (dr, dc) in [
            (-1, -1),
            (-1, 0),
            (-1, 1),
            (0, -1),
            (0, 1),
            (1, -1),
            (1, 0),
            (1, 1),
        ] {
            let (rr, cc) = (r + dr, c + dc);
            if rr < 0 || cc < 0 || rr >= rows as isize || cc >= cols as isize {
                continue;
            }
            let j = rr as usize * cols + cc as usize;
            let d = dist[k] + grid[k].distance(grid[j]);
            if d < dist[j] {
                dist[j] = d;
                anchor[j] = anchor[k];
                parent_up[j] = k + cols == j;
                heap.push(Reverse((d.to_bits(), j)));
            }
        }
    }
    for k in 0..n {
        if pinned[k] || dist[k] == f32::INFINITY {
            dist[k] = f32::INFINITY;
            anchor[k] = usize::MAX;
            parent_up[k] = false;
        }
    }
    dist
}

#[inline]
fn set(v: &mut F32Lanes, l: usize, x: f32) {
    v.as_mut_array()[l] = x;
}
