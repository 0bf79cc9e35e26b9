//! Opaque triangles drawn as tasks: binned into the hair raster's
//! [`TILE`] x [`TILE`] tiles, then filled tile by tile.
//!
//! A mesh's triangles (a character's body) are drawn in four steps:
//!
//! 1. every triangle's tile range `[tx0, tx1) x [ty0, ty1)`, from the
//!    pixels whose centre can be inside its bounding box (the pixels
//!    [`fill_triangle`] scans);
//! 2. a count per tile, and its prefix sum: where each tile's list starts;
//! 3. the lists, filled in triangle order: a tile's list holds the
//!    triangles touching it in the order of the mesh;
//! 4. the tiles cut into runs of about equal list entries, one task per
//!    run (four per thread of the executor, at most [`MAX_TASKS`]): each
//!    task fills its tiles' triangles, clipped to the tile, in list order.
//!
//! **The same bytes as one pass over the mesh**: a pixel belongs to one
//! tile, whose task visits the triangles covering it in mesh order, and a
//! pixel's coverage, depth and colour depend on the pixel alone (the edge
//! functions are evaluated at its centre, never stepped), so every pixel
//! sees the same depth tests in the same order as in
//! [`fill_triangle`] called triangle after
//! triangle. Steps 1 to 3 are a few operations per triangle on the calling
//! thread; step 4, the pixels, is the work.
//!
//! The lists hold [`TriangleBins::new`]'s capacity (four entries per
//! triangle plus one per tile); a frame that needs more (a mesh seen from
//! very near, its triangles spanning many tiles) is drawn in one pass on
//! the calling thread instead: the same bytes, no allocation. So is every
//! draw on an executor of one thread ([`Executor::threads`]), which the
//! tiles would only cost (binning, and a triangle's set-up once per tile
//! it touches: on Sintel's body 185 M instructions for 8 frames against
//! 142 M in one pass).

use super::raster::{for_each_tile, TILE};
use super::triangle::{fill_triangle, TriangleSetup, TriangleVertex};
use super::Framebuffer;
use coif_base::tasks::{DisjointMut, Executor};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Most tasks of one draw.
pub const MAX_TASKS: usize = 64;

/// List entries per triangle the bins hold (besides one per tile).
const ENTRIES_PER_TRIANGLE: usize = 4;

/// The buffers of a binned triangle draw for one frame size and up to a
/// number of triangles, allocated once ([`TriangleBins::new`]).
#[derive(Clone, Debug)]
pub struct TriangleBins {
    width: usize,
    height: usize,
    tiles_x: usize,
    /// Per triangle: its tiles `[tx0, tx1, ty0, ty1]` (empty when it draws
    /// nothing).
    rects: Vec<[u16; 4]>,
    /// Per tile: where its list starts (and one past the last tile).
    starts: Vec<u32>,
    /// Per tile: the next free slot while filling.
    cursor: Vec<u32>,
    /// The lists: triangle indices, tile after tile.
    entries: Vec<u32>,
}

impl TriangleBins {
    /// Bins for a `width x height` frame and up to `triangles` triangles
    /// per draw (more are drawn, in one pass on the calling thread).
    /// Sizes of zero are taken as one.
    pub fn new(width: usize, height: usize, triangles: usize) -> TriangleBins {
        let (width, height) = (width.max(1), height.max(1));
        let tiles_x = width.div_ceil(TILE);
        let tiles = tiles_x * height.div_ceil(TILE);
        TriangleBins {
            width,
            height,
            tiles_x,
            rects: vec![[0; 4]; triangles],
            starts: vec![0; tiles + 1],
            cursor: vec![0; tiles],
            entries: vec![0; ENTRIES_PER_TRIANGLE * triangles + tiles],
        }
    }

    /// Draws `triangles` (corner indices into `corners`; a corner that is
    /// `None`, behind the near plane, or an index out of range skips the
    /// triangle) opaque and depth-tested into `frame`, as
    /// [`fill_triangle`] called for each
    /// triangle in order would (the same bytes; module doc), the tiles'
    /// pixels as tasks on `executor`. Returns the pixels written. A frame
    /// of another size than the bins', or more triangles than they were
    /// made for, is drawn in one pass on the calling thread, and so is
    /// every draw on an executor of one thread.
    pub fn draw(
        &mut self,
        frame: &mut Framebuffer,
        corners: &[Option<TriangleVertex>],
        triangles: &[[u32; 3]],
        executor: &dyn Executor,
    ) -> usize {
        let corner = |i: u32| corners.get(i as usize).copied().flatten();
        let (width, height) = (frame.width(), frame.height());
        let setup = |t: &[u32; 3]| {
            let [a, b, c] = t.map(corner);
            TriangleSetup::new(&a?, &b?, &c?, width, height)
        };
        let fits =
            width == self.width && height == self.height && triangles.len() <= self.rects.len();
        // One thread gains nothing from tiles: the one pass, without the
        // binning and a triangle's set-up per tile it touches, is the same
        // bytes (module doc) and about a quarter fewer instructions on
        // Sintel's body.
        if executor.threads() <= 1 || !fits || !self.bin(triangles, &corner) {
            return draw_in_order(frame, corners, triangles);
        }
        self.fill_tiles(frame, triangles, &setup, executor)
    }

    /// Steps 1 to 3; `false` when the lists would overflow.
    fn bin(
        &mut self,
        triangles: &[[u32; 3]],
        corner: &impl Fn(u32) -> Option<TriangleVertex>,
    ) -> bool {
        self.cursor.fill(0);
        let mut total = 0usize;
        let (width, height) = (self.width, self.height);
        for (rect, t) in self.rects.iter_mut().zip(triangles) {
            let [a, b, c] = t.map(corner);
            let bounds = (a.zip(b).zip(c))
                .and_then(|((a, b), c)| TriangleSetup::pixel_bounds(&a, &b, &c, width, height));
            *rect = match bounds {
                Some([x0, x1, y0, y1]) => [
                    x0 / TILE,
                    (x1 - 1) / TILE + 1,
                    y0 / TILE,
                    (y1 - 1) / TILE + 1,
                ]
                .map(|v| v as u16),
                None => [0; 4],
            };
            let cursor = &mut self.cursor;
            total += for_each_tile(*rect, self.tiles_x, |tile| cursor[tile] += 1) as usize;
        }
        if total > self.entries.len() {
            return false;
        }
        let mut sum = 0u32;
        for (start, count) in self.starts.iter_mut().zip(&mut self.cursor) {
            *start = sum;
            sum += *count;
            *count = *start;
        }
        self.starts[self.cursor.len()] = sum;
        let (cursor, entries) = (&mut self.cursor, &mut self.entries);
        for (k, rect) in self.rects[..triangles.len()].iter().enumerate() {
            for_each_tile(*rect, self.tiles_x, |tile| {
                entries[cursor[tile] as usize] = k as u32;
                cursor[tile] += 1;
            });
        }
        true
    }

    /// Step 4: runs of tiles as tasks, each tile's list clipped to it.
    fn fill_tiles(
        &self,
        frame: &mut Framebuffer,
        triangles: &[[u32; 3]],
        setup: &(impl Fn(&[u32; 3]) -> Option<TriangleSetup> + Sync),
        executor: &dyn Executor,
    ) -> usize {
        let (width, height) = (self.width, self.height);
        let tiles = self.cursor.len();
        let total = self.starts[tiles] as u64;
        let tasks = (4 * executor.threads()).clamp(1, MAX_TASKS).min(tiles);
        // Task c starts at the first tile whose list starts at or after
        // c / tasks of all entries.
        let first_tile = |c: usize| {
            let at = (total * c as u64).div_ceil(tasks as u64);
            self.starts[..tiles].partition_point(|&s| (s as u64) < at)
        };
        let sum = AtomicUsize::new(0);
        let pixels = DisjointMut::new(&mut frame.pixels);
        executor.run(tasks, &|c| {
            let end = if c + 1 == tasks {
                tiles
            } else {
                first_tile(c + 1)
            };
            let mut written = 0;
            for t in first_tile(c)..end {
                let list = &self.entries[self.starts[t] as usize..self.starts[t + 1] as usize];
                let (tx, ty) = (t % self.tiles_x, t / self.tiles_x);
                let (x0, y0) = (tx * TILE, ty * TILE);
                let (x1, y1) = ((x0 + TILE).min(width), (y0 + TILE).min(height));
                for &k in list {
                    let Some(s) = setup(&triangles[k as usize]) else {
                        continue;
                    };
                    let [sx0, sx1, sy0, sy1] = s.pixels;
                    for y in sy0.max(y0)..sy1.min(y1) {
                        // SAFETY: tile t belongs to task c's run only (the
                        // runs cut the tiles' sequence), and its pixels
                        // [x0, x1) of row y are no other tile's.
                        let row = unsafe { pixels.range(y * width + x0, x1 - x0) };
                        written += s.fill_row(y, sx0.max(x0)..sx1.min(x1), row, x0, |_| {});
                    }
                }
            }
            sum.fetch_add(written, Ordering::Relaxed);
        });
        sum.into_inner()
    }
}

/// Every triangle in order over the whole frame, on the calling thread.
fn draw_in_order(
    frame: &mut Framebuffer,
    corners: &[Option<TriangleVertex>],
    triangles: &[[u32; 3]],
) -> usize {
    let corner = |i: u32| corners.get(i as usize).copied().flatten();
    let mut written = 0;
    for t in triangles {
        if let [Some(a), Some(b), Some(c)] = t.map(corner) {
            written += fill_triangle(frame, &a, &b, &c, |_| {});
        }
    }
    written
}
