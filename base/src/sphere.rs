//! The collision rig's primitive: a sphere in world coordinates.

use glam::Vec3;

/// A collision sphere of the engine's rig (head, neck, shoulders...), in world
/// coordinates. Moved by the engine every frame; non-finite spheres are ignored.
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, world coordinates (metres).
    pub center: Vec3,
    /// Radius in metres.
    pub radius: f32,
}
