//! `Strands`: a set of equal-length hair strands stored in SIMD lanes.
//!
//! Layout: strands are grouped in blocks of [`LANES`];
//! vertex `v` of block `b` lives at index `b * V + v` of every per-vertex array,
//! and its lane `l` is strand `b * LANES + l`. A constraint on segment `v`
//! therefore processes eight strands with straight-line SIMD code.
//!
//! Positions are kept relative to a local origin (an `f64` point near the
//! roots): the next f32 after 10,000 is 10,000.00098, so a groom simulated in
//! world coordinates 10 km from the world origin would lose every move below a
//! millimetre. The public boundary speaks world-space `Vec3`; `*_local`
//! variants let an engine with f64 world positions keep full precision.

use crate::lanes::{Vec3Lanes, LANES};
use crate::Error;
use coif_base::lanes::F32Lanes;
use coif_base::StrandBlocks;
use glam::{Affine3A, DVec3, Mat3, Vec3};

/// Local coordinates beyond this distance from the origin trigger a rebase
/// in `set_roots` (f32 spacing at 64 m is 7.6e-6 m).
const REBASE_DISTANCE: f32 = 64.0;

/// A set of hair strands with the same vertex count, in SIMD lanes.
#[derive(Clone, Debug)]
pub struct Strands {
    pub(crate) strand_count: usize,
    pub(crate) verts: usize,
    pub(crate) blocks: usize,
    /// World position of local (0, 0, 0).
    pub(crate) origin: DVec3,
    /// Current positions, relative to `origin`.
    pub(crate) pos: Vec<Vec3Lanes>,
    /// The pinned roots per block, as last set (restores start from here).
    pub(crate) roots: Vec<Vec3Lanes>,
    /// Positions one step ago (Verlet's implicit velocity).
    pub(crate) prev: Vec<Vec3Lanes>,
    /// Rest pose relative to the strand's root, in the groom frame.
    pub(crate) rest_offset: Vec<Vec3Lanes>,
    /// Inverse mass per vertex: 0 = pinned (roots, padding lanes).
    pub(crate) inv_mass: Vec<F32Lanes>,
    /// Rest length of segment v -> v + 1 (the last vertex's entry is 0).
    pub(crate) rest_len: Vec<F32Lanes>,
    /// The shape springs' rest vector of segment v -> v + 1 in the groom
    /// frame: the groom's segment, or its sag-free rest
    /// ([`Strands::solve_sag_free`]).
    pub(crate) rest_vec: Vec<Vec3Lanes>,
    /// Mass shares of the bending constraint v -> v + 2:
    /// `w_v / (w_v + w_{v+2})` and `w_{v+2} / (w_v + w_{v+2})` (0 where both are pinned).
    pub(crate) bend_share: Vec<[F32Lanes; 2]>,
    /// Rest distance v -> v + 2 for bending (0 where v + 2 is past the tip).
    pub(crate) bend_len: Vec<F32Lanes>,
    /// Rest arc length from the root to vertex v.
    pub(crate) rest_arc: Vec<F32Lanes>,
    /// Per block and vertex: the longest rest arc from the root over the
    /// block's lanes (the broad phase's reach).
    pub(crate) reach_arc: Vec<f32>,
    /// Shape-keeping weight 1 - arc(v) / arc(tip): 1 at the root, 0 at the tip.
    pub(crate) shape_weight: Vec<F32Lanes>,
    /// Per block: all bits set in lanes that hold a real strand.
    pub(crate) active: Vec<F32Lanes>,
    /// Longest rest segment of the set (the broad phase's slack).
    pub(crate) max_rest_segment: f32,
    /// Rotation applied to `rest_offset` (the groom frame's orientation).
    pub(crate) rest_rotation: Mat3,
    /// The groom frame's orientation at the end of the last step: the
    /// next step turns the shape springs' rest vectors from it to
    /// `rest_rotation` over its substeps, as it moves the roots.
    pub(crate) stepped_rotation: Mat3,
    /// Strands restored to rest after going non-finite, since creation.
    pub(crate) restored: u64,
    /// Simulated time in seconds (the steps' `dt` summed): the gusts' clock.
    pub(crate) time: f64,
    /// Per block: whether it sleeps, how long it has been still.
    pub(crate) sleep: Vec<BlockSleep>,
    /// Strands the last step advanced (all of them before the first step).
    pub(crate) awake: usize,
    /// The parameters of the last step (different ones wake every block).
    pub(crate) params_seen: Option<crate::SimParams>,
    /// The step's buffers, one set per task, grown only when the rig grows.
    pub(crate) scratch: StepScratch,
    /// The hair grid (volume and friction), sized at its first use.
    pub(crate) hair_grid: crate::hair_grid::HairGrid,
    /// Every strand's root as built (world, f64): where
    /// [`Strands::set_head_pose`] moves them from.
    pub(crate) rest_roots: Vec<DVec3>,
    /// Per block: how much of the hair each strand stands for (1 each
    /// unless [`Strands::set_hair_shares`] said otherwise); its weight in
    /// the hair grid.
    pub(crate) hair_share: Vec<F32Lanes>,
}

/// The step's reusable buffers (no per-frame allocation once sized): the
/// rig in local coordinates, shared, and one [`Scratch`] per task of the
/// step (`crate::drive::task_count`), sized when the set is built.
#[derive(Clone, Debug, Default)]
pub(crate) struct StepScratch {
    /// The colliders in local coordinates, this step's and the last one's.
    pub(crate) rig: crate::collide::rig::LocalRig,
    /// Task `t`'s buffers.
    pub(crate) tasks: Vec<Scratch>,
    /// Blocks per task (the last task may have fewer): `tasks` holds one
    /// buffer per task of this many.
    pub(crate) task_blocks: usize,
}

/// One task's buffers (no per-frame allocation once sized).
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    /// Colliders that may touch the current group of blocks.
    pub(crate) candidates: Vec<crate::collide::broad_phase::ShapeCandidate>,
    /// The SIMD step's per-chain scratch, one per block stepped together.
    pub(crate) chains: [crate::step::ChainScratch<F32Lanes>; crate::drive::PAIR],
    /// The scalar step's copy of one lane.
    pub(crate) lane: crate::scalar::LaneBuffers,
    /// The positions of the blocks stepped together at the start of their
    /// step (sleeping on), one after the other.
    pub(crate) start: Vec<Vec3Lanes>,
    /// Their previous positions, kept when a group of a block that runs
    /// sleeps (16 lanes only: an 8-lane block is one group).
    pub(crate) start_prev: Vec<Vec3Lanes>,
    /// Strands this task restored in the last step.
    pub(crate) restored: u64,
}

/// One sleep group's state (eight lanes of a block: one per block at 8
/// lanes, two at 16; `crate::drive::SLEEP_GROUPS`). Written only by the
/// step of its own block (and by the state-changing methods, which wake
/// every group).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BlockSleep {
    /// Steps in a row that ended with every vertex slower than `sleep_speed`.
    pub(crate) still: u32,
    /// Not stepped until something wakes it.
    pub(crate) asleep: bool,
    /// Advanced by the last step.
    pub(crate) stepped: bool,
    /// The group's swept box when it fell asleep: while it sleeps (roots
    /// still, zero velocity) this is what `block_sweep_aabb` would give.
    pub(crate) bounds: crate::collide::broad_phase::Aabb,
}

impl BlockSleep {
    /// Awake, never still.
    pub(crate) const AWAKE: BlockSleep = BlockSleep {
        still: 0,
        asleep: false,
        stepped: true,
        bounds: crate::drive::EMPTY_BOX,
    };
}

impl Scratch {
    /// Room for the candidates of `counts` colliders (spheres, capsules,
    /// fields) in every buffer that holds
    /// them (allocates only when a kind grew).
    pub(crate) fn reserve(&mut self, counts: [usize; 3]) {
        let n = counts.iter().sum::<usize>();
        self.candidates
            .reserve(n.saturating_sub(self.candidates.len()));
        for c in &mut self.chains {
            c.reserve(counts);
        }
        self.lane.reserve(counts);
    }

    fn new(verts: usize) -> Scratch {
        Scratch {
            candidates: Vec::new(),
            chains: std::array::from_fn(|_| crate::step::ChainScratch::new(verts)),
            lane: crate::scalar::LaneBuffers::new(verts),
            start: vec![Vec3Lanes::ZERO; verts * crate::drive::PAIR],
            start_prev: vec![Vec3Lanes::ZERO; verts * crate::drive::PAIR],
            restored: 0,
        }
    }
}

impl StepScratch {
    fn new(blocks: usize, verts: usize) -> StepScratch {
        Self::with_task_blocks(blocks, verts, crate::drive::task_blocks(blocks))
    }

    /// Buffers for tasks of `task_blocks` blocks (the step's own split is
    /// [`crate::drive::task_blocks`]; tests try others).
    pub(crate) fn with_task_blocks(blocks: usize, verts: usize, task_blocks: usize) -> Self {
        let task_blocks = task_blocks.max(1);
        StepScratch {
            rig: Default::default(),
            tasks: vec![Scratch::new(verts); blocks.div_ceil(task_blocks)],
            task_blocks,
        }
    }
}

impl Strands {
    /// Builds a set from `verts_per_strand` points per strand, strand after
    /// strand, root first, in world coordinates. Rest lengths come from these
    /// points; vertex 0 of every strand is pinned.
    ///
    /// Errors (never panics) on `verts_per_strand < 2`, a point count that is
    /// not a whole number of strands, no points, or a non-finite coordinate.
    ///
    /// # Errors
    ///
    /// [`Error::TooFewVertices`] on `verts_per_strand < 2`,
    /// [`Error::NotWholeStrands`] on a point count that is not a whole number
    /// of strands, [`Error::NoStrands`] on no points, [`Error::NonFinite`] on a
    /// non-finite coordinate.
    ///
    /// ```
    /// use coif_kernels::{step, SimParams, Strands};
    /// use glam::Vec3;
    /// // Two strands of four points, hanging from their roots.
    /// let points: Vec<Vec3> = [Vec3::ZERO, Vec3::X * 0.02]
    ///     .iter()
    ///     .flat_map(|r| (0..4).map(move |v| *r + Vec3::new(0.01 * v as f32, 0.0, 0.0)))
    ///     .collect();
    /// let mut hair = Strands::from_polylines(&points, 4).unwrap();
    /// step(&mut hair, &SimParams::default(), &[]);
    /// assert_eq!(hair.positions()[0], points[0]); // roots are pinned
    /// assert!(hair.positions()[3].y < 0.0);       // the rest falls
    /// assert!(Strands::from_polylines(&points[..3], 4).is_err());
    /// ```
    pub fn from_polylines(points: &[Vec3], verts_per_strand: usize) -> Result<Strands, Error> {
        validate_polylines(points, verts_per_strand)?;
        let verts = verts_per_strand;
        let strand_count = points.len() / verts;
        let mut s = Strands::zeroed(strand_count, verts, mean_root(points, verts));
        for b in 0..s.blocks {
            s.active.push(active_mask(s.lanes_in_block(b)));
            for l in 0..LANES {
                s.fill_lane(points, b, l);
            }
        }
        s.fill_mass_shares();
        s.rest_roots = points.iter().step_by(verts).map(|p| p.as_dvec3()).collect();
        for (r, a) in s.reach_arc.iter_mut().zip(&s.rest_arc) {
            *r = a.to_array().into_iter().fold(0.0, f32::max);
        }
        Ok(s)
    }

    /// A set of `strand_count` strands of `verts` vertices with every
    /// per-vertex array sized and zero (no active mask yet).
    fn zeroed(strand_count: usize, verts: usize, origin: DVec3) -> Strands {
        let blocks = strand_count.div_ceil(LANES);
        let n = blocks * verts;
        Strands {
            strand_count,
            verts,
            blocks,
            origin,
            pos: vec![Vec3Lanes::ZERO; n],
            prev: vec![Vec3Lanes::ZERO; n],
            roots: vec![Vec3Lanes::ZERO; blocks],
            rest_offset: vec![Vec3Lanes::ZERO; n],
            inv_mass: vec![F32Lanes::ZERO; n],
            rest_len: vec![F32Lanes::ZERO; n],
            rest_vec: vec![Vec3Lanes::ZERO; n],
            bend_share: vec![[F32Lanes::ZERO; 2]; n],
            bend_len: vec![F32Lanes::ZERO; n],
            rest_arc: vec![F32Lanes::ZERO; n],
            reach_arc: vec![0.0; n],
            shape_weight: vec![F32Lanes::ZERO; n],
            active: Vec::with_capacity(blocks),
            max_rest_segment: 0.0,
            rest_rotation: Mat3::IDENTITY,
            stepped_rotation: Mat3::IDENTITY,
            restored: 0,
            time: 0.0,
            sleep: vec![BlockSleep::AWAKE; blocks * crate::drive::SLEEP_GROUPS],
            awake: strand_count,
            params_seen: None,
            scratch: StepScratch::new(blocks, verts),
            hair_grid: Default::default(),
            rest_roots: Vec::new(),
            hair_share: vec![F32Lanes::ONE; blocks],
        }
    }

    /// Writes lane `l` of block `b`: positions (local), root, rest offsets,
    /// inverse masses, rest lengths (segment and bending), rest arc length
    /// and shape weight. Padding lanes copy the block's last strand and are
    /// fully pinned: inert, and inside the block's bounding box.
    fn fill_lane(&mut self, points: &[Vec3], b: usize, l: usize) {
        let verts = self.verts;
        let lanes = self.lanes_in_block(b);
        let strand = b * LANES + l.min(lanes - 1);
        let pts = &points[strand * verts..(strand + 1) * verts];
        let origin = self.origin;
        let local = |p: Vec3| (p.as_dvec3() - origin).as_vec3();
        let mut arc = 0.0f32;
        let total: f32 = pts.windows(2).map(|w| (w[1] - w[0]).length()).sum();
        for v in 0..verts {
            let i = b * verts + v;
            let p = local(pts[v]);
            self.pos[i].set_lane(l, p);
            self.prev[i].set_lane(l, p);
            if v == 0 {
                self.roots[b].set_lane(l, p);
            }
            self.rest_offset[i].set_lane(l, pts[v] - pts[0]);
            let free = v > 0 && l < lanes;
            self.inv_mass[i].as_mut_array()[l] = if free { 1.0 } else { 0.0 };
            let seg = if v + 1 < verts {
                (pts[v + 1] - pts[v]).length()
            } else {
                0.0
            };
            self.rest_len[i].as_mut_array()[l] = seg;
            if v + 1 < verts {
                let d = pts[v + 1] - pts[v];
                self.rest_vec[i].set_lane(l, d);
            }
            self.max_rest_segment = self.max_rest_segment.max(seg);
            self.bend_len[i].as_mut_array()[l] = if v + 2 < verts {
                (pts[v + 2] - pts[v]).length()
            } else {
                0.0
            };
            self.rest_arc[i].as_mut_array()[l] = arc;
            self.shape_weight[i].as_mut_array()[l] = if total > 0.0 {
                (1.0 - arc / total).max(0.0)
            } else {
                0.0
            };
            arc += seg;
        }
    }

    /// The mass shares `w_i / (w_i + w_j)` of every bending (v, v + 2)
    /// constraint, from the inverse masses.
    fn fill_mass_shares(&mut self) {
        let verts = self.verts;
        for b in 0..self.blocks {
            for v in 0..verts {
                let i = b * verts + v;
                if v + 2 < verts {
                    self.bend_share[i] = mass_shares(self.inv_mass[i], self.inv_mass[i + 2]);
                }
            }
        }
    }

    /// Number of strands in the set.
    pub fn strand_count(&self) -> usize {
        self.strand_count
    }

    /// Vertices per strand (the same for every strand), root included.
    pub fn verts_per_strand(&self) -> usize {
        self.verts
    }

    /// Number of SIMD blocks (`ceil(strand_count / LANES)`).
    pub fn block_count(&self) -> usize {
        self.blocks
    }

    /// Real strands in block `b` (the rest of its lanes are inert padding);
    /// 0 for a block past the end.
    pub fn lanes_in_block(&self, b: usize) -> usize {
        self.strand_count
            .saturating_sub(b.saturating_mul(LANES))
            .min(LANES)
    }

    /// Real strands in sleep group `i` (lanes `8 (i % G)..` of block
    /// `i / G`, `G` the groups per block).
    pub(crate) fn lanes_in_sleep_group(&self, i: usize) -> usize {
        let g = crate::drive::SLEEP_GROUPS;
        self.lanes_in_block(i / g)
            .saturating_sub((i % g) * crate::drive::SLEEP_GROUP_LANES)
            .min(crate::drive::SLEEP_GROUP_LANES)
    }

    /// World position of the local origin that positions are relative to.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Block `b`'s current positions relative to [`Strands::origin`]: `V`
    /// entries, root first, lane `l` = strand `b * LANES + l`. Padding lanes
    /// repeat the block's last real strand. Empty for a block past the end.
    pub fn block_positions_local(&self, b: usize) -> &[Vec3Lanes] {
        b.checked_mul(self.verts)
            .and_then(|start| self.pos.get(start..start.checked_add(self.verts)?))
            .unwrap_or(&[])
    }

    /// The positions as a read-only lane-layout view, what LOD reads.
    pub fn blocks(&self) -> StrandBlocks<'_> {
        StrandBlocks::new(&self.pos, self.strand_count, self.verts, self.origin)
            .expect("Strands keeps blocks * verts positions")
    }

    /// Per block: all bits set in lanes holding a real strand (a `select`
    /// mask); no bit set for a block `b >= block_count()`.
    pub fn block_active_mask(&self, b: usize) -> F32Lanes {
        self.active.get(b).copied().unwrap_or(F32Lanes::ZERO)
    }

    /// Current positions in world space, strand after strand, root first.
    pub fn positions(&self) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; self.strand_count * self.verts];
        let o = self.origin;
        self.for_each_point(&mut out, |p| (o + p.as_dvec3()).as_vec3());
        out
    }

    /// Writes world positions into `out` (strand after strand, root first):
    /// the first `strand_count * V` entries; the rest of a longer `out` is
    /// left as it was. Returns the number of points written,
    /// `strand_count * V`. Allocates nothing.
    ///
    /// # Errors
    ///
    /// [`Error::BufferTooSmall`] (and nothing written) if `out` holds fewer
    /// than `strand_count * V` points.
    pub fn write_positions(&self, out: &mut [Vec3]) -> Result<usize, Error> {
        let needed = self.strand_count * self.verts;
        if out.len() < needed {
            return Err(Error::BufferTooSmall {
                needed,
                got: out.len(),
            });
        }
        let o = self.origin;
        self.for_each_point(&mut out[..needed], |p| (o + p.as_dvec3()).as_vec3());
        Ok(needed)
    }

    /// Current positions relative to [`Strands::origin`], full f32 precision.
    pub fn positions_local(&self) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; self.strand_count * self.verts];
        self.for_each_point(&mut out, |p| p);
        out
    }

    fn for_each_point(&self, out: &mut [Vec3], f: impl Fn(Vec3) -> Vec3) {
        for (k, slot) in out
            .iter_mut()
            .enumerate()
            .take(self.strand_count * self.verts)
        {
            let (strand, v) = (k / self.verts, k % self.verts);
            let (b, l) = (strand / LANES, strand % LANES);
            *slot = f(self.pos[b * self.verts + v].lane(l));
        }
    }

    /// Current world position of vertex `v` of strand `i` (None if out of range).
    pub fn vertex(&self, i: usize, v: usize) -> Option<Vec3> {
        (i < self.strand_count && v < self.verts).then(|| {
            let p = self.pos[(i / LANES) * self.verts + v].lane(i % LANES);
            (self.origin + p.as_dvec3()).as_vec3()
        })
    }

    /// Rest length of segment `v -> v + 1` of strand `i`.
    pub fn rest_length(&self, i: usize, v: usize) -> Option<f32> {
        (i < self.strand_count && v + 1 < self.verts)
            .then(|| self.rest_len[(i / LANES) * self.verts + v].as_array()[i % LANES])
    }

    /// Rest arc length from the root to the tip of strand `i`.
    pub fn rest_strand_length(&self, i: usize) -> Option<f32> {
        (i < self.strand_count)
            .then(|| self.rest_arc[(i / LANES) * self.verts + self.verts - 1].as_array()[i % LANES])
    }

    /// Moves the pinned roots (one per strand, world space): skinning or head
    /// motion. The next step carries each root from where it was to here
    /// over its substeps. Rebases the local origin if the roots have
    /// wandered far.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] unless there is one root per strand,
    /// [`Error::NonFinite`] on a non-finite root; nothing changes then.
    pub fn set_roots(&mut self, roots: &[Vec3]) -> Result<(), Error> {
        self.check_roots(roots)?;
        let o = self.origin;
        self.write_roots(roots.iter().map(|r| (r.as_dvec3() - o).as_vec3()));
        self.rebase_if_far();
        Ok(())
    }

    /// Like [`Strands::set_roots`], with roots relative to [`Strands::origin`].
    ///
    /// # Errors
    ///
    /// As [`Strands::set_roots`].
    pub fn set_roots_local(&mut self, roots_local: &[Vec3]) -> Result<(), Error> {
        self.check_roots(roots_local)?;
        self.write_roots(roots_local.iter().copied());
        self.rebase_if_far();
        Ok(())
    }

    fn check_roots(&self, roots: &[Vec3]) -> Result<(), Error> {
        if roots.len() != self.strand_count {
            return Err(Error::CountMismatch {
                what: "roots (one per strand)",
                expected: self.strand_count,
                got: roots.len(),
            });
        }
        match roots.iter().position(|r| !r.is_finite()) {
            Some(index) => Err(Error::NonFinite { index }),
            None => Ok(()),
        }
    }

    fn write_roots(&mut self, roots_local: impl Iterator<Item = Vec3>) {
        for (i, r) in roots_local.enumerate() {
            let k = (i / LANES) * self.verts;
            // Padding lanes after the last strand follow it.
            let lanes = if i + 1 == self.strand_count {
                i % LANES..LANES
            } else {
                i % LANES..i % LANES + 1
            };
            // The previous position keeps where the root was at the end of
            // the last step: the step moves it from there to `r` over its
            // substeps.
            for l in lanes {
                self.pos[k].set_lane(l, r);
                self.roots[i / LANES].set_lane(l, r);
            }
        }
    }

    /// Rebases on the root nearest the local origin when even that one is
    /// more than [`REBASE_DISTANCE`] away: the hair has moved off as a
    /// whole. One strand sent far (a bad root, 1e30 m) is not the nearest
    /// and moves nothing; a mean would have dragged the origin after it
    /// and every other strand out of range or precision.
    fn rebase_if_far(&mut self) {
        let mut nearest = Vec3::splat(f32::INFINITY);
        for i in 0..self.strand_count {
            let Some(block) = self.roots.get(i / LANES) else {
                break;
            };
            let root = block.lane(i % LANES);
            if root.is_finite() && root.length_squared() < nearest.length_squared() {
                nearest = root;
            }
        }
        if nearest.is_finite() && nearest.length() > REBASE_DISTANCE {
            self.rebase(self.origin + nearest.as_dvec3());
        }
    }

    /// Moves the local origin to `new_origin` (world space) without moving
    /// anything in the world. Called automatically when roots wander more
    /// than 64 m from the origin.
    pub fn rebase(&mut self, new_origin: DVec3) {
        if !new_origin.is_finite() {
            return;
        }
        let shift = Vec3Lanes::splat((new_origin - self.origin).as_vec3());
        for p in self
            .pos
            .iter_mut()
            .chain(self.prev.iter_mut())
            .chain(self.roots.iter_mut())
        {
            *p = *p - shift;
        }
        self.origin = new_origin;
        // The sleeping blocks' boxes are in the old local frame.
        self.wake();
    }

    /// Moves the whole set rigidly by `xform` (world space), positions and
    /// previous positions alike, so no velocity is injected: a teleport, a
    /// cut in a cinematic, a respawn. `xform` must be rigid (rotation and
    /// translation); the rest shape's orientation turns with it.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidTransform`] on a non-finite or non-rigid `xform`;
    /// nothing changes then.
    pub fn teleport(&mut self, xform: Affine3A) -> Result<(), Error> {
        let Some(m) = rigid_rotation(xform)? else {
            return Err(Error::InvalidTransform {
                reason: "not a rotation and a translation",
            });
        };
        // world' = M (origin + local) + T: the origin takes M origin + T in
        // f64 and the local positions turn by M, so no translation, however
        // far, rounds them.
        self.origin = xform.matrix3.as_dmat3() * self.origin + xform.translation.as_dvec3();
        for p in self
            .pos
            .iter_mut()
            .chain(self.prev.iter_mut())
            .chain(self.roots.iter_mut())
        {
            for l in 0..LANES {
                p.set_lane(l, m * p.lane(l));
            }
        }
        self.rest_rotation = m * self.rest_rotation;
        self.stepped_rotation = m * self.stepped_rotation;
        self.wake();
        // The colliders' record is of the old place: the next step takes
        // them as standing still rather than sweeping from there.
        self.scratch.rig.forget();
        self.rebase_if_far();
        Ok(())
    }

    /// Poses the head in one call: every root moves to `world_from_rest`
    /// applied to where it was built ([`Strands::from_polylines`]), and the
    /// rest frame turns with the pose's rotation
    /// ([`Strands::set_rest_rotation`]), so that the local shape springs
    /// keep the groom as the head turns. This is `set_roots` plus
    /// `set_rest_rotation` for a rigid head; a skinned scalp calls those two
    /// itself. Allocates nothing.
    ///
    /// # Errors
    /// [`Error::NonFinite`] (index of the first non-finite matrix entry)
    /// or [`Error::InvalidParameter`] for a transform that is not a
    /// rotation and a translation (columns not orthonormal within 1e-3, or
    /// a reflection); nothing changes then.
    ///
    /// ```
    /// use coif_kernels::Strands;
    /// use glam::{Affine3A, Quat, Vec3};
    /// let groom = [Vec3::new(0.0, 1.7, 0.1), Vec3::new(0.0, 1.6, 0.12)];
    /// let mut hair = Strands::from_polylines(&groom, 2).unwrap();
    /// let turn = Affine3A::from_rotation_translation(Quat::from_rotation_y(1.0), Vec3::X);
    /// hair.set_head_pose(turn).unwrap();
    /// let root = hair.positions()[0];
    /// assert!(root.distance(turn.transform_point3(groom[0])) < 1e-5);
    /// ```
    pub fn set_head_pose(&mut self, world_from_rest: Affine3A) -> Result<(), Error> {
        let Some(m) = rigid_rotation(world_from_rest)? else {
            return Err(Error::InvalidParameter {
                name: "world_from_rest",
                value: Mat3::from(world_from_rest.matrix3).determinant(),
                expected: "a rotation and a translation",
            });
        };
        let (m64, t64) = (
            world_from_rest.matrix3.as_dmat3(),
            world_from_rest.translation.as_dvec3(),
        );
        let o = self.origin;
        let roots = std::mem::take(&mut self.rest_roots);
        self.write_roots(roots.iter().map(|r| (m64 * *r + t64 - o).as_vec3()));
        self.rest_roots = roots;
        self.rebase_if_far();
        self.set_rest_rotation(glam::Quat::from_mat3(&m))
    }

    /// How much of the hair each strand stands for, one value per strand
    /// (default 1 each): its weight in the hair grid of
    /// `SimParams::volume_stiffness` and `hair_friction`, so that a guide
    /// standing for twice the hair packs twice as densely. A frame that
    /// knows it (render hairs per guide from the interpolation, a level of
    /// a simulation LOD that keeps every other guide) sets it; only the
    /// ratios matter (the target density is the groomed pose's, with the
    /// same shares). Forgets the grid's target, which the next step
    /// recomputes.
    ///
    /// # Errors
    /// [`Error::CountMismatch`] for a count other than the strands',
    /// [`Error::NonFinite`] or [`Error::InvalidParameter`] for a share
    /// that is not finite or is negative; nothing changes then.
    pub fn set_hair_shares(&mut self, shares: &[f32]) -> Result<(), Error> {
        if shares.len() != self.strand_count {
            return Err(Error::CountMismatch {
                what: "hair shares (one per strand)",
                expected: self.strand_count,
                got: shares.len(),
            });
        }
        if let Some(index) = shares.iter().position(|s| !s.is_finite()) {
            return Err(Error::NonFinite { index });
        }
        if let Some(&bad) = shares.iter().find(|s| **s < 0.0) {
            return Err(Error::InvalidParameter {
                name: "hair share",
                value: bad,
                expected: ">= 0",
            });
        }
        for (b, block) in self.hair_share.iter_mut().enumerate() {
            let mut lanes = [0.0f32; LANES];
            for (l, v) in lanes.iter_mut().enumerate() {
                *v = shares.get(b * LANES + l).copied().unwrap_or(0.0);
            }
            *block = F32Lanes::new(lanes);
        }
        self.hair_grid.forget_target();
        Ok(())
    }

    /// Orientation of the groom frame that the rest shape (used by
    /// `local_shape_stiffness`, `shape_stiffness` and resets) is turned by: set it to the head's
    /// rotation when the engine turns the head.
    ///
    /// # Errors
    ///
    /// [`Error::NonFinite`] on a non-finite rotation; nothing changes then.
    pub fn set_rest_rotation(&mut self, rotation: glam::Quat) -> Result<(), Error> {
        if !rotation.is_finite() {
            return Err(Error::NonFinite { index: 0 });
        }
        let m = Mat3::from_quat(rotation.normalize());
        if m != self.rest_rotation {
            self.rest_rotation = m;
            self.wake();
        }
        Ok(())
    }

    /// Puts every strand in its rest shape at its current root, at rest
    /// (previous positions equal current ones), in the current groom frame
    /// ([`Strands::set_rest_rotation`]): the next step has no turn of the
    /// frame left to spread over its substeps.
    pub fn reset_to_rest(&mut self) {
        for i in 0..self.strand_count {
            self.reset_strand(i / LANES, i % LANES);
        }
        self.stepped_rotation = self.rest_rotation;
        self.wake();
    }

    /// Rest pose of one lane at its current root, zero velocity.
    pub(crate) fn reset_strand(&mut self, b: usize, l: usize) {
        let r = b * self.verts..(b + 1) * self.verts;
        let (pos, prev) = (&mut self.pos[r.clone()], &mut self.prev[r.clone()]);
        rest_pose(
            self.roots[b],
            self.rest_rotation,
            &self.rest_offset[r],
            l,
            pos,
            prev,
        );
    }

    /// Gives every free vertex the velocity `v` (m/s) for a step of `dt`
    /// seconds, by moving its previous position to `x - v dt`.
    pub fn set_velocity(&mut self, v: Vec3, dt: f32) {
        let d = v * dt;
        for i in 0..self.pos.len() {
            let free =
                self.inv_mass[i].simd_lt(F32Lanes::ZERO) | F32Lanes::ZERO.simd_lt(self.inv_mass[i]);
            let moved = self.pos[i] - Vec3Lanes::splat(d);
            self.prev[i] = Vec3Lanes::select(free, moved, self.pos[i]);
        }
        self.wake();
    }

    /// Sets every vertex's position and previous position (world space,
    /// strand after strand, root first, `strand_count * V` of each): the
    /// state of another simulation of the same strands (a level switch of a
    /// simulation LOD, a saved state). Vertex 0 becomes the root (pinned;
    /// its previous position is taken equal to it). Rest lengths and shape
    /// are unchanged; the state is taken as of the current groom frame
    /// ([`Strands::set_rest_rotation`]), so the next step spreads no turn
    /// of it. Wakes every block. Errors, changing nothing, on a
    /// wrong count or a non-finite point.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] unless both slices hold `strand_count * V`
    /// points, [`Error::NonFinite`] on a non-finite point; nothing changes then.
    pub fn set_state(&mut self, positions: &[Vec3], previous: &[Vec3]) -> Result<(), Error> {
        let n = self.strand_count * self.verts;
        for pts in [positions, previous] {
            if pts.len() != n {
                return Err(Error::CountMismatch {
                    what: "points (strands times vertices per strand)",
                    expected: n,
                    got: pts.len(),
                });
            }
            if let Some(index) = pts.iter().position(|p| !p.is_finite()) {
                return Err(Error::NonFinite { index });
            }
        }
        let o = self.origin;
        let local = |p: Vec3| (p.as_dvec3() - o).as_vec3();
        for b in 0..self.blocks {
            let lanes = self.lanes_in_block(b);
            for l in 0..LANES {
                // Padding lanes copy the block's last strand.
                let strand = b * LANES + l.min(lanes - 1);
                for v in 0..self.verts {
                    let k = strand * self.verts + v;
                    let i = b * self.verts + v;
                    let x = local(positions[k]);
                    let xp = if v == 0 { x } else { local(previous[k]) };
                    self.pos[i].set_lane(l, x);
                    self.prev[i].set_lane(l, xp);
                    if v == 0 {
                        self.roots[b].set_lane(l, x);
                    }
                }
            }
        }
        self.stepped_rotation = self.rest_rotation;
        self.wake();
        // A state from elsewhere (another level, a saved game): the
        // colliders' record may be of another time.
        self.scratch.rig.forget();
        self.rebase_if_far();
        Ok(())
    }

    /// Sizes the step's rig buffers for rigs of up to `spheres` spheres, so
    /// that not even the first step allocates (a step otherwise sizes them
    /// itself, once, when the rig grows).
    pub fn reserve_rig(&mut self, spheres: usize) {
        self.reserve_counts([spheres, 0, 0]);
    }

    /// Sizes the step's collider buffers for `colliders` (spheres, capsules
    /// and fields), so that not even the first step allocates.
    pub fn reserve_colliders(&mut self, colliders: &crate::Colliders<'_>) {
        self.reserve_counts(crate::collide::counts(colliders));
    }

    fn reserve_counts(&mut self, counts: [usize; 3]) {
        let sc = &mut self.scratch;
        sc.rig.reserve(counts);
        for t in &mut sc.tasks {
            t.reserve(counts);
        }
    }

    /// Strands that the last step advanced (awake); all of them before the
    /// first step. Strands skipped because they sleep are not counted
    /// (sleeping goes by blocks of [`LANES`] strands: see
    /// [`crate::SimParams::sleep_speed`]).
    pub fn awake_strands(&self) -> usize {
        self.awake
    }

    /// Strands in blocks that sleep now (the next step skips them unless
    /// something wakes them).
    pub fn sleeping_strands(&self) -> usize {
        (0..self.blocks * crate::drive::SLEEP_GROUPS)
            .filter(|&i| self.sleep[i].asleep)
            .map(|i| self.lanes_in_sleep_group(i))
            .sum()
    }

    /// Wakes every block: its next step advances it, and it must be still
    /// for `SLEEP_AFTER` seconds again before it sleeps.
    pub fn wake(&mut self) {
        for s in &mut self.sleep {
            *s = BlockSleep {
                stepped: s.stepped,
                ..BlockSleep::AWAKE
            };
        }
    }

    /// Strands restored to their rest pose because they went non-finite (or
    /// absurdly far), since creation.
    pub fn restored_strands(&self) -> u64 {
        self.restored
    }
}

/// The input checks of [`Strands::from_polylines`].
/// The rotation of a rigid transform: [`Error::NonFinite`] for a
/// non-finite entry, `None` when the 3x3 part is not a rotation (columns
/// orthonormal within 1e-3, determinant above 0).
fn rigid_rotation(xform: Affine3A) -> Result<Option<Mat3>, Error> {
    let cols = xform.to_cols_array();
    if let Some(index) = cols.iter().position(|c| !c.is_finite()) {
        return Err(Error::NonFinite { index });
    }
    let m = Mat3::from(xform.matrix3);
    let orthonormal = (m.transpose() * m - Mat3::IDENTITY)
        .to_cols_array()
        .iter()
        .all(|e| e.abs() <= 1e-3);
    Ok((orthonormal && m.determinant() > 0.0).then_some(m))
}

fn validate_polylines(points: &[Vec3], verts_per_strand: usize) -> Result<(), Error> {
    if verts_per_strand < 2 {
        return Err(Error::TooFewVertices { verts_per_strand });
    }
    if !points.len().is_multiple_of(verts_per_strand) {
        return Err(Error::NotWholeStrands {
            points: points.len(),
            verts_per_strand,
        });
    }
    if points.is_empty() {
        return Err(Error::NoStrands);
    }
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(Error::NonFinite { index });
    }
    // A strand farther than the step's guard from its root (1e6 m) is
    // restored to its rest pose every step: refused here instead (points
    // near f32::MAX made segments of infinite length).
    for strand in points.chunks_exact(verts_per_strand) {
        let root = strand[0];
        if let Some(far) = strand
            .iter()
            .map(|p| (*p - root).length())
            .find(|d| d.is_nan() || *d > crate::constraints::BLOWN_UP)
        {
            return Err(Error::InvalidParameter {
                name: "points",
                value: far,
                expected: "every point within 1e6 m of its strand's root",
            });
        }
    }
    Ok(())
}

/// The mean of the roots, in f64: the local origin of a new set.
fn mean_root(points: &[Vec3], verts: usize) -> DVec3 {
    let strand_count = points.len() / verts;
    points
        .iter()
        .step_by(verts)
        .map(|p| p.as_dvec3())
        .sum::<DVec3>()
        / strand_count as f64
}

/// All bits set in the first `lanes` lanes (those holding a real strand).
fn active_mask(lanes: usize) -> F32Lanes {
    let lane_index = F32Lanes::new(std::array::from_fn(|l| l as f32));
    lane_index.simd_lt(F32Lanes::splat(lanes as f32))
}

/// Mass shares of a constraint between inverse masses `wi` and `wj`, per
/// lane: `[wi / (wi + wj), wj / (wi + wj)]`, 0 where both are pinned.
fn mass_shares(wi: F32Lanes, wj: F32Lanes) -> [F32Lanes; 2] {
    let (wi, wj) = (wi.to_array(), wj.to_array());
    let part = |a: f32, c: f32| if a + c > 0.0 { a / (a + c) } else { 0.0 };
    [
        F32Lanes::new(std::array::from_fn(|l| part(wi[l], wj[l]))),
        F32Lanes::new(std::array::from_fn(|l| part(wj[l], wi[l]))),
    ]
}

/// Writes lane `l` of one block's `pos` and `prev` (its `V` entries): the
/// rest pose `root + R rest_offset_v` at the block's `roots`, zero velocity.
pub(crate) fn rest_pose(
    roots: Vec3Lanes,
    rotation: Mat3,
    rest_offset: &[Vec3Lanes],
    l: usize,
    pos: &mut [Vec3Lanes],
    prev: &mut [Vec3Lanes],
) {
    let root = roots.lane(l);
    for ((x, xp), off) in pos.iter_mut().zip(prev.iter_mut()).zip(rest_offset) {
        let p = root + rotation * off.lane(l);
        x.set_lane(l, p);
        xp.set_lane(l, p);
    }
}
