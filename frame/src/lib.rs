//! The frame pipeline of the demo: a [`FramePipeline`] owns every buffer
//! (sized once) and runs one frame per call:
//!
//! ```text
//! head pose -> roots + rig -> FixedStep substeps of kernels::step
//!   -> lod: distance_lod, cull, level, refine_strands, interpolate, write_render_vertices
//!   -> shadow map (opacity shadow map of the render hair)
//!   -> shade per vertex (Kajiya-Kay | Marschner table | pbrt table) x shadow
//!   -> rasterise: background, ray-cast head, strands sorted back to front, blended lines
//! ```
//!
//! [`HairScene`] builds what a frame draws: the built-in sphere head with
//! grown guides, or a loaded groom (guides, scalp triangles from the roots'
//! directions, rig). See `docs/PIPELINE.md`.

mod error;
mod frame;
mod hair_scene;
pub mod motion;
pub mod ribbon;
mod settings;
mod shading_model;
mod shadow;
pub mod timings;
pub mod triangulate;

pub use error::Error;
pub use frame::{
    strand_tint, FramePipeline, FrameStats, BACKGROUND, HAIR_AMBIENT_ALBEDO, SKIN_ALBEDO,
};
pub use hair_scene::{HairScene, GROOM_RIBBON_ATTACH, PROCEDURAL_RIBBON_ATTACH};
pub use settings::{FrameSettings, Light};
pub use shading_model::{demo_sigma_a, Shader, ShadingModel, PHYSICAL_LIGHT_SCALE};
pub use timings::{Stage, StageTimings};
