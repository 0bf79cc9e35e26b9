//! The scalar twin of [`crate::raster`]: the same projection
//! ([`crate::raster::project`], one vertex at a time), binning (one
//! segment's tile range at a time), tile order and per-pixel step
//! ([`Segment::pixel`] on `f32`), one pixel at a time instead of eight.
//! Its frames equal the SIMD path's bit for bit.

use crate::line::{ScreenVertex, Segment, Walk};
use crate::raster::{HairRaster, Job, Path, TileArea, TileBuffer, TILE};
use crate::sort::DepthOrder;
use crate::{Camera, Framebuffer, ShadedVertex};
use coif_base::tasks::Executor;

/// The scalar twin of [`HairRaster::draw`]: the same arguments, buffers,
/// result and bytes.
#[allow(clippy::too_many_arguments)]
pub fn draw(
    raster: &mut HairRaster,
    frame: &mut Framebuffer,
    camera: &Camera,
    vertices: &[ShadedVertex],
    verts_per_strand: usize,
    order: &DepthOrder,
    opacity: f32,
    executor: &dyn Executor,
) -> usize {
    let job = Job {
        camera,
        vertices,
        verts_per_strand,
        order,
        opacity,
    };
    raster.run(frame, &job, executor, Path::Scalar)
}

/// Step 5 for one tile, one pixel at a time: every segment of `list` in
/// order, walked along its major axis as the SIMD path does
/// ([`Segment::walk`]), each row (or column) pixel by pixel over
/// its span clipped to the tile. (The SIMD path visits a segment's pixels
/// eight lines at a time; they are distinct pixels, so the order among
/// them changes no bit.)
pub(crate) fn draw_tile(
    tile: &mut TileBuffer,
    area: &TileArea,
    list: &[u32],
    screen: &[ScreenVertex],
    opacity: f32,
) {
    let opaque = tile.opaque;
    for &k in list {
        let k = k as usize;
        // 5a. Set up the segment (its list entry guarantees it draws).
        let Some(seg) = Segment::new(&screen[k], &screen[k + 1], area.width, area.height) else {
            continue;
        };
        let walk = seg.walk();
        let columns = walk == Walk::BandColumns;
        // 5b. The candidates of each row (column), clipped to the tile.
        let (lo, hi) = area.lines(&seg, walk);
        let (cross_lo, cross_hi) = area.cross(columns);
        let mut line = lo;
        while line < hi {
            let (ca, cb) = match walk {
                Walk::Rows => seg.row_spans(line),
                _ => seg.band(line, columns),
            };
            let (ca, cb) = (ca.max(cross_lo), cb.min(cross_hi));
            let centre = line + 0.5;
            let mut c = ca;
            // 5c. The pixels of the span.
            while c < cb {
                let (xc, yc) = if columns {
                    (centre, c + 0.5)
                } else {
                    (c + 0.5, centre)
                };
                let f = seg.fragment(xc, yc, opacity);
                if f.mask {
                    // 5d. Depth test and blend.
                    // Whole numbers in the tile: exact as i32.
                    let (x, y) = if columns { (line, c) } else { (c, line) };
                    let i = (y as i32 as usize - area.y0) * TILE + (x as i32 as usize - area.x0);
                    if opaque {
                        tile.blend::<true>(i, f.depth, f.alpha, f.color.to_vec3().to_array());
                    } else {
                        tile.blend::<false>(i, f.depth, f.alpha, f.color.to_vec3().to_array());
                    }
                }
                c += 1.0;
            }
            line += 1.0;
        }
    }
}
