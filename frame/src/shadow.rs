//! The shadow stage of a frame: a deep opacity map
//! (`coif::shading::shadow`, `ShadowMode::Deep`, Yuksel & Keyser 2008, 3
//! layers from each texel's first hair, 128 x 128 texels) of the render hair, built each
//! frame (the reference pass: from the render vertices' positions; the fused
//! pass: from the drawn groups in lanes, [`DrawnHair`]) and looked up at
//! every vertex and at the head's surface.
//!
//! Why deep layers and not 16 slices between the hair's nearest and
//! farthest depth: over the built-in head the hair spans about 36 cm along
//! the light, so a slice is 2.3 cm deep, thicker than the hair lying on the
//! scalp. With slices the lit surface hair was interpolated into the first
//! slice's opacity (mean transmittance 0.48 over the tenth of the vertices
//! nearest the light) and the grazed hair over the crown showed a dark
//! ring; 64 slices turned the ring into concentric bands. Deep layers
//! start at the first hit (0.82 for that tenth, no ring). At 256 texels a
//! side, texels whose first hit is a stray strand in front of the rest
//! showed as dark blocks on lit hair (bilinear lookups across texels with
//! different first depths, the deep maps' known artifact); 128 texels
//! (3 mm over the built-in head) soften them to faint smudges.

use super::{Error, FrameSettings};
use coif_base::lanes::{F32Lanes, GROUPS_PER_BLOCK};
use coif_base::tasks::Executor;
use coif_base::Vec3Lanes;
use coif_lod::{Interpolation, RefinedGuides, RenderVertex};
use coif_shading::shadow::{BuildScratch, OpacityShadowMap, ShadowSettings, StrandLanes};
use glam::Vec3;

/// Texels per side of the shadow map.
pub const SHADOW_RESOLUTION: usize = 128;

/// Opacity of the shadow map per hair crossing (`k` in `alpha = 1 - exp(-k)`).
pub const SHADOW_DENSITY: f32 = 0.5;

/// Most tasks of one shadow-map build (and partial maps in its scratch).
pub const MAX_SHADOW_TASKS: usize = 8;

/// Strands (hairs in the map) per task of the shadow-map build, at least:
/// below this a task's work is no longer worth its partial map (a
/// 128 x 128 map to clear and to add in the reduction, about 0.02 ms).
pub const SHADOW_STRANDS_PER_TASK: usize = 256;

/// How many tasks build a shadow map from at most `strands` strands:
/// `clamp(strands / SHADOW_STRANDS_PER_TASK, 1, MAX_SHADOW_TASKS)`. The
/// count depends on the scene alone, never on the thread count, so the map
/// has the same bytes on every executor
/// (`OpacityShadowMap::build_tasks` sums the partial maps in task order).
pub fn shadow_tasks(strands: usize) -> usize {
    (strands / SHADOW_STRANDS_PER_TASK).clamp(1, MAX_SHADOW_TASKS)
}

/// Owns the shadow map, its point buffer and the build's partial maps (all
/// sized once).
pub struct ShadowStage {
    map: Option<OpacityShadowMap>,
    scratch: Option<BuildScratch>,
    points: Vec<Vec3>,
}

impl ShadowStage {
    /// The map for `settings.shadows` (none if off), with a point buffer for
    /// `capacity` render vertices (the reference pass's build; 0 for the
    /// fused pass, which needs none). The capsule radius of a render hair is
    /// half its width at the root (`hair_width.root` times the
    /// real-to-render density ratio), times `thinning` when the map is
    /// built from every `thinning`-th hair only (each stands for that many:
    /// the shadow area a segment deposits, `2 r |d_xy|`, grows by the same
    /// factor, so the expected opacity per texel is kept). The build runs
    /// as [`shadow_tasks`]`(strands)` tasks, `strands` being the most hairs
    /// the map is built from.
    pub fn new(
        settings: &FrameSettings,
        capacity: usize,
        thinning: usize,
        strands: usize,
    ) -> Result<ShadowStage, Error> {
        if !settings.shadows {
            return Ok(ShadowStage {
                map: None,
                scratch: None,
                points: Vec::new(),
            });
        }
        let ratio = settings.real_hairs_per_cm2 / settings.render_hairs_per_cm2;
        let shadow_settings = ShadowSettings {
            density: SHADOW_DENSITY,
            hair_radius: (0.5 * settings.hair_width.root * ratio * thinning.max(1) as f32)
                .max(1e-6),
            resolution: SHADOW_RESOLUTION,
            ..ShadowSettings::deep()
        };
        let scratch = BuildScratch::new(&shadow_settings, shadow_tasks(strands))?;
        let map = OpacityShadowMap::new(shadow_settings)?;
        Ok(ShadowStage {
            map: Some(map),
            scratch: Some(scratch),
            points: Vec::with_capacity(capacity),
        })
    }

    /// Tasks per build (0 without a map).
    pub fn tasks(&self) -> usize {
        self.scratch.as_ref().map_or(0, BuildScratch::tasks)
    }

    /// Whether there is a map (self-shadowing on).
    pub fn enabled(&self) -> bool {
        self.map.is_some()
    }

    /// Rebuilds the map for a light toward `to_light` from the hair
    /// polylines of `vertices` (`verts_per_strand` each), its tasks on
    /// `executor`.
    pub fn build(
        &mut self,
        to_light: Vec3,
        vertices: &[RenderVertex],
        verts_per_strand: usize,
        executor: &dyn Executor,
    ) {
        if self.map.is_none() {
            return;
        }
        self.points.clear();
        let room = self.points.capacity();
        self.points
            .extend(vertices.iter().take(room).map(|v| Vec3::from(v.position)));
        self.build_from_points(to_light, verts_per_strand, executor);
    }

    /// Rebuilds the map from the point buffer (`verts_per_strand` each):
    /// `OpacityShadowMap::build_tasks`, [`ShadowStage::tasks`] tasks on
    /// `executor` (contiguous runs of strands, partial maps reduced in task
    /// order on the calling thread).
    pub fn build_from_points(
        &mut self,
        to_light: Vec3,
        verts_per_strand: usize,
        executor: &dyn Executor,
    ) {
        if let (Some(map), Some(scratch)) = (&mut self.map, &mut self.scratch) {
            // The scratch is made with the map's settings, so this cannot
            // fail; were it to, the map is empty (no self-shadowing).
            let built =
                map.build_tasks(executor, scratch, -to_light, &self.points, verts_per_strand);
            debug_assert!(built.is_ok(), "{built:?}");
        }
    }

    /// Rebuilds the map from hair in lane layout
    /// (`OpacityShadowMap::build_lanes`, [`ShadowStage::tasks`] tasks on
    /// `executor`): the fused pass's drawn groups ([`DrawnHair`]),
    /// interpolated on the fly, no point buffer.
    pub fn build_lanes(
        &mut self,
        to_light: Vec3,
        hair: &(impl StrandLanes + ?Sized),
        executor: &dyn Executor,
    ) {
        if let (Some(map), Some(scratch)) = (&mut self.map, &mut self.scratch) {
            // As in `build_from_points`: cannot fail, an empty map if it did.
            let built = map.build_lanes(executor, scratch, -to_light, hair);
            debug_assert!(built.is_ok(), "{built:?}");
        }
    }

    /// The map, if self-shadowing is on.
    pub fn map(&self) -> Option<&OpacityShadowMap> {
        self.map.as_ref()
    }

    /// Transmittance toward the light of every vertex of the last build
    /// into `out` (1 without a map).
    pub fn transmittance(&self, _vertices: &[RenderVertex], out: &mut [f32]) {
        match &self.map {
            Some(map) => {
                let n = out.len().min(self.points.len());
                let (looked_up, rest) = out.split_at_mut(n);
                match map.transmittance_batch(&self.points[..n], looked_up) {
                    Ok(()) => rest.fill(1.0),
                    // Equal lengths by construction; unlit never beats lit.
                    Err(_) => out.fill(1.0),
                }
            }
            None => out.fill(1.0),
        }
    }

    /// Transmittance at one point; 1 without a map.
    pub fn transmittance_at(&self, p: Vec3) -> f32 {
        self.map.as_ref().map_or(1.0, |m| m.transmittance(p))
    }

    /// Transmittance at eight points (the head's lit pixels,
    /// `OpacityShadowMap::transmittance_simd`: the one-point value to the
    /// rounding of the exponential); 1 without a map.
    pub fn transmittance_simd(&self, p: Vec3Lanes) -> F32Lanes {
        self.map
            .as_ref()
            .map_or(F32Lanes::ONE, |m| m.transmittance_simd(p))
    }
}

/// The hair of the fused pass's shadow map in lane layout: every `step`-th
/// drawn group (up to eight hairs of one scalp triangle), `GROUPS_PER_BLOCK`
/// of them per block (one per eight lanes), its rows interpolated from the
/// refined guides when the build asks for them
/// (`coif_lod::GroupBlend::position_simd`, the numbers `interpolate`
/// writes), so no frame-sized point buffer is written or read.
pub(crate) struct DrawnHair<'a> {
    pub interpolation: &'a Interpolation,
    pub guides: &'a RefinedGuides,
    /// `(group, first hair)` of the drawn groups, in draw order.
    pub drawn: &'a [(u32, u32)],
    /// Every `step`-th drawn group is in the map (at least 1).
    pub step: usize,
}

impl StrandLanes for DrawnHair<'_> {
    fn verts(&self) -> usize {
        self.guides.verts_per_strand()
    }

    fn blocks(&self) -> usize {
        self.groups().div_ceil(GROUPS_PER_BLOCK)
    }

    fn groups(&self) -> usize {
        self.drawn.len().div_ceil(self.step.max(1))
    }

    fn block(&self, b: usize) -> (u32, impl Fn(usize) -> Vec3Lanes + '_) {
        // Groups `b G ..` of the map (G = GROUPS_PER_BLOCK): drawn groups
        // `b G step, (b G + 1) step, ...`.
        let mut groups = [0usize; GROUPS_PER_BLOCK];
        let mut n = 0;
        for k in 0..GROUPS_PER_BLOCK {
            let at = (b * GROUPS_PER_BLOCK + k).saturating_mul(self.step.max(1));
            if let Some(&(g, _)) = self.drawn.get(at) {
                groups[n] = g as usize;
                n += 1;
            }
        }
        let blend = (n > 0)
            .then(|| self.interpolation.groups_blend(self.guides, &groups[..n]))
            .flatten()
            .filter(|blend| blend.verts() == self.verts());
        let bits = blend.map_or(0, |blend| blend.hair_bits());
        (bits, move |r: usize| {
            blend.map_or(Vec3Lanes::ZERO, |blend| blend.position_simd(r))
        })
    }
}
