//! Quality of a shadow-map setting: its transmittance against the exact
//! reference at the hair's own vertices, where shading needs it.

use super::exact::count_crossings;
use super::light_frame::LightFrame;
use super::map::OpacityShadowMap;
use super::settings::ShadowSettings;
use crate::Error;
use glam::Vec3;

/// Differences `T_map - T_exact` over a set of sample points.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadowError {
    /// Mean of `|T_map - T_exact|`.
    pub mean_abs: f32,
    /// Root mean square of `T_map - T_exact`.
    pub rms: f32,
    /// Largest `|T_map - T_exact|`.
    pub max_abs: f32,
    /// Mean of `T_map - T_exact` (negative: the map over-shadows).
    pub bias: f32,
    /// Number of points compared.
    pub samples: usize,
}

/// Builds a map with `settings` for the hair (`points`, `verts_per_strand`
/// per strand) lit along `light_dir`, and compares its transmittance with
/// [`super::exact_transmittance`] at every vertex of every
/// `strand_stride`-th strand (stride 0 counts as 1). The reference is brute
/// force (every segment per point), so keep `vertices x segments` modest,
/// e.g. a stride of 8 to 16 for a few thousand strands.
pub fn shadow_error(
    settings: &ShadowSettings,
    light_dir: Vec3,
    points: &[Vec3],
    verts_per_strand: usize,
    strand_stride: usize,
) -> Result<ShadowError, Error> {
    let mut map = OpacityShadowMap::new(settings.clone())?;
    map.build(light_dir, points, verts_per_strand);
    Ok(error_of_map(
        &map,
        light_dir,
        points,
        verts_per_strand,
        strand_stride,
    ))
}

/// [`shadow_error`] of an already built map (built from the same hair and
/// light), so several measurements can share one build.
pub fn error_of_map(
    map: &OpacityShadowMap,
    light_dir: Vec3,
    points: &[Vec3],
    verts_per_strand: usize,
    strand_stride: usize,
) -> ShadowError {
    let Some(frame) = LightFrame::new(light_dir) else {
        return ShadowError::default();
    };
    if verts_per_strand < 2 {
        return ShadowError::default();
    }
    let s = map.settings();
    let (mut sum_abs, mut sum_sq, mut sum, mut max_abs, mut count) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f32, 0);
    for strand in points
        .chunks_exact(verts_per_strand)
        .step_by(strand_stride.max(1))
    {
        for &p in strand.iter().filter(|p| p.is_finite()) {
            let n = count_crossings(&frame, s.hair_radius, points, verts_per_strand, p);
            let exact = (-s.density * n as f32).exp();
            let d = map.transmittance(p) - exact;
            sum_abs += d.abs() as f64;
            sum_sq += (d * d) as f64;
            sum += d as f64;
            max_abs = max_abs.max(d.abs());
            count += 1;
        }
    }
    if count == 0 {
        return ShadowError::default();
    }
    let c = count as f64;
    ShadowError {
        mean_abs: (sum_abs / c) as f32,
        rms: (sum_sq / c).sqrt() as f32,
        max_abs,
        bias: (sum / c) as f32,
        samples: count,
    }
}
