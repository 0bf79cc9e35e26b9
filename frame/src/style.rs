//! Styled hair in motion, measured: how a groom keeps its style at rest,
//! swings when the head turns and returns to it afterwards. The scene and
//! measures of the local shape goals (`kernels/README.md`, "Styled hair
//! that moves"), shared by the kernels' style tests, the report's `shape`
//! family and `examples/style`.
//!
//! The run ([`StyleScene::run`]), one step of `params.dt` per frame:
//!
//! 1. **Rest**: the groom from its authored pose, the head still, for
//!    [`REST_SECONDS`];
//! 2. **Turn**: the head (and the body whose field the hair collides
//!    with) turns [`TURN_DEGREES`] about the vertical through the pivot in
//!    [`TURN_SECONDS`] (`(1 - cos(pi s)) / 2`, C1), then holds for
//!    [`HOLD_SECONDS`].
//!
//! Measures (every one against the groom or the hair carried rigidly, not
//! against another run of the solver):
//!
//! - **rest drift**: the 95th percentile over free vertices of their
//!   distance from the groom after the rest;
//! - **kinks**: the share of interior vertices whose turning angle
//!   (between the segments that meet there) exceeds the groomed one by
//!   [`KINK_DEGREES`] or more: after the rest, and the largest share over
//!   the frames of the turn and hold;
//! - **swing**: the largest RMS over strands, during the turn and hold, of
//!   the tips' distance from where the rested hair carried rigidly by the
//!   head would put them;
//! - **return**: that RMS at the end of the hold.

use super::motion::head_pose;
use super::{Error, HairScene};
use coif_base::tasks::Executor;
use coif_kernels::{step_colliders_with, Colliders, Sdf, SimParams, Strands};
use glam::{Affine3A, Vec3};
use std::f32::consts::PI;
use std::time::Instant;

/// The local shape stiffness of the scenes that keep a groom's style
/// (Sintel's, a loaded groom's; the demo and the Bevy plugin): with the
/// sag-free rest state her bob keeps its shape at rest, swings 13 mm RMS
/// at the tips in a 40-degree head turn and is back within 0.2 mm 2.5 s
/// after (`kernels/README.md`, "Styled hair that moves").
pub const SCENE_STIFFNESS: f32 = 0.7;

/// Seconds at rest before the turn.
pub const REST_SECONDS: f32 = 3.0;
/// The head's turn about the vertical (degrees).
pub const TURN_DEGREES: f32 = 40.0;
/// Seconds the turn takes.
pub const TURN_SECONDS: f32 = 0.5;
/// Seconds the head holds still after the turn before the return is read.
pub const HOLD_SECONDS: f32 = 2.5;
/// A vertex turning this much more than groomed counts as a kink (degrees).
pub const KINK_DEGREES: f32 = 30.0;

/// A groom on the body it collides with, ready to run.
#[derive(Clone, Debug)]
pub struct StyleScene {
    /// The groomed guides (world metres, head at rest).
    pub guides: Vec<Vec3>,
    /// Points per guide.
    pub verts: usize,
    /// The body's field at rest (None: nothing to collide with, for a
    /// diagnosis).
    pub field: Option<Sdf>,
    /// The point the head turns about.
    pub pivot: Vec3,
}

/// What one run measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StyleRun {
    /// 95th percentile distance of free vertices from the groom after the
    /// rest (m).
    pub rest_drift_p95: f32,
    /// Share of interior vertices kinked after the rest.
    pub kinked_at_rest: f32,
    /// Largest share of kinked interior vertices over the turn and hold.
    pub kinked_in_turn: f32,
    /// Largest tip RMS from the rigidly carried hair over the turn and
    /// hold (m).
    pub swing: f32,
    /// Tip RMS from the rigidly carried hair at the end of the hold (m).
    pub returned: f32,
    /// Seconds the rest state's solve took (0 without).
    pub solve_seconds: f64,
    /// Median seconds per step over the run.
    pub step_seconds: f64,
}

impl StyleScene {
    /// Sintel's groom and bust (the default scene, 228 guides of 32
    /// points) on her bust's 4 mm field.
    ///
    /// # Errors
    /// As [`HairScene::sintel`].
    pub fn sintel() -> Result<StyleScene, Error> {
        StyleScene::from_scene(&HairScene::sintel()?)
    }

    /// The guides, body field and pivot of a scene with a body; a scene
    /// without one errors.
    ///
    /// # Errors
    /// [`Error::Scene`] for a scene without a body.
    pub fn from_scene(scene: &HairScene) -> Result<StyleScene, Error> {
        let body = scene
            .body
            .as_ref()
            .ok_or(Error::Scene("the style run needs a body to collide with"))?;
        Ok(StyleScene {
            guides: scene.guides.clone(),
            verts: scene.verts_per_strand,
            field: Some(body.field().clone()),
            pivot: scene.pivot,
        })
    }

    /// The strands of the groom with the head at rest.
    ///
    /// # Errors
    /// As [`Strands::from_polylines`].
    pub fn strands(&self) -> Result<Strands, Error> {
        let mut s = Strands::from_polylines(&self.guides, self.verts)?;
        s.set_head_pose(Affine3A::IDENTITY)?;
        Ok(s)
    }

    /// The head's pose `t` seconds after the turn began (identity before).
    pub fn pose(&self, t: f32) -> Affine3A {
        let s = (t / TURN_SECONDS).clamp(0.0, 1.0);
        let yaw = TURN_DEGREES.to_radians() * (0.5 - 0.5 * (PI * s).cos());
        head_pose(self.pivot, yaw, 0.0, Vec3::ZERO)
    }

    /// Runs the rest and the turn under `params`, each step by
    /// `coif_kernels::step_colliders_with` on `executor`; `prepare` is
    /// called once on the strands at their rest pose before the first
    /// step (the rest state's solve, or nothing) and timed.
    ///
    /// # Errors
    /// What `prepare` returns, and the strands' and poses' errors.
    pub fn run(
        &self,
        params: &SimParams,
        executor: &dyn Executor,
        prepare: impl FnOnce(&mut Strands, &SimParams, &Colliders<'_>) -> Result<(), Error>,
    ) -> Result<StyleRun, Error> {
        self.run_stepped(
            params,
            |s, p, c| step_colliders_with(s, p, c, executor),
            prepare,
        )
    }

    /// [`StyleScene::run`] with each step taken by `step` (the scalar
    /// twin, for one).
    ///
    /// # Errors
    /// As [`StyleScene::run`].
    pub fn run_stepped(
        &self,
        params: &SimParams,
        mut step_with: impl FnMut(&mut Strands, &SimParams, &Colliders<'_>),
        prepare: impl FnOnce(&mut Strands, &SimParams, &Colliders<'_>) -> Result<(), Error>,
    ) -> Result<StyleRun, Error> {
        let mut s = self.strands()?;
        let mut field = self.field.clone();
        if let Some(f) = field.as_mut() {
            f.set_transform(Affine3A::IDENTITY)?;
        }
        let mut times = Vec::new();
        let solve_start = Instant::now();
        prepare(
            &mut s,
            params,
            &Colliders {
                sdfs: field.as_slice(),
                ..Colliders::default()
            },
        )?;
        let solve_seconds = solve_start.elapsed().as_secs_f64();
        let dt = params.dt;
        let mut step =
            |s: &mut Strands, field: &mut Option<Sdf>, pose: Affine3A| -> Result<(), Error> {
                s.set_head_pose(pose)?;
                if let Some(f) = field.as_mut() {
                    f.set_transform(pose)?;
                }
                let colliders = Colliders {
                    sdfs: field.as_slice(),
                    ..Colliders::default()
                };
                let start = Instant::now();
                step_with(s, params, &colliders);
                times.push(start.elapsed().as_secs_f64());
                Ok(())
            };
        for _ in 0..(REST_SECONDS / dt).round() as usize {
            step(&mut s, &mut field, Affine3A::IDENTITY)?;
        }
        let rested = s.positions();
        let rest_drift_p95 = groom_distance_percentile(&rested, &self.guides, self.verts, 0.95);
        let kinked_at_rest = kinked_share(&rested, &self.guides, self.verts, KINK_DEGREES);
        let (mut kinked_in_turn, mut swing, mut returned) = (0.0f32, 0.0f32, 0.0f32);
        let frames = ((TURN_SECONDS + HOLD_SECONDS) / dt).round() as usize;
        for f in 1..=frames {
            let pose = self.pose(f as f32 * dt);
            step(&mut s, &mut field, pose)?;
            let now = s.positions();
            let share = kinked_share(&now, &self.guides, self.verts, KINK_DEGREES);
            kinked_in_turn = kinked_in_turn.max(share);
            let rms = tip_rms(&now, &rested, self.verts, &pose);
            swing = swing.max(rms);
            returned = rms;
        }
        times.sort_by(f64::total_cmp);
        Ok(StyleRun {
            rest_drift_p95,
            kinked_at_rest,
            kinked_in_turn,
            swing,
            returned,
            solve_seconds,
            step_seconds: times.get(times.len() / 2).copied().unwrap_or(0.0),
        })
    }
}

/// The `q` quantile (0 to 1) over free vertices (all but each strand's
/// root) of their distance from `groom` (m).
pub fn groom_distance_percentile(now: &[Vec3], groom: &[Vec3], verts: usize, q: f32) -> f32 {
    let mut d: Vec<f32> = now
        .chunks(verts)
        .zip(groom.chunks(verts))
        .flat_map(|(p, g)| p.iter().zip(g).skip(1).map(|(a, b)| (*a - *b).length()))
        .collect();
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f32::total_cmp);
    let at = ((d.len() - 1) as f32 * q.clamp(0.0, 1.0)).round() as usize;
    d[at]
}

/// The turning angle at interior vertex `v` of `p` (radians): the angle
/// between the segments that meet there.
fn turning(p: &[Vec3], v: usize) -> f32 {
    (p[v] - p[v - 1]).angle_between(p[v + 1] - p[v])
}

/// The share of interior vertices whose turning angle exceeds the
/// groomed one by `degrees` or more (a kink).
pub fn kinked_share(now: &[Vec3], groom: &[Vec3], verts: usize, degrees: f32) -> f32 {
    if verts < 3 {
        return 0.0;
    }
    let limit = degrees.to_radians();
    let (mut kinked, mut count) = (0usize, 0usize);
    for (p, g) in now.chunks(verts).zip(groom.chunks(verts)) {
        for v in 1..verts - 1 {
            count += 1;
            let extra = turning(p, v) - turning(g, v);
            // NaN (a degenerate segment) counts as a kink.
            if extra >= limit || extra.is_nan() {
                kinked += 1;
            }
        }
    }
    kinked as f32 / count.max(1) as f32
}

/// RMS over strands of the distance between each tip in `now` and the
/// tip of `rested` carried by `pose` (m).
pub fn tip_rms(now: &[Vec3], rested: &[Vec3], verts: usize, pose: &Affine3A) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (p, r) in now.chunks(verts).zip(rested.chunks(verts)) {
        if let (Some(a), Some(b)) = (p.last(), r.last()) {
            sum += (*a - pose.transform_point3(*b)).length_squared() as f64;
            n += 1;
        }
    }
    (sum / n.max(1) as f64).sqrt() as f32
}
