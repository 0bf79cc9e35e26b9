//! Dev-only fixtures of the coif-shading tests.
#![allow(dead_code)]

use glam::Vec3;

/// A unit direction at longitudinal angle `theta` from the normal plane of
/// the fibre axis `X` (`sin theta = w . X`) and azimuth `phi` around `X`.
pub fn fibre_direction(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(
        theta.sin(),
        theta.cos() * phi.cos(),
        theta.cos() * phi.sin(),
    )
}
