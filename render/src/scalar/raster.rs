//! The scalar twin of [`crate::raster`]: the same projection
//! ([`crate::raster::project`], one vertex at a time), binning (one
//! segment's tile range at a time), tile order and per-pixel step
//! ([`Segment::pixel`] on `f32`), one pixel at a time instead of eight.
//! Its frames equal the SIMD path's bit for bit.

use crate::line::{blend, ScreenVertex, Segment};
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
/// order, each row of it pixel by pixel over the row's span.
pub(crate) fn draw_tile(
    tile: &mut TileBuffer,
    area: &TileArea,
    list: &[u32],
    screen: &[ScreenVertex],
    opacity: f32,
) {
    for &k in list {
        let k = k as usize;
        // 5a. Set up the segment (its list entry guarantees it draws).
        let Some(seg) = Segment::new(&screen[k], &screen[k + 1], area.width, area.height) else {
            continue;
        };
        // 5b. The row spans, one row at a time.
        let (lo, hi) = area.rows(&seg);
        for y in lo..hi {
            let (xa, xb) = seg.row_spans(y as f32);
            let Some((xa, xb)) = area.clip(xa, xb) else {
                continue;
            };
            let ly = y - area.y0;
            // 5c. The pixels of [xa, xb).
            for x in xa..xb {
                let (i, l) = ((ly * TILE + x) / 8, x % 8);
                // 5d. The fragment and the blend.
                let xc = (area.x0 + x) as f32 + 0.5;
                let yc = y as f32 + 0.5;
                let f = seg.pixel(xc, yc, tile.depth[i].as_array()[l], opacity);
                if f.mask {
                    let r = &mut tile.r[i].as_mut_array()[l];
                    *r = blend(*r, f.color.x, f.alpha);
                    let g = &mut tile.g[i].as_mut_array()[l];
                    *g = blend(*g, f.color.y, f.alpha);
                    let b = &mut tile.b[i].as_mut_array()[l];
                    *b = blend(*b, f.color.z, f.alpha);
                }
            }
        }
    }
}
