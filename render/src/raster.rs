//! The binned hair rasteriser: every hair segment drawn tile by tile, eight
//! pixels at a time.
//!
//! The direct reference ([`crate::hair::draw_strands`]) walks each segment
//! over the whole frame; with hundreds of thousands of segments a few pixels
//! long, it spends its time on per-segment set-up and on cache misses in a
//! frame that does not fit in L1. Here (the sort-middle tiling of
//! hardware rasterisers, Molnar et al. 1994, "A sorting classification of
//! parallel rendering"; the binning of software rasterisers such as
//! Laine & Karras 2011, "High-performance software rasterization on GPUs"):
//!
//! 1. **Project** every vertex once ([`project`]): pixel position, view
//!    depth, width in pixels, colour; a vertex behind the near plane or
//!    with a non-finite position, width or colour is marked invalid (its
//!    two segments are skipped, nothing else is touched).
//! 2. **Count**: in back-to-front strand order, each segment's pixel bounds
//!    (the strip's reach around its ends, [`Segment::new`]) give the range
//!    of [`TILE`] x [`TILE`] tiles it touches; every tile counts it.
//! 3. **Prefix sum** of the counts: where each tile's list starts.
//! 4. **Fill**: the same segments in the same order append their index to
//!    every tile they touch, so each tile's list is in back-to-front order
//!    (blending is order dependent, and the order within a pixel is all
//!    that matters: the lists give every pixel its segments in exactly the
//!    reference's order).
//! 5. **Rasterise** tile by tile: the tile's colour and depth are copied
//!    into a tile-local buffer (16 KiB, in L1), every segment of its list
//!    is set up ([`Segment`]) and blended row by row
//!    ([`Segment::row_span`]) with the exact-area coverage of
//!    [`Segment::pixel`] (eight pixels per `f32x8` here, one at a time in
//!    [`crate::scalar::draw`]), and the tile is copied back.
//!
//! Each row of tiles is an independent task on the caller's
//! [`Executor`]: it writes only its own rows of the frame, so the bytes do
//! not depend on the thread count. The bins are sized once
//! ([`HairRaster::with_bin_capacity`]); when a frame's segments touch more
//! tiles than they hold, steps 2 to 5 run over consecutive runs of the
//! ordered segments (batches), each drawn completely before the next:
//! every pixel still sees its segments in the same order, so the result is
//! the same bytes as with one batch.
//!
//! The per-pixel arithmetic is [`Segment::pixel`], shared with the direct
//! reference and done without fused multiply-adds, so the SIMD path, its
//! scalar twin and the reference blend exactly the same values: their
//! frames agree bit for bit (the tests compare them on the default scene).

use super::hair::NEAR;
use super::line::{blend, ScreenVertex, Segment};
use super::sort::DepthOrder;
use super::{Camera, Framebuffer, Pixel, ShadedVertex};
use coif_base::tasks::{for_each_chunk_mut, Executor};
use glam::Vec3;
use wide::f32x8;

/// Tile side in pixels: a tile's colour and depth (4 x 32 x 32 floats,
/// 16 KiB) stay in L1 while its segments are drawn. 32 was the fastest of
/// 16, 32 and 64 on the default scene (`render/README.md`).
pub const TILE: usize = 32;
const TILE_PIXELS: usize = TILE * TILE;
const TILE_GROUPS: usize = TILE_PIXELS / 8;

/// Why a [`HairRaster`] cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// The frame is empty or has more than 65,535 tiles along a side.
    Size {
        /// Frame width in pixels.
        width: usize,
        /// Frame height in pixels.
        height: usize,
    },
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::Size { width, height } => write!(
                f,
                "frame {width} x {height}: expected 1 to {} pixels per side",
                TILE * u16::MAX as usize
            ),
        }
    }
}

impl std::error::Error for Error {}

/// What the last draw did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RasterStats {
    /// Segments with both ends valid (the count the reference returns).
    pub segments: usize,
    /// Tile-list entries written (segments times the tiles each touches).
    pub entries: usize,
    /// Batches the segments were drawn in (1 unless the bins overflowed).
    pub batches: usize,
}

/// The binned rasteriser's buffers, sized once: projected vertices and
/// segment tile ranges for `vertex_capacity` vertices, per-tile counts and
/// the tile lists. Drawing allocates nothing.
#[derive(Clone, Debug)]
pub struct HairRaster {
    width: usize,
    height: usize,
    tiles_x: usize,
    tiles_y: usize,
    /// Projected vertices; invalid ones have a NaN depth.
    pub(crate) screen: Vec<ScreenVertex>,
    /// Per segment (indexed by its first vertex): tiles `[x0, x1) x [y0, y1)`.
    rects: Vec<[u16; 4]>,
    /// Per tile: the start of its list in `bins` (tiles + 1 entries).
    starts: Vec<u32>,
    /// Per tile: the next free slot while filling.
    cursor: Vec<u32>,
    /// The tile lists, tile after tile: first vertex index of each segment.
    bins: Vec<u32>,
    stats: RasterStats,
}

impl HairRaster {
    /// Buffers for a `width x height` frame and up to `vertex_capacity`
    /// vertices, with room in the tile lists for two tiles per segment (the
    /// default scene averages 1.3 at [`TILE`] = 32).
    pub fn new(width: usize, height: usize, vertex_capacity: usize) -> Result<HairRaster, Error> {
        HairRaster::with_bin_capacity(width, height, vertex_capacity, 2 * vertex_capacity)
    }

    /// As [`HairRaster::new`], with room for `bin_capacity` tile-list
    /// entries (at least one per tile; fewer than the frame needs makes
    /// more batches, never a different picture).
    pub fn with_bin_capacity(
        width: usize,
        height: usize,
        vertex_capacity: usize,
        bin_capacity: usize,
    ) -> Result<HairRaster, Error> {
        let (tiles_x, tiles_y) = (width.div_ceil(TILE), height.div_ceil(TILE));
        if width == 0 || height == 0 || tiles_x > u16::MAX as usize || tiles_y > u16::MAX as usize {
            return Err(Error::Size { width, height });
        }
        let tiles = tiles_x * tiles_y;
        let bin_capacity = bin_capacity.max(tiles).min(u32::MAX as usize);
        Ok(HairRaster {
            width,
            height,
            tiles_x,
            tiles_y,
            screen: vec![ScreenVertex::default(); vertex_capacity],
            rects: vec![[0; 4]; vertex_capacity],
            starts: vec![0; tiles + 1],
            cursor: vec![0; tiles],
            bins: vec![0; bin_capacity],
            stats: RasterStats::default(),
        })
    }

    /// Frame size the buffers were built for.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Number of vertices the buffers hold.
    pub fn vertex_capacity(&self) -> usize {
        self.screen.len()
    }

    /// What the last draw did.
    pub fn stats(&self) -> RasterStats {
        self.stats
    }

    /// Draws the strands of `vertices` (`verts_per_strand` each, strand
    /// after strand, in the camera's space) in `order` (farthest first),
    /// every segment blended with `alpha = coverage * opacity` over the
    /// frame's colour, hidden where the frame's depth (head, ribbons) is
    /// nearer: the same pixels and bits as [`crate::hair::draw_strands`]
    /// on the same data. SIMD, eight pixels at a time; the scalar twin is
    /// [`crate::scalar::draw`]. Rows of tiles run as tasks on `executor`.
    ///
    /// Only the first [`HairRaster::vertex_capacity`] vertices are read;
    /// a frame of another size than the buffers' is left alone. Returns
    /// the number of segments with both ends valid.
    #[allow(clippy::too_many_arguments)]
    pub fn draw(
        &mut self,
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
        self.run(frame, &job, executor, draw_tile)
    }

    /// Steps 1 to 5 of the module doc, with `tile` drawing one tile's list
    /// (the SIMD or the scalar body).
    pub(crate) fn run(
        &mut self,
        frame: &mut Framebuffer,
        job: &Job<'_>,
        executor: &dyn Executor,
        tile: TileFn,
    ) -> usize {
        self.stats = RasterStats::default();
        let vps = job.verts_per_strand;
        if frame.width() != self.width || frame.height() != self.height || vps < 2 {
            return 0;
        }
        let n = job.vertices.len().min(self.screen.len());
        // 1. Project every vertex once.
        for (dst, v) in self.screen[..n].iter_mut().zip(&job.vertices[..n]) {
            *dst = project(job.camera, v);
        }
        let mut from = (0, 0);
        while from.0 < job.order.len() {
            // 2. Count, in order, until the bins would overflow.
            let to = self.count(job.order, vps, n, from);
            // 3. Prefix sum.
            let mut sum = 0u32;
            for (start, count) in self.starts.iter_mut().zip(&mut self.cursor) {
                *start = sum;
                sum += *count;
                *count = *start;
            }
            self.starts[self.cursor.len()] = sum;
            // 4. Fill the lists in the same order.
            self.fill(job.order, vps, n, from, to);
            // 5. Rasterise tile by tile, a row of tiles per task.
            self.rasterise(frame, job.opacity, executor, tile);
            self.stats.entries += sum as usize;
            self.stats.batches += 1;
            from = to;
        }
        self.stats.segments
    }

    /// Step 2: computes the tile range of the segments from position
    /// `from` (order index, segment in strand) on, counting them per tile
    /// in `cursor`, until the next would not fit in the bins; returns where
    /// it stopped.
    fn count(
        &mut self,
        order: &DepthOrder,
        vps: usize,
        n: usize,
        from: (usize, usize),
    ) -> (usize, usize) {
        self.cursor.fill(0);
        let room = self.bins.len();
        let mut used = 0usize;
        let (mut i, mut j) = from;
        while i < order.len() {
            let base = order.strand(i) * vps;
            if base + vps <= n {
                while j + 1 < vps {
                    let k = base + j;
                    let (a, b) = (&self.screen[k], &self.screen[k + 1]);
                    let mut rect = [0u16; 4];
                    if valid(a) && valid(b) {
                        if let Some(r) = self.tile_rect(a, b) {
                            let area = (r[1] - r[0]) as usize * (r[3] - r[2]) as usize;
                            if used + area > room {
                                return (i, j);
                            }
                            used += area;
                            for ty in r[2] as usize..r[3] as usize {
                                let row = &mut self.cursor[ty * self.tiles_x..][..self.tiles_x];
                                for c in &mut row[r[0] as usize..r[1] as usize] {
                                    *c += 1;
                                }
                            }
                            rect = r;
                        }
                        self.stats.segments += 1;
                    }
                    self.rects[k] = rect;
                    j += 1;
                }
            }
            i += 1;
            j = 0;
        }
        (i, j)
    }

    /// The tiles `[x0, x1) x [y0, y1)` segment `a -> b` can touch, or
    /// `None` when it draws nothing ([`Segment::new`]'s bounds).
    #[inline]
    fn tile_rect(&self, a: &ScreenVertex, b: &ScreenVertex) -> Option<[u16; 4]> {
        let [x0, x1, y0, y1] = Segment::pixel_bounds(a, b, self.width, self.height)?;
        Some([
            (x0 / TILE) as u16,
            ((x1 - 1) / TILE + 1) as u16,
            (y0 / TILE) as u16,
            ((y1 - 1) / TILE + 1) as u16,
        ])
    }

    /// Step 4: appends the segments from `from` to `to` to the lists of
    /// the tiles they touch, in order.
    fn fill(
        &mut self,
        order: &DepthOrder,
        vps: usize,
        n: usize,
        from: (usize, usize),
        to: (usize, usize),
    ) {
        let (mut i, mut j) = from;
        while (i, j) < to {
            let base = order.strand(i) * vps;
            if base + vps <= n {
                let last = if i == to.0 { to.1 } else { vps - 1 };
                while j < last {
                    let k = base + j;
                    let r = self.rects[k];
                    for ty in r[2] as usize..r[3] as usize {
                        for tx in r[0] as usize..r[1] as usize {
                            let c = &mut self.cursor[ty * self.tiles_x + tx];
                            self.bins[*c as usize] = k as u32;
                            *c += 1;
                        }
                    }
                    j += 1;
                }
            }
            i += 1;
            j = 0;
        }
    }

    /// Step 5: one task per row of tiles, each drawing its tiles left to
    /// right into its own rows of the frame.
    fn rasterise(
        &self,
        frame: &mut Framebuffer,
        opacity: f32,
        executor: &dyn Executor,
        tile: TileFn,
    ) {
        let width = self.width;
        for_each_chunk_mut(executor, &mut frame.pixels, TILE * width, &|ty, band| {
            let rows = band.len() / width;
            let mut buffer = TileBuffer::zeroed();
            for tx in 0..self.tiles_x {
                let t = ty * self.tiles_x + tx;
                let list = &self.bins[self.starts[t] as usize..self.starts[t + 1] as usize];
                if list.is_empty() {
                    continue;
                }
                let x0 = tx * TILE;
                let area = TileArea {
                    x0,
                    y0: ty * TILE,
                    columns: TILE.min(width - x0),
                    rows,
                    width,
                    height: self.height,
                };
                buffer.load(band, &area);
                tile(&mut buffer, &area, list, &self.screen, opacity);
                buffer.store(band, &area);
            }
        });
        debug_assert_eq!(self.tiles_y, frame.height().div_ceil(TILE));
    }
}

/// The draw call's inputs, shared by the SIMD path and its scalar twin.
pub(crate) struct Job<'a> {
    pub camera: &'a Camera,
    pub vertices: &'a [ShadedVertex],
    pub verts_per_strand: usize,
    pub order: &'a DepthOrder,
    pub opacity: f32,
}

/// Draws one tile's list into its buffer: `(buffer, area, list, screen
/// vertices, opacity)`.
pub(crate) type TileFn = fn(&mut TileBuffer, &TileArea, &[u32], &[ScreenVertex], f32);

/// Where a tile lies: its first pixel `(x0, y0)` in the frame, its size
/// (`columns x rows`, smaller than [`TILE`] at the frame's right and
/// bottom edges) and the frame's size.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TileArea {
    pub x0: usize,
    pub y0: usize,
    pub columns: usize,
    pub rows: usize,
    pub width: usize,
    pub height: usize,
}

impl TileArea {
    /// The frame rows `[lo, hi)` of the tile that `seg`'s bounds cross.
    #[inline(always)]
    pub fn rows(&self, seg: &Segment) -> (usize, usize) {
        let [_, _, y0, y1] = seg.bounds();
        (y0.max(self.y0), y1.min(self.y0 + self.rows))
    }

    /// A row span `[xa, xb)` ([`Segment::row_spans`], frame columns as
    /// whole floats in `[0, width]`) clipped to the tile, in tile columns;
    /// `None` when empty.
    #[inline(always)]
    pub fn clip(&self, xa: f32, xb: f32) -> Option<(usize, usize)> {
        self.clip_int(xa as i32, xb as i32)
    }

    /// [`TileArea::clip`] of a span already in whole numbers.
    #[inline(always)]
    pub fn clip_int(&self, xa: i32, xb: i32) -> Option<(usize, usize)> {
        let x0 = self.x0 as i32;
        let (xa, xb) = ((xa - x0).max(0), (xb - x0).min(self.columns as i32));
        (xa < xb).then_some((xa as usize, xb as usize))
    }
}

/// A tile's colour and depth as planes of `f32x8` (row-major, [`TILE`]
/// pixels per row); lanes outside the frame are never drawn.
#[derive(Clone, Copy)]
#[repr(C)]
pub(crate) struct TileBuffer {
    pub r: [f32x8; TILE_GROUPS],
    pub g: [f32x8; TILE_GROUPS],
    pub b: [f32x8; TILE_GROUPS],
    pub depth: [f32x8; TILE_GROUPS],
}

impl TileBuffer {
    /// A buffer of zeros (one per task, reused for its tiles).
    fn zeroed() -> TileBuffer {
        TileBuffer {
            r: [f32x8::ZERO; TILE_GROUPS],
            g: [f32x8::ZERO; TILE_GROUPS],
            b: [f32x8::ZERO; TILE_GROUPS],
            depth: [f32x8::ZERO; TILE_GROUPS],
        }
    }

    /// Copies the tile's pixels out of its band of rows.
    #[inline]
    fn load(&mut self, band: &[Pixel], area: &TileArea) {
        let planes: [&mut [f32]; 4] = [
            bytemuck::cast_slice_mut(&mut self.r),
            bytemuck::cast_slice_mut(&mut self.g),
            bytemuck::cast_slice_mut(&mut self.b),
            bytemuck::cast_slice_mut(&mut self.depth),
        ];
        let [r, g, b, depth] = planes;
        for y in 0..area.rows {
            let src = &band[y * area.width + area.x0..][..area.columns];
            let at = y * TILE;
            for (x, p) in src.iter().enumerate() {
                r[at + x] = p.color.x;
                g[at + x] = p.color.y;
                b[at + x] = p.color.z;
                depth[at + x] = p.depth;
            }
        }
    }

    /// Copies the tile's colours back into its band of rows.
    #[inline]
    fn store(&self, band: &mut [Pixel], area: &TileArea) {
        let r: &[f32] = bytemuck::cast_slice(&self.r);
        let g: &[f32] = bytemuck::cast_slice(&self.g);
        let b: &[f32] = bytemuck::cast_slice(&self.b);
        for y in 0..area.rows {
            let dst = &mut band[y * area.width + area.x0..][..area.columns];
            let at = y * TILE;
            for (x, p) in dst.iter_mut().enumerate() {
                p.color = Vec3::new(r[at + x], g[at + x], b[at + x]);
            }
        }
    }
}

/// Whether a projected vertex can be drawn ([`project`] marks the others
/// with a NaN depth).
#[inline(always)]
pub(crate) fn valid(v: &ScreenVertex) -> bool {
    !v.depth.is_nan()
}

/// Projects `v` as the reference does ([`Camera::project`] with
/// [`NEAR`], width `w f / z` pixels for focal length `f` in pixels):
/// `None` behind the near plane or for a non-finite position; also
/// invalid here (NaN depth) for a non-finite colour or a width that is
/// not finite and non-negative, so bad data never reaches a pixel.
#[inline]
pub fn project(camera: &Camera, v: &ShadedVertex) -> ScreenVertex {
    let invalid = ScreenVertex {
        depth: f32::NAN,
        ..ScreenVertex::default()
    };
    let Some(p) = camera.project(Vec3::from(v.position), NEAR) else {
        return invalid;
    };
    let color = Vec3::from(v.color);
    let width_px = v.width * camera.pixels_per_metre(1.0) / p.z;
    if !(color.is_finite() && width_px.is_finite() && width_px >= 0.0) {
        return invalid;
    }
    ScreenVertex {
        x: p.x,
        y: p.y,
        depth: p.z,
        width_px,
        color,
    }
}

/// Lane `l` holds `l as f32`.
const LANE_INDEX: f32x8 = f32x8::new([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);

/// Up to eight pixels of one segment gathered into lanes: their centres,
/// their index in the tile and the stored depths.
struct Lanes {
    xc: [f32; 8],
    yc: [f32; 8],
    index: [u32; 8],
    depth: [f32; 8],
    len: usize,
}

impl Lanes {
    /// 5d. The fragments of the gathered pixels, eight at a time; then the
    /// blend of each drawn lane, in lane order (the pixels are distinct).
    #[inline(always)]
    fn flush(&mut self, seg: &Segment, planes: [&mut [f32]; 3], opacity: f32) {
        let f = seg.pixel(
            f32x8::new(self.xc),
            f32x8::new(self.yc),
            f32x8::new(self.depth),
            opacity,
        );
        let live = f.mask & LANE_INDEX.simd_lt(f32x8::splat(self.len as f32));
        let mut bits = live.to_bitmask();
        self.len = 0;
        if bits == 0 {
            return;
        }
        let (alpha, r, g, b) = (
            f.alpha.to_array(),
            f.color.x.to_array(),
            f.color.y.to_array(),
            f.color.z.to_array(),
        );
        let [tr, tg, tb] = planes;
        while bits != 0 {
            let l = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let i = self.index[l] as usize;
            tr[i] = blend(tr[i], r[l], alpha[l]);
            tg[i] = blend(tg[i], g[l], alpha[l]);
            tb[i] = blend(tb[i], b[l], alpha[l]);
        }
    }
}

/// Step 5 for one tile, eight pixels at a time: every segment of `list`
/// in order; the pixels of its row spans are packed eight to a register
/// (a thin segment has a few pixels per row: rows of eight would leave
/// most lanes idle), their fragments computed together, the drawn ones
/// blended.
fn draw_tile(
    tile: &mut TileBuffer,
    area: &TileArea,
    list: &[u32],
    screen: &[ScreenVertex],
    opacity: f32,
) {
    let mut lanes = Lanes {
        xc: [0.0; 8],
        yc: [0.0; 8],
        index: [0; 8],
        depth: [0.0; 8],
        len: 0,
    };
    let TileBuffer { r, g, b, depth } = tile;
    let depth: &[f32] = bytemuck::cast_slice(&depth[..]);
    let r: &mut [f32] = bytemuck::cast_slice_mut(&mut r[..]);
    let g: &mut [f32] = bytemuck::cast_slice_mut(&mut g[..]);
    let b: &mut [f32] = bytemuck::cast_slice_mut(&mut b[..]);
    for &k in list {
        let k = k as usize;
        // 5a. Set up the segment (its list entry guarantees it draws).
        let Some(seg) = Segment::new(&screen[k], &screen[k + 1], area.width, area.height) else {
            continue;
        };
        // 5b. The row spans, eight rows at a time.
        let (lo, hi) = area.rows(&seg);
        let mut first_row = lo;
        while first_row < hi {
            let (xa8, xb8) = seg.row_spans(LANE_INDEX + f32x8::splat(first_row as f32));
            let (xa8, xb8) = (xa8.trunc_int().to_array(), xb8.trunc_int().to_array());
            for row in 0..(hi - first_row).min(8) {
                let Some((xa, xb)) = area.clip_int(xa8[row], xb8[row]) else {
                    continue;
                };
                let y = first_row + row;
                let at = (y - area.y0) * TILE;
                let yc = y as f32 + 0.5;
                let mut xc = (area.x0 + xa) as f32 + 0.5;
                // 5c. Each pixel of [xa, xb) into the next lane.
                for (x, &d) in depth[at..at + TILE].iter().enumerate().take(xb).skip(xa) {
                    let l = lanes.len & 7;
                    lanes.xc[l] = xc;
                    lanes.yc[l] = yc;
                    lanes.index[l] = (at + x) as u32;
                    lanes.depth[l] = d;
                    lanes.len = l + 1;
                    xc += 1.0;
                    if lanes.len == 8 {
                        lanes.flush(&seg, [&mut *r, &mut *g, &mut *b], opacity);
                    }
                }
            }
            first_row += 8;
        }
        if lanes.len > 0 {
            lanes.flush(&seg, [&mut *r, &mut *g, &mut *b], opacity);
        }
    }
}
