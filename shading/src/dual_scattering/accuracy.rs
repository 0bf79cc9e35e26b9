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
//! The caller traces the patch (`PathTracer::estimate`), then shades its
//! [`first_hits`] with [`shade_hits`] and compares with [`relative_rms`].

use super::DualScattering;
use crate::path_tracer::FibreScene;
use crate::pbrt;
use glam::{DVec3, Vec3};

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
