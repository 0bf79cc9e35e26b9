//! coif on the GPU: render hairs made in shaders from the simulated guides.
//!
//! The CPU path (coif-lod) refines every guide, interpolates every render
//! hair and writes every render vertex on the CPU, about 1.3 M vertices a
//! frame for Sintel. Here the CPU uploads only the guides (16 bytes per
//! guide vertex, [`pack_guides`]) and a 192-byte [`HairView`]; the render
//! hairs ([`RenderHair`], built once by [`pack_hairs`]) stay on the GPU, and
//! one WGSL function, `render_vertex(hair, r)`, makes vertex `r` of a hair
//! with the formulas of `lod::refine_strands`, `lod::interpolate` and
//! `lod::write_render_vertices`, in their order (the GPU twin:
//! `tests/twin.rs` compares every vertex with them on a real adapter).
//!
//! | buffer | type | size | written |
//! |---|---|---|---|
//! | guides (storage) | [`GuideVertex`] | 16 B per guide vertex | every frame, [`pack_guides`] |
//! | hairs (storage) | [`RenderHair`] | 32 B per render hair | once, [`pack_hairs`] |
//! | view (uniform) | [`HairView`] | 192 B | every frame |
//!
//! Shaders ([`shaders`]): a compute entry point writing render vertices
//! (`compute.wgsl`), and vertex/fragment stages drawing camera-facing
//! ribbons by vertex pulling (`draw.wgsl`, one triangle strip of `2 R`
//! vertices per instance, one instance per hair), lit with coif's
//! Kajiya-Kay and Marschner tables. `cargo run --release -p coif-gpu
//! --example emit -- <wgsl|spv|hlsl|msl|glsl> OUT_DIR` writes them for
//! other engines (translated by naga). gpu/README.md has the whole recipe.
#![warn(missing_docs)]

pub mod layout;
pub mod pack;
pub mod shaders;

pub use coif_lod::Error;
pub use layout::{GuideVertex, HairView, RenderHair};
pub use pack::{pack_guides, pack_hairs, render_hair_count};
