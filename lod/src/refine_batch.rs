//! Batch refinement of a whole [`Strands`] set: eight strands per SIMD block,
//! positions and unit tangents of the uniform cubic B-spline (see
//! [`crate::bspline`]) written into a caller-owned [`RefinedGuides`].
//!
//! The output keeps the lane layout of `Strands`: refined vertex `r` of block
//! `b` is `positions[b * R + r]`, lane `l` = strand `b * LANES + l`, with
//! `R = (V - 1) N + 1`. Positions are relative to [`Strands::origin`].
//! Weights for the current `N` are precomputed; nothing allocates per frame.
//!
//! Steps, in both twins ([`refine_strands`] here, eight strands per
//! instruction, and [`crate::scalar::refine_strands`], one lane at a time):
//!
//! 1. Skip the blocks `visibility` marks as not needed.
//! 2. Per span `j`: the four control points `P_{j-1} .. P_{j+2}`, with the
//!    phantom ends `2 P_0 - P_1` and `2 P_{n-1} - P_{n-2}`.
//! 3. Per refined vertex of the span: position `sum_i w_i(t) P_i` and
//!    tangent `unit(sum_i w_i'(t) P_i)` (or `+Y`), with [`combine`].
//! 4. Pin the end points to the first and last control points.

use crate::bspline::{basis, basis_derivative, refined_len};
use crate::culling::Visibility;
use crate::Error;
use coif_base::lanes::F32Lanes;
use coif_base::lanes::Lane;
use coif_base::{StrandBlocks, Vec3Lanes, LANES};
use glam::Vec3;

/// Default upper bound on segments per span for [`RefinedGuides::new`].
pub const DEFAULT_MAX_SEGMENTS_PER_SPAN: usize = 16;

/// Caller-owned output of [`refine_strands`]: refined positions and unit
/// tangents of every guide strand, sized once for the largest level.
#[derive(Clone, Debug)]
pub struct RefinedGuides {
    pub(crate) strand_count: usize,
    pub(crate) blocks: usize,
    pub(crate) control_verts: usize,
    pub(crate) max_segments: usize,
    pub(crate) segments: usize,
    pub(crate) verts: usize,
    /// Per k = 0..=N: position weights then derivative weights at t = k / N.
    pub(crate) weights: Vec<[f32; 8]>,
    pub(crate) positions: Vec<Vec3Lanes>,
    pub(crate) tangents: Vec<Vec3Lanes>,
    pub(crate) refined: Vec<bool>,
}

impl RefinedGuides {
    /// A buffer for `strands`, able to hold any level up to
    /// `max_segments_per_span` (1..=256) without reallocating. Starts at
    /// `N = max_segments_per_span`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] if `max_segments_per_span` is outside
    /// `1 ..= 256`.
    pub fn new(
        strands: StrandBlocks<'_>,
        max_segments_per_span: usize,
    ) -> Result<RefinedGuides, Error> {
        RefinedGuides::with_shape(
            strands.strand_count(),
            strands.verts_per_strand(),
            max_segments_per_span,
        )
    }

    /// As [`RefinedGuides::new`], from the set's shape.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] if `max_segments_per_span` is outside
    /// `1 ..= 256`, if `verts_per_strand < 2`, or if the buffers would hold
    /// more than `isize::MAX` bytes (`strand_count` absurdly large).
    pub fn with_shape(
        strand_count: usize,
        verts_per_strand: usize,
        max_segments_per_span: usize,
    ) -> Result<RefinedGuides, Error> {
        if !(1..=256).contains(&max_segments_per_span) {
            return Err(Error::InvalidParameter {
                name: "max_segments_per_span",
                value: max_segments_per_span as f64,
                expected: "1 ..= 256",
            });
        }
        if verts_per_strand < 2 {
            return Err(Error::InvalidParameter {
                name: "verts_per_strand",
                value: verts_per_strand as f64,
                expected: ">= 2",
            });
        }
        let blocks = strand_count.div_ceil(LANES);
        // Refuse sizes whose buffers could not exist instead of aborting on
        // a capacity overflow (or wrapping the multiplication).
        let len = blocks
            .checked_mul(verts_per_strand - 1)
            .and_then(|x| x.checked_mul(max_segments_per_span))
            .and_then(|x| x.checked_add(blocks))
            .filter(|&len| len <= isize::MAX as usize / (2 * std::mem::size_of::<Vec3Lanes>()))
            .ok_or(Error::InvalidParameter {
                name: "strand_count",
                value: strand_count as f64,
                expected: "a set whose refined buffers fit in memory",
            })?;
        let mut out = RefinedGuides {
            strand_count,
            blocks,
            control_verts: verts_per_strand,
            max_segments: max_segments_per_span,
            segments: 0,
            verts: 0,
            weights: Vec::with_capacity(max_segments_per_span + 1),
            positions: vec![Vec3Lanes::ZERO; len],
            tangents: vec![Vec3Lanes::ZERO; len],
            refined: vec![false; blocks],
        };
        out.set_segments_per_span_clamped(max_segments_per_span);
        Ok(out)
    }

    /// Number of `Vec3Lanes` entries per output array for a set of
    /// `strand_count` strands of `verts_per_strand` control points at
    /// `segments_per_span`: `ceil(strands / 8) * ((V - 1) N + 1)`.
    pub fn buffer_len(
        strand_count: usize,
        verts_per_strand: usize,
        segments_per_span: usize,
    ) -> usize {
        strand_count.div_ceil(LANES) * refined_len(verts_per_strand, segments_per_span)
    }

    /// Chooses the level for the next [`refine_strands`]: `n` segments per
    /// span. Recomputes the weight table (N + 1 entries) without allocating.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] (and the level unchanged) if `n` is
    /// outside `1 ..= max_segments_per_span()`; use
    /// [`RefinedGuides::set_segments_per_span_clamped`] to clamp instead.
    pub fn set_segments_per_span(&mut self, n: usize) -> Result<(), Error> {
        if !(1..=self.max_segments).contains(&n) {
            return Err(Error::InvalidParameter {
                name: "segments_per_span",
                value: n as f64,
                expected: "1 ..= max_segments_per_span",
            });
        }
        self.set_segments_per_span_clamped(n);
        Ok(())
    }

    /// As [`RefinedGuides::set_segments_per_span`], with `n` clamped to
    /// `1 ..= max_segments_per_span()` (for a level computed from the view,
    /// where the buffer's largest level is the intended cap); returns the
    /// level in use.
    pub fn set_segments_per_span_clamped(&mut self, n: usize) -> usize {
        let n = n.clamp(1, self.max_segments);
        if n != self.segments {
            // Straight from the basis functions into the table reserved for
            // max_segments + 1 entries: a level change allocates nothing
            // (SpanWeights::new would).
            self.weights.clear();
            for k in 0..=n {
                let t = k as f32 / n as f32;
                let (p, d) = (basis(t), basis_derivative(t));
                self.weights
                    .push([p[0], p[1], p[2], p[3], d[0], d[1], d[2], d[3]]);
            }
            self.segments = n;
            self.verts = refined_len(self.control_verts, n);
            self.refined.iter_mut().for_each(|r| *r = false);
        }
        n
    }

    /// The level in use, `N` segments per span.
    pub fn segments_per_span(&self) -> usize {
        self.segments
    }

    /// The largest level the buffer holds without reallocating.
    pub fn max_segments_per_span(&self) -> usize {
        self.max_segments
    }

    /// Refined vertices per strand, `R = (V - 1) N + 1`.
    pub fn verts_per_strand(&self) -> usize {
        self.verts
    }

    /// Number of guide strands.
    pub fn strand_count(&self) -> usize {
        self.strand_count
    }

    /// Number of SIMD blocks, `ceil(strands / 8)`.
    pub fn block_count(&self) -> usize {
        self.blocks
    }

    /// Control points per strand of the set this buffer was made for.
    pub fn control_verts_per_strand(&self) -> usize {
        self.control_verts
    }

    /// Whether the last refinement wrote block `b` (false if it was culled).
    pub fn is_block_refined(&self, b: usize) -> bool {
        self.refined.get(b).copied().unwrap_or(false)
    }

    /// Block `b`'s refined positions (local coordinates), `R` entries;
    /// empty for a block past the end.
    pub fn block_positions(&self, b: usize) -> &[Vec3Lanes] {
        block_slice(&self.positions, b, self.verts)
    }

    /// Block `b`'s unit tangents, `R` entries; empty for a block past the
    /// end.
    pub fn block_tangents(&self, b: usize) -> &[Vec3Lanes] {
        block_slice(&self.tangents, b, self.verts)
    }

    /// [`RefinedGuides::position`], or `None` for a vertex that does not
    /// exist.
    pub fn get_position(&self, i: usize, r: usize) -> Option<Vec3> {
        (i < self.strand_count() && r < self.verts).then(|| self.position(i, r))
    }

    /// [`RefinedGuides::tangent`], or `None` for a vertex that does not
    /// exist.
    pub fn get_tangent(&self, i: usize, r: usize) -> Option<Vec3> {
        (i < self.strand_count() && r < self.verts).then(|| self.tangent(i, r))
    }

    /// Refined vertex `r` of strand `i` (local coordinates).
    ///
    /// # Panics
    ///
    /// If `i >= strand_count()` or `r >= verts_per_strand()` (as slice
    /// indexing does); [`RefinedGuides::get_position`] does not.
    pub fn position(&self, i: usize, r: usize) -> Vec3 {
        self.check_vertex(i, r);
        self.positions[(i / LANES) * self.verts + r].lane(i % LANES)
    }

    /// Unit tangent at refined vertex `r` of strand `i`.
    ///
    /// # Panics
    ///
    /// If `i >= strand_count()` or `r >= verts_per_strand()` (as slice
    /// indexing does).
    pub fn tangent(&self, i: usize, r: usize) -> Vec3 {
        self.check_vertex(i, r);
        self.tangents[(i / LANES) * self.verts + r].lane(i % LANES)
    }

    /// Strand `i`'s refined positions, root first, into `out` (cleared).
    ///
    /// # Panics
    ///
    /// If `i >= strand_count()`.
    pub fn strand_positions(&self, i: usize, out: &mut Vec<Vec3>) {
        out.clear();
        out.extend((0..self.verts).map(|r| self.position(i, r)));
    }

    /// Panics unless vertex `r` of strand `i` exists (an `r` past the end
    /// would otherwise read the next block's vertices).
    fn check_vertex(&self, i: usize, r: usize) {
        assert!(
            i < self.strand_count && r < self.verts,
            "refined vertex ({i}, {r}) out of range: {} strands of {} vertices",
            self.strand_count,
            self.verts
        );
    }

    /// `Ok` if `strands` has the shape this buffer was made for.
    pub(crate) fn check_fits(&self, strands: StrandBlocks<'_>) -> Result<(), Error> {
        if strands.strand_count() != self.strand_count {
            return Err(Error::CountMismatch {
                what: "guide strands (RefinedGuides made for another set)",
                expected: self.strand_count,
                got: strands.strand_count(),
            });
        }
        if strands.verts_per_strand() != self.control_verts {
            return Err(Error::CountMismatch {
                what: "control points per strand (RefinedGuides made for another set)",
                expected: self.control_verts,
                got: strands.verts_per_strand(),
            });
        }
        Ok(())
    }
}

/// Whether block `b` must be refined this frame.
pub(crate) fn block_needed(visibility: Option<&Visibility>, b: usize) -> bool {
    visibility.is_none_or(|v| v.guide_block_needed(b))
}

/// Refines every needed block of `strands` into `out` at
/// `out.segments_per_span()` (SIMD path, eight strands per instruction).
///
/// Blocks that `visibility` marks as not needed are skipped (their entries
/// keep stale data and [`RefinedGuides::is_block_refined`] says false).
/// Returns the number of blocks refined. End points are the first and last
/// control points exactly; tangents whose derivative vanishes (or is not
/// finite) are `Vec3::Y`. Allocates nothing.
///
/// # Errors
///
/// [`Error::CountMismatch`] (and nothing written) if `out` was made for a
/// set of another shape (strand count or control points per strand).
pub fn refine_strands(
    strands: StrandBlocks<'_>,
    visibility: Option<&Visibility>,
    out: &mut RefinedGuides,
) -> Result<usize, Error> {
    refine_blocks::<true>(strands, visibility, out)
}

/// [`refine_strands`] without tangents: positions only, half the
/// arithmetic and stores (for pipelines that take tangents from the render
/// hair's positions, see [`crate::interpolate_positions`]). The tangent
/// arrays of `out` are left as they were.
///
/// # Errors
///
/// As [`refine_strands`].
pub fn refine_strands_positions(
    strands: StrandBlocks<'_>,
    visibility: Option<&Visibility>,
    out: &mut RefinedGuides,
) -> Result<usize, Error> {
    refine_blocks::<false>(strands, visibility, out)
}

fn refine_blocks<const TANGENTS: bool>(
    strands: StrandBlocks<'_>,
    visibility: Option<&Visibility>,
    out: &mut RefinedGuides,
) -> Result<usize, Error> {
    out.check_fits(strands)?;
    let (v, r, n) = (out.control_verts, out.verts, out.segments);
    let mut count = 0;
    for b in 0..out.blocks {
        // 1. Skip the blocks not needed.
        let needed = block_needed(visibility, b);
        out.refined[b] = needed;
        if !needed {
            continue;
        }
        count += 1;
        let ctrl = strands.block_positions_local(b);
        let pos = &mut out.positions[b * r..(b + 1) * r];
        let tan = &mut out.tangents[b * r..(b + 1) * r];
        for j in 0..v - 1 {
            // 2. The span's four control points, phantom ends at the ends.
            let p0 = if j == 0 {
                ctrl[0] + ctrl[0] - ctrl[1]
            } else {
                ctrl[j - 1]
            };
            let p1 = ctrl[j];
            let p2 = ctrl[j + 1];
            let p3 = if j + 2 < v {
                ctrl[j + 2]
            } else {
                ctrl[v - 1] + ctrl[v - 1] - ctrl[v - 2]
            };
            let ks = if j == v - 2 { n + 1 } else { n };
            // 3. Positions and tangents of the span's refined vertices.
            let span = j * n..j * n + ks;
            for ((p, t), w) in pos[span.clone()]
                .iter_mut()
                .zip(&mut tan[span])
                .zip(&out.weights)
            {
                *p = combine_simd(p0, p1, p2, p3, [w[0], w[1], w[2], w[3]]);
                if TANGENTS {
                    let d = combine_simd(p0, p1, p2, p3, [w[4], w[5], w[6], w[7]]);
                    *t = unit_or_y_simd(d);
                }
            }
        }
        // 4. Pin the end points.
        pos[0] = ctrl[0];
        pos[r - 1] = ctrl[v - 1];
    }
    Ok(count)
}

/// `p0 w0 + p1 w1 + p2 w2 + p3 w3` per lane: [`combine`] on each coordinate.
#[inline(always)]
fn combine_simd(
    p0: Vec3Lanes,
    p1: Vec3Lanes,
    p2: Vec3Lanes,
    p3: Vec3Lanes,
    w: [f32; 4],
) -> Vec3Lanes {
    Vec3Lanes {
        x: combine(p0.x, p1.x, p2.x, p3.x, w),
        y: combine(p0.y, p1.y, p2.y, p3.y, w),
        z: combine(p0.z, p1.z, p2.z, p3.z, w),
    }
}

/// `p0 w0 + p1 w1 + p2 w2 + p3 w3`, accumulated left to right with fused
/// multiply-adds: one body for one coordinate (`f32`, the scalar twin) and
/// eight lanes (`F32Lanes`), so both round identically.
#[inline(always)]
pub(crate) fn combine<L: Lane>(p0: L, p1: L, p2: L, p3: L, w: [f32; 4]) -> L {
    let [w0, w1, w2, w3] = w.map(L::splat);
    p3.mul_add(w3, p2.mul_add(w2, p1.mul_add(w1, p0 * w0)))
}

/// `d / |d|`, or `+Y` where `|d|^2 <= 1e-30` or not finite.
#[inline(always)]
pub(crate) fn unit_or_y_simd(d: Vec3Lanes) -> Vec3Lanes {
    let len2 = d.dot(d);
    let ok = len2.simd_gt(F32Lanes::splat(MIN_LENGTH_SQUARED))
        & len2.simd_lt(F32Lanes::splat(f32::INFINITY));
    // rsqrt (12 bits) refined by one Newton step y (3 - x y^2) / 2 (about
    // 23 bits, within a few ulp of 1 / sqrt(x)): no divide, no sqrt.
    let y = len2.recip_sqrt();
    let y = y * (F32Lanes::splat(1.5) - F32Lanes::splat(0.5) * len2 * y * y);
    Vec3Lanes::select(ok, d * y, Vec3Lanes::splat(Vec3::Y))
}

/// Tangents with `|d|^2` at or below this fall back to `+Y`.
pub(crate) const MIN_LENGTH_SQUARED: f32 = 1e-30;

/// Entries `b * len .. (b + 1) * len` of `v`, or empty past its end.
pub(crate) fn block_slice<T>(v: &[T], b: usize, len: usize) -> &[T] {
    b.checked_mul(len)
        .and_then(|start| v.get(start..start.checked_add(len)?))
        .unwrap_or(&[])
}
