//! The vertex the hair rasteriser reads: position, width and final colour.

use bytemuck::{Pod, Zeroable};

/// One shaded hair vertex, 32 bytes, `#[repr(C)]`, written once by the
/// frame's prepare pass and read by the rasteriser: `position` (render
/// space, metres), `width` (metres), linear-RGB `color` (lighting, shadow
/// and tint already applied) and `strand_parameter` `s` in `[0, 1]` (0 at
/// the root, 1 at the tip).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ShadedVertex {
    /// Position in render space, metres.
    pub position: [f32; 3],
    /// Hair width at this vertex, metres.
    pub width: f32,
    /// Final linear-RGB colour.
    pub color: [f32; 3],
    /// Parameter along the strand, 0 at the root, 1 at the tip.
    pub strand_parameter: f32,
}
