//! coif-frame: the frame pipeline, simulation to pixels. A
//! [`FramePipeline`] owns every buffer (sized once, so a frame allocates
//! nothing) and runs one frame per call, one method per [`Stage`]:
//!
//! ```text
//! simulate: head pose -> roots + rig -> FixedStep substeps of coif_kernels::step
//!           (+ the ribbons: skinned cloth patches, coif_kernels::patch::step)
//! render:   lod          distance_lod, cull, level, refine_strands, interpolate,
//!                        write_render_vertices (coif_lod)
//!           shadow map   deep opacity map of the render hair (coif_shading::shadow;
//!                        Yuksel and Keyser 2008)
//!           shade        per vertex: Kajiya-Kay | Marschner table | pbrt table,
//!                        x shadow transmittance, x head occlusion, + ambient
//!           head         background gradient, ray-cast sphere head
//!           ribbons      opaque depth-tested triangles
//!           sort         render hairs back to front
//!           hair         anti-aliased segments blended in that order (coif_render)
//! ```
//!
//! [`FramePipeline::frame_with`] runs the parallel stages (the guides' and
//! ribbons' steps, the shadow-map build, the prepare pass, the hair's tile
//! rows) as tasks on the caller's `coif_base::tasks::Executor`, with the
//! same bytes on any executor; [`FramePipeline::frame`] runs them on the
//! calling thread.
//!
//! [`HairScene`] builds what a frame draws: the built-in sphere head with
//! grown guides, or a loaded groom (guides, scalp triangles from the roots'
//! directions, rig). [`drape`] settles grown hair under gravity (the
//! built-in scenes that need the simulation). The data flow, buffers,
//! picture, choices and measured times are described in `frame/README.md`
//! at the repository root.
#![warn(missing_docs)]

pub mod body;
pub mod crowd;
pub mod drape;
mod error;
mod frame;
mod hair_scene;
pub mod motion;
mod prepare;
pub mod ribbon;
mod settings;
mod shading_model;
mod shadow;
pub mod sim_lod;
pub mod style;
pub mod timings;
/// Scalp triangles from guide roots (moved to `coif_geometry`; this path
/// stays).
pub use coif_geometry::triangulate;

pub use error::Error;
pub use frame::{
    strand_tint, FramePipeline, FrameStats, BACKGROUND, HAIR_AMBIENT_ALBEDO, MAX_RENDER_VERTICES,
    MAX_SETTLE_SECONDS, SKIN_ALBEDO,
};
pub use hair_scene::{HairScene, GROOM_RIBBON_ATTACH, PROCEDURAL_RIBBON_ATTACH};
pub use settings::{FrameSettings, Light, PrepareMode, DEFAULT_SHADOW_THINNING};
pub use shading_model::{demo_sigma_a, HairColor, Shader, ShadingModel, PHYSICAL_LIGHT_SCALE};
pub use sim_lod::SimLod;
pub use timings::{Stage, StageTimings};
