//! Scalar twin of `shadow/lookup.rs`: the batch lookup, one point at a time
//! with [`OpacityShadowMap::transmittance`].

use crate::shadow::OpacityShadowMap;
use glam::Vec3;

/// Scalar twin of [`OpacityShadowMap::transmittance_batch`]: one
/// [`OpacityShadowMap::transmittance`] per point, into `out` (one per point).
///
/// # Errors
///
/// As [`OpacityShadowMap::transmittance_batch`]: [`crate::Error::CountMismatch`]
/// (and nothing written) unless `out.len() == points.len()`.
pub fn transmittance_batch(
    map: &OpacityShadowMap,
    points: &[Vec3],
    out: &mut [f32],
) -> Result<(), crate::Error> {
    crate::shadow::lookup::check_lengths(points, out)?;
    for (o, p) in out.iter_mut().zip(points) {
        *o = map.transmittance(*p);
    }
    Ok(())
}
