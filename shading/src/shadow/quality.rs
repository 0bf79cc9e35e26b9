//! Quality of a shadow-map setting: its transmittance against the exact
//! reference at the hair's own vertices, where shading needs it.
//!
//! Two references:
//! * the point reference, [`super::exact_transmittance`]: one ray per
//!   vertex. A ray either hits a hair or not, so this reference is as
//!   grainy as the hair; no map, which stores texel averages, gets close to
//!   it, and its error has a floor set by the hair's spacing;
//! * the footprint reference: the mean of the exact transmittance over
//!   `rays` parallel rays spread over a disk of `radius` across the light
//!   (a Vogel spiral), the light that reaches a small patch around the
//!   vertex. With a radius near the map's texel size it has little noise,
//!   and the remaining error is the map's own (slicing, self-shadowing,
//!   texel filtering).

use super::exact::count_crossings_many;
use super::light_frame::LightFrame;
use super::map::OpacityShadowMap;
use super::settings::ShadowSettings;
use crate::Error;
use glam::Vec3;

/// Differences `T_map - T_reference` over a set of sample points.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadowError {
    /// Mean of `|T_map - T_ref|`.
    pub mean_abs: f32,
    /// Root mean square of `T_map - T_ref`.
    pub rms: f32,
    /// Largest `|T_map - T_ref|`.
    pub max_abs: f32,
    /// Mean of `T_map - T_ref` (negative: the map over-shadows).
    pub bias: f32,
    /// Mean of `T_ref` (how shadowed the scene is).
    pub mean_reference: f32,
    /// Number of points compared.
    pub samples: usize,
}

/// The reference's footprint around each vertex: `rays` rays over a disk of
/// `radius` metres across the light. `rays = 1` is the point reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Rays averaged per point.
    pub rays: usize,
    /// Radius of the disc the rays start on, metres.
    pub radius: f32,
}

impl Footprint {
    /// One ray through the vertex: [`super::exact_transmittance`].
    pub const POINT: Footprint = Footprint {
        rays: 1,
        radius: 0.0,
    };
}

/// Builds a map with `settings` for the hair (`points`, `verts_per_strand`
/// per strand) lit along `light_dir`, and compares its transmittance with
/// the point reference [`super::exact_transmittance`] at every vertex of
/// every `strand_stride`-th strand (stride 0 counts as 1). The reference
/// visits every segment per point, so its cost is `vertices x segments`:
/// keep that modest, e.g. a stride of 8 to 16 for a thousand strands.
///
/// # Errors
///
/// As [`ShadowSettings::validate`] for invalid settings.
pub fn shadow_error(
    settings: &ShadowSettings,
    light_dir: Vec3,
    points: &[Vec3],
    verts_per_strand: usize,
    strand_stride: usize,
) -> Result<ShadowError, Error> {
    shadow_error_footprint(
        settings,
        light_dir,
        points,
        verts_per_strand,
        strand_stride,
        Footprint::POINT,
    )
}

/// [`shadow_error`] against the footprint reference (see the module
/// documentation); costs `footprint.rays` times as much.
///
/// # Errors
///
/// As [`shadow_error`].
pub fn shadow_error_footprint(
    settings: &ShadowSettings,
    light_dir: Vec3,
    points: &[Vec3],
    verts_per_strand: usize,
    strand_stride: usize,
    footprint: Footprint,
) -> Result<ShadowError, Error> {
    let mut map = OpacityShadowMap::new(settings.clone())?;
    map.build(light_dir, points, verts_per_strand);
    let reference = reference_transmittance(
        settings,
        light_dir,
        points,
        verts_per_strand,
        strand_stride,
        footprint,
    );
    Ok(error_of_map(
        &map,
        points,
        verts_per_strand,
        strand_stride,
        &reference,
    ))
}

/// The reference transmittance at every vertex of every `strand_stride`-th
/// strand (non-finite vertices skipped), in that order: compute it once and
/// compare several maps with [`error_of_map`]. Uses `settings.density` and
/// `settings.hair_radius` only.
pub fn reference_transmittance(
    settings: &ShadowSettings,
    light_dir: Vec3,
    points: &[Vec3],
    verts_per_strand: usize,
    strand_stride: usize,
    footprint: Footprint,
) -> Vec<f32> {
    let Some(frame) = LightFrame::new(light_dir) else {
        return Vec::new();
    };
    if verts_per_strand < 2 {
        return Vec::new();
    }
    let rays = footprint.rays.max(1);
    // Vogel spiral: ray j at radius R sqrt((j + 0.5) / rays), angle j * golden.
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let offsets: Vec<Vec3> = (0..rays)
        .map(|j| {
            let rho = footprint.radius * ((j as f32 + 0.5) / rays as f32).sqrt();
            let a = golden * j as f32;
            (frame.x_axis * a.cos() + frame.y_axis * a.sin()) * rho
        })
        .collect();
    let mut out = Vec::new();
    let mut origins = vec![Vec3::ZERO; rays];
    let mut counts = vec![0usize; rays];
    for strand in sampled_strands(points, verts_per_strand, strand_stride) {
        for &p in strand.iter().filter(|p| p.is_finite()) {
            for (origin, &o) in origins.iter_mut().zip(&offsets) {
                *origin = frame.to_light(p + o);
            }
            count_crossings_many(
                &frame,
                settings.hair_radius,
                points,
                verts_per_strand,
                p,
                &origins,
                &mut counts,
            );
            let mut sum = 0.0;
            for &n in &counts {
                sum += (-settings.density * n as f32).exp();
            }
            out.push(sum / rays as f32);
        }
    }
    out
}

/// Compares a built map with a reference from [`reference_transmittance`]
/// (same hair, stride and light).
pub fn error_of_map(
    map: &OpacityShadowMap,
    points: &[Vec3],
    verts_per_strand: usize,
    strand_stride: usize,
    reference: &[f32],
) -> ShadowError {
    if verts_per_strand < 2 {
        return ShadowError::default();
    }
    let mut acc = [0.0f64; 4];
    let (mut max_abs, mut count) = (0.0f32, 0usize);
    let vertices = sampled_strands(points, verts_per_strand, strand_stride)
        .flat_map(|s| s.iter().filter(|p| p.is_finite()));
    for (p, &exact) in vertices.zip(reference) {
        let d = map.transmittance(*p) - exact;
        acc[0] += d.abs() as f64;
        acc[1] += (d * d) as f64;
        acc[2] += d as f64;
        acc[3] += exact as f64;
        max_abs = max_abs.max(d.abs());
        count += 1;
    }
    if count == 0 {
        return ShadowError::default();
    }
    let c = count as f64;
    ShadowError {
        mean_abs: (acc[0] / c) as f32,
        rms: (acc[1] / c).sqrt() as f32,
        max_abs,
        bias: (acc[2] / c) as f32,
        mean_reference: (acc[3] / c) as f32,
        samples: count,
    }
}

fn sampled_strands(points: &[Vec3], verts: usize, stride: usize) -> impl Iterator<Item = &[Vec3]> {
    points.chunks_exact(verts).step_by(stride.max(1))
}
