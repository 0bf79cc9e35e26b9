//! The binned hair rasteriser: every hair segment drawn tile by tile,
//! [`LANES`] segments (or pixels) at a time: 8 in an AVX2 build, 16 where
//! the build targets AVX-512 or has `lanes16` (`coif_base::lanes`). The
//! pixels are the same bits at both widths: every pixel's fragments are
//! computed alone and blended in list order.
//!
//! The direct reference ([`crate::hair::draw_strands`]) walks each segment
//! over the whole frame; with hundreds of thousands of segments a few pixels
//! long, it spends its time on per-segment set-up and on cache misses in a
//! frame that does not fit in L1. Here (the sort-middle tiling of
//! hardware rasterisers, Molnar et al. 1994, "A sorting classification of
//! parallel rendering"; the binning of software rasterisers such as
//! Laine & Karras 2011, "High-performance software rasterization on GPUs"):
//!
//! 1. **Project** every vertex once ([`project_simd`], a block per register;
//!    [`project`] in the scalar twin, the same bits): pixel position, view
//!    depth, width in pixels, colour; a vertex behind the near plane or
//!    with a non-finite position, width or colour is marked invalid (its
//!    two segments are skipped, nothing else is touched).
//! 2. **Cull and count**: a segment hidden behind an opaque sphere the
//!    caller drew before ([`HairRaster::set_occluders`],
//!    `crate::occlusion`) gets no tiles, which changes no pixel. In
//!    back-to-front strand order, each segment's pixel bounds
//!    (the strip's reach around its ends, [`Segment::new`]) give the range
//!    of [`TILE`] x [`TILE`] tiles it touches ([`LANES`] consecutive
//!    segments of a strand at once in the SIMD path); every tile counts it.
//! 3. **Prefix sum** of the counts: where each tile's list starts.
//! 4. **Fill**: the same segments in the same order append their index to
//!    every tile they touch, so each tile's list is in back-to-front order
//!    (blending is order dependent, and the order within a pixel is all
//!    that matters: the lists give every pixel its segments in exactly the
//!    reference's order).
//! 5. **Rasterise** tile by tile: the tile's colour and depth are copied
//!    into a tile-local buffer (64 KiB); its list's segments are set up
//!    [`LANES`] at a time ([`Segment::new_simd`]) and drawn one per lane
//!    (`draw_lanes`): each lane walks its segment's lines along the
//!    segment's major axis ([`Segment::walk`], [`Segment::lines`]) and
//!    each line's candidate pixels ([`Segment::band`]), pass `k`
//!    evaluating every lane's `k`-th candidate with the exact-area
//!    coverage of [`Segment::fragment`]; the drawn pixels are then
//!    depth-tested and blended segment by segment in list order (one
//!    pixel at a time in [`crate::scalar::draw`]), and the tile is copied
//!    back. The candidates contain every pixel the reference draws, so
//!    the bits are the reference's ([`crate::line::Walk`]).
//!
//! Every step runs as tasks on the caller's [`Executor`], and none of them
//! changes a bit with the number of tasks: projection in chunks of
//! vertices; the tile ranges in chunks of strands; counting and filling in
//! consecutive runs of the sorted strands, one row of per-tile counts per
//! task, whose prefix sum goes tile by tile and within a tile task by task,
//! so the lists are exactly those of one pass in order
//! (`HairRaster::bin_in_tasks`); rasterisation by runs of tiles of about
//! equal work, each tile's pixels read and written by its run's task alone. The bins are sized once
//! ([`HairRaster::with_bin_capacity`]); when a frame's segments touch more
//! tiles than they hold, steps 2 to 5 run over consecutive runs of the
//! ordered segments (batches), each drawn completely before the next:
//! every pixel still sees its segments in the same order, so the result is
//! the same bytes as with one batch.
//!
//! The per-pixel arithmetic is [`Segment::fragment`], shared with the direct
//! reference and done without fused multiply-adds, so the SIMD path, its
//! scalar twin and the reference blend exactly the same values: their
//! frames agree bit for bit (the tests compare them on the default scene).

use super::hair::NEAR;
use super::line::{ScreenVertex, Segment, SegmentsLanes, Walk};
use super::occlusion::OccluderCones;
use super::occlusion::MAX_OCCLUDERS;
use super::sort::DepthOrder;
use super::{Camera, Framebuffer, Pixel, ShadedVertex};
use coif_base::lanes::{planes_to_rows, rows_to_planes, F32Group, F32Lanes, I32Lanes, LANES};
use coif_base::tasks::{for_each_chunk_mut, DisjointMut, Executor};
use coif_base::Sphere;
use glam::Vec3;
use std::sync::atomic::{AtomicUsize, Ordering};
use wide::f32x4;

/// Vertices projected per task (a multiple of [`LANES`]): enough work per
/// task (about 0.1 ms) that a job system's cost per task stays small.
const PROJECT_CHUNK: usize = 16_384;

/// Most tasks a stage of the rasteriser makes (the task API's promise to
/// job systems with fixed-size pools).
const MAX_TASKS: usize = 64;

/// Most tasks binning makes: each has a row of per-tile counts, sized once.
const MAX_BIN_TASKS: usize = 16;

/// Fewest strands a tile-range or binning task takes.
const MIN_TASK_STRANDS: usize = 64;

/// Tile side in pixels: a tile's colour and depth are 4 x 64 x 64 floats
/// (64 KiB, in L2). 64 was faster than 32 on the default scene (1.12
/// instead of 1.27 tile entries per segment: `render/README.md`).
pub const TILE: usize = 64;
const TILE_PIXELS: usize = TILE * TILE;

/// Most pixels a [`HairRaster`] frame has (2^28: 16,384 x 16,384).
pub const MAX_RASTER_PIXELS: usize = 1 << 28;

/// Most vertices a [`HairRaster`] is sized for (2^28; its buffers hold
/// about 80 bytes per vertex).
pub const MAX_RASTER_VERTICES: usize = 1 << 28;

/// Why a [`HairRaster`] cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// The frame is empty, has more than 65,535 tiles along a side or more
    /// than [`MAX_RASTER_PIXELS`] pixels.
    Size {
        /// Frame width in pixels.
        width: usize,
        /// Frame height in pixels.
        height: usize,
    },
    /// More than [`MAX_RASTER_VERTICES`] vertices asked for.
    Capacity {
        /// The vertex capacity asked for.
        vertices: usize,
    },
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::Size { width, height } => write!(
                f,
                "frame {width} x {height}: expected 1 to {} pixels per side and at most \
                 {MAX_RASTER_PIXELS} pixels",
                TILE * u16::MAX as usize
            ),
            Error::Capacity { vertices } => write!(
                f,
                "{vertices} vertices: expected at most {MAX_RASTER_VERTICES}"
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
    /// Segments left out as hidden behind an occluder
    /// ([`HairRaster::set_occluders`]), of `segments`.
    pub hidden: usize,
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
    /// The projected `x`, `y`, depth and width as planes ([`LANES`]
    /// entries of padding), for the block-wide tile ranges of step 2.
    planes: [Vec<f32>; 4],
    /// Per segment (indexed by its first vertex): tiles `[x0, x1) x [y0, y1)`.
    rects: Vec<[u16; 4]>,
    /// Per tile: the start of its list in `bins` (tiles + 1 entries).
    starts: Vec<u32>,
    /// Per tile: the next free slot while filling (batched path).
    cursor: Vec<u32>,
    /// Per binning task, a row of `2 tiles + 1`: the task's count per tile,
    /// then its next and end slots per tile, and its total in the last slot.
    task_bins: Vec<u32>,
    /// The tile lists, tile after tile: first vertex index of each segment.
    bins: Vec<u32>,
    /// Opaque spheres already drawn into the frame, in the camera's space
    /// ([`HairRaster::set_occluders`]).
    occluders: [Sphere; MAX_OCCLUDERS],
    occluder_count: usize,
    /// The occluders' cones for the camera of the current draw.
    cones: OccluderCones,
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
        if width == 0
            || height == 0
            || tiles_x > u16::MAX as usize
            || tiles_y > u16::MAX as usize
            || width.saturating_mul(height) > MAX_RASTER_PIXELS
        {
            return Err(Error::Size { width, height });
        }
        if vertex_capacity > MAX_RASTER_VERTICES {
            return Err(Error::Capacity {
                vertices: vertex_capacity,
            });
        }
        let tiles = tiles_x * tiles_y;
        let bin_capacity = bin_capacity.max(tiles).min(u32::MAX as usize);
        Ok(HairRaster {
            width,
            height,
            tiles_x,
            tiles_y,
            screen: vec![ScreenVertex::default(); vertex_capacity],
            planes: std::array::from_fn(|_| vec![0.0; vertex_capacity + LANES]),
            rects: vec![[0; 4]; vertex_capacity],
            starts: vec![0; tiles + 1],
            cursor: vec![0; tiles],
            task_bins: vec![0; MAX_BIN_TASKS * (2 * tiles + 1)],
            bins: vec![0; bin_capacity],
            occluders: std::array::from_fn(|_| Sphere {
                center: Vec3::ZERO,
                radius: 0.0,
            }),
            occluder_count: 0,
            cones: OccluderCones::default(),
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

    /// Declares the opaque spheres the caller has drawn into the frame
    /// before the hair (their depth written, as
    /// [`crate::head::draw_spheres`] does, and no depth moved farther
    /// since), in the camera's space: the draws that follow leave out the
    /// segments these hide (`crate::occlusion`: both ends inside a
    /// sphere's screen disc shrunk by the segment's reach and a pixel,
    /// and behind its centre), which changes no pixel. At most
    /// [`MAX_OCCLUDERS`] are kept (returned); an empty slice turns culling
    /// off. Spheres that hold the eye or cover too few pixels are ignored
    /// at draw time.
    pub fn set_occluders(&mut self, spheres: &[Sphere]) -> usize {
        let n = spheres.len().min(MAX_OCCLUDERS);
        self.occluders[..n].clone_from_slice(&spheres[..n]);
        self.occluder_count = n;
        n
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
    /// on the same data. SIMD, [`LANES`] segments per register; the scalar twin is
    /// [`crate::scalar::draw`]. Every step runs as tasks on `executor`.
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
        self.run(frame, &job, executor, Path::Simd)
    }

    /// Steps 1 to 5 of the module doc, [`LANES`] lanes at a time
    /// ([`Path::Simd`]) or one at a time ([`Path::Scalar`], the twin).
    pub(crate) fn run(
        &mut self,
        frame: &mut Framebuffer,
        job: &Job<'_>,
        executor: &dyn Executor,
        path: Path,
    ) -> usize {
        let simd = matches!(path, Path::Simd);
        let tile: TileFn = if simd {
            draw_tile
        } else {
            crate::scalar::raster::draw_tile
        };
        self.stats = RasterStats::default();
        let vps = job.verts_per_strand;
        if frame.width() != self.width || frame.height() != self.height || vps < 2 {
            return 0;
        }
        let n = job.vertices.len().min(self.screen.len());
        self.cones = OccluderCones::new(job.camera, &self.occluders[..self.occluder_count]);
        // 1. Project every vertex once.
        self.project(job, n, executor, simd);
        // 2a. Every segment's tile range.
        self.stats.segments = self.segment_rects(job, n, executor, simd);
        if job.order.is_empty() {
            return 0;
        }
        // 2b-4. Count, prefix sum and fill in tasks over the order, when
        // the lists hold the whole frame.
        if self.bin_in_tasks(job.order, vps, n, executor) {
            // 5. Rasterise tile by tile, runs of tiles as tasks.
            self.rasterise(frame, job.opacity, executor, tile);
            self.stats.entries = self.starts[self.cursor.len()] as usize;
            self.stats.batches = 1;
            return self.stats.segments;
        }
        let mut from = (0, 0);
        while from.0 < job.order.len() {
            // 2b. Count, in order, until the bins would overflow.
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
            // 5. Rasterise tile by tile, runs of tiles as tasks.
            self.rasterise(frame, job.opacity, executor, tile);
            self.stats.entries += sum as usize;
            self.stats.batches += 1;
            from = to;
        }
        self.stats.segments
    }

    /// Step 1: `screen[k]` for every vertex `k < n`, and in the SIMD path
    /// the planes of `x`, `y`, depth and width that step 2a loads a block
    /// at a time. The SIMD path runs in tasks of at least [`PROJECT_CHUNK`]
    /// vertices (each vertex's projection depends on it alone, so the split
    /// changes no bit); the scalar twin projects one vertex at a time.
    fn project(&mut self, job: &Job<'_>, n: usize, executor: &dyn Executor, simd: bool) {
        if !simd {
            for (dst, v) in self.screen[..n].iter_mut().zip(&job.vertices[..n]) {
                *dst = project(job.camera, v);
            }
            return;
        }
        let chunk = PROJECT_CHUNK.max(n.div_ceil(MAX_TASKS).next_multiple_of(LANES));
        let vertices = &job.vertices[..n];
        // The planes hold `LANES` entries past the capacity, so every task
        // writes whole blocks of lanes.
        let planes = self.planes.each_mut().map(|p| DisjointMut::new(&mut p[..]));
        for_each_chunk_mut(executor, &mut self.screen[..n], chunk, &|t, out| {
            let (start, len) = (t * chunk, out.len().next_multiple_of(LANES));
            // SAFETY: task t alone writes entries [start, start + len) of
            // the planes: `chunk` is a multiple of `LANES`, so only the last
            // task's range is rounded up, into the padding.
            let [px, py, pd, pw] = planes.each_ref().map(|p| unsafe { p.range(start, len) });
            let chunks = out.chunks_mut(LANES).zip(vertices[start..].chunks(LANES));
            for (c, (dst, v)) in chunks.enumerate() {
                let p = project_planes_simd(job.camera, v);
                let at = LANES * c..LANES * c + LANES;
                px[at.clone()].copy_from_slice(p[0].as_array());
                py[at.clone()].copy_from_slice(p[1].as_array());
                pd[at.clone()].copy_from_slice(p[2].as_array());
                pw[at].copy_from_slice(p[3].as_array());
                dst.copy_from_slice(&screen_rows(p)[..dst.len()]);
            }
        });
    }

    /// Step 2a: `rects[k]` of every segment `k -> k + 1` of the strands
    /// an order can draw (the first `min(order, n / vps)`; the
    /// strand's last vertex gets an empty range), [`LANES`] consecutive
    /// segments of a strand at once in the SIMD path, in tasks of whole
    /// strands. Returns the number of segments with both ends valid.
    fn segment_rects(
        &mut self,
        job: &Job<'_>,
        n: usize,
        executor: &dyn Executor,
        simd: bool,
    ) -> usize {
        let vps = job.verts_per_strand;
        let strands = job.order.len().min(n / vps);
        let per_task = MIN_TASK_STRANDS.max(strands.div_ceil(MAX_TASKS));
        let drawn_total = AtomicUsize::new(0);
        let hidden_total = AtomicUsize::new(0);
        let mut rects = std::mem::take(&mut self.rects);
        let this = &*self;
        for_each_chunk_mut(
            executor,
            &mut rects[..strands * vps],
            per_task * vps,
            &|t, out| {
                let first = t * per_task * vps;
                let (mut drawn_here, mut hidden_here) = (0, 0);
                for (s, strand) in out.chunks_mut(vps).enumerate() {
                    let base = first + s * vps;
                    let segments = &mut strand[..vps - 1];
                    if simd {
                        for (c, rects8) in segments.chunks_mut(LANES).enumerate() {
                            let r = this.tile_rects_simd(base + LANES * c);
                            let lanes = (1u32 << rects8.len()) - 1;
                            drawn_here += (r.drawn & lanes).count_ones() as usize;
                            hidden_here += (r.hidden & lanes).count_ones() as usize;
                            for (l, rect) in rects8.iter_mut().enumerate() {
                                *rect = r.rect(l);
                            }
                        }
                    } else {
                        for (j, rect) in segments.iter_mut().enumerate() {
                            let k = base + j;
                            let (a, b) = (&this.screen[k], &this.screen[k + 1]);
                            let drawn = valid(a) && valid(b);
                            let hidden = drawn && this.cones.any() && this.cones.hides(a, b);
                            drawn_here += drawn as usize;
                            hidden_here += hidden as usize;
                            *rect = (drawn && !hidden)
                                .then(|| this.tile_rect(a, b))
                                .flatten()
                                .unwrap_or_default();
                        }
                    }
                    strand[vps - 1] = [0; 4];
                }
                drawn_total.fetch_add(drawn_here, Ordering::Relaxed);
                hidden_total.fetch_add(hidden_here, Ordering::Relaxed);
            },
        );
        self.rects = rects;
        self.stats.hidden = hidden_total.into_inner();
        drawn_total.into_inner()
    }

    /// Steps 2b to 4 in tasks: the order is cut into consecutive runs of
    /// strands, one per task. Each task counts its segments per tile in its
    /// own row of `task_bins` (2b); the prefix sum (3) goes tile by tile
    /// and, within a tile, task by task, so task `c`'s entries for tile `t`
    /// follow every earlier task's; each task then fills its slots (4). The
    /// lists come out exactly as one pass over the order would write them,
    /// whatever the number of tasks. Returns `false` (and does nothing
    /// else) when the frame needs more entries than the lists hold: the
    /// caller then draws in batches.
    fn bin_in_tasks(
        &mut self,
        order: &DepthOrder,
        vps: usize,
        n: usize,
        executor: &dyn Executor,
    ) -> bool {
        let tiles = self.cursor.len();
        let row = 2 * tiles + 1;
        let tasks = executor
            .threads()
            .clamp(1, MAX_BIN_TASKS)
            .min(order.len().div_ceil(MIN_TASK_STRANDS))
            .max(1);
        let per_task = order.len().div_ceil(tasks);
        let tiles_x = self.tiles_x;
        let rects = &self.rects[..];
        let runs = |t: usize| (t * per_task, ((t + 1) * per_task).min(order.len()));
        let task_bins = &mut self.task_bins[..tasks * row];
        // 2b. Count per tile, and the task's total in its row's last slot.
        for_each_chunk_mut(executor, task_bins, row, &|t, counts| {
            counts.fill(0);
            let mut total = 0u32;
            for_segments(order, rects, vps, n, runs(t), |_, r| {
                let area = for_each_tile(r, tiles_x, |tile| counts[tile] += 1);
                total = total.saturating_add(area);
            });
            counts[2 * tiles] = total;
        });
        let total: u64 = task_bins.chunks(row).map(|r| r[2 * tiles] as u64).sum();
        if total > self.bins.len() as u64 {
            return false;
        }
        // 3. Prefix sum: the row's first half becomes each task's next
        // slot per tile, the second half the end of its slots.
        let mut sum = 0u32;
        for t in 0..tiles {
            self.starts[t] = sum;
            for counts in task_bins.chunks_mut(row) {
                let count = counts[t];
                counts[t] = sum;
                sum += count;
                counts[tiles + t] = sum;
            }
        }
        self.starts[tiles] = sum;
        // 4. Fill: every task writes only slots in [next, end) of its own
        // row, ranges that the prefix sum made disjoint.
        let bins = DisjointMut::new(&mut self.bins);
        for_each_chunk_mut(executor, task_bins, row, &|t, slots| {
            let (next, end) = slots.split_at_mut(tiles);
            let mut put = |tile: usize, k: usize| {
                let slot = next[tile];
                if slot < end[tile] {
                    // SAFETY: [next, end) of this task and tile overlaps no
                    // other task's or tile's range.
                    unsafe { bins.set(slot as usize, k as u32) };
                    next[tile] = slot + 1;
                }
            };
            for_segments(order, rects, vps, n, runs(t), |k, r| {
                for_each_tile(r, tiles_x, |tile| put(tile, k));
            });
        });
        true
    }

    /// Step 2b when the lists overflow: counts the segments from position
    /// `from` (order index, segment in strand) on per tile in `cursor`,
    /// until the next would not fit in the bins; returns where it stopped.
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
                    let r = self.rects[base + j];
                    let area = (r[1] - r[0]) as usize * (r[3] - r[2]) as usize;
                    if used + area > room {
                        return (i, j);
                    }
                    used += area;
                    for_each_tile(r, self.tiles_x, |tile| self.cursor[tile] += 1);
                    j += 1;
                }
            }
            i += 1;
            j = 0;
        }
        (i, j)
    }

    /// [`HairRaster::tile_rect`] of the [`LANES`] segments from vertex `k` on
    /// (`k + l -> k + l + 1` in lane `l`; lanes past the strand's end are
    /// read from the planes' padding and ignored by the caller), computed
    /// with the same operations in the same order as
    /// [`Segment::pixel_bounds`].
    #[inline]
    fn tile_rects_simd(&self, k: usize) -> TileRects {
        let load = |p: &Vec<f32>, at: usize| F32Lanes::new(p[at..at + LANES].try_into().unwrap());
        let [px, py, pd, pw] = &self.planes;
        let (ax, ay, aw) = (load(px, k), load(py, k), load(pw, k));
        let (bx, by, bw) = (load(px, k + 1), load(py, k + 1), load(pw, k + 1));
        let (az, bz) = (load(pd, k), load(pd, k + 1));
        let drawn = !(az.is_nan() | bz.is_nan());
        // 0. Hidden behind an occluder (`crate::occlusion`; NaN lanes
        // never are).
        let hidden = if self.cones.any() {
            self.cones.hides_lanes([ax, ay, az, aw], [bx, by, bz, bw]) & drawn
        } else {
            F32Lanes::ZERO
        };
        // 1. Length: not NaN, above 1e-12 and finite.
        let (ex, ey) = (bx - ax, by - ay);
        let len2 = ex * ex + ey * ey;
        let long = len2.simd_gt(F32Lanes::splat(1e-12)) & len2.is_finite();
        // 2. The float bounds (`float_bounds`).
        let reach = F32Lanes::splat(0.5) * aw.fast_max(bw) + F32Lanes::splat(0.75);
        let (w, h) = (self.width as f32, self.height as f32);
        let x0 = (ax.fast_min(bx) - reach).floor().fast_max(F32Lanes::ZERO);
        let x1 = (ax.fast_max(bx) + reach)
            .ceil()
            .fast_min(F32Lanes::splat(w));
        let y0 = (ay.fast_min(by) - reach).floor().fast_max(F32Lanes::ZERO);
        let y1 = (ay.fast_max(by) + reach)
            .ceil()
            .fast_min(F32Lanes::splat(h));
        let some = long & x0.simd_lt(x1) & y0.simd_lt(y1);
        // 3. Tiles: whole pixel numbers in [0, 2^26] divided by a power of two.
        let inv = F32Lanes::splat(1.0 / TILE as f32);
        let one = F32Lanes::splat(1.0);
        let tiles = [
            (x0 * inv).floor(),
            ((x1 - one) * inv).floor() + one,
            (y0 * inv).floor(),
            ((y1 - one) * inv).floor() + one,
        ]
        .map(|v| {
            (some & drawn & !hidden)
                .select(v, F32Lanes::ZERO)
                .trunc_int()
        });
        // Tile numbers below 65,536 ([`HairRaster::with_bin_capacity`]).
        let pack =
            |lo: I32Lanes, hi: I32Lanes| bytemuck::cast::<I32Lanes, [u32; LANES]>(lo | (hi << 16));
        TileRects {
            drawn: drawn.to_bitmask(),
            hidden: hidden.to_bitmask(),
            packed: [pack(tiles[0], tiles[1]), pack(tiles[2], tiles[3])],
        }
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
                    let (cursor, bins) = (&mut self.cursor, &mut self.bins);
                    for_each_tile(self.rects[k], self.tiles_x, |tile| {
                        bins[cursor[tile] as usize] = k as u32;
                        cursor[tile] += 1;
                    });
                    j += 1;
                }
            }
            i += 1;
            j = 0;
        }
    }

    /// Step 5: the tiles in row-major order cut into runs of about equal
    /// list entries, one task per run (at most four per thread and
    /// [`MAX_TASKS`]): each tile belongs to one task, which alone reads and
    /// writes its pixels, so the bytes do not depend on the split.
    fn rasterise(
        &self,
        frame: &mut Framebuffer,
        opacity: f32,
        executor: &dyn Executor,
        tile: TileFn,
    ) {
        debug_assert_eq!(self.tiles_y, frame.height().div_ceil(TILE));
        let (width, tiles) = (self.width, self.tiles_x * self.tiles_y);
        let total = self.starts[tiles] as u64;
        let tasks = (4 * executor.threads()).clamp(1, MAX_TASKS);
        // Task c starts at the first tile whose list starts at or after
        // c / tasks of all entries.
        let first_tile = |c: usize| {
            let at = (total * c as u64).div_ceil(tasks as u64);
            self.starts[..tiles].partition_point(|&s| (s as u64) < at)
        };
        let pixels = DisjointMut::new(&mut frame.pixels);
        executor.run(tasks, &|c| {
            let mut buffer = TileBuffer::zeroed();
            let end = if c + 1 == tasks {
                tiles
            } else {
                first_tile(c + 1)
            };
            for t in first_tile(c)..end {
                let list = &self.bins[self.starts[t] as usize..self.starts[t + 1] as usize];
                if list.is_empty() {
                    continue;
                }
                let (tx, ty) = (t % self.tiles_x, t / self.tiles_x);
                let (x0, y0) = (tx * TILE, ty * TILE);
                let area = TileArea {
                    x0,
                    y0,
                    columns: TILE.min(width - x0),
                    rows: TILE.min(self.height - y0),
                    width,
                    height: self.height,
                };
                // SAFETY: tile t is in task c's run only (the runs cut the
                // tiles' sequence), and a tile's pixels are no other tile's.
                unsafe { buffer.load(&pixels, &area) };
                tile(&mut buffer, &area, list, &self.screen, opacity);
                // SAFETY: as above.
                unsafe { buffer.store(&pixels, &area) };
            }
        });
    }
}

/// Calls `f(tile)` for every tile of the range `[x0, x1) x [y0, y1)` in
/// row-major order (`tiles_x` tiles per row), a one-tile range (four
/// segments in five) without the loops; returns the number of tiles.
#[inline(always)]
pub(crate) fn for_each_tile(r: [u16; 4], tiles_x: usize, mut f: impl FnMut(usize)) -> u32 {
    let [x0, x1, y0, y1] = r.map(usize::from);
    let area = (x1 - x0) * (y1 - y0);
    if area == 1 {
        f(y0 * tiles_x + x0);
    } else {
        for ty in y0..y1 {
            for tx in x0..x1 {
                f(ty * tiles_x + tx);
            }
        }
    }
    area as u32
}

/// Calls `f(first vertex, tile range)` for every segment of the strands at
/// order positions `[i0, i1)` that the first `n` vertices hold, in order.
#[inline(always)]
fn for_segments(
    order: &DepthOrder,
    rects: &[[u16; 4]],
    vps: usize,
    n: usize,
    (i0, i1): (usize, usize),
    mut f: impl FnMut(usize, [u16; 4]),
) {
    for i in i0..i1 {
        let base = order.strand(i) * vps;
        if base + vps <= n {
            for (j, &r) in rects[base..base + vps - 1].iter().enumerate() {
                f(base + j, r);
            }
        }
    }
}

/// Which body [`HairRaster::run`] uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Path {
    /// [`LANES`] lanes at a time: [`project_simd`], a block of tile ranges at a time,
    /// [`draw_tile`].
    Simd,
    /// One at a time: [`project`], [`HairRaster::tile_rect`], the scalar tile body.
    Scalar,
}

/// Eight segments' tile ranges ([`HairRaster::tile_rects_simd`]).
#[derive(Clone, Copy, Debug, Default)]
struct TileRects {
    /// Lanes whose two ends are valid.
    drawn: u32,
    /// Lanes (of `drawn`) hidden behind an occluder, given no tile.
    hidden: u32,
    /// Per lane `x0 | x1 << 16` and `y0 | y1 << 16` of its tiles
    /// `[x0, x1) x [y0, y1)`; zero (no tile) when the lane draws nothing.
    packed: [[u32; LANES]; 2],
}

impl TileRects {
    /// Lane `l`'s tiles as `[x0, x1, y0, y1]`.
    #[inline(always)]
    fn rect(&self, l: usize) -> [u16; 4] {
        let [x, y] = [self.packed[0][l], self.packed[1][l]];
        [x as u16, (x >> 16) as u16, y as u16, (y >> 16) as u16]
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
    /// The frame rows or columns `[lo, hi)` of the tile that `seg`
    /// walks with `walk`, as whole floats: those its bounds cross, and
    /// for a band walk only those where a drawn pixel centre can lie
    /// ([`Segment::lines`]).
    #[inline(always)]
    pub fn lines(&self, seg: &Segment, walk: Walk) -> (f32, f32) {
        let columns = walk == Walk::BandColumns;
        let [x0, x1, y0, y1] = seg.float_bounds();
        let (lo, hi, start, len) = if columns {
            (x0, x1, self.x0, self.columns)
        } else {
            (y0, y1, self.y0, self.rows)
        };
        let (lo, hi) = (lo.max(start as f32), hi.min((start + len) as f32));
        if walk == Walk::Rows {
            return (lo, hi);
        }
        let (near_lo, near_hi) = seg.lines(columns);
        (lo.max(near_lo), hi.min(near_hi))
    }

    /// The tile's frame columns (`columns` false) or rows `[lo, hi)`
    /// across those lines, as floats.
    #[inline(always)]
    pub fn cross(&self, columns: bool) -> (f32, f32) {
        let (lo, len) = if columns {
            (self.y0, self.rows)
        } else {
            (self.x0, self.columns)
        };
        (lo as f32, (lo + len) as f32)
    }

    /// Row `y` of the tile (`0..rows`) in the frame's pixels.
    ///
    /// # Safety
    ///
    /// As [`DisjointMut::range`]: nobody else touches the row meanwhile.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    unsafe fn row<'p>(&self, pixels: &'p DisjointMut<'_, Pixel>, y: usize) -> &'p mut [Pixel] {
        // SAFETY: the caller's promise.
        unsafe { pixels.range((self.y0 + y) * self.width + self.x0, self.columns) }
    }
}

/// A tile's pixels, row-major ([`TILE`] pixels per row), each as one
/// `f32x4` (red, green, blue, depth): a fragment's depth test and blend
/// read and write one 16-byte slot. Slots outside the frame are never
/// drawn.
#[derive(Clone, Copy)]
#[repr(C)]
pub(crate) struct TileBuffer {
    pub pixels: [f32x4; TILE_PIXELS],
    /// Whether any pixel of the tile holds an opaque depth (not
    /// `+inf`); without one, every fragment passes the depth test (a
    /// segment's depth is finite) and the tile body skips it.
    pub opaque: bool,
}

impl TileBuffer {
    /// A buffer of zeros (one per task, reused for its tiles).
    fn zeroed() -> TileBuffer {
        TileBuffer {
            pixels: [f32x4::ZERO; TILE_PIXELS],
            opaque: false,
        }
    }

    /// 5d. The depth test (when `DEPTH`: skipped for a tile without
    /// opaque depth) and the blend of one fragment at index `i` (taken
    /// modulo the tile's size): each colour channel `c + alpha (colour -
    /// c)` ([`crate::line::blend`]'s operations, lane by lane, so the same
    /// bits), the depth kept.
    #[inline(always)]
    pub fn blend<const DEPTH: bool>(&mut self, i: usize, z: f32, alpha: f32, [r, g, b]: [f32; 3]) {
        let p = &mut self.pixels[i % TILE_PIXELS];
        let depth = p.to_array()[3];
        if !DEPTH || z < depth {
            let colour = f32x4::new([r, g, b, depth]);
            let keep = f32x4::new([0.0, 0.0, 0.0, f32::from_bits(u32::MAX)]);
            *p = keep.select(*p, *p + (colour - *p) * f32x4::splat(alpha));
        }
    }

    /// Copies the tile's pixels out of the frame.
    ///
    /// # Safety
    ///
    /// No other task reads or writes this tile's pixels meanwhile.
    #[inline]
    unsafe fn load(&mut self, pixels: &DisjointMut<'_, Pixel>, area: &TileArea) {
        let mut opaque = false;
        for y in 0..area.rows {
            // SAFETY: the tile's pixels are this task's alone (the caller).
            let src = unsafe { area.row(pixels, y) };
            let at = y * TILE;
            for (dst, p) in self.pixels[at..at + src.len()].iter_mut().zip(src.iter()) {
                *dst = f32x4::new([p.color.x, p.color.y, p.color.z, p.depth]);
                opaque |= p.depth != f32::INFINITY;
            }
        }
        self.opaque = opaque;
    }

    /// Copies the tile's colours back into the frame.
    ///
    /// # Safety
    ///
    /// As [`TileBuffer::load`].
    #[inline]
    unsafe fn store(&self, pixels: &DisjointMut<'_, Pixel>, area: &TileArea) {
        for y in 0..area.rows {
            // SAFETY: as in `load`.
            let dst = unsafe { area.row(pixels, y) };
            let at = y * TILE;
            for (p, src) in dst.iter_mut().zip(&self.pixels[at..]) {
                let [r, g, b, _] = src.to_array();
                p.color = Vec3::new(r, g, b);
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

/// [`project`] of up to [`LANES`] vertices at once (lanes past
/// `vertices.len()` come back invalid), with the operations of
/// [`Camera::project`] in the same order (no fused multiply-add): the
/// same bits as [`project`] vertex by vertex.
pub fn project_simd(camera: &Camera, vertices: &[ShadedVertex]) -> [ScreenVertex; LANES] {
    screen_rows(project_planes_simd(camera, vertices))
}

/// [`project_simd`] as planes: pixel `x`, `y`, view depth, width in pixels,
/// red, green, blue; an invalid lane holds a NaN depth and zeros
/// elsewhere (as the invalid [`ScreenVertex`] of [`project`]). The
/// vertices (eight floats each) come into lanes by one 8 x 8 transpose per
/// group of eight lanes.
#[inline(always)]
fn project_planes_simd(camera: &Camera, vertices: &[ShadedVertex]) -> [F32Lanes; 7] {
    let (eye, forward, right, down, focal) = camera.basis();
    let n = vertices.len().min(LANES);
    let rows: [F32Group; LANES] = if n == LANES {
        let rows: &[[f32; 8]] = bytemuck::cast_slice(&vertices[..LANES]);
        std::array::from_fn(|l| F32Group::new(rows[l]))
    } else {
        std::array::from_fn(|l| match vertices.get(l) {
            Some(v) => F32Group::new(bytemuck::cast(*v)),
            None => F32Group::ZERO,
        })
    };
    let [x, y, z, width, r, g, b, _] = rows_to_planes(rows);
    let s = F32Lanes::splat;
    // 1. Depth along the view direction, as `Vec3::dot`: (x + y) + z.
    let (dx, dy, dz) = (x - s(eye.x), y - s(eye.y), z - s(eye.z));
    let dot = |e: Vec3| (dx * s(e.x) + dy * s(e.y)) + dz * s(e.z);
    let depth = dot(forward);
    let front = depth.simd_gt(s(NEAR));
    // 2. Pixel position.
    let k = s(focal) / depth;
    let px = s(0.5 * camera.width() as f32) + k * dot(right);
    let py = s(0.5 * camera.height() as f32) + k * dot(down);
    // 3. Width in pixels, `w f / z` (`pixels_per_metre(1.0)` is `f`).
    let width_px = (width * s(focal)) / depth;
    let ok = front
        & px.is_finite()
        & py.is_finite()
        & r.is_finite()
        & g.is_finite()
        & b.is_finite()
        & width_px.is_finite()
        & width_px.simd_ge(F32Lanes::ZERO)
        & lane_index().simd_lt(s(n as f32));
    let zero = F32Lanes::ZERO;
    [
        ok.select(px, zero),
        ok.select(py, zero),
        ok.select(depth, s(f32::NAN)),
        ok.select(width_px, zero),
        ok.select(r, zero),
        ok.select(g, zero),
        ok.select(b, zero),
    ]
}

/// The [`ScreenVertex`]es of [`project_planes_simd`]'s planes (an 8 x 8
/// transpose back per group of eight lanes).
#[inline(always)]
fn screen_rows(planes: [F32Lanes; 7]) -> [ScreenVertex; LANES] {
    let [x, y, d, w, r, g, b] = planes;
    let rows = planes_to_rows([x, y, d, w, r, g, b, F32Lanes::ZERO]);
    rows.map(|row| {
        let a = row.to_array();
        ScreenVertex {
            x: a[0],
            y: a[1],
            depth: a[2],
            width_px: a[3],
            color: Vec3::new(a[4], a[5], a[6]),
        }
    })
}

/// Lane `l` holds `l as f32`.
#[inline(always)]
fn lane_index() -> F32Lanes {
    F32Lanes::new(std::array::from_fn(|l| l as f32))
}

/// Step 5 for one tile: the segments of `list` [`LANES`] at a time, set up
/// at once ([`Segment::new_simd`]) and drawn one per lane
/// ([`draw_lanes`]: each lane walks its own segment's lines along its
/// major axis and each line's candidates, one candidate per pass, then
/// the block's fragments are blended segment by segment in list
/// order). A block of segments that needs more passes, or holds one with
/// an end beyond [`crate::line::BAND_REACH`], are walked one by one
/// ([`draw_lines`]: [`LANES`] lines of a segment per register). The pixels
/// of one segment are distinct, so their order changes no bit.
pub(crate) fn draw_tile(
    tile: &mut TileBuffer,
    area: &TileArea,
    list: &[u32],
    screen: &[ScreenVertex],
    opacity: f32,
) {
    let opaque = tile.opaque;
    let mut passes = [Pass::default(); MAX_PASSES];
    for (c, first) in list.chunks(LANES).enumerate() {
        // The next chunk's ends, from memory (the lists visit strands
        // back to front, far apart in `screen`), while this one draws.
        for &k in list.iter().skip(LANES * c + LANES).take(LANES) {
            prefetch(screen.get(k as usize + 1));
        }
        // 5a. Set up a block of segments at once (the bits of `Segment::new`).
        let segments = Segment::new_simd(screen, first, area.width, area.height);
        if segments.near() {
            let done = match opaque {
                false => draw_lanes::<false>(&segments, area, tile, opacity, &mut passes),
                true => draw_lanes::<true>(&segments, area, tile, opacity, &mut passes),
            };
            if done {
                continue;
            }
        }
        for l in 0..first.len() {
            let Some(seg) = segments.lane(l) else {
                continue;
            };
            let (p, o) = (&mut *tile, opacity);
            match (seg.walk(), opaque) {
                (Walk::BandRows, false) => draw_lines::<BAND_ROWS, false>(&seg, area, p, o),
                (Walk::BandRows, true) => draw_lines::<BAND_ROWS, true>(&seg, area, p, o),
                (Walk::BandColumns, false) => draw_lines::<BAND_COLUMNS, false>(&seg, area, p, o),
                (Walk::BandColumns, true) => draw_lines::<BAND_COLUMNS, true>(&seg, area, p, o),
                (Walk::Rows, _) => draw_lines::<ROWS, true>(&seg, area, p, o),
            }
        }
    }
}

/// Asks for the cache lines of `v` and the vertex before it (a hint:
/// nothing is read, nothing can fault; no-op off x86-64).
#[inline(always)]
fn prefetch(v: Option<&ScreenVertex>) {
    #[cfg(target_arch = "x86_64")]
    if let Some(v) = v {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = v as *const ScreenVertex as *const i8;
        // SAFETY: prefetching is a hint; the address is a live reference.
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(p);
            _mm_prefetch::<_MM_HINT_T0>(p.wrapping_sub(std::mem::size_of::<ScreenVertex>()));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = v;
}

/// [`Walk`] as a const parameter of [`draw_lines`].
const ROWS: u8 = 0;
const BAND_ROWS: u8 = 1;
const BAND_COLUMNS: u8 = 2;

/// 5b-5d for one segment in one tile, its rows (or columns for
/// `WALK` = [`BAND_COLUMNS`]) [`LANES`] at a time, with the depth test when
/// `DEPTH`.
#[inline(always)]
fn draw_lines<const WALK: u8, const DEPTH: bool>(
    seg: &Segment,
    area: &TileArea,
    tile: &mut TileBuffer,
    opacity: f32,
) {
    const { assert!(WALK <= BAND_COLUMNS) };
    let columns = WALK == BAND_COLUMNS;
    let s = F32Lanes::splat;
    let walk = match WALK {
        ROWS => Walk::Rows,
        BAND_ROWS => Walk::BandRows,
        _ => Walk::BandColumns,
    };
    let (lo, hi) = area.lines(seg, walk);
    let (cross_lo, cross_hi) = area.cross(columns);
    // Tile index of pixel (x, y): (y - y0) TILE + (x - x0), exact in f32.
    let (x0, y0) = (area.x0 as f32, area.y0 as f32);
    let mut first = lo;
    while first < hi {
        // 5b. The candidates of a block of rows (columns), clipped to the tile.
        let line = lane_index() + s(first);
        let (ca, cb) = match WALK {
            ROWS => seg.row_spans(line),
            _ => seg.band(line, columns),
        };
        let ca = ca.fast_max(s(cross_lo));
        let cb = line.simd_lt(s(hi)).select(cb.fast_min(s(cross_hi)), s(0.0));
        let centre = line + s(0.5);
        let mut c = ca;
        let mut live = c.simd_lt(cb).to_bitmask();
        while live != 0 {
            // 5c. The c-th pixel of every live span.
            let (xc, yc) = if columns {
                (centre, c + s(0.5))
            } else {
                (c + s(0.5), centre)
            };
            let f = seg.fragment(xc, yc, opacity);
            let mut bits = live & f.mask.to_bitmask();
            if bits != 0 {
                let (x, y) = if columns { (line, c) } else { (c, line) };
                let index = ((y - s(y0)) * s(TILE as f32) + (x - s(x0)))
                    .trunc_int()
                    .to_array();
                let (z, alpha) = (f.depth.to_array(), f.alpha.to_array());
                let (r, g, b) = (
                    f.color.x.to_array(),
                    f.color.y.to_array(),
                    f.color.z.to_array(),
                );
                // 5d. Depth test and blend of the drawn lanes.
                while bits != 0 {
                    let l = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    tile.blend::<DEPTH>(index[l] as usize, z[l], alpha[l], [r[l], g[l], b[l]]);
                }
            }
            c += s(1.0);
            live = c.simd_lt(cb).to_bitmask();
        }
        first += LANES as f32;
    }
}

/// The most passes [`draw_lanes`] holds before it gives the block's
/// segments back to the one-segment walk (a thin hair needs about 20).
const MAX_PASSES: usize = 32;

/// One pass of [`draw_lanes`]: the fragment of every lane's candidate
/// pixel (tile index, depth, alpha, colour).
#[derive(Clone, Copy, Default)]
struct Pass {
    index: [i32; LANES],
    z: [f32; LANES],
    alpha: [f32; LANES],
    color: [[f32; LANES]; 3],
}

/// 5b-5d for [`LANES`] segments at once, one per lane (all band walks):
/// each lane walks its own segment's lines (rows, or columns where
/// `|e_x| > |e_y|`) and each line's candidates ([`SegmentsLanes::band`],
/// clipped to the tile as in [`draw_lines`]), one candidate per pass
/// ([`SegmentsLanes::fragment`]), the constants staying in their lanes. The
/// passes are kept, then blended segment by segment in list order (each
/// segment's pixels are distinct: their order changes no bit). Returns
/// false, having blended nothing, when the segments need more than
/// [`MAX_PASSES`] passes (wide or long segments: the caller walks them
/// one by one).
#[inline(always)]
fn draw_lanes<const DEPTH: bool>(
    segments: &SegmentsLanes,
    area: &TileArea,
    tile: &mut TileBuffer,
    opacity: f32,
    passes: &mut [Pass; MAX_PASSES],
) -> bool {
    let s = F32Lanes::splat;
    let columns = segments.columns();
    // The tile's lines and cross range per lane (`TileArea::lines`,
    // `TileArea::cross`); lanes without a segment get no line.
    let [x0, x1, y0, y1] = segments.float_bounds();
    let pick = |c: F32Lanes, r: F32Lanes| columns.select(c, r);
    let (tx, ty) = (area.x0 as f32, area.y0 as f32);
    let (tx1, ty1) = (
        (area.x0 + area.columns) as f32,
        (area.y0 + area.rows) as f32,
    );
    let bit = I32Lanes::new(std::array::from_fn(|l| 1 << l));
    let drawn = (I32Lanes::splat(segments.drawn() as i32) & bit).simd_eq(bit);
    let drawn: F32Lanes = bytemuck::cast(drawn);
    let (near_lo, near_hi) = segments.lines(columns);
    let lo = pick(x0, y0).fast_max(pick(s(tx), s(ty))).fast_max(near_lo);
    let hi = pick(x1, y1)
        .fast_min(pick(s(tx1), s(ty1)))
        .fast_min(near_hi);
    let hi = drawn.select(hi, s(f32::NEG_INFINITY));
    let (cross_lo, cross_hi) = (pick(s(ty), s(tx)), pick(s(ty1), s(tx1)));
    // Each lane's line, its next candidate c and the end of its band.
    let mut line = lo - s(1.0);
    let (mut c, mut cb) = (F32Lanes::ZERO, F32Lanes::ZERO);
    let mut n = 0;
    let mut lane_passes = I32Lanes::ZERO;
    loop {
        // 5b. Lanes past their band move to their next line with a
        // non-empty band, while they have lines left.
        let mut next = !c.simd_lt(cb) & (line + s(1.0)).simd_lt(hi);
        while next.any() {
            line = next.select(line + s(1.0), line);
            let (ca, band_end) = segments.band(line, columns);
            c = next.select(ca.fast_max(cross_lo), c);
            cb = next.select(band_end.fast_min(cross_hi), cb);
            next = next & !c.simd_lt(cb) & (line + s(1.0)).simd_lt(hi);
        }
        let live = c.simd_lt(cb) & line.simd_lt(hi);
        if live.none() {
            break;
        }
        if n == MAX_PASSES {
            return false;
        }
        // 5c. Every live lane's candidate pixel.
        let centre = line + s(0.5);
        let xc = pick(centre, c + s(0.5));
        let yc = pick(c + s(0.5), centre);
        let f = segments.fragment(xc, yc, opacity);
        let hit = live & f.mask;
        let (x, y) = (pick(line, c), pick(c, line));
        let index = ((y - s(ty)) * s(TILE as f32) + (x - s(tx))).trunc_int();
        let pass = &mut passes[n];
        pass.index = index.to_array();
        pass.z = f.depth.to_array();
        pass.alpha = f.alpha.to_array();
        pass.color = [f.color.x, f.color.y, f.color.z].map(|v| v.to_array());
        lane_passes |= bytemuck::cast::<F32Lanes, I32Lanes>(hit) & I32Lanes::splat(1 << n);
        n += 1;
        c += s(1.0);
    }
    // 5d. Depth test and blend, segment by segment in list order.
    for (l, bits) in lane_passes.to_array().into_iter().enumerate() {
        let mut bits = bits as u32;
        while bits != 0 {
            let p = &passes[bits.trailing_zeros() as usize];
            bits &= bits - 1;
            let rgb = [p.color[0][l], p.color[1][l], p.color[2][l]];
            tile.blend::<DEPTH>(p.index[l] as usize, p.z[l], p.alpha[l], rgb);
        }
    }
    true
}
