//! Simulation level of detail: fewer guides simulated when a character is
//! small on screen.
//!
//! Level `k` simulates a subset of the guides: every `stride_k`-th guide
//! (strides 1, 2, 4, 8 by default), plus every guide whose root is farther
//! than `cover_k = 1.5 sqrt(stride_k) s` from the subset's roots (`s`, the
//! median distance from a root to its nearest neighbour), so that the
//! subset covers the scalp. The subset is its own [`Strands`] (its lanes
//! stay full: a level of 2,048 / 8 guides is 32 full blocks, not 256 blocks
//! with one lane in eight awake). Every other guide **follows** its three
//! nearest simulated guides (by root distance, inverse-square-distance
//! weights `w_i`, summing to 1), as a displacement from its own pose:
//!
//! `x_j = P r_j + sum_i w_i (x_i - P r_i)`
//!
//! with `P` the head pose and `r` the reference pose (the settled groom at
//! the identity pose): each follower keeps its own shape and borrows its
//! neighbours' motion (the interpolation of Nalu, Nguyen and Donnelly 2005,
//! applied to displacements; HairWorks and TressFX interpolate render hair
//! from guides the same way).
//!
//! **Switching levels** does not pop: the new level's simulated guides
//! start from the current output (positions and the previous step's, so
//! they keep their velocity: [`Strands::set_state`]), and the difference
//! between the old output and the new one (head-local) is added back and
//! faded out linearly over [`BLEND_STEPS`] steps.
//!
//! **Off screen** ([`SimLod::follow_rigidly`]): the hair is carried
//! rigidly by the head, nothing is stepped; the motion is kept as one rigid
//! transform and applied once when the simulation resumes
//! ([`SimLod::catch_up`], a [`Strands::teleport`]: no velocity injected),
//! which then goes on from that state (a settle-in, as after a teleport).
//!
//! Nothing allocates per step (every buffer is sized at construction).

use crate::Error;
use coif_kernels::{self as kernels, SimParams, Sphere, Strands};
use glam::{Affine3A, Mat3, Quat, Vec3};

/// Steps over which a level switch fades the old output into the new one.
pub const BLEND_STEPS: u32 = 10;

/// The default strides of the levels: level `k` simulates about every
/// `STRIDES[k]`-th guide.
pub const STRIDES: [usize; 4] = [1, 2, 4, 8];

/// Height on screen (pixels) at and above which every guide is simulated;
/// each halving of the height below it takes the next level.
pub const FULL_DETAIL_PX: f32 = 240.0;

/// A guide that follows simulated ones.
#[derive(Clone, Copy, Debug)]
struct Follower {
    /// Index of the guide (in the whole groom).
    guide: u32,
    /// Indices (in the level's simulated list) of its three nearest
    /// simulated guides, and their weights.
    from: [u32; 3],
    weight: [f32; 3],
}

/// One level: the simulated subset as its own strands, the followers.
#[derive(Clone, Debug)]
struct Level {
    stride: usize,
    /// Guides simulated, in groom order.
    simulated: Vec<u32>,
    strands: Strands,
    followers: Vec<Follower>,
    /// Per follower and vertex: `r_j - sum_i w_i r_i` (reference pose).
    offsets: Vec<Vec3>,
    /// The subset's world positions (written each step), its roots and a
    /// second buffer for `set_state`.
    buf: Vec<Vec3>,
    buf_prev: Vec<Vec3>,
    roots: Vec<Vec3>,
    /// Rest length of segment v -> v + 1 of each simulated guide.
    rest_len: Vec<f32>,
}

/// A groom's guides simulated at one of several levels of detail; writes
/// every guide's positions each step.
#[derive(Clone, Debug)]
pub struct SimLod {
    verts: usize,
    guides: usize,
    /// The reference pose (head pose = identity), world space.
    reference: Vec<Vec3>,
    levels: Vec<Level>,
    current: usize,
    /// Every guide's positions (world), this step and the last.
    out: Vec<Vec3>,
    out_prev: Vec<Vec3>,
    /// Old output minus new output at the last switch, head-local.
    blend: Vec<Vec3>,
    blend_left: u32,
    /// The head pose `out` and the strands are at.
    pose: Affine3A,
    /// The head pose the hair is carried to off screen (`pose` when on).
    carried: Affine3A,
}

impl SimLod {
    /// Builds the levels of `strides` (each >= 1; the first is usually 1)
    /// for guides whose rest shape (rest lengths, local shape) is `rest`
    /// and whose reference pose is `reference` (both `verts` points per
    /// guide, world space at the identity head pose; `reference` is where
    /// the simulation starts, e.g. the settled groom). Starts at level 0.
    ///
    /// Errors on mismatched or non-finite input or an empty list of strides.
    pub fn new(
        rest: &[Vec3],
        reference: &[Vec3],
        verts: usize,
        strides: &[usize],
    ) -> Result<SimLod, Error> {
        if strides.is_empty() || strides.contains(&0) {
            return Err(Error::Setting {
                name: "strides",
                expected: "at least one stride, each >= 1",
            });
        }
        if rest.len() != reference.len() {
            return Err(Error::Simulation(kernels::Error::CountMismatch {
                what: "reference points (one per rest point)",
                expected: rest.len(),
                got: reference.len(),
            }));
        }
        // Validates counts and finiteness.
        Strands::from_polylines(reference, verts)?;
        let guides = rest.len() / verts;
        let roots: Vec<Vec3> = reference.iter().step_by(verts).copied().collect();
        let spacing = median_nearest(&roots);
        let mut levels = Vec::with_capacity(strides.len());
        for &stride in strides {
            levels.push(Level::new(rest, reference, verts, &roots, stride, spacing)?);
        }
        Ok(SimLod {
            verts,
            guides,
            reference: reference.to_vec(),
            levels,
            current: 0,
            out: reference.to_vec(),
            out_prev: reference.to_vec(),
            blend: vec![Vec3::ZERO; reference.len()],
            blend_left: 0,
            pose: Affine3A::IDENTITY,
            carried: Affine3A::IDENTITY,
        })
    }

    /// Sizes every level's rig buffers for up to `spheres` spheres, so that
    /// no step allocates, not even a level's first ([`Strands::reserve_rig`]).
    pub fn reserve_rig(&mut self, spheres: usize) {
        for l in &mut self.levels {
            l.strands.reserve_rig(spheres);
        }
    }

    /// Number of levels.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// The level in use.
    pub fn level(&self) -> usize {
        self.current
    }

    /// Guides simulated at level `level` (None past the last level).
    pub fn simulated_guides(&self, level: usize) -> Option<usize> {
        self.levels.get(level).map(|l| l.simulated.len())
    }

    /// The stride level `level` was built with.
    pub fn stride(&self, level: usize) -> Option<usize> {
        self.levels.get(level).map(|l| l.stride)
    }

    /// Every guide.
    pub fn guide_count(&self) -> usize {
        self.guides
    }

    /// Points per guide.
    pub fn verts_per_strand(&self) -> usize {
        self.verts
    }

    /// The level for a character `height_px` pixels tall on screen: 0 at
    /// [`FULL_DETAIL_PX`] and above, one more per halving, at most the last.
    pub fn level_for_height(&self, height_px: f32) -> usize {
        if height_px.is_nan() || height_px >= FULL_DETAIL_PX {
            return 0;
        }
        let halvings = (FULL_DETAIL_PX / height_px.max(1e-3)).log2().floor();
        (halvings as usize).min(self.levels.len() - 1)
    }

    /// The strands simulated at the current level.
    pub fn strands(&self) -> &Strands {
        &self.levels[self.current].strands
    }

    /// Every guide's positions, world space, strand after strand, as of the
    /// last step: while the hair follows the head rigidly off screen, move
    /// them by [`SimLod::carried`] (or call [`SimLod::catch_up`] first).
    pub fn positions(&self) -> &[Vec3] {
        &self.out
    }

    /// The rigid motion from the pose of [`SimLod::positions`] to where the
    /// head has carried the hair since (identity on screen).
    pub fn carried(&self) -> Affine3A {
        self.carried * self.pose.inverse()
    }

    /// Applies the rigid motion of the steps spent off screen to the
    /// strands and the output ([`Strands::teleport`]: no velocity). `step`
    /// and `set_level` call it; it costs one pass over the vertices, once,
    /// however long the hair was off screen.
    pub fn catch_up(&mut self) {
        if self.carried == self.pose {
            return;
        }
        let delta = self.carried();
        let level = &mut self.levels[self.current];
        let _ = level.strands.teleport(delta);
        for p in self.out.iter_mut().chain(self.out_prev.iter_mut()) {
            *p = delta.transform_point3(*p);
        }
        self.pose = self.carried;
    }

    /// Switches to `level` (clamped to the last) without a pop: the new
    /// subset starts from the current output and its velocity, made valid
    /// (each segment at its rest length, root to tip, and every vertex out
    /// of `spheres`, the rig where it is now, grown by `pearl_radius`: a
    /// guide that followed may have been stretched or inside the head),
    /// and the output difference fades out over [`BLEND_STEPS`] steps.
    pub fn set_level(&mut self, level: usize, spheres: &[Sphere], pearl_radius: f32) {
        let level = level.min(self.levels.len() - 1);
        if level == self.current {
            return;
        }
        self.catch_up();
        let verts = self.verts;
        // What is shown now, head-local, before the switch.
        let rot_inv = Mat3::from(self.pose.matrix3).transpose();
        for (b, o) in self.blend.iter_mut().zip(&self.out) {
            *b = rot_inv * *o;
        }
        // (`out` already holds a blend still running: it is folded in.)
        let new = &mut self.levels[level];
        for (k, &g) in new.simulated.iter().enumerate() {
            let (src, dst) = (g as usize * verts, k * verts);
            new.buf[dst..dst + verts].copy_from_slice(&self.out[src..src + verts]);
            new.buf_prev[dst..dst + verts].copy_from_slice(&self.out_prev[src..src + verts]);
            make_valid(
                &mut new.buf[dst..dst + verts],
                &mut new.buf_prev[dst..dst + verts],
                &new.rest_len[dst..dst + verts],
                spheres,
                pearl_radius,
            );
        }
        // The output is as of the last pose: the level's groom frame first,
        // so that `set_state` takes the state in it and its next step
        // spreads only the turn from there (not from when the level last
        // ran). Finite by construction (the output is); an error leaves the
        // level's old state.
        let _ = new
            .strands
            .set_rest_rotation(Quat::from_mat3(&Mat3::from(self.pose.matrix3)));
        let _ = new.strands.set_state(&new.buf, &new.buf_prev);
        self.current = level;
        self.blend_left = 0;
        self.write_output();
        for (b, o) in self.blend.iter_mut().zip(&self.out) {
            *b -= rot_inv * *o;
        }
        self.blend_left = BLEND_STEPS;
        self.apply_blend();
    }

    /// One step of the current level with the head at `pose` (rigid; the
    /// reference pose moved by it gives the roots and the rest orientation)
    /// and the rig `spheres` (world space), then the followers and the
    /// blend of a recent switch.
    pub fn step(&mut self, params: &SimParams, pose: Affine3A, spheres: &[Sphere]) {
        self.step_with(kernels::step, params, pose, spheres);
    }

    /// [`SimLod::step`] with another strand step, e.g. the scalar reference
    /// `coif_kernels::scalar::step` (the report times both).
    pub fn step_with(
        &mut self,
        stepper: fn(&mut Strands, &SimParams, &[Sphere]),
        params: &SimParams,
        pose: Affine3A,
        spheres: &[Sphere],
    ) {
        self.catch_up();
        let verts = self.verts;
        let level = &mut self.levels[self.current];
        for (r, &g) in level.roots.iter_mut().zip(&level.simulated) {
            *r = pose.transform_point3(self.reference[g as usize * verts]);
        }
        let _ = level.strands.set_roots(&level.roots);
        let _ = level
            .strands
            .set_rest_rotation(Quat::from_mat3(&Mat3::from(pose.matrix3)));
        stepper(&mut level.strands, params, spheres);
        self.pose = pose;
        self.carried = pose;
        std::mem::swap(&mut self.out, &mut self.out_prev);
        self.write_output();
        if self.blend_left > 0 {
            self.blend_left -= 1;
            self.apply_blend();
        }
    }

    /// Off screen: the hair follows the head rigidly to `pose`, nothing is
    /// stepped. Costs nothing per step: the motion is kept as one rigid
    /// transform ([`SimLod::carried`]) and applied once when the
    /// simulation resumes ([`SimLod::catch_up`]), which then starts from
    /// the carried state with the velocity it had (a settle-in, as after a
    /// teleport).
    pub fn follow_rigidly(&mut self, pose: Affine3A) {
        self.carried = pose;
    }

    /// The current level's simulated guides to the output, then the
    /// followers: `x_j = P r_j + sum_i w_i (x_i - P r_i)`.
    fn write_output(&mut self) {
        let verts = self.verts;
        let pose = self.pose;
        let level = &mut self.levels[self.current];
        // `buf` holds the level's strands exactly (sized at construction).
        let written = level.strands.write_positions(&mut level.buf);
        debug_assert!(written.is_ok(), "{written:?}");
        for (k, &g) in level.simulated.iter().enumerate() {
            let (src, dst) = (k * verts, g as usize * verts);
            self.out[dst..dst + verts].copy_from_slice(&level.buf[src..src + verts]);
        }
        // x_j = M (r_j - sum_i w_i r_i) + sum_i w_i x_i (the weights sum to 1,
        // so the pose's translation cancels).
        let m = Mat3::from(pose.matrix3);
        for (f, off) in level
            .followers
            .iter()
            .zip(level.offsets.chunks_exact(verts))
        {
            let j = f.guide as usize * verts;
            let from = f.from.map(|i| i as usize * verts);
            for (v, o) in off.iter().enumerate() {
                self.out[j + v] = m * *o
                    + level.buf[from[0] + v] * f.weight[0]
                    + level.buf[from[1] + v] * f.weight[1]
                    + level.buf[from[2] + v] * f.weight[2];
            }
        }
    }

    /// Adds the fading switch difference: `blend_left / BLEND_STEPS` of it,
    /// turned with the head.
    fn apply_blend(&mut self) {
        let share = self.blend_left as f32 / BLEND_STEPS as f32;
        let rot = Mat3::from(self.pose.matrix3);
        for (o, b) in self.out.iter_mut().zip(&self.blend) {
            *o += rot * (*b * share);
        }
    }
}

impl Level {
    fn new(
        rest: &[Vec3],
        reference: &[Vec3],
        verts: usize,
        roots: &[Vec3],
        stride: usize,
        spacing: f32,
    ) -> Result<Level, Error> {
        let guides = roots.len();
        let simulated = cover(roots, stride, spacing);
        let mut picked_rest = Vec::with_capacity(simulated.len() * verts);
        let mut picked_ref = Vec::with_capacity(simulated.len() * verts);
        for &g in &simulated {
            let r = g as usize * verts..(g as usize + 1) * verts;
            picked_rest.extend_from_slice(&rest[r.clone()]);
            picked_ref.extend_from_slice(&reference[r]);
        }
        let mut strands = Strands::from_polylines(&picked_rest, verts)?;
        strands.set_state(&picked_ref, &picked_ref)?;
        let mut is_sim = vec![false; guides];
        for &g in &simulated {
            is_sim[g as usize] = true;
        }
        let followers: Vec<Follower> = (0..guides)
            .filter(|&g| !is_sim[g])
            .map(|g| follower(g, roots, &simulated))
            .collect();
        let mut offsets = Vec::with_capacity(followers.len() * verts);
        for f in &followers {
            for v in 0..verts {
                let mut o = reference[f.guide as usize * verts + v];
                for (&i, &w) in f.from.iter().zip(&f.weight) {
                    o -= reference[simulated[i as usize] as usize * verts + v] * w;
                }
                offsets.push(o);
            }
        }
        let rest_len = picked_rest
            .chunks_exact(verts)
            .flat_map(|g| {
                (0..verts).map(move |v| {
                    if v + 1 < verts {
                        g[v].distance(g[v + 1])
                    } else {
                        0.0
                    }
                })
            })
            .collect();
        Ok(Level {
            offsets,
            rest_len,
            stride,
            roots: vec![Vec3::ZERO; simulated.len()],
            buf: picked_ref.clone(),
            buf_prev: picked_ref,
            simulated,
            strands,
            followers,
        })
    }
}

/// One strand's state made valid, root to tip: each segment scaled to its
/// rest length (Follow-The-Leader, Muller et al. 2012), then the vertex
/// pushed out of every sphere (grown by `pearl_radius`); the previous
/// position moves with the vertex, so its velocity is kept.
fn make_valid(
    pos: &mut [Vec3],
    prev: &mut [Vec3],
    rest_len: &[f32],
    spheres: &[Sphere],
    pearl_radius: f32,
) {
    for v in 1..pos.len() {
        let d = pos[v] - pos[v - 1];
        let len = d.length();
        let mut x = if len > 1e-9 {
            pos[v - 1] + d * (rest_len[v - 1] / len)
        } else {
            pos[v]
        };
        for s in spheres {
            let reach = s.radius + pearl_radius;
            let out = x - s.center;
            let dist = out.length();
            if dist < reach && dist > 1e-9 && s.center.is_finite() {
                x = s.center + out * (reach / dist);
            }
        }
        prev[v] += x - pos[v];
        pos[v] = x;
    }
}

/// Every `stride`-th guide, then each guide farther than
/// `1.5 sqrt(stride) spacing` from every chosen root, in groom order.
fn cover(roots: &[Vec3], stride: usize, spacing: f32) -> Vec<u32> {
    let mut chosen: Vec<u32> = (0..roots.len()).step_by(stride).map(|g| g as u32).collect();
    if stride > 1 {
        let reach = 1.5 * (stride as f32).sqrt() * spacing;
        for g in 0..roots.len() {
            let covered = chosen
                .iter()
                .any(|&c| roots[c as usize].distance_squared(roots[g]) <= reach * reach);
            if !covered {
                chosen.push(g as u32);
            }
        }
        chosen.sort_unstable();
    }
    chosen
}

/// Guide `g`'s three nearest simulated guides (by root) and weights
/// `1 / (d^2 + e)`, normalised (`e` = 1e-8 m^2).
fn follower(g: usize, roots: &[Vec3], simulated: &[u32]) -> Follower {
    let mut best = [(f32::INFINITY, 0u32); 3];
    for (k, &s) in simulated.iter().enumerate() {
        let d = roots[s as usize].distance_squared(roots[g]);
        if d < best[2].0 {
            best[2] = (d, k as u32);
            best.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
    }
    // Fewer than three simulated guides: repeat the nearest.
    for i in 1..3 {
        if !best[i].0.is_finite() {
            best[i] = best[0];
        }
    }
    let raw = best.map(|(d, _)| 1.0 / (d + 1e-8));
    let sum: f32 = raw.iter().sum();
    Follower {
        guide: g as u32,
        from: best.map(|(_, k)| k),
        weight: raw.map(|w| w / sum),
    }
}

/// The median distance from a root to its nearest other root (0 for one root).
fn median_nearest(roots: &[Vec3]) -> f32 {
    let mut d: Vec<f32> = roots
        .iter()
        .enumerate()
        .map(|(i, a)| {
            roots
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, b)| a.distance(*b))
                .fold(f32::INFINITY, f32::min)
        })
        .filter(|d| d.is_finite())
        .collect();
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f32::total_cmp);
    d[d.len() / 2]
}
