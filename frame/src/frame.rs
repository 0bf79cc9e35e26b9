//! The frame pipeline: one struct owning every buffer, one call per frame.

use super::body::{BodyStage, IRIS_ALBEDO, SCLERA_ALBEDO};
use super::motion::blend_poses;
use super::prepare::{shade_block, GroupShading, SharedOut};
use super::ribbon::RibbonStage;
use super::shadow::{DrawnHair, ShadowStage};
use super::timings::{Stage, StageTimings};
use super::{Error, FrameSettings, HairScene, PrepareMode, Shader};
use coif_base::lanes::GROUPS_PER_BLOCK;
use coif_base::tasks::{Executor, Serial};
use coif_kernels::{self as kernels, Colliders, FixedStep, SimParams, Sphere, Strands};
use coif_lod::{
    self as lod, level, HairWidth, Interpolation, RefinedGuides, RenderHairs, RenderVertex,
    Visibility,
};
use coif_render::head::{draw_spheres_lanes, occluded, HeadShading};
use coif_render::raster::HairRaster;
use coif_render::sort::DepthOrder;
use coif_render::{Camera, Framebuffer, RgbImage, ShadedVertex};
use coif_shading::{RgbBuffer, ShadingSamples};
use glam::{Affine3A, Vec3};
use std::time::Instant;

/// Hair albedo lit by the ambient light (brown, Kajiya-Kay's default diffuse).
pub const HAIR_AMBIENT_ALBEDO: Vec3 = Vec3::new(0.30, 0.18, 0.10);
/// Skin albedo of the head.
pub const SKIN_ALBEDO: Vec3 = Vec3::new(0.62, 0.42, 0.33);
/// Background gradient, top and bottom (linear RGB).
pub const BACKGROUND: (Vec3, Vec3) = (Vec3::new(0.16, 0.19, 0.24), Vec3::new(0.035, 0.04, 0.05));
/// Culling margin (metres) around strand bounds.
const CULL_MARGIN: f32 = 2e-3;
/// Near and far planes of the culling frustum (metres).
const NEAR_FAR: (f32, f32) = (0.01, 100.0);

/// Brightness of render hair `hair` in `[0.75, 1.25]`, from a hash of its
/// index (SplitMix64's finaliser): real hairs differ in pigment, and a
/// little variation keeps neighbouring strands apart in the picture.
#[inline]
pub fn strand_tint(hair: usize) -> f32 {
    let mut z = (hair as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    0.75 + 0.5 * ((z >> 40) as f32 / (1u64 << 24) as f32)
}

/// Fills `samples` with one sample per vertex: `t` = the vertex tangent,
/// `wi` = `to_light`, `wo` = the unit vector toward `eye`. The nine arrays
/// are written column by column (no allocation once they have the capacity).
fn write_samples(
    samples: &mut ShadingSamples,
    vertices: &[RenderVertex],
    to_light: Vec3,
    eye: Vec3,
) {
    let columns = samples.columns_mut(vertices.len());
    for (c, a) in columns.wi.into_iter().enumerate() {
        a.fill(to_light[c]);
    }
    for (c, a) in columns.t.into_iter().enumerate() {
        for (dst, v) in a.iter_mut().zip(vertices) {
            *dst = v.tangent[c];
        }
    }
    let [wx, wy, wz] = columns.wo;
    for (((v, x), y), z) in vertices
        .iter()
        .zip(wx.iter_mut())
        .zip(wy.iter_mut())
        .zip(wz.iter_mut())
    {
        let wo = (eye - Vec3::from(v.position)).normalize_or(Vec3::Z);
        (*x, *y, *z) = (wo.x, wo.y, wo.z);
    }
}

/// Checks the settings the pipeline cannot work with: the frame size and
/// the hair densities (the simulation parameters check themselves).
fn validate(settings: &FrameSettings) -> Result<(), Error> {
    let pixels = settings.width.saturating_mul(settings.height);
    if settings.width == 0 || settings.height == 0 || pixels > 1 << 26 {
        return Err(Error::Setting {
            name: "width x height",
            expected: "between 1 x 1 and 64 Mpixels",
        });
    }
    if !(settings.render_hairs_per_cm2 > 0.0 && settings.real_hairs_per_cm2 > 0.0) {
        return Err(Error::Setting {
            name: "hairs_per_cm2",
            expected: "> 0",
        });
    }
    settings.simulation.validate()?;
    Ok(())
}

/// A camera on the bounding box of the `settled` hair and the head near it: it
/// looks at the box's centre from `view_distance` half-diagonals along the
/// view direction (the settings', else the scene's).
fn frame_camera(settled: &[Vec3], scene: &HairScene, settings: &FrameSettings) -> Camera {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in settled {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    // The head too, as far as it reaches within a quarter of the hair's size of the
    // hair: a whole groom's scalp sphere can be far larger than the hair
    // (the mohawk's is), and framing only its centre cut it off.
    let margin = 0.25 * (hi - lo);
    let (near_lo, near_hi) = (lo - margin, hi + margin);
    for s in &scene.head {
        let r = Vec3::splat(s.radius);
        lo = lo.min((s.center - r).clamp(near_lo, near_hi));
        hi = hi.max((s.center + r).clamp(near_lo, near_hi));
    }
    // A body is framed whole (a bust: head and shoulders).
    if let Some(body) = &scene.body {
        let (body_lo, body_hi) = body.mesh().bounds();
        lo = lo.min(body_lo);
        hi = hi.max(body_hi);
    }
    let (focus, extent) = (0.5 * (lo + hi), 0.5 * (hi - lo).length());
    let view = settings
        .view_direction
        .unwrap_or(scene.view_direction)
        .try_normalize()
        .unwrap_or(Vec3::Z);
    Camera::look_at(
        focus + view * (settings.view_distance * extent),
        focus,
        Vec3::Y,
        settings.fov_y,
        settings.width,
        settings.height,
    )
}

/// Render hairs stand for `real / render` real hairs each (densities per
/// cm^2), so they are that much wider than a real hair: the same coverage
/// with fewer hairs.
fn render_width(settings: &FrameSettings) -> HairWidth {
    let ratio = settings.real_hairs_per_cm2 / settings.render_hairs_per_cm2;
    HairWidth {
        root: settings.hair_width.root * ratio,
        tip: settings.hair_width.tip * ratio,
    }
}

/// What the last frame did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// Fixed simulation steps run.
    pub substeps: u32,
    /// Render hairs written and drawn.
    pub hairs: usize,
    /// Render vertices shaded.
    pub vertices: usize,
    /// B-spline segments per span chosen by the LOD level.
    pub segments_per_span: usize,
    /// Hair width multiplier from distance LOD.
    pub width_factor: f32,
    /// Hair segments rasterised (both ends valid).
    pub segments: usize,
    /// Of `segments`, those left out as hidden behind the head
    /// ([`FrameSettings::occlusion_culling`]).
    pub hidden_segments: usize,
    /// Pixels covered by the head.
    pub head_pixels: usize,
    /// Pixels written by the ribbons (opaque triangles).
    pub ribbon_pixels: usize,
    /// Pixels written by the body (opaque triangles).
    pub body_pixels: usize,
}

/// One hair frame, end to end, into buffers sized once at construction:
/// move the head (rig and roots follow a rigid pose), step the simulation
/// with a fixed-step accumulator, prepare (LOD, shadow map, per-vertex
/// shading, fused per interpolation group or stage by stage as the
/// reference, [`PrepareMode`]) into one buffer of [`ShadedVertex`]es,
/// rasterisation. [`FramePipeline::frame`] allocates nothing.
pub struct FramePipeline {
    settings: FrameSettings,
    // Scene at rest (world space; the roots' rest is the strands' own).
    rest_rig: Vec<Sphere>,
    rest_head: Vec<Sphere>,
    pivot: Vec3,
    // Simulation.
    strands: Strands,
    params: SimParams,
    fixed: FixedStep,
    pose: Affine3A,
    rig: Vec<Sphere>,
    head_local: Vec<Sphere>,
    ribbons: RibbonStage,
    /// The body the guides collide with and the frame draws, if any.
    body: Option<BodyStage>,
    // LOD.
    interpolation: Interpolation,
    visibility: Visibility,
    guides: RefinedGuides,
    hairs: RenderHairs,
    vertices: Vec<RenderVertex>,
    vertex_count: usize,
    render_width: HairWidth,
    // Shading.
    shader: Shader,
    samples: ShadingSamples,
    scattering: RgbBuffer,
    colors: RgbBuffer,
    transmittance: Vec<f32>,
    shadow: ShadowStage,
    /// Drawn groups of this frame and the index of each one's first hair
    /// (a prefix sum, so every group knows where its vertices go).
    drawn: Vec<(u32, u32)>,
    /// The one place the prepare pass writes: every drawn render vertex,
    /// shaded, hair after hair (the rasteriser's input).
    shaded: Vec<ShadedVertex>,
    shaded_count: usize,
    groups_drawn: usize,
    width_factor: f32,
    // Rasterisation.
    camera: Camera,
    framebuffer: Framebuffer,
    order: DepthOrder,
    raster: HairRaster,
    timings: StageTimings,
    stats: FrameStats,
}

/// Most seconds [`FramePipeline::new`] settles the hair for (an infinite
/// settle never ended).
pub const MAX_SETTLE_SECONDS: f32 = 600.0;

/// Most render vertices at the finest level a [`FramePipeline`] sizes its
/// buffers for: 2^26 (about 67 million, 38 times the default scene's;
/// each costs some tens of bytes across the frame's buffers).
pub const MAX_RENDER_VERTICES: usize = 1 << 26;

impl FramePipeline {
    /// Builds the pipeline for `scene`: the simulation, interpolation,
    /// shading tables and every per-frame buffer (sized for all render
    /// hairs at the finest level). With local shape on, the groom's
    /// sag-free rest state is solved first (`Strands::solve_sag_free`
    /// against the scene's rig and body at rest). The hair is then settled
    /// for `settle_seconds` at rest (0 to [`MAX_SETTLE_SECONDS`]), and the
    /// camera framed on the settled hair. Errors: a setting out of range,
    /// a settle out of range, more than [`MAX_RENDER_VERTICES`] render
    /// vertices, or the scene's own.
    pub fn new(
        scene: &HairScene,
        settings: FrameSettings,
        settle_seconds: f32,
    ) -> Result<FramePipeline, Error> {
        validate(&settings)?;
        if !(0.0..=MAX_SETTLE_SECONDS).contains(&settle_seconds) {
            return Err(Error::Setting {
                name: "settle_seconds",
                expected: "0 to 600 seconds",
            });
        }
        let mut strands = Strands::from_polylines(&scene.guides, scene.verts_per_strand)?;
        let params = settings.simulation.clone();
        let fixed = FixedStep::new(params.dt, settings.max_substeps.max(1))?;
        let rest_roots: Vec<Vec3> = scene.roots().collect();
        let settle_steps = (settle_seconds / params.dt).round() as usize;
        let interpolation = Interpolation::new(
            &rest_roots,
            &scene.triangles,
            settings.render_hairs_per_cm2,
            settings.seed,
        )?;
        // Every render vertex at the finest level, bounded before any
        // buffer is sized (a density and a span count that pass their own
        // checks could still ask for tens of gigabytes together).
        let capacity = interpolation
            .hair_count()
            .checked_mul(lod::refined_len(
                strands.verts_per_strand(),
                settings.max_segments_per_span.max(1),
            ))
            .filter(|&c| c <= MAX_RENDER_VERTICES)
            .ok_or(Error::Setting {
                name: "render_hairs_per_cm2 x max_segments_per_span",
                expected: "at most 2^26 render vertices at the finest level",
            })?;
        // Each guide weighs in the hair grid as the render hairs it carries.
        strands.set_hair_shares(&interpolation.guide_shares())?;
        let body =
            (scene.body.as_ref()).map(|b| BodyStage::new(b, settings.width, settings.height));
        let fields = body.as_ref().map(|b| std::slice::from_ref(b.field()));
        let colliders = Colliders {
            spheres: &scene.rig,
            capsules: &[],
            sdfs: fields.unwrap_or(&[]),
        };
        // With local shape on, the groom (out of the colliders' skins) is
        // the springs' equilibrium under these parameters: the hair keeps
        // its style at rest and returns to it after a turn or a gust.
        if params.local_shape_stiffness > 0.0 {
            strands.solve_sag_free(&params, &colliders)?;
        }
        for _ in 0..settle_steps {
            kernels::step_colliders(&mut strands, &params, &colliders);
        }
        let ribbons = RibbonStage::new(scene, &params, settle_steps)?;
        let camera = frame_camera(&strands.positions(), scene, &settings);
        let visibility = Visibility::new(strands.strand_count(), interpolation.group_count());
        let guides = RefinedGuides::new(strands.blocks(), settings.max_segments_per_span.max(1))?;
        let hairs = RenderHairs::new(&interpolation, &guides);
        let render_width = render_width(&settings);
        let shader = Shader::with_material(
            settings.shading,
            settings.hair_sigma_a,
            settings.multiple_scattering,
        )?;
        let raster = HairRaster::new(settings.width, settings.height, capacity).map_err(|_| {
            Error::Setting {
                name: "width x height",
                expected: "at most 4,194,240 pixels per side and 2^28 pixels",
            }
        })?;
        let group_count = interpolation.group_count();
        let thinning = match settings.prepare {
            PrepareMode::Fused => settings.shadow_thinning.max(1),
            PrepareMode::Reference => 1,
        };
        // The fused pass builds its map from the refined guides in lanes:
        // no point buffer.
        let points = match settings.prepare {
            PrepareMode::Fused => 0,
            PrepareMode::Reference => capacity,
        };
        let shadow = ShadowStage::new(
            &settings,
            points,
            thinning,
            interpolation.hair_count().div_ceil(thinning),
        )?;
        Ok(FramePipeline {
            rest_rig: scene.rig.clone(),
            rest_head: scene.head.clone(),
            head_local: scene.head.clone(),
            ribbons,
            body,
            rig: scene.rig.clone(),
            pivot: scene.pivot,
            strands,
            params,
            fixed,
            pose: Affine3A::IDENTITY,
            order: DepthOrder::with_capacity(interpolation.hair_count()),
            interpolation,
            visibility,
            guides,
            hairs,
            vertices: vec![RenderVertex::default(); capacity],
            vertex_count: 0,
            render_width,
            shader,
            samples: ShadingSamples::with_capacity(capacity),
            scattering: RgbBuffer::zeros(capacity),
            colors: RgbBuffer::zeros(capacity),
            transmittance: vec![1.0; capacity],
            shadow,
            drawn: Vec::with_capacity(group_count),
            shaded: vec![ShadedVertex::default(); capacity],
            shaded_count: 0,
            groups_drawn: 0,
            width_factor: 1.0,
            camera,
            framebuffer: Framebuffer::new(settings.width, settings.height),
            raster,
            settings,
            timings: StageTimings::default(),
            stats: FrameStats::default(),
        })
    }

    /// One frame: [`FramePipeline::simulate`], then [`FramePipeline::render`]
    /// (every task on the calling thread: [`FramePipeline::frame_with`] on
    /// [`Serial`]).
    pub fn frame(&mut self, frame_time: f32, head_pose: Affine3A) -> FrameStats {
        self.frame_with(frame_time, head_pose, &Serial)
    }

    /// [`FramePipeline::frame`] with every parallel stage's tasks run by
    /// `executor` ([`FramePipeline::simulate_with`], then
    /// [`FramePipeline::render_with`]): the guides' step, the ribbons'
    /// patches, the shadow-map build, the prepare pass and the hair's tile
    /// rows. Task counts come from the scene, never from the executor, and
    /// every reduction runs in task order, so the frame has the same bytes
    /// with any executor and any number of threads. The pipeline starts no
    /// thread of its own: the caller's executor is the only one used.
    pub fn frame_with(
        &mut self,
        frame_time: f32,
        head_pose: Affine3A,
        executor: &dyn Executor,
    ) -> FrameStats {
        let start = Instant::now();
        self.simulate_with(frame_time, head_pose, executor);
        self.render_with(executor);
        self.timings.record(Stage::Frame, start.elapsed());
        self.stats
    }

    /// The simulation part of a frame: `frame_time` seconds are added to
    /// the fixed-step accumulator; each fixed step sees the head pose blended
    /// from the last frame's to `head_pose` (rigid, world space, applied to
    /// the scene at rest), with roots, rig and rest orientation following it.
    /// Every task on the calling thread ([`FramePipeline::simulate_with`] on
    /// [`Serial`]).
    pub fn simulate(&mut self, frame_time: f32, head_pose: Affine3A) {
        self.simulate_with(frame_time, head_pose, &Serial);
    }

    /// [`FramePipeline::simulate`] with the guides' fixed steps
    /// (`coif_kernels::step_with`, at most `MAX_STEP_TASKS` tasks of
    /// blocks) and the ribbons' (`patch::step_all`, runs of patches) run by
    /// `executor`; placing the head and roots, and the ribbons' skinning,
    /// blending and normals, stay on the calling thread. The same bytes with
    /// any executor.
    pub fn simulate_with(&mut self, frame_time: f32, head_pose: Affine3A, executor: &dyn Executor) {
        let start = Instant::now();
        // Workers asleep since the last frame start waking while the head
        // and the rig are placed (`Executor::wake`).
        executor.wake();
        let head_pose = if head_pose.is_finite() {
            head_pose
        } else {
            self.pose
        };
        let steps = self.fixed.advance(frame_time);
        let from = self.pose;
        let mut ribbon_time = std::time::Duration::ZERO;
        for k in 0..steps.max(1) {
            let pose = if steps == 0 {
                head_pose
            } else {
                blend_poses(&from, &head_pose, (k + 1) as f32 / steps as f32)
            };
            self.place_head(&pose);
            if steps > 0 {
                let fields = self.body.as_ref().map(|b| std::slice::from_ref(b.field()));
                let colliders = Colliders {
                    spheres: &self.rig,
                    capsules: &[],
                    sdfs: fields.unwrap_or(&[]),
                };
                kernels::step_colliders_with(&mut self.strands, &self.params, &colliders, executor);
            }
            let ribbon_start = Instant::now();
            self.ribbons.place(&pose);
            if steps > 0 {
                self.ribbons.step(executor);
            }
            ribbon_time += ribbon_start.elapsed();
        }
        let ribbon_start = Instant::now();
        self.ribbons.finish();
        ribbon_time += ribbon_start.elapsed();
        self.pose = head_pose;
        self.stats.substeps = steps;
        self.timings.record(Stage::Simulate, start.elapsed());
        if !self.ribbons.is_empty() {
            self.timings.record(Stage::Ribbon, ribbon_time);
        }
    }

    fn place_head(&mut self, pose: &Affine3A) {
        for (dst, s) in self.rig.iter_mut().zip(&self.rest_rig) {
            dst.center = pose.transform_point3(s.center);
        }
        if let Some(body) = &mut self.body {
            body.place(pose);
        }
        // One call moves the roots and turns the rest frame (finite and
        // rigid: checked by the caller; a refused pose keeps the last).
        let _ = self.strands.set_head_pose(*pose);
    }

    /// Prepare (LOD, shadow map, shading) and rasterisation of the current
    /// hair, each stage timed ([`Stage`]), tasks on the calling thread.
    /// Everything is drawn in render space: world space shifted by the
    /// simulation's origin (`Strands::origin`), so that hair far from the
    /// world origin keeps its precision.
    pub fn render(&mut self) {
        self.render_with(&Serial);
    }

    /// [`FramePipeline::render`] with the parallel stages' tasks run by
    /// `executor`: the shadow-map build, the prepare pass (one task per
    /// block of drawn interpolation groups), the head's ray-cast (bands of rows) and
    /// the hair's rasterisation (projection, binning and runs of tiles). LOD
    /// set-up, background, ribbons and sort stay on the calling thread. The
    /// same bytes with any executor.
    pub fn render_with(&mut self, executor: &dyn Executor) {
        self.prepare_with(executor);
        let origin = self.strands.origin().as_vec3();
        let camera = self.camera.shifted(origin);
        let start = Instant::now();
        self.timed(Stage::Head, |p| p.draw_head(&camera, executor));
        if self.body.is_some() {
            self.timed(Stage::Body, |p| p.draw_body(origin, &camera, executor));
        }
        if !self.ribbons.is_empty() {
            self.timed(Stage::RibbonDraw, |p| p.draw_ribbons(origin, &camera));
        }
        self.timed(Stage::Sort, |p| p.sort_hair(&camera));
        self.timed(Stage::Hair, |p| p.draw_hair(&camera, executor));
        self.timings.record(Stage::Raster, start.elapsed());
    }

    /// The prepare part of [`FramePipeline::render_with`] alone (LOD, shadow
    /// map, shading into [`FramePipeline::shaded_vertices`]), timed as
    /// [`Stage::Prepare`]: for benchmarks and engines that rasterise
    /// elsewhere.
    pub fn prepare_with(&mut self, executor: &dyn Executor) {
        let origin = self.strands.origin().as_vec3();
        let eye = self.camera.shifted(origin).eye();
        self.place_head_spheres(origin);
        let start = Instant::now();
        match self.settings.prepare {
            PrepareMode::Fused => self.prepare_fused(eye, executor),
            PrepareMode::Reference => self.prepare_reference(eye, executor),
        }
        self.timings.record(Stage::Prepare, start.elapsed());
    }

    /// Runs the fused pass's task `i` again (the `i`-th block of drawn groups
    /// of the last frame, `GROUPS_PER_BLOCK` groups in the lanes:
    /// interpolate, shade, shadow, colour, write), with the last
    /// frame's LOD and shadow map; returns the vertices it wrote (0 if there
    /// is no such group or the pipeline is the reference). One cache-sized
    /// chunk of the prepare pass, for benchmarks.
    pub fn shade_drawn_group(&mut self, i: usize) -> usize {
        if self.settings.prepare != PrepareMode::Fused {
            return 0;
        }
        let eye = self.camera.shifted(self.strands.origin().as_vec3()).eye();
        let len = self.shaded_count.min(self.shaded.len());
        let shared = SharedOut(self.shaded.as_mut_ptr());
        // SAFETY: `shared` points to `self.shaded` (at least `len` long),
        // and this is the only task running.
        unsafe { self.shade_task(&shared, len, i, eye) }
    }

    /// Task `i` of the fused pass: the `i`-th block of drawn groups (drawn
    /// groups `i G .. i G + G` for `G = GROUPS_PER_BLOCK`, whose hairs are
    /// consecutive in the frame's order) interpolated, shaded and written
    /// into its range of the shaded vertices. Returns the vertices written.
    ///
    /// # Safety
    /// `shared` points to `self.shaded`, at least `len` vertices long, and
    /// no other task with the same `i` runs at the same time (the groups'
    /// ranges, from the prefix sum of `list_drawn_groups`, are disjoint).
    unsafe fn shade_task(&self, shared: &SharedOut, len: usize, i: usize, eye: Vec3) -> usize {
        let start = i.saturating_mul(GROUPS_PER_BLOCK).min(self.drawn.len());
        let block = &self.drawn[start..(start + GROUPS_PER_BLOCK).min(self.drawn.len())];
        let Some(&(_, first)) = block.first() else {
            return 0;
        };
        let mut groups = [0usize; GROUPS_PER_BLOCK];
        for (dst, &(g, _)) in groups.iter_mut().zip(block) {
            *dst = g as usize;
        }
        let Some(blend) = self
            .interpolation
            .groups_blend(&self.guides, &groups[..block.len()])
        else {
            return 0;
        };
        let r_len = blend.verts();
        let (start, n) = (
            first as usize * r_len,
            blend.hairs().min(coif_base::LANES) * r_len,
        );
        if start + n > len {
            return 0;
        }
        let ctx = GroupShading {
            shader: &self.shader,
            shadow: self.shadow.map(),
            head: &self.head_local,
            light: self.settings.light,
            eye,
            width: self.render_width,
            width_factor: self.width_factor,
        };
        // SAFETY: within the first `len` vertices of `self.shaded` and
        // disjoint from every other task's range (the caller's promise).
        let out = unsafe { shared.range(start, n) };
        shade_block(&ctx, &blend, first as usize, out);
        n
    }

    /// The reference prepare: [`FramePipeline::level_of_detail`], the
    /// shadow map of every render vertex, the batch shading, then the
    /// shaded vertices.
    fn prepare_reference(&mut self, eye: Vec3, executor: &dyn Executor) {
        self.timed(Stage::Lod, |p| p.level_of_detail());
        if self.shadow.enabled() {
            self.timed(Stage::Shadow, |p| p.build_shadow_map(executor));
        }
        self.shade(eye);
    }

    /// The fused prepare: [`FramePipeline::lod_setup`], the shadow map of
    /// every `shadow_thinning`-th drawn group, then one task per block of
    /// drawn groups that interpolates, shades and writes their vertices once.
    fn prepare_fused(&mut self, eye: Vec3, executor: &dyn Executor) {
        // The reference's per-vertex colours are not kept (keeps capacity).
        self.colors.resize(0);
        self.timed(Stage::Lod, |p| {
            let width_factor = p.lod_setup();
            p.list_drawn_groups(width_factor);
        });
        if self.shadow.enabled() {
            self.timed(Stage::Shadow, |p| p.build_thinned_shadow_map(executor));
        }
        self.timed(Stage::Shade, |p| p.shade_fused(eye, executor));
    }

    /// Runs `stage` and records its wall-clock time.
    fn timed(&mut self, stage: Stage, run: impl FnOnce(&mut Self)) {
        let start = Instant::now();
        run(self);
        self.timings.record(stage, start.elapsed());
    }

    /// The head's spheres at the current pose, in render space.
    fn place_head_spheres(&mut self, origin: Vec3) {
        for (dst, s) in self.head_local.iter_mut().zip(&self.rest_head) {
            dst.center = self.pose.transform_point3(s.center) - origin;
        }
    }

    /// Vertices per render hair at the current LOD level (at least 1).
    fn verts_per_hair(&self) -> usize {
        self.guides.verts_per_strand().max(1)
    }

    /// Stage [`Stage::Lod`]: distance LOD (fewer, wider hairs far away),
    /// frustum culling of guides and interpolation groups, the level
    /// (B-spline segments per span for `pixel_error`), refinement of the
    /// visible guides, interpolation of the render hairs and their render
    /// vertices (`coif_lod`).
    fn level_of_detail(&mut self) {
        let width_factor = self.lod_setup();
        let groups_drawn = self.groups_drawn;
        // The hairs and vertex buffers are made for this interpolation at its
        // largest level, so neither call can fail; were one to, the frame
        // draws no hair rather than stale hair.
        let written = lod::interpolate(
            &self.interpolation,
            &self.guides,
            Some(&self.visibility),
            groups_drawn,
            &mut self.hairs,
        )
        .and_then(|_| {
            lod::write_render_vertices(
                &self.interpolation,
                &self.hairs,
                groups_drawn,
                self.render_width,
                width_factor,
                &mut self.vertices,
            )
        });
        debug_assert!(
            written.is_ok(),
            "LOD buffers sized at construction: {written:?}"
        );
        self.vertex_count = written.unwrap_or(0);
        self.stats.vertices = self.vertex_count;
        self.stats.hairs = self.vertex_count / self.verts_per_hair();
    }

    /// The part of the LOD both prepare passes share: distance LOD, culling
    /// of guides and groups, the level, refinement of the visible guides.
    /// Returns the distance-LOD width factor.
    fn lod_setup(&mut self) -> f32 {
        let distance = (self.camera.target() - self.camera.eye()).length();
        let px_per_m =
            level::pixels_per_metre(distance, self.camera.fov_y(), self.settings.height as f32);
        let d = lod::distance_lod(
            &self.interpolation,
            self.render_width.root * px_per_m,
            self.settings.min_lod_fraction,
        );
        let frustum =
            lod::Frustum::from_view_projection(self.camera.view_projection(NEAR_FAR.0, NEAR_FAR.1));
        let culled = lod::cull(
            self.strands.blocks(),
            Some(&self.interpolation),
            d.groups_drawn,
            &frustum,
            CULL_MARGIN,
            &mut self.visibility,
        );
        let n = level::segments_per_span(
            level::max_second_difference_strands(self.strands.blocks()),
            px_per_m,
            self.settings.pixel_error,
            self.settings.max_segments_per_span,
        );
        // The level is clamped to the guides buffer's largest level by intent.
        let n = self.guides.set_segments_per_span_clamped(n);
        let refined = culled.and_then(|()| {
            lod::refine_strands(
                self.strands.blocks(),
                Some(&self.visibility),
                &mut self.guides,
            )
        });
        // Visibility and guides are made for these strands at construction,
        // so this cannot fail; were it to, no hair is drawn this frame.
        debug_assert!(
            refined.is_ok(),
            "LOD buffers sized at construction: {refined:?}"
        );
        self.groups_drawn = if refined.is_ok() { d.groups_drawn } else { 0 };
        self.stats.segments_per_span = n;
        self.stats.width_factor = d.width_factor;
        d.width_factor
    }

    /// The drawn groups in draw order with each one's first hair (a prefix
    /// sum over their real hairs), as many as fit the shaded buffer.
    fn list_drawn_groups(&mut self, width_factor: f32) {
        let r_len = self.guides.verts_per_strand().max(1);
        let room = self.shaded.len() / r_len;
        self.drawn.clear();
        let mut hairs = 0usize;
        for g in 0..self.groups_drawn.min(self.interpolation.group_count()) {
            if !self.interpolation.is_group_drawn(
                g,
                self.groups_drawn,
                Some(&self.visibility),
                &self.guides,
            ) {
                continue;
            }
            let n = self.interpolation.groups()[g].hairs as usize;
            if hairs + n > room {
                break;
            }
            self.drawn.push((g as u32, hairs as u32));
            hairs += n;
        }
        self.width_factor = width_factor;
        self.shaded_count = hairs * r_len;
        self.vertex_count = self.shaded_count;
        self.stats.vertices = self.shaded_count;
        self.stats.hairs = hairs;
    }

    /// Stage [`Stage::Shadow`] of the fused pass: the map of every
    /// `shadow_thinning`-th drawn group's hairs, interpolated on the fly in
    /// lane layout ([`DrawnHair`]); its hair radius was widened as many
    /// times at construction. The build runs as tasks on `executor`.
    fn build_thinned_shadow_map(&mut self, executor: &dyn Executor) {
        let hair = DrawnHair {
            interpolation: &self.interpolation,
            guides: &self.guides,
            drawn: &self.drawn,
            step: self.settings.shadow_thinning.max(1),
        };
        self.shadow
            .build_lanes(self.settings.light.to_light, &hair, executor);
    }

    /// Stage [`Stage::Shade`] of the fused pass: one task per block of
    /// `GROUPS_PER_BLOCK` drawn groups (interpolate, shade, shadow, head
    /// shadow, colour; `prepare.rs`),
    /// each writing its own range of [`FramePipeline::shaded_vertices`].
    fn shade_fused(&mut self, eye: Vec3, executor: &dyn Executor) {
        // Every group's range [first R, (first + hairs) R) lies within the
        // first `shaded_count` vertices (list_drawn_groups stopped before
        // overflowing them), and the ranges are disjoint (a prefix sum).
        let len = self.shaded_count.min(self.shaded.len());
        let shared = SharedOut(self.shaded.as_mut_ptr());
        let this = &*self;
        executor.run(this.drawn.len().div_ceil(GROUPS_PER_BLOCK), &|i| {
            // SAFETY: `shared` points to `self.shaded`; the executor runs
            // each `i` once (its contract), so no two tasks share a range.
            unsafe { this.shade_task(&shared, len, i, eye) };
        });
    }

    /// Stage [`Stage::Shadow`]: the opacity shadow map of the render hair
    /// toward the light, its tasks on `executor`.
    fn build_shadow_map(&mut self, executor: &dyn Executor) {
        let verts_per_hair = self.verts_per_hair();
        self.shadow.build(
            self.settings.light.to_light,
            &self.vertices[..self.vertex_count],
            verts_per_hair,
            executor,
        );
    }

    /// Stages [`Stage::Shade`] and, inside it but timed apart,
    /// [`Stage::ShadowLookup`]: the shading model's scattering at every
    /// render vertex, the shadow map's transmittance there, and the colours.
    fn shade(&mut self, eye: Vec3) {
        let start = Instant::now();
        write_samples(
            &mut self.samples,
            &self.vertices[..self.vertex_count],
            self.settings.light.to_light,
            eye,
        );
        self.shader.shade_batch(&self.samples, &mut self.scattering);
        let mut lookup_time = std::time::Duration::ZERO;
        if self.shadow.enabled() {
            let lookups = Instant::now();
            self.shadow.transmittance(
                &self.vertices[..self.vertex_count],
                &mut self.transmittance[..self.vertex_count],
            );
            lookup_time = lookups.elapsed();
            self.timings.record(Stage::ShadowLookup, lookup_time);
        } else {
            self.transmittance[..self.vertex_count].fill(1.0);
        }
        self.write_colors();
        self.timings
            .record(Stage::Shade, start.elapsed().saturating_sub(lookup_time));
    }

    /// The colour of every render vertex: the direct light (scattering x
    /// irradiance x shadow transmittance, zero where the head blocks the
    /// light; times the sine of the tangent-light angle for models that
    /// need the cosine factor), plus the ambient term, times the hair's tint.
    fn write_colors(&mut self) {
        let verts_per_hair = self.verts_per_hair();
        let light = self.settings.light;
        let vertices = &self.vertices[..self.vertex_count];
        let transmittance = &self.transmittance[..self.vertex_count];
        self.colors.resize(self.vertex_count);
        let cosine = self.shader.needs_cosine();
        let irradiance = light.irradiance * self.shader.light_scale();
        let ambient = HAIR_AMBIENT_ALBEDO * light.ambient;
        for (h, hair) in vertices.chunks(verts_per_hair).enumerate() {
            let tint = strand_tint(h);
            for (j, v) in hair.iter().enumerate() {
                let k = h * verts_per_hair + j;
                let p = Vec3::from(v.position);
                let mut visible = transmittance[k];
                let mut single = self.scattering.get(k);
                if let Some(ds) = self.shader.dual_scattering() {
                    // The map's hair count from its transmittance
                    // (`T = exp(-alpha sigma)`), as the fused pass reads it.
                    // The hair in front of the point and on the light's
                    // whole ray through it, as the fused pass reads them.
                    let (fibres, behind) = match self.shadow.map() {
                        Some(m) => {
                            let (front, through) = m.hairs_in_front_and_through(p);
                            (front, (through - front).max(0.0))
                        }
                        None => (0.0, f32::INFINITY),
                    };
                    let (t, wi, wo) = self.samples.get(k);
                    single = ds.shade_layered(single, t, wi, wo, fibres, behind, visible);
                    visible = 1.0;
                }
                if occluded(p, light.to_light, &self.head_local, 1e-3) {
                    visible = 0.0;
                }
                let mut direct = single * irradiance * visible;
                if cosine {
                    let c = Vec3::from(v.tangent).dot(light.to_light);
                    direct *= (1.0 - c * c).max(0.0).sqrt();
                }
                let c = (direct + ambient) * tint;
                self.colors.set(k, if c.is_finite() { c } else { ambient });
            }
        }
        self.shaded_count = self.vertex_count.min(self.shaded.len());
        for (k, (s, v)) in self.shaded[..self.shaded_count]
            .iter_mut()
            .zip(vertices)
            .enumerate()
        {
            *s = ShadedVertex {
                position: v.position,
                width: v.width,
                color: self.colors.get(k).to_array(),
                strand_parameter: v.strand_parameter,
            };
        }
    }

    /// Stage [`Stage::Head`]: the background gradient and the ray-cast head,
    /// shadowed by the hair.
    fn draw_head(&mut self, camera: &Camera, executor: &dyn Executor) {
        let light = self.settings.light;
        self.framebuffer
            .clear_gradient_with(BACKGROUND.0, BACKGROUND.1, executor);
        let head_shading = HeadShading {
            albedo: SKIN_ALBEDO,
            to_light: light.to_light,
            light: light.irradiance,
            ambient: light.ambient,
        };
        let shadow = &self.shadow;
        // With a body, the head spheres are inside it and not drawn.
        let drawn: &[Sphere] = if self.body.is_some() {
            &[]
        } else {
            &self.head_local
        };
        self.stats.head_pixels = draw_spheres_lanes(
            &mut self.framebuffer,
            camera,
            drawn,
            &head_shading,
            &|p| shadow.transmittance_simd(p),
            executor,
        );
    }

    /// Stage [`Stage::Body`]: the body posed, shaded per vertex (lit as the
    /// head, shadowed by the hair's map and the head), its eyeballs and
    /// irises ray-cast (`draw_spheres_lanes`, before the triangles, which
    /// then hide all of them but what shows through the eye openings), and its
    /// triangles rasterised as opaque, depth-writing triangles (`body.rs`).
    fn draw_body(&mut self, origin: Vec3, camera: &Camera, executor: &dyn Executor) {
        let light = self.settings.light;
        let Some(body) = &mut self.body else {
            return;
        };
        body.shade(
            &self.pose,
            origin,
            camera,
            &light,
            &self.head_local,
            &self.shadow,
            executor,
        );
        let shadow = &self.shadow;
        let (eyeballs, irises) = body.eyes();
        let mut eye_pixels = 0;
        for (spheres, albedo) in [(eyeballs, SCLERA_ALBEDO), (irises, IRIS_ALBEDO)] {
            let shading = HeadShading {
                albedo,
                to_light: light.to_light,
                light: light.irradiance,
                ambient: light.ambient,
            };
            eye_pixels += draw_spheres_lanes(
                &mut self.framebuffer,
                camera,
                spheres,
                &shading,
                &|p| shadow.transmittance_simd(p),
                executor,
            );
        }
        self.stats.body_pixels = eye_pixels + body.draw(&mut self.framebuffer, executor);
    }

    /// Stage [`Stage::RibbonDraw`]: the ribbons, opaque, depth-tested and
    /// depth-writing, so the hair drawn next is hidden behind them and
    /// blends over them in front.
    fn draw_ribbons(&mut self, origin: Vec3, camera: &Camera) {
        let light = self.settings.light;
        self.ribbons
            .shade(origin, camera.eye(), &light, &self.head_local, &self.shadow);
        self.stats.ribbon_pixels = self.ribbons.draw(&mut self.framebuffer, camera);
    }

    /// Stage [`Stage::Sort`]: render hairs back to front, by the shaded
    /// vertices the prepare pass wrote.
    fn sort_hair(&mut self, camera: &Camera) {
        let verts_per_hair = self.verts_per_hair();
        let n = self.shaded_count.min(self.shaded.len());
        self.order.sort(camera, &self.shaded[..n], verts_per_hair);
    }

    /// Stage [`Stage::Hair`]: the hair's anti-aliased segments, blended in
    /// the sorted order by the binned rasteriser (`coif_render::raster`),
    /// its runs of tiles as tasks on `executor`.
    fn draw_hair(&mut self, camera: &Camera, executor: &dyn Executor) {
        let verts_per_hair = self.verts_per_hair();
        // The head's spheres were drawn opaque (`draw_head`) and the
        // ribbons only ever bring depths nearer: what they hide is culled.
        let occluders: &[Sphere] = if self.settings.occlusion_culling {
            &self.head_local
        } else {
            &[]
        };
        self.raster.set_occluders(occluders);
        self.stats.segments = self.raster.draw(
            &mut self.framebuffer,
            camera,
            &self.shaded[..self.shaded_count.min(self.shaded.len())],
            verts_per_hair,
            &self.order,
            self.settings.hair_opacity,
            executor,
        );
        self.stats.hidden_segments = self.raster.stats().hidden;
    }

    /// The linear-RGB frame of the last [`FramePipeline::render`].
    pub fn framebuffer(&self) -> &Framebuffer {
        &self.framebuffer
    }

    /// Tone-mapped sRGB image of the last frame.
    pub fn image(&self) -> RgbImage {
        RgbImage::from_frame(&self.framebuffer, self.settings.exposure)
    }

    /// Tone-maps the last frame into `out` (no allocation once sized).
    pub fn encode_into(&self, out: &mut RgbImage) {
        out.encode(&self.framebuffer, self.settings.exposure);
    }

    /// [`FramePipeline::encode_into`] in bands of rows as tasks on
    /// `executor` (`RgbImage::encode_with`: the same bytes on any).
    pub fn encode_into_with(&self, out: &mut RgbImage, executor: &dyn Executor) {
        out.encode_with(&self.framebuffer, self.settings.exposure, executor);
    }

    /// Per-stage wall-clock times of the frames run so far.
    pub fn timings(&self) -> &StageTimings {
        &self.timings
    }

    /// Forgets the timings (e.g. after warm-up frames).
    pub fn reset_timings(&mut self) {
        self.timings.reset();
    }

    /// What the last frame did.
    pub fn stats(&self) -> FrameStats {
        self.stats
    }

    /// The settings the pipeline was built with.
    pub fn settings(&self) -> &FrameSettings {
        &self.settings
    }

    /// The world-space camera (framed on the settled hair at rest).
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The air's velocity (m/s, world space) from the next fixed step on:
    /// the simulation's `SimParams::wind`, which pulls the hair through
    /// `SimParams::drag` (and its gusts, `SimParams::turbulence`). A
    /// non-finite wind is ignored.
    pub fn set_wind(&mut self, wind: Vec3) {
        if wind.is_finite() {
            self.params.wind = wind;
        }
    }

    /// The gusts' RMS speed (m/s) from the next fixed step on: the
    /// simulation's `SimParams::turbulence`, the deterministic turbulent
    /// field added to the wind (through `SimParams::drag`). A negative or
    /// non-finite speed is ignored.
    pub fn set_turbulence(&mut self, turbulence: f32) {
        if turbulence.is_finite() && turbulence >= 0.0 {
            self.params.turbulence = turbulence;
        }
    }

    /// The simulation's parameters (with the wind of the last
    /// [`FramePipeline::set_wind`] and the turbulence of the last
    /// [`FramePipeline::set_turbulence`]).
    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// The body's field as placed at the last fixed step (None without a
    /// body): what the guides collide with.
    pub fn body_field(&self) -> Option<&kernels::Sdf> {
        self.body.as_ref().map(|b| b.field())
    }

    /// The point the head turns about (for [`super::motion`]).
    pub fn pivot(&self) -> Vec3 {
        self.pivot
    }

    /// The ribbons: blended and skinned positions, colours of the last frame.
    pub fn ribbons(&self) -> &RibbonStage {
        &self.ribbons
    }

    /// The simulated guides.
    pub fn strands(&self) -> &Strands {
        &self.strands
    }

    /// The shaded vertices of the last frame (positions relative to
    /// `strands().origin()`, final colours): what the prepare pass hands
    /// the rasteriser, hair after hair, [`FramePipeline::render_vertices`]'s
    /// vertices per hair each.
    pub fn shaded_vertices(&self) -> &[ShadedVertex] {
        &self.shaded[..self.shaded_count]
    }

    /// Render vertices of the last frame (positions relative to
    /// `strands().origin()`, with tangents), and vertices per hair. Only
    /// [`PrepareMode::Reference`] keeps them: the fused pass writes
    /// [`FramePipeline::shaded_vertices`] alone (an empty slice then).
    pub fn render_vertices(&self) -> (&[RenderVertex], usize) {
        let vertices = match self.settings.prepare {
            PrepareMode::Reference => &self.vertices[..self.vertex_count],
            PrepareMode::Fused => &[],
        };
        (vertices, self.verts_per_hair())
    }

    /// Shadow-map transmittance toward the light of each render vertex of
    /// the last frame (1 everywhere without a shadow map); only
    /// [`PrepareMode::Reference`] keeps it (empty with the fused pass).
    pub fn vertex_transmittance(&self) -> &[f32] {
        match self.settings.prepare {
            PrepareMode::Reference => &self.transmittance[..self.vertex_count],
            PrepareMode::Fused => &[],
        }
    }

    /// Final linear-RGB colour of each render vertex of the last frame;
    /// only [`PrepareMode::Reference`] keeps them (the fused pass writes
    /// the colours into [`FramePipeline::shaded_vertices`] alone).
    pub fn vertex_colors(&self) -> &RgbBuffer {
        &self.colors
    }

    /// The head's spheres as drawn in the last frame (relative to
    /// `strands().origin()`, like the render vertices).
    pub fn head_spheres(&self) -> &[Sphere] {
        &self.head_local
    }

    /// Number of render hairs the interpolation places.
    pub fn render_hair_count(&self) -> usize {
        self.interpolation.hair_count()
    }

    /// The hair shadow map of the last frame (`None` with shadows off).
    pub fn shadow_map(&self) -> Option<&coif_shading::shadow::OpacityShadowMap> {
        self.shadow.map()
    }

    /// Whether hair self-shadowing (the deep opacity map) is on.
    pub fn has_shadow_map(&self) -> bool {
        self.shadow.enabled()
    }

    /// Tasks of one shadow-map build (0 with shadows off): fixed at
    /// construction from the most hairs the map is built from (one task
    /// per 256, at most 8), never from an executor's thread count.
    pub fn shadow_tasks(&self) -> usize {
        self.shadow.tasks()
    }
}
