//! Opacity shadow maps for hair: how much light reaches each point of a
//! hair volume from a directional light.
//!
//! * [`OpacityShadowMap`] in [`ShadowMode::Slices`]: opacity shadow maps
//!   (Kim & Neumann 2001), `L` planes perpendicular to the light between the
//!   hair's nearest and farthest depth, each holding the opacity in front of
//!   it, linear in depth between planes, `T = exp(-k sigma)`. Nalu (GPU
//!   Gems 2 ch. 23) used 16 slices packed 4 per RGBA texel and
//!   `exp(-5.5 * sum)`.
//! * [`ShadowMode::Deep`]: deep opacity maps (Yuksel & Keyser 2008), the
//!   layers start at a depth map of the first hair per texel, which removes
//!   OSM's layering artefacts with few (3) layers.
//! * Builds: [`OpacityShadowMap::build`] (SIMD, eight segments' samples
//!   per `F32Lanes`, deposits in the scalar order) and [`scalar::build`] (the
//!   reference) make the same map bit for bit; likewise the batch lookups
//!   [`OpacityShadowMap::transmittance_batch`] and
//!   [`scalar::transmittance_batch`] agree to float rounding, and so do the
//!   per-point [`OpacityShadowMap::transmittance_simd`] (eight points in
//!   lanes, for a fused per-vertex pass) and
//!   [`OpacityShadowMap::transmittance`]. Files mirror:
//!   `build.rs`, `raster.rs`, `lookup.rs` (SIMD) and `scalar/build.rs`,
//!   `scalar/raster.rs`, `scalar/lookup.rs`.
//! * [`exact_transmittance`]: the reference, `exp(-k n)` with `n` the number
//!   of hair segments (capsules) the ray toward the light passes through.
//! * [`quality`]: error of a setting against the reference.
//!
//! See `shading/SHADOWS.md` for formulas, storage layout and measured
//! figures.

mod build;
pub use build::BuildScratch;
mod exact;
mod gather;
pub mod layers;
pub mod light_frame;
mod lookup;
mod map;
pub mod quality;
mod raster;
pub mod scalar;
mod settings;
mod strand_lanes;

pub use exact::exact_transmittance;
pub use light_frame::{LightFrame, MapPlacement};
pub use map::OpacityShadowMap;
pub use settings::{ShadowMode, ShadowSettings, MAX_LAYERS, MAX_MAP_TEXELS, MAX_RESOLUTION};
pub use strand_lanes::{to_lane_rows, LaneRows, StrandLanes};
