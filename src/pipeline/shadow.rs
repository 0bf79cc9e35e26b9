//! The shadow stage of a frame. This build has no opacity shadow map yet
//! (`coif::shading::shadow` lands with issue 5's other half): the stage is
//! disabled, hair is fully visible to the light except where the head's
//! spheres block it, and no time is recorded for it.

use super::{Error, FrameSettings};
use crate::lod::RenderVertex;
use glam::Vec3;

/// Owns the shadow map and its point buffer.
pub struct ShadowStage;

impl ShadowStage {
    pub fn new(_settings: &FrameSettings, _capacity: usize) -> Result<ShadowStage, Error> {
        Ok(ShadowStage)
    }

    pub fn enabled(&self) -> bool {
        false
    }

    pub fn build(&mut self, _to_light: Vec3, _vertices: &[RenderVertex], _verts_per_strand: usize) {
    }

    /// Transmittance toward the light of every vertex into `out`.
    pub fn transmittance(&self, _vertices: &[RenderVertex], out: &mut [f32]) {
        out.fill(1.0);
    }

    pub fn transmittance_at(&self, _p: Vec3) -> f32 {
        1.0
    }
}
