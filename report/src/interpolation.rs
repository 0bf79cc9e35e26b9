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
use coif::render::Camera;
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

/// The `interpolation` rows: every share of hairs drawn, SIMD and scalar.
pub fn rows(options: Options) -> Vec<Row> {
    let scene = Scene::new(options);
    fractions(scene.default)
        .into_iter()
        .flat_map(|fraction| scene.measure(fraction, options.reps()))
        .collect()
}

/// [`FRACTIONS`], and the pipeline's default fraction if it is not one of
/// them.
fn fractions(default: f32) -> Vec<f32> {
    let mut fractions = FRACTIONS.to_vec();
    if !fractions.iter().any(|f| (f - default).abs() < 1e-6) {
        fractions.push(default);
    }
    fractions
}

/// The built-in head, settled, refined and interpolated at full density,
/// and the default camera that sees it.
struct Scene {
    interp: Interpolation,
    guides: RefinedGuides,
    /// Every render hair (the reference of the thinning error).
    hairs: RenderHairs,
    /// The render hairs' width at full density, widened by real over
    /// render hairs per cm^2 so they cover what the real hairs do.
    width: HairWidth,
    camera: Camera,
    /// The fraction the pipeline draws from this camera.
    default: f32,
}

impl Scene {
    fn new(options: Options) -> Scene {
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
        lod::refine_strands(strands.blocks(), None, &mut guides).unwrap();
        let mut hairs = RenderHairs::new(&interp, &guides);
        lod::interpolate(&interp, &guides, None, interp.group_count(), &mut hairs).unwrap();
        let ratio = defaults.real_hairs_per_cm2 / defaults.render_hairs_per_cm2;
        let width = HairWidth {
            root: defaults.hair_width.root * ratio,
            tip: defaults.hair_width.tip * ratio,
        };
        Scene {
            interp,
            guides,
            hairs,
            width,
            camera,
            default,
        }
    }

    /// A point's pixel position and pixels per metre at its depth.
    fn project(&self, p: Vec3) -> Option<[f32; 3]> {
        self.camera
            .project(p, 1e-3)
            .map(|s| [s.x, s.y, self.camera.pixels_per_metre(s.z)])
    }

    /// The thinning error of `fraction` and the time to interpolate its
    /// drawn prefix, SIMD and scalar.
    fn measure(&self, fraction: f32, reps: usize) -> [Row; 2] {
        let (interp, guides) = (&self.interp, &self.guides);
        let grid = [GRID, GRID];
        let error = thinning_error(interp, &self.hairs, self.width, fraction, grid, |p| {
            self.project(p)
        });
        let drawn = lod::distance_lod(interp, fraction, fraction).groups_drawn;
        let elements = interp.hair_count() * guides.verts_per_strand();
        let mut out = RenderHairs::new(interp, guides);
        let simd = time_batch(reps, elements, || {
            lod::interpolate(interp, guides, None, drawn, &mut out).unwrap();
            std::hint::black_box(&out);
        });
        let scalar = time_batch(reps, elements, || {
            lod::scalar::interpolate(interp, guides, None, drawn, &mut out).unwrap();
            std::hint::black_box(&out);
        });
        [(Path::Simd, simd), (Path::Scalar, scalar)].map(|(path, time)| Row {
            kernel: "interpolation".into(),
            setting: format!("{:.1} % of hairs", 100.0 * fraction),
            path,
            element: "output vertex at full density",
            time,
            error_metric: "relative RMS of per-pixel optical depth vs all hairs",
            error,
            is_default: (fraction - self.default).abs() < 1e-6,
        })
    }
}
