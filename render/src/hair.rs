//! Drawing hair strands as blended anti-aliased polylines.

use super::line::{draw_segment, ScreenVertex};
use super::sort::DepthOrder;
use super::{raster, Camera, Framebuffer, ShadedVertex};
use coif_lod::RenderVertex;
use coif_shading::RgbBuffer;
use glam::Vec3;

/// Nearest view depth drawn (metres).
pub const NEAR: f32 = 1e-3;

/// Draws the strands of `vertices` (`verts_per_strand` each, strand after
/// strand, positions in the camera's space) in `order` (farthest first),
/// each vertex with the colour `colors[k]` (linear RGB) and its width
/// projected to pixels; every segment is blended with
/// [`draw_segment`] at `opacity`. A segment with an end behind the camera
/// or a non-finite vertex is skipped. Returns the number of segments drawn.
pub fn draw_strands(
    frame: &mut Framebuffer,
    camera: &Camera,
    vertices: &[RenderVertex],
    colors: &RgbBuffer,
    verts_per_strand: usize,
    order: &DepthOrder,
    opacity: f32,
) -> usize {
    let ppm_at_unit_depth = camera.pixels_per_metre(1.0);
    let project = |k: usize| -> Option<ScreenVertex> {
        let v = vertices.get(k)?;
        let p = camera.project(Vec3::from(v.position), NEAR)?;
        let color = if k < colors.len() {
            colors.get(k)
        } else {
            Vec3::ZERO
        };
        color.is_finite().then_some(ScreenVertex {
            x: p.x,
            y: p.y,
            depth: p.z,
            width_px: v.width * ppm_at_unit_depth / p.z,
            color,
        })
    };
    draw_projected(
        frame,
        project,
        vertices.len(),
        verts_per_strand,
        order,
        opacity,
    )
}

/// [`draw_strands`] over [`ShadedVertex`]es (colour in the vertex), with
/// the binned rasteriser's projection ([`crate::raster::project`]: a
/// vertex with a non-finite or negative width is skipped too): the direct
/// reference the binned rasteriser is compared with.
pub fn draw_shaded(
    frame: &mut Framebuffer,
    camera: &Camera,
    vertices: &[ShadedVertex],
    verts_per_strand: usize,
    order: &DepthOrder,
    opacity: f32,
) -> usize {
    let project = |k: usize| -> Option<ScreenVertex> {
        let v = raster::project(camera, vertices.get(k)?);
        (!v.depth.is_nan()).then_some(v)
    };
    draw_projected(
        frame,
        project,
        vertices.len(),
        verts_per_strand,
        order,
        opacity,
    )
}

/// The strands' segments in `order`, each vertex from `project` (`None`:
/// skipped with its two segments), each segment by [`draw_segment`].
fn draw_projected(
    frame: &mut Framebuffer,
    project: impl Fn(usize) -> Option<ScreenVertex>,
    len: usize,
    verts_per_strand: usize,
    order: &DepthOrder,
    opacity: f32,
) -> usize {
    if verts_per_strand < 2 {
        return 0;
    }
    let mut drawn = 0;
    for s in order.strands() {
        let base = s * verts_per_strand;
        if base + verts_per_strand > len {
            continue;
        }
        let mut prev = project(base);
        for k in base + 1..base + verts_per_strand {
            let next = project(k);
            if let (Some(a), Some(b)) = (&prev, &next) {
                draw_segment(frame, a, b, opacity, |_, _| {});
                drawn += 1;
            }
            prev = next;
        }
    }
    drawn
}
