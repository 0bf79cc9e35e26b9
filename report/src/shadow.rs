//! Shadow maps: opacity shadow map slices (Kim and Neumann 2001) and deep
//! opacity map layers (Yuksel and Keyser 2008) against the exact
//! transmittance `T = exp(-sigma)` of the optical depth `sigma` along the
//! light ray (Kim and Neumann 2001, eq. 1).
//!
//! Hair: a grown head (512 strands of 16 vertices, curl 0.3) draped by 90
//! simulation steps, lit from above and to the side; map of 128 x 128
//! texels, density 0.5 (the frame pipeline's), as in shading/SHADOWS.md.
//! Error: mean `|T_map - T_ref|` at every vertex of every 8th strand,
//! against the footprint reference
//! ([`coif::shading::shadow::quality::reference_transmittance`], 16 rays
//! over a 2 mm disk), computed once for all settings.
//!
//! Two timed kernels per setting: `shadow build` (per hair segment: SIMD
//! `build` and scalar `shadow::scalar::build`, which make the same map bit for bit)
//! and `shadow lookup` (per sample: SIMD `transmittance_batch` and scalar
//! `shadow::scalar::transmittance_batch` at every vertex).

use super::timing::time_batch;
use super::{Options, Path, Row};
use coif::frame::drape::draped_on_sphere;
use coif::shading::shadow::quality::{error_of_map, reference_transmittance, Footprint};
use coif::shading::shadow::{self, OpacityShadowMap, ShadowMode, ShadowSettings};
use glam::Vec3;

/// Slices of opacity shadow maps measured.
pub const SLICES: [usize; 5] = [4, 8, 16, 32, 64];
/// Layers of deep opacity maps measured.
pub const DEEP_LAYERS: [usize; 3] = [2, 3, 4];
/// The frame pipeline's map resolution.
pub const RESOLUTION: usize = 128;
const STRIDE: usize = 8;
const DRAPE_STEPS: usize = 90;

/// Error metric of both shadow kernels.
const METRIC: &str = "mean |T_map - T_exact| (footprint reference)";

/// The `shadow build` and `shadow lookup` rows: every slice and layer
/// count, SIMD and scalar.
pub fn rows(options: Options) -> Vec<Row> {
    let scene = Scene::new(options);
    settings(&scene.base)
        .into_iter()
        .flat_map(|(name, s, is_default)| scene.measure(name, s, is_default, options.reps()))
        .collect()
}

/// Every setting measured: (name, settings, whether it is a default).
/// Defaults: the pipeline's deep map of 3 layers, and the library's
/// `ShadowSettings::default()` of 16 slices.
fn settings(base: &ShadowSettings) -> Vec<(String, ShadowSettings, bool)> {
    let slices = SLICES.iter().map(|&n| (ShadowMode::Slices, n));
    let deep = DEEP_LAYERS.iter().map(|&n| (ShadowMode::Deep, n));
    slices
        .chain(deep)
        .map(|(mode, layers)| {
            let name = match mode {
                ShadowMode::Slices => format!("slices {layers}"),
                ShadowMode::Deep => format!("deep {layers}"),
            };
            let s = ShadowSettings {
                mode,
                layers,
                ..base.clone()
            };
            let default = (mode, layers) == (ShadowMode::Deep, 3)
                || (mode, layers) == (ShadowMode::Slices, 16);
            (name, s, default)
        })
        .collect()
}

/// Draped hair, the light, and the exact transmittance to compare with.
struct Scene {
    points: Vec<Vec3>,
    /// Vertices per strand.
    verts: usize,
    light: Vec3,
    /// The pipeline's resolution and density; mode and layers vary.
    base: ShadowSettings,
    /// Footprint transmittance at every vertex of every [`STRIDE`]th strand.
    reference: Vec<f32>,
}

impl Scene {
    fn new(options: Options) -> Scene {
        let (strand_count, verts) = if options.quick { (96, 12) } else { (512, 16) };
        let (points, _) = draped_on_sphere(strand_count, verts, DRAPE_STEPS);
        let light = Vec3::new(0.4, -1.0, 0.3).normalize();
        let base = ShadowSettings {
            resolution: RESOLUTION,
            ..Default::default()
        };
        let (lo, hi) = points.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let texel = (hi - lo).max_element() / RESOLUTION as f32;
        let footprint = Footprint {
            rays: if options.quick { 4 } else { 16 },
            radius: 0.5 * texel,
        };
        let reference = reference_transmittance(&base, light, &points, verts, STRIDE, footprint);
        Scene {
            points,
            verts,
            light,
            base,
            reference,
        }
    }

    /// One setting: build and lookup timed, SIMD and scalar; the built
    /// map's error against the reference.
    fn measure(&self, name: String, s: ShadowSettings, is_default: bool, reps: usize) -> Vec<Row> {
        let (points, verts, light) = (&self.points, self.verts, self.light);
        let segments = (points.len() / verts) * (verts - 1);
        let mut map = OpacityShadowMap::new(s).expect("valid shadow settings");
        let build_scalar = time_batch(reps, segments, || {
            shadow::scalar::build(&mut map, light, points, verts)
        });
        let build = time_batch(reps, segments, || map.build(light, points, verts));
        let error = error_of_map(&map, points, verts, STRIDE, &self.reference).mean_abs as f64;
        let mut out = vec![0.0f32; points.len()];
        let simd = time_batch(reps, points.len(), || {
            map.transmittance_batch(points, &mut out).unwrap();
            std::hint::black_box(&out);
        });
        let scalar = time_batch(reps, points.len(), || {
            shadow::scalar::transmittance_batch(&map, points, &mut out).unwrap();
            std::hint::black_box(&out);
        });
        [
            ("shadow build", "segment", Path::Simd, build),
            ("shadow build", "segment", Path::Scalar, build_scalar),
            ("shadow lookup", "sample", Path::Simd, simd),
            ("shadow lookup", "sample", Path::Scalar, scalar),
        ]
        .into_iter()
        .map(|(kernel, element, path, time)| Row {
            kernel: kernel.into(),
            setting: name.clone(),
            path,
            element,
            time,
            error_metric: METRIC,
            error,
            is_default,
        })
        .collect()
    }
}
