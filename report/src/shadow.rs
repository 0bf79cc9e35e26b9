//! Shadow maps: opacity shadow map slices and deep opacity map layers
//! against the exact transmittance.
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
use coif::shading::shadow::{OpacityShadowMap, ShadowMode, ShadowSettings};
use glam::Vec3;

/// Slices of opacity shadow maps measured.
pub const SLICES: [usize; 5] = [4, 8, 16, 32, 64];
/// Layers of deep opacity maps measured.
pub const DEEP_LAYERS: [usize; 3] = [2, 3, 4];
/// The frame pipeline's map resolution.
pub const RESOLUTION: usize = 128;
const STRIDE: usize = 8;
const DRAPE_STEPS: usize = 90;

pub fn rows(options: Options) -> Vec<Row> {
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
    let settings: Vec<(String, ShadowSettings, bool)> = SLICES
        .iter()
        .map(|&n| (format!("slices {n}"), ShadowMode::Slices, n))
        .chain(
            DEEP_LAYERS
                .iter()
                .map(|&n| (format!("deep {n}"), ShadowMode::Deep, n)),
        )
        .map(|(name, mode, layers)| {
            let s = ShadowSettings {
                mode,
                layers,
                ..base.clone()
            };
            // Defaults: the pipeline's deep map of 3 layers, and the
            // library's ShadowSettings::default() of 16 slices.
            let default = (mode, layers) == (ShadowMode::Deep, 3)
                || (mode, layers) == (ShadowMode::Slices, 16);
            (name, s, default)
        })
        .collect();
    let segments = (points.len() / verts) * (verts - 1);
    let mut out = vec![0.0f32; points.len()];
    let mut rows = Vec::new();
    const METRIC: &str = "mean |T_map - T_exact| (footprint reference)";
    for (name, s, is_default) in settings {
        let mut map = OpacityShadowMap::new(s).expect("valid shadow settings");
        let build_scalar = time_batch(options.reps(), segments, || {
            coif::shading::shadow::scalar::build(&mut map, light, &points, verts)
        });
        let build = time_batch(options.reps(), segments, || {
            map.build(light, &points, verts)
        });
        let error = error_of_map(&map, &points, verts, STRIDE, &reference).mean_abs as f64;
        let simd = time_batch(options.reps(), points.len(), || {
            map.transmittance_batch(&points, &mut out);
            std::hint::black_box(&out);
        });
        let scalar = time_batch(options.reps(), points.len(), || {
            coif::shading::shadow::scalar::transmittance_batch(&map, &points, &mut out);
            std::hint::black_box(&out);
        });
        for (kernel, element, path, time) in [
            ("shadow build", "segment", Path::Simd, build),
            ("shadow build", "segment", Path::Scalar, build_scalar),
            ("shadow lookup", "sample", Path::Simd, simd),
            ("shadow lookup", "sample", Path::Scalar, scalar),
        ] {
            rows.push(Row {
                kernel: kernel.into(),
                setting: name.clone(),
                path,
                element,
                time,
                error_metric: METRIC,
                error,
                is_default,
            });
        }
    }
    rows
}
