//! Scalar twin of `shadow/lookup.rs`: the batch lookup, one point at a time
//! with [`OpacityShadowMap::transmittance`].

use crate::shadow::OpacityShadowMap;
use glam::Vec3;

/// Scalar twin of [`OpacityShadowMap::transmittance_batch`]: one
/// [`OpacityShadowMap::transmittance`] per point, into `out` (same length;
/// extra entries of either are ignored).
pub fn transmittance_batch(map: &OpacityShadowMap, points: &[Vec3], out: &mut [f32]) {
    for (o, p) in out.iter_mut().zip(points) {
        *o = map.transmittance(*p);
    }
}
