//! A small deterministic software renderer for the demo: hair as
//! anti-aliased lines of sub-pixel width, alpha-blended back to front over a
//! ray-cast sphere head and a background, tone-mapped and written as PNG.
//!
//! Deterministic: the stages that run as tasks on the caller's executor
//! (`coif_base::tasks`) write disjoint pixels in a fixed order, so the same
//! input gives the same bytes at any thread count. Every buffer is owned by the caller and sized once ([`Framebuffer`],
//! the sort keys of [`sort::DepthOrder`]); drawing allocates nothing.
//!
//! - [`Camera`]: perspective look-at camera, projection to pixels.
//! - [`Framebuffer`]: linear-RGB float colour and view depth per pixel.
//! - [`mod@line`]: coverage of a pixel by a line of sub-pixel width, and the
//!   blended segment.
//! - [`head`]: the ray-cast, Lambert-lit sphere head.
//! - [`sort`]: back-to-front order of hair strands.
//! - [`hair`]: drawing every strand's segments in that order, directly
//!   (the reference).
//! - [`raster`]: the binned rasteriser the frame uses: segments sorted into
//!   screen tiles, each tile drawn in cache eight segments per register
//!   ([`raster::HairRaster`]; scalar twin [`scalar::draw`]).
//! - [`triangle`]: opaque triangles (edge functions, top-left rule, depth
//!   test) and [`grid`]: a row-major grid mesh of them (the ribbon);
//!   [`triangle_bins`]: a mesh's triangles binned into the hair's tiles
//!   and filled as tasks (the body), the same bytes as one pass.
//! - [`ShadedVertex`]: the shaded vertex the hair rasteriser reads.
//! - [`image`]: tone map and sRGB encode to 8-bit RGB, contact sheets, PNG.

#![warn(missing_docs)]

mod camera;
mod framebuffer;
pub mod grid;
pub mod hair;
pub mod head;
pub mod image;
pub mod line;
pub mod occlusion;
pub mod raster;
pub mod scalar;
pub mod sort;
pub mod triangle;
pub mod triangle_bins;
mod vertex;

pub use camera::Camera;
pub use framebuffer::{Framebuffer, Pixel};
pub use image::RgbImage;
pub use vertex::ShadedVertex;
