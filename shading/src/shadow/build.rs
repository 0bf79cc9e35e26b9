//! The SIMD build of an [`OpacityShadowMap`]: bounds, sample positions,
//! bilinear weights, depths and plane intervals eight at a time in `F32Lanes`
//! lanes, deposits in lane order with scalar adds (the scalar sample
//! order), the prefix sum sixteen texels at a time. Scalar twin:
//! `shadow/scalar/build.rs`, bit for bit the same map.

use super::layers::Layering;
use super::light_frame::{LightFrame, MapPlacement};
use super::map::OpacityShadowMap;
use super::raster::{for_each_sample, for_each_sample_lanes, SplatX8};
use super::settings::{ShadowMode, ShadowSettings};
use super::strand_lanes::StrandLanes;
use crate::Error;
use coif_base::lanes::lanes_of_bits;
use coif_base::lanes::{F32Lanes, I32Lanes};
use coif_base::tasks::{for_each_chunk_mut, DisjointMut, Executor};
use coif_base::{Vec3Lanes, LANES};
use glam::Vec3;
use std::ops::Range;
use wide::f32x8;

impl OpacityShadowMap {
    /// Rebuilds the map for a directional light shining along `light_dir`
    /// (from the light toward the scene; normalised here) from hair
    /// polylines: `points` holds `verts_per_strand` points per strand,
    /// strand after strand (a trailing partial strand is ignored).
    /// Segments with a non-finite end are skipped. No allocation.
    ///
    /// Steps (numbered alike in the scalar twin): 1. light frame; light-space bounds of the finite points (the
    /// footprint in x, y padded by the hair radius and a texel, and
    /// `[near, far]` in z); 2. deep mode only, the depth map `z0` (the nearest
    /// sample splatted into each texel); 3. every segment's samples deposit
    /// their coverage into the interval of planes they lie in; 4. a prefix
    /// sum along depth per texel makes the opacity cumulative.
    ///
    /// The SIMD path: bounds, sample positions, bilinear weights, depths and
    /// plane intervals eight at a time in `F32Lanes` lanes, deposits in lane
    /// order with scalar adds (the scalar sample order), and the prefix sum
    /// sixteen texels at a time. The map is bit for bit the one
    /// [`super::scalar::build`] makes (tested).
    pub fn build(&mut self, light_dir: Vec3, points: &[Vec3], verts_per_strand: usize) {
        let Some(points) = self.prepare(light_dir, points, verts_per_strand, light_bounds) else {
            return;
        };
        let pass = Pass::of(self);
        let src = Points {
            points,
            verts: verts_per_strand,
        };
        let all = 0..src.units();
        if self.settings.mode == ShadowMode::Deep {
            // 2. The depth map z0: the nearest sample per texel.
            self.first_depth.fill(f32::INFINITY);
            pass.depth(&mut self.first_depth, &src, all.clone());
            pass.finish_depth(&mut self.first_depth);
        }
        // 3. Deposit every sample into its plane interval.
        pass.deposit(&mut self.texels, &self.first_depth, &src, all);
        // 4. Prefix sum along depth.
        prefix_sum(&mut self.texels, pass.nn, self.settings.layers);
        self.keep_depth_in_texels();
        self.ready = true;
    }

    /// [`OpacityShadowMap::build`] as independent tasks on `executor`, so
    /// that it can run on threads with the same bytes at any thread count:
    /// the strands are split into `scratch.tasks()` contiguous ranges
    /// (a count fixed by the caller, never by the executor); 2. each task
    /// splats its range's depth map into its own partial map, reduced by
    /// `min` (exact in any order); 3. each task deposits its range into its
    /// own partial map, and the partial maps are summed texel by texel in
    /// task order; 4. the prefix sum. With one task the map is bit for bit
    /// [`OpacityShadowMap::build`]'s; with more, each texel sums the same
    /// deposits grouped by task (float rounding apart, the same map:
    /// tested). No allocation: `scratch` holds the partial maps.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] if `scratch` was made for other settings
    /// (its partial maps have another size); the map is then left empty
    /// (every transmittance 1).
    pub fn build_tasks(
        &mut self,
        executor: &dyn Executor,
        scratch: &mut BuildScratch,
        light_dir: Vec3,
        points: &[Vec3],
        verts_per_strand: usize,
    ) -> Result<(), Error> {
        scratch.check_fits(self)?;
        let Some(points) = self.prepare(light_dir, points, verts_per_strand, light_bounds) else {
            return Ok(());
        };
        let src = Points {
            points,
            verts: verts_per_strand,
        };
        self.build_parts(executor, scratch, &src);
        Ok(())
    }

    /// [`OpacityShadowMap::build_tasks`] from hair in lane layout (blocks
    /// of up to eight strands in the lanes of `F32Lanes`, [`StrandLanes`]):
    /// the same steps, with the tasks' ranges of eight-lane groups instead
    /// of strands (so the same ranges of strands at 8 and 16 lanes)
    /// and each group of eight segments taken as segment `r` of a block's
    /// eight strands (rows `r`, `r + 1`) instead of eight consecutive
    /// segments of one strand. The same samples as
    /// [`OpacityShadowMap::build`] on the same strands (hair after hair),
    /// deposited in another order: the same first depths bit for bit, the
    /// same opacities to float rounding (tested). The rows are asked for
    /// three times per block (bounds, depth map, deposits), never stored:
    /// a fused pass interpolates them on the fly. Scalar twin
    /// [`super::scalar::build_lanes`] (bit for bit, one task). No
    /// allocation.
    ///
    /// # Errors
    ///
    /// As [`OpacityShadowMap::build_tasks`]: [`Error::CountMismatch`] if
    /// `scratch` was made for other settings (the map is then left empty).
    pub fn build_lanes<H: StrandLanes + ?Sized>(
        &mut self,
        executor: &dyn Executor,
        scratch: &mut BuildScratch,
        light_dir: Vec3,
        hair: &H,
    ) -> Result<(), Error> {
        scratch.check_fits(self)?;
        let bounds = |frame: &LightFrame| lane_bounds(frame, hair, executor);
        if !self.prepare_with(light_dir, hair.verts(), bounds) {
            return Ok(());
        }
        self.build_parts(executor, scratch, &Lanes(hair));
        Ok(())
    }

    /// Steps 2 to 4 of the task builds, after `prepare`.
    fn build_parts(
        &mut self,
        executor: &dyn Executor,
        scratch: &mut BuildScratch,
        src: &impl Source,
    ) {
        let texels_len = self.texels.len();
        let depth_len = self.first_depth.len();
        let tasks = scratch.tasks;
        let pass = Pass::of(self);
        let units = src.units();
        let range = |i: usize| i * units / tasks..(i + 1) * units / tasks;
        if self.settings.mode == ShadowMode::Deep {
            // 2. Partial depth maps, reduced by min.
            for_each_chunk_mut(executor, &mut scratch.depth, depth_len, &|i, z0| {
                z0.fill(f32::INFINITY);
                pass.depth(z0, src, range(i));
            });
            let parts = &scratch.depth[..];
            let chunk = depth_len.div_ceil((4 * executor.threads()).clamp(1, MAX_TEXEL_RUNS));
            for_each_chunk_mut(executor, &mut self.first_depth, chunk, &|c, z0| {
                z0.fill(f32::INFINITY);
                for part in parts.chunks_exact(depth_len) {
                    for (z, p) in z0.iter_mut().zip(&part[c * chunk..]) {
                        *z = z.min(*p);
                    }
                }
                pass.finish_depth(z0);
            });
        }
        // 3. Partial deposits.
        let z0 = &self.first_depth;
        for_each_chunk_mut(executor, &mut scratch.texels, texels_len, &|i, part| {
            part.fill([0.0; 4]);
            pass.deposit(part, z0, src, range(i));
        });
        // 3b and 4., as tasks over runs of texels (of every plane group):
        // the partial maps summed in task order, then the prefix sum along
        // depth. Each texel's adds are the same in any split.
        let (nn, layers, groups) = (pass.nn, self.settings.layers, self.settings.groups());
        let parts = &scratch.texels[..];
        let runs = (4 * executor.threads()).clamp(1, MAX_TEXEL_RUNS);
        let per_run = nn.div_ceil(runs).next_multiple_of(16);
        let texels = DisjointMut::new(&mut self.texels);
        executor.run(nn.div_ceil(per_run), &|r| {
            let run = r * per_run..((r + 1) * per_run).min(nn);
            for g in 0..groups {
                let at = g * nn + run.start;
                // SAFETY: run r of every group is this task's alone.
                let dst = unsafe { texels.range(at, run.len()) };
                let mut part = parts.chunks_exact(texels_len);
                if let Some(first) = part.next() {
                    dst.copy_from_slice(&first[at..at + run.len()]);
                }
                for p in part {
                    for (t, p) in dst.iter_mut().zip(&p[at..at + run.len()]) {
                        for k in 0..4 {
                            t[k] += p[k];
                        }
                    }
                }
            }
            prefix_sum_of(&texels, nn, layers, run);
        });
        self.keep_depth_in_texels();
        self.ready = true;
    }
}

/// The hair of one build, in units (strands or blocks) that tasks split
/// into contiguous ranges.
trait Source: Sync {
    /// Number of units.
    fn units(&self) -> usize;
    /// Every sample of the units in `units`, in order.
    fn samples(&self, pass: &Pass, units: Range<usize>, deposit: impl FnMut(&SplatX8));
}

/// Strands of `verts` points each, one after another (units: strands).
struct Points<'a> {
    points: &'a [Vec3],
    verts: usize,
}

impl Source for Points<'_> {
    fn units(&self) -> usize {
        self.points.len() / self.verts.max(1)
    }

    fn samples(&self, pass: &Pass, units: Range<usize>, deposit: impl FnMut(&SplatX8)) {
        let points = &self.points[units.start * self.verts..units.end * self.verts];
        let (frame, placement) = (&pass.frame, &pass.placement);
        for_each_sample(
            frame,
            placement,
            pass.n,
            pass.radius,
            points,
            self.verts,
            deposit,
        );
    }
}

/// Hair in lane layout (units: groups of eight lanes, so that tasks split
/// it at the same strands at 8 and 16 lanes).
struct Lanes<'a, H: ?Sized>(&'a H);

impl<H: StrandLanes + ?Sized> Source for Lanes<'_, H> {
    fn units(&self) -> usize {
        self.0.groups()
    }

    fn samples(&self, pass: &Pass, units: Range<usize>, deposit: impl FnMut(&SplatX8)) {
        let (frame, placement) = (&pass.frame, &pass.placement);
        for_each_sample_lanes(
            frame,
            placement,
            pass.n,
            pass.radius,
            self.0,
            units,
            deposit,
        );
    }
}

/// Caller-owned partial maps for [`OpacityShadowMap::build_tasks`]: one
/// map's texels (and depth map, in deep mode) per task, allocated once.
#[derive(Clone, Debug)]
pub struct BuildScratch {
    tasks: usize,
    texels: Vec<[f32; 4]>,
    depth: Vec<f32>,
}

impl BuildScratch {
    /// Partial maps for `tasks` tasks (at least 1) of maps made with
    /// `settings`.
    ///
    /// # Errors
    ///
    /// As [`ShadowSettings::validate`], and [`Error::InvalidShadowSetting`]
    /// (`tasks`) if the partial maps of `tasks` tasks would not fit in memory.
    pub fn new(settings: &ShadowSettings, tasks: usize) -> Result<BuildScratch, Error> {
        settings.validate()?;
        let tasks = tasks.max(1);
        let nn = settings.resolution * settings.resolution;
        let too_many = Error::InvalidShadowSetting {
            name: "tasks",
            value: tasks as f32,
            expected: "few enough partial maps to fit in memory",
        };
        let texels = tasks
            .checked_mul(nn * settings.groups())
            .filter(|&n| n <= isize::MAX as usize / 16)
            .ok_or(too_many.clone())?;
        if tasks.checked_mul(nn).is_none() {
            return Err(too_many);
        }
        Ok(BuildScratch {
            tasks,
            texels: vec![[0.0; 4]; texels],
            depth: match settings.mode {
                ShadowMode::Slices => Vec::new(),
                ShadowMode::Deep => vec![0.0; tasks * nn],
            },
        })
    }

    /// The number of tasks (and partial maps).
    pub fn tasks(&self) -> usize {
        self.tasks
    }

    /// `Ok` if the partial maps have `map`'s sizes; otherwise the map is
    /// marked empty and the mismatch returned.
    fn check_fits(&self, map: &mut OpacityShadowMap) -> Result<(), Error> {
        let (texels, depth) = (
            self.tasks.saturating_mul(map.texels.len()),
            self.tasks.saturating_mul(map.first_depth.len()),
        );
        if self.texels.len() == texels && self.depth.len() == depth {
            return Ok(());
        }
        map.ready = false;
        Err(Error::CountMismatch {
            what: "partial-map texels (BuildScratch made for other settings)",
            expected: texels,
            got: self.texels.len(),
        })
    }
}

/// What the rasterising passes of one build share: the light frame and
/// placement of `prepare`, the layering, resolution and hair radius.
#[derive(Clone, Copy)]
struct Pass {
    frame: LightFrame,
    placement: MapPlacement,
    layering: Layering,
    mode: ShadowMode,
    n: usize,
    nn: usize,
    radius: f32,
    /// Float indices into the flat map fit in i32 lanes (every map up to
    /// 2^29 texels; larger ones index lane by lane).
    flat_fits: bool,
}

impl Pass {
    fn of(map: &OpacityShadowMap) -> Pass {
        let n = map.settings.resolution;
        Pass {
            frame: map.frame,
            placement: map.placement,
            layering: map.layering,
            mode: map.settings.mode,
            n,
            nn: n * n,
            radius: map.settings.hair_radius,
            flat_fits: map.texels.len() <= (i32::MAX as usize) / 4,
        }
    }

    /// The four texels of a splat, relative to its lower-left one.
    fn offsets(&self) -> [usize; 4] {
        [0, 1, self.n, self.n + 1]
    }

    /// Step 2 into `z0` (filled with infinity by the caller): the nearest
    /// sample of `points` per texel.
    fn depth(&self, z0: &mut [f32], src: &impl Source, units: Range<usize>) {
        let n = self.n;
        let Some(top) = self.top_texel(z0.len()) else {
            return;
        };
        let z0 = z0.as_mut_ptr();
        src.samples(self, units, move |sp| {
            let z = sp.z.to_array();
            let t0 = clamped_t0(sp, top);
            for l in sp.lanes() {
                let (t, zl) = (t0[l] as usize, z[l]);
                // Neither z0 (infinity or a depth) nor a sample's depth
                // is NaN, so this compare is `f32::min` (one
                // instruction, no NaN handling).
                let min = |o: usize| {
                    // SAFETY: t <= top = n^2 - n - 2 and o <= n + 1, so
                    // t + o < n^2 <= z0.len() (`top_texel`).
                    let d = unsafe { &mut *z0.add(t + o) };
                    *d = if zl < *d { zl } else { *d };
                };
                min(0);
                min(1);
                min(n);
                min(n + 1);
            }
        });
    }

    /// The largest lower-left texel of a splat, `n^2 - n - 2`, as lanes,
    /// when a map of `len` values (the depth map or one plane group) holds
    /// the `n^2` texels (`None` otherwise, and for maps under two texels a
    /// side, which the raster never splats into).
    fn top_texel(&self, len: usize) -> Option<I32Lanes> {
        (self.n >= 2 && len >= self.nn && self.nn <= i32::MAX as usize)
            .then(|| I32Lanes::splat((self.nn - self.n - 2) as i32))
    }

    /// Texels no sample reached start their layers at the near plane.
    fn finish_depth(&self, z0: &mut [f32]) {
        for z in z0.iter_mut().filter(|z| **z == f32::INFINITY) {
            *z = self.placement.near;
        }
    }

    /// Step 3 into `texels`: every sample of `points` into its plane
    /// interval (from `near`, or in deep mode from each corner's `z0`).
    fn deposit(&self, texels: &mut [[f32; 4]], z0: &[f32], src: &impl Source, units: Range<usize>) {
        let (n, nn, offsets, layering) = (self.n, self.nn, self.offsets(), self.layering);
        match self.mode {
            ShadowMode::Slices => {
                let near = F32Lanes::splat(self.placement.near);
                src.samples(self, units, |sp| {
                    let slices = layering.interval_simd(sp.z - near);
                    let w = sp.weights.map(|w| w.to_array());
                    for l in sp.lanes() {
                        let slice = slices[l];
                        let start = (slice / 4) * nn + sp.t0[l];
                        // One bounds check for the four texels.
                        let quad = &mut texels[start..start + n + 2];
                        for (c, o) in offsets.iter().enumerate() {
                            quad[*o][slice % 4] += w[c][l];
                        }
                    }
                });
            }
            ShadowMode::Deep => match layering.few_thresholds() {
                // Up to four quadratic layers (the frame's 3): the interval
                // by a fixed number of comparisons, no branch per corner.
                Some(thresholds) => self.deposit_deep(texels, z0, src, units, move |x| {
                    layering.interval_few_i32x8(&thresholds, x)
                }),
                None => {
                    self.deposit_deep(texels, z0, src, units, move |x| layering.interval_i32x8(x))
                }
            },
        }
    }

    /// [`Pass::deposit`] in deep mode, `interval` giving the plane interval
    /// of eight depths behind their corners' `z0` (the layering's).
    fn deposit_deep(
        &self,
        texels: &mut [[f32; 4]],
        z0: &[f32],
        src: &impl Source,
        units: Range<usize>,
        interval: impl Fn(F32Lanes) -> I32Lanes,
    ) {
        let (nn, offsets, layering) = (self.nn, self.offsets(), self.layering);
        let nn4 = I32Lanes::splat((4 * nn).min(i32::MAX as usize) as i32);
        let flat_fits = self.flat_fits;
        let Some(top) = self.top_texel(z0.len()) else {
            return;
        };
        src.samples(self, units, move |sp| {
            // Each corner's plane interval, relative to its own z0,
            // gathered lane by lane (every lane's `t0` is in the map,
            // also the inactive lanes').
            let t0 = clamped_t0(sp, top);
            let base: [[f32; LANES]; 4] = std::array::from_fn(|c| {
                std::array::from_fn(|l| {
                    // SAFETY: t0 <= top = n^2 - n - 2 and an offset is at
                    // most n + 1, so the texel is below n^2 <= z0.len()
                    // (`top_texel`).
                    unsafe { *z0.get_unchecked(t0[l] as usize + offsets[c]) }
                })
            });
            let w = sp.weights.map(|w| w.to_array());
            if flat_fits {
                // Each corner's float index into the flat map,
                // (slice / 4) 4 n^2 + 4 (t0 + o) + slice % 4, in
                // i32 lanes; the same deposits in the same order.
                // Clamped into the map (a no-op: the interval is below
                // the layer count and t0 in the map), so the adds below
                // need no bounds check.
                let flat = texels.as_flattened_mut();
                let last = I32Lanes::splat(flat.len().saturating_sub(1) as i32);
                let index: [[i32; LANES]; 4] = std::array::from_fn(|c| {
                    let s = interval(sp.z - F32Lanes::new(base[c]));
                    let t = sp.t0_simd + I32Lanes::splat(offsets[c] as i32);
                    let group: I32Lanes = s >> 2;
                    let texel: I32Lanes = t << 2;
                    (group * nn4 + texel + (s & I32Lanes::splat(3)))
                        .max(I32Lanes::ZERO)
                        .min(last)
                        .to_array()
                });
                if flat.is_empty() {
                    return;
                }
                for l in sp.lanes() {
                    for c in 0..4 {
                        // SAFETY: 0 <= index <= flat.len() - 1 (clamped
                        // above; flat is not empty).
                        unsafe { *flat.get_unchecked_mut(index[c][l] as usize) += w[c][l] };
                    }
                }
            } else {
                let slices = base.map(|b| layering.interval_simd(sp.z - F32Lanes::new(b)));
                for l in sp.lanes() {
                    for (c, o) in offsets.iter().enumerate() {
                        let slice = slices[c][l];
                        texels[(slice / 4) * nn + sp.t0[l] + o][slice % 4] += w[c][l];
                    }
                }
            }
        });
    }
}

/// Each lane's lower-left texel clamped into `[0, top]`: a no-op on the
/// raster's splats (already clamped so), repeated so that the unchecked
/// map reads of the passes stay in the map whatever a source passes.
#[inline(always)]
fn clamped_t0(sp: &SplatX8, top: I32Lanes) -> [i32; LANES] {
    sp.t0_simd.max(I32Lanes::ZERO).min(top).to_array()
}

/// Light-space bounding box `(min, max)` of the finite points (SIMD twin
/// of the scalar build's `light_bounds`): eight points per step, the same dot
/// products (`p.x a.x + p.y a.y + p.z a.z`, unfused), lane-wise minimum and
/// maximum over the finite points, reduced over the lanes at the end (min
/// and max of non-NaN numbers do not depend on the order).
fn light_bounds(frame: &LightFrame, points: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let mut bounds = BoundsX8::new(frame);
    for chunk in points.chunks(LANES) {
        let mut p = Vec3Lanes::ZERO;
        let mut finite = [0.0f32; LANES];
        for (l, q) in chunk.iter().enumerate() {
            if q.is_finite() {
                p.set_lane(l, *q);
                finite[l] = 1.0;
            }
        }
        bounds.add(p, F32Lanes::new(finite).simd_gt(F32Lanes::ZERO));
    }
    bounds.finish()
}

/// Most tasks of [`lane_bounds`].
const BOUNDS_TASKS: usize = 16;

/// Most tasks of the partial maps' sum and the prefix sum.
const MAX_TEXEL_RUNS: usize = 16;

/// Light-space bounding box `(min, max)` of the finite vertices of hair in
/// lane layout (SIMD twin of the scalar `lane_bounds`; the same as
/// [`light_bounds`] of the same points): per row, the lanes that are hair
/// and finite, the same dot products, lane-wise minimum and maximum. Runs
/// of blocks are tasks on `executor` (four per thread, at most
/// [`BOUNDS_TASKS`]; a fused pass interpolates the rows here, so this is a
/// third of the build's hair reads), each with its own bounds, merged
/// after: minima and maxima of numbers do not depend on their order, so
/// the box is the same bits with any split.
fn lane_bounds<H: StrandLanes + ?Sized>(
    frame: &LightFrame,
    hair: &H,
    executor: &dyn Executor,
) -> Option<(Vec3, Vec3)> {
    let blocks = hair.blocks();
    let tasks = (4 * executor.threads())
        .clamp(1, BOUNDS_TASKS)
        .min(blocks.max(1));
    let mut parts = [PartBounds::Empty; BOUNDS_TASKS];
    for_each_chunk_mut(executor, &mut parts[..tasks], 1, &|t, out| {
        let mut bounds = BoundsX8::new(frame);
        for b in t * blocks / tasks..(t + 1) * blocks / tasks {
            let (bits, row) = hair.block(b);
            if bits == 0 {
                continue;
            }
            let hair_lanes = lanes_of_bits(bits);
            for r in 0..hair.verts() {
                let p = row(r);
                bounds.add(p, p.finite() & hair_lanes);
            }
        }
        out[0] = bounds.finish_part();
    });
    let mut merged: Option<(Vec3, Vec3)> = None;
    for part in &parts[..tasks] {
        match *part {
            PartBounds::Overflow => return None,
            PartBounds::Empty => {}
            PartBounds::Box(lo, hi) => {
                merged = Some(merged.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
            }
        }
    }
    merged
}

/// One task's share of [`lane_bounds`].
#[derive(Clone, Copy, Debug)]
enum PartBounds {
    /// No finite hair point.
    Empty,
    /// A finite point whose light-space coordinates overflow: no map.
    Overflow,
    /// The box of the task's finite points.
    Box(Vec3, Vec3),
}

/// Lane-wise light-space bounds of the points added so far.
struct BoundsX8 {
    axes: [Vec3Lanes; 3],
    min: [F32Lanes; 3],
    max: [F32Lanes; 3],
    overflow: F32Lanes,
}

impl BoundsX8 {
    fn new(frame: &LightFrame) -> BoundsX8 {
        BoundsX8 {
            axes: [frame.x_axis, frame.y_axis, frame.z_axis].map(Vec3Lanes::splat),
            min: [F32Lanes::splat(f32::INFINITY); 3],
            max: [F32Lanes::splat(f32::NEG_INFINITY); 3],
            overflow: F32Lanes::ZERO,
        }
    }

    /// Eight points, the lanes of `finite` only (the dot products
    /// `p.x a.x + p.y a.y + p.z a.z`, unfused, as the scalar's).
    #[inline(always)]
    fn add(&mut self, p: Vec3Lanes, finite: F32Lanes) {
        let (inf, neg_inf) = (
            F32Lanes::splat(f32::INFINITY),
            F32Lanes::splat(f32::NEG_INFINITY),
        );
        for k in 0..3 {
            let c = p.dot(self.axes[k]);
            self.overflow |= finite & !c.is_finite();
            self.min[k] = self.min[k].min(finite.select(c, inf));
            self.max[k] = self.max[k].max(finite.select(c, neg_inf));
        }
    }

    /// The lanes reduced (min and max of non-NaN numbers do not depend on
    /// the order); `None` on overflow or when no point was finite.
    fn finish(self) -> Option<(Vec3, Vec3)> {
        match self.finish_part() {
            PartBounds::Box(lo, hi) => Some((lo, hi)),
            PartBounds::Empty | PartBounds::Overflow => None,
        }
    }

    /// [`BoundsX8::finish`], telling an overflow from no point.
    fn finish_part(self) -> PartBounds {
        if self.overflow.any() {
            return PartBounds::Overflow;
        }
        let reduce = |v: [F32Lanes; 3], f: fn(f32, f32) -> f32| {
            let [x, y, z] = v.map(|c| c.to_array().into_iter().reduce(f).unwrap_or(0.0));
            Vec3::new(x, y, z)
        };
        let (min, max) = (reduce(self.min, f32::min), reduce(self.max, f32::max));
        if min.x <= max.x {
            PartBounds::Box(min, max)
        } else {
            PartBounds::Empty
        }
    }
}

/// SIMD twin of the scalar build's prefix sum along depth
/// (`S[s] = S[s - 1] + deposit[s]` per texel, `S[-1] = 0`, in plane order):
/// sixteen texels at a time, whose four-plane groups (two texels per
/// `f32x8`) are transposed into one vector per plane of the even and one
/// per plane of the odd texels, summed plane after plane (the same adds in
/// the same order as the scalar, so the same bits), and transposed back.
/// Texels past the last multiple of sixteen take the scalar loop. Planes
/// past `layers` in the last group stay untouched, as in the scalar.
/// Texels, not strands: eight lanes (`f32x8`) at every lane width.
fn prefix_sum(texels: &mut [[f32; 4]], nn: usize, layers: usize) {
    prefix_sum_of(&DisjointMut::new(texels), nn, layers, 0..nn);
}

/// [`prefix_sum`] of the texels `range` (its start a multiple of
/// sixteen) of every plane group, through a view that other tasks share:
/// the same operations on each texel, so the same bits, whatever the
/// ranges. Blocks of sixteen below the last multiple of sixteen of `nn`
/// take the SIMD path, the texels past it the scalar loop, as in one pass.
fn prefix_sum_of(
    texels: &DisjointMut<'_, [f32; 4]>,
    nn: usize,
    layers: usize,
    range: Range<usize>,
) {
    const BLOCK: usize = 16;
    let groups = layers.div_ceil(4);
    let simd_end = (nn / BLOCK * BLOCK).min(range.end);
    let mut t0 = range.start;
    while t0 + BLOCK <= simd_end {
        let mut carry = [f32x8::ZERO; 2];
        for g in 0..groups {
            // SAFETY: the caller's task alone touches texels `range` of
            // every group (one call of one task at a time).
            let chunk = unsafe { texels.range(g * nn + t0, BLOCK) }.as_flattened_mut();
            let rows: [f32x8; 8] = std::array::from_fn(|r| {
                let lanes: [f32; 8] = chunk[r * 8..(r + 1) * 8].try_into().unwrap();
                f32x8::new(lanes)
            });
            // planes[k] = plane 4g + k of the even texels, planes[4 + k] of the odd.
            let mut planes = f32x8::transpose(rows);
            let valid = (layers - 4 * g).min(4);
            for half in 0..2 {
                let p = &mut planes[4 * half..4 * half + 4];
                p[0] = carry[half] + p[0];
                for k in 1..valid {
                    p[k] = p[k - 1] + p[k];
                }
                carry[half] = p[3];
            }
            for (r, row) in f32x8::transpose(planes).iter().enumerate() {
                chunk[r * 8..(r + 1) * 8].copy_from_slice(row.as_array());
            }
        }
        t0 += BLOCK;
    }
    for t in t0..range.end {
        let mut sum = 0.0;
        for s in 0..layers {
            // SAFETY: as above.
            let texel = &mut unsafe { texels.range((s / 4) * nn + t, 1) }[0][s % 4];
            sum += *texel;
            *texel = sum;
        }
    }
}
