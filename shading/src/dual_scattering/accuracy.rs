//! Dual scattering measured against the path tracer through explicit
//! fibres ([`crate::path_tracer`]), which shares none of its assumptions:
//! no fibre averages, no Gaussian spreads, no density factors, pbrt-v3's
//! BSDF sampled at the hit's own offset at every scattering.
//!
//! A patch of camera rays is traced through a fibre scene lit by a
//! directional light. For each ray the path tracer gives the reference
//! radiance (all orders of scattering). Both approximations shade the ray's
//! first hit with the far-field table of the same material: single
//! scattering with the exact shadow `S D E` (`D` = 1 when the ray from the
//! hit toward the light leaves the hair without meeting a fibre, else 0:
//! what a perfect shadow map gives), and dual scattering `F(S, n, D) E`
//! with `n` the number of fibres that ray crosses. The patch's mean of
//! each is compared; misses count as 0 in all three (no environment light).

use super::DualScattering;
use crate::path_tracer::{DirectionalLight, FibreScene, PathTracer};
use crate::{pbrt, Error};
use glam::{DVec3, Vec3};

/// Mean radiance over a patch of rays: the path-traced reference and the
/// two approximations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchComparison {
    /// The path tracer's mean radiance.
    pub path_traced: Vec3,
    /// Standard error of that mean (from the per-ray standard errors).
    pub standard_error: Vec3,
    /// Dual scattering's mean radiance.
    pub dual: Vec3,
    /// Single scattering times the exact shadow.
    pub single: Vec3,
    /// Mean number of fibres between the hits and the light.
    pub mean_fibres: f32,
    /// Fraction of the hits that see the light directly.
    pub direct_fraction: f32,
    /// Rays that hit a fibre.
    pub hits: usize,
    /// Rays in the patch.
    pub rays: usize,
}

/// What the approximations need at a camera ray's first hit: the fibre's
/// tangent, the directions, and the exact fibres and visibility toward the
/// light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitLighting {
    /// Unit tangent of the fibre hit.
    pub tangent: Vec3,
    /// Unit direction toward the light.
    pub wi: Vec3,
    /// Unit direction toward the camera.
    pub wo: Vec3,
    /// Fibres the ray from the hit toward the light crosses.
    pub fibres: f32,
    /// Fibres the ray from the hit away from the light crosses (the hair
    /// behind it).
    pub behind: f32,
    /// 1 if that ray meets no fibre, else 0.
    pub direct: f32,
}

/// The first hit of each ray (`None` for a miss) with its lighting
/// geometry toward `to_light`.
pub fn first_hits(
    scene: &FibreScene,
    rays: &[(Vec3, Vec3)],
    to_light: Vec3,
) -> Vec<Option<HitLighting>> {
    let wi = to_light.normalize_or_zero();
    rays.iter()
        .map(|&(origin, dir)| {
            let hit = scene.intersect(origin, dir, f32::INFINITY)?;
            // From the fibre's axis: the far field shades a whole fibre,
            // lit or not, as a shadow map sees it (not the hit's side).
            let axis = match scene.segment(hit.segment) {
                Some((a, b)) => {
                    let ab = b - a;
                    let u =
                        ((hit.point - a).dot(ab) / ab.length_squared().max(1e-30)).clamp(0.0, 1.0);
                    a + ab * u
                }
                None => hit.point,
            };
            let blocked = scene.occluded_excluding(axis, wi, f32::INFINITY, Some(hit.segment));
            Some(HitLighting {
                tangent: hit.tangent,
                wi,
                wo: -dir.normalize_or_zero(),
                fibres: scene.crossings(axis, wi, f32::INFINITY) as f32,
                behind: scene.crossings(axis, -wi, f32::INFINITY) as f32,
                direct: if blocked { 0.0 } else { 1.0 },
            })
        })
        .collect()
}

/// Mean radiance over `hits` (misses count as 0) of dual scattering and
/// of single scattering with the exact shadow, for a light of
/// `irradiance`: `(dual, single)`.
pub fn shade_hits(
    hits: &[Option<HitLighting>],
    table: &pbrt::Table,
    ds: &DualScattering,
    irradiance: Vec3,
) -> (Vec3, Vec3) {
    let (mut dual, mut single) = (DVec3::ZERO, DVec3::ZERO);
    for h in hits.iter().flatten() {
        let s = table.scattering(h.tangent, h.wi, h.wo);
        let f = ds.shade_layered(s, h.tangent, h.wi, h.wo, h.fibres, h.behind, h.direct);
        if f.is_finite() && s.is_finite() {
            dual += (f * irradiance).as_dvec3();
            single += (s * h.direct * irradiance).as_dvec3();
        }
    }
    let count = hits.len().max(1) as f64;
    ((dual / count).as_vec3(), (single / count).as_vec3())
}

/// The patch `rays` (origin, direction) through `scene`: `paths_per_ray`
/// paths of `tracer` per ray (seeded with `seed`, on `threads` threads:
/// the same bytes for any count) against `ds` and `table` (the far field
/// of the tracer's material) at each ray's first hit, lit by `light`.
///
/// # Errors
///
/// As [`PathTracer::estimate`].
#[allow(clippy::too_many_arguments)]
pub fn compare_patch(
    scene: &FibreScene,
    rays: &[(Vec3, Vec3)],
    tracer: &PathTracer,
    light: DirectionalLight,
    table: &pbrt::Table,
    ds: &DualScattering,
    paths_per_ray: usize,
    seed: u64,
    threads: usize,
) -> Result<PatchComparison, Error> {
    let estimates = tracer.estimate_threaded(scene, rays, paths_per_ray, seed, threads)?;
    let (mut traced, mut var) = (DVec3::ZERO, DVec3::ZERO);
    for e in &estimates {
        traced += e.mean.as_dvec3();
        var += (e.standard_error * e.standard_error).as_dvec3();
    }
    let hits = first_hits(scene, rays, light.to_light);
    let (dual, single) = shade_hits(&hits, table, ds, light.irradiance);
    let lit: Vec<&HitLighting> = hits.iter().flatten().collect();
    let per_hit = lit.len().max(1) as f32;
    let count = rays.len().max(1) as f64;
    Ok(PatchComparison {
        path_traced: (traced / count).as_vec3(),
        standard_error: (DVec3::new(var.x.sqrt(), var.y.sqrt(), var.z.sqrt()) / count).as_vec3(),
        dual,
        single,
        mean_fibres: lit.iter().map(|h| h.fibres).sum::<f32>() / per_hit,
        direct_fraction: lit.iter().map(|h| h.direct).sum::<f32>() / per_hit,
        hits: lit.len(),
        rays: rays.len(),
    })
}

/// Relative RMS error of `estimate` against `reference` over a set of
/// patches and their RGB channels: `sqrt(sum (e - r)^2 / sum r^2)`.
pub fn relative_rms(pairs: impl IntoIterator<Item = (Vec3, Vec3)>) -> f64 {
    let (mut err, mut norm) = (0.0f64, 0.0f64);
    for (estimate, reference) in pairs {
        let d = (estimate - reference).as_dvec3();
        err += d.length_squared();
        norm += reference.as_dvec3().length_squared();
    }
    if norm > 0.0 {
        (err / norm).sqrt()
    } else {
        0.0
    }
}
