//! Interpolation: how many render hairs are drawn (the distance-LOD
//! thinning) against what it costs on screen.
//!
//! The knob is the fraction of the render hairs drawn: the shuffled prefix
//! of hair groups that [`coif::lod::distance_lod`] draws, widened by
//! `hair_count / hairs_drawn` so the coverage is kept (100 %, 50 %, 25 %,
//! 12.5 % of the full density). Scene: the built-in head of the `coif`
//! binary (2048 guides, settled 1.5 s) with the pipeline's default render
//! density, seed and hair width, seen from the default camera.
//!
//! - Time: [`coif::lod::interpolate`] (SIMD) and
//!   [`coif::lod::scalar::interpolate`] of the drawn prefix, positions and
//!   tangents, per output vertex of the full density (every render hair x
//!   vertices per hair): the same unit at every setting, so the time that
//!   thinning saves shows on the plot and the Pareto front. Per vertex
//!   actually written the time hardly changes with the fraction; divide by
//!   the fraction to get it.
//! - Error: [`coif::lod::quality::thinning_error`], the relative RMS
//!   difference of per-pixel optical depth (projected hair area per pixel)
//!   between the thinned, widened set and every hair at its own width, on
//!   the default camera's view at 64 x 64 pixels (each pixel 8 x 8 of the
//!   default 512 x 512 image).
//! - Default: the fraction the pipeline draws at its default settings,
//!   `clamp(render hair width in pixels, min_lod_fraction, 1)`.

use super::timing::time_batch;
use super::{Options, Path, Row};
use coif::frame::{FramePipeline, FrameSettings, HairScene};
use coif::geometry::scene::GrowOptions;
use coif::lod::{
    self, level, quality::thinning_error, HairWidth, Interpolation, RefinedGuides, RenderHairs,
};
use glam::Vec3;

/// Fractions of the render hairs drawn.
pub const FRACTIONS: [f32; 4] = [1.0, 0.5, 0.25, 0.125];
/// Side of the pixel grid the optical depth is compared on.
pub const GRID: usize = 64;

/// The fraction of render hairs the pipeline draws with
/// [`FrameSettings::default`] from its default camera (at `distance`
/// metres, vertical field of view `fov_y`).
pub fn default_fraction(distance: f32, fov_y: f32) -> f32 {
    let s = FrameSettings::default();
    let px_per_m = level::pixels_per_metre(distance, fov_y, s.height as f32);
    let render_root = s.hair_width.root * s.real_hairs_per_cm2 / s.render_hairs_per_cm2;
    (render_root * px_per_m).clamp(s.min_lod_fraction, 1.0)
}

pub fn rows(options: Options) -> Vec<Row> {
    let (strand_count, settle) = if options.quick {
        (256, 0.0)
    } else {
        (2048, 1.5)
    };
    let scene = HairScene::procedural(&GrowOptions {
        strand_count,
        curl: 0.15,
        ..GrowOptions::default()
    })
    .expect("built-in head");
    let defaults = FrameSettings::default();
    // The default camera's framing at a coarse grid: the camera depends on
    // the field of view and the hair's extent, not on the image size.
    let settings = FrameSettings {
        width: GRID,
        height: GRID,
        shadows: false,
        ..FrameSettings::default()
    };
    let pipeline = FramePipeline::new(&scene, settings, settle).expect("default pipeline");
    let strands = pipeline.strands();
    let camera = pipeline.camera().shifted(strands.origin().as_vec3());
    let project = |p: Vec3| {
        camera
            .project(p, 1e-3)
            .map(|s| [s.x, s.y, camera.pixels_per_metre(s.z)])
    };
    let distance = (camera.target() - camera.eye()).length();
    let default = default_fraction(distance, camera.fov_y());

    let roots: Vec<Vec3> = scene.roots().collect();
    let interp = Interpolation::new(
        &roots,
        &scene.triangles,
        defaults.render_hairs_per_cm2,
        defaults.seed,
    )
    .expect("default interpolation");
    let mut guides = RefinedGuides::new(strands.blocks(), defaults.max_segments_per_span)
        .expect("refinable guides");
    lod::refine_strands(strands.blocks(), None, &mut guides);
    let mut hairs = RenderHairs::new(&interp, &guides);
    let all = interp.group_count();
    lod::interpolate(&interp, &guides, None, all, &mut hairs);
    let ratio = defaults.real_hairs_per_cm2 / defaults.render_hairs_per_cm2;
    let width = HairWidth {
        root: defaults.hair_width.root * ratio,
        tip: defaults.hair_width.tip * ratio,
    };

    let mut fractions = FRACTIONS.to_vec();
    if !fractions.iter().any(|f| (f - default).abs() < 1e-6) {
        fractions.push(default);
    }
    let mut rows = Vec::new();
    for &fraction in &fractions {
        let error = thinning_error(&interp, &hairs, width, fraction, [GRID, GRID], project);
        let drawn = lod::distance_lod(&interp, fraction, fraction);
        let elements = interp.hair_count() * guides.verts_per_strand();
        let mut out = RenderHairs::new(&interp, &guides);
        let simd = time_batch(options.reps(), elements, || {
            lod::interpolate(&interp, &guides, None, drawn.groups_drawn, &mut out);
            std::hint::black_box(&out);
        });
        let scalar = time_batch(options.reps(), elements, || {
            lod::scalar::interpolate(&interp, &guides, None, drawn.groups_drawn, &mut out);
            std::hint::black_box(&out);
        });
        for (path, time) in [(Path::Simd, simd), (Path::Scalar, scalar)] {
            rows.push(Row {
                kernel: "interpolation".into(),
                setting: format!("{:.1} % of hairs", 100.0 * fraction),
                path,
                element: "output vertex at full density",
                time,
                error_metric: "relative RMS of per-pixel optical depth vs all hairs",
                error,
                is_default: (fraction - default).abs() < 1e-6,
            });
        }
    }
    rows
}
