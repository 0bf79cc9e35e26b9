//! Anti-aliased lines of sub-pixel width.
//!
//! A hair segment is a strip of width `w` pixels around the line through its
//! two projected ends. Its alpha in a pixel is the **exact area of the pixel
//! square that the strip covers** (a box filter over the pixel): with `d` the
//! signed distance of the pixel centre from the line and `n = (n_x, n_y)`
//! the line's unit normal, the unit square's width profile along `n` is a
//! trapezoid `g` of half-width `(|n_x| + |n_y|) / 2`, plateau half-width
//! `||n_x| - |n_y|| / 2` and height `1 / max(|n_x|, |n_y|)` (unit area), and
//!
//! ```text
//! coverage(d, w, n) = G(d + w/2) - G(d - w/2),     G = the integral of g (a CDF)
//! ```
//!
//! A line thinner than a pixel thus gets alpha of about `w` (its width in
//! pixels) spread over the one or two pixels it crosses, and a wide line's
//! inside gets 1. Because the pixel squares tile the plane, the coverage
//! summed over all pixels is exactly the strip's area `w L` (up to the
//! ends); the test draws lines at several angles and widths and compares.
//! Along the line, a pixel belongs to the segment when its centre projects
//! to a parameter `t` in `[0, 1)`: consecutive segments of a polyline abut
//! without double-blending their shared end.

use super::Framebuffer;
use coif_base::lanes::{rows_to_planes, F32Group, F32Lanes, Lane, LANES, V3};
use glam::Vec3;

/// A projected hair vertex: pixel position, view depth, width in pixels and
/// linear-RGB colour. Seven `f32` in this order, nothing between them
/// (`repr(C)`: [`Segment::new_simd`] reads two consecutive vertices as 14
/// floats).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct ScreenVertex {
    /// Pixel column (x right).
    pub x: f32,
    /// Pixel row (y down).
    pub y: f32,
    /// View depth (> 0).
    pub depth: f32,
    /// Line width in pixels.
    pub width_px: f32,
    /// Linear-RGB colour.
    pub color: Vec3,
}

/// The unit pixel square's width profile across a line with unit normal
/// `(n_x, n_y)`, as its cumulative integral `G` (see the module doc).
///
/// [`PixelProfile::cumulative`] evaluates `G` piecewise (the formula as
/// written in the module doc); [`PixelProfile::coverage`] uses the same
/// `G` in a branch-free form that the SIMD rasteriser evaluates eight
/// pixels at a time ([`coverage_lanes`]): with `a = |x|`,
///
/// ```text
/// G(x) - 1/2 = sign(x) S(a),   S(a) = H min(a, p) + H r / 2 - (H / (2 r)) q^2,
/// q = clamp(h - a, 0, r)
/// ```
///
/// (`h` the half-width, `p` the plateau half-width, `r = h - p` the ramp,
/// `H` the plateau height): `S` is the plateau's share `H min(a, p)` plus
/// the part of the ramp between `p` and `a`. The two forms agree to
/// float rounding (a test compares them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelProfile {
    /// Half-width of the support, `(|n_x| + |n_y|) / 2`.
    half: f32,
    /// Half-width of the plateau, `||n_x| - |n_y|| / 2`.
    plateau: f32,
    /// Length of each ramp, `min(|n_x|, |n_y|)`.
    ramp: f32,
    /// Height of the plateau, `1 / max(|n_x|, |n_y|)`.
    height: f32,
    /// `H r / 2`: the ramp's share of `S` beyond the support.
    ramp_area: f32,
    /// `H / (2 r)`, or 0 for a ramp shorter than `1e-20` (an axis-aligned
    /// line: no ramp, and no `0 * inf`).
    ramp_curve: f32,
}

impl PixelProfile {
    /// The profile across a line of direction `(dx, dy)` (any length > 0).
    pub fn for_direction(dx: f32, dy: f32) -> PixelProfile {
        let len = (dx * dx + dy * dy).sqrt();
        let (a, b) = ((dy / len).abs(), (dx / len).abs());
        let (lo, hi) = (Lane::min(a, b), Lane::max(a, b));
        let height = 1.0 / hi;
        PixelProfile {
            half: 0.5 * (a + b),
            plateau: 0.5 * (hi - lo),
            ramp: lo,
            height,
            ramp_area: 0.5 * height * lo,
            ramp_curve: if lo > 1e-20 { 0.5 * height / lo } else { 0.0 },
        }
    }

    /// Half-width of the profile's support, `(|n_x| + |n_y|) / 2` pixels:
    /// a pixel whose centre is farther than this plus half the line's
    /// width from the line gets no coverage.
    pub fn half_width(&self) -> f32 {
        self.half
    }

    /// `G(x)`: the share of the pixel on the side `<= x` of a line at
    /// signed distance `x` from its centre (piecewise, as in the module doc).
    #[inline]
    pub fn cumulative(&self, x: f32) -> f32 {
        if x <= -self.half {
            0.0
        } else if x >= self.half {
            1.0
        } else if x < -self.plateau {
            let u = x + self.half;
            0.5 * u * u * self.height / self.ramp
        } else if x <= self.plateau {
            0.5 * self.ramp * self.height + (x + self.plateau) * self.height
        } else {
            let u = self.half - x;
            1.0 - 0.5 * u * u * self.height / self.ramp
        }
    }

    /// Share of the pixel covered by a strip of width `width_px` whose
    /// centre line is `distance` pixels from the pixel's centre:
    /// `G(d + w/2) - G(d - w/2)` clamped to `[0, 1]`, 0 for a width that is
    /// not positive (or NaN). One lane of [`coverage_lanes`].
    #[inline]
    pub fn coverage(&self, distance: f32, width_px: f32) -> f32 {
        coverage_lanes(self, distance, width_px)
    }
}

/// A [`PixelProfile`]'s constants in lanes: splatted from one profile
/// ([`PixelProfile::lanes`]), or one segment's profile per lane
/// ([`SegmentsLanes`]).
#[derive(Clone, Copy, Debug)]
struct ProfileLanes<T> {
    half: T,
    plateau: T,
    ramp: T,
    height: T,
    ramp_area: T,
    ramp_curve: T,
}

impl PixelProfile {
    /// The profile's constants splatted to every lane.
    #[inline(always)]
    fn lanes<T: Lane>(&self) -> ProfileLanes<T> {
        ProfileLanes {
            half: T::splat(self.half),
            plateau: T::splat(self.plateau),
            ramp: T::splat(self.ramp),
            height: T::splat(self.height),
            ramp_area: T::splat(self.ramp_area),
            ramp_curve: T::splat(self.ramp_curve),
        }
    }
}

/// `G(x) - 1/2` of `profile` in every lane (see [`PixelProfile`]): the
/// branch-free form, one generic body for `f32` and `F32Lanes`.
#[inline(always)]
fn centred_cumulative<T: Lane>(profile: &ProfileLanes<T>, x: T) -> T {
    // 1. a = |x|; q = clamp(h - a, 0, r)
    let a = x.abs();
    let q = (profile.half - a).max(T::splat(0.0)).min(profile.ramp);
    // 2. S(a) = H min(a, p) + (H r / 2 - (H / (2 r)) q q)
    let ramp = profile.ramp_area - (profile.ramp_curve * q) * q;
    let s = a.min(profile.plateau).mul_add(profile.height, ramp);
    // 3. The sign of x.
    T::select(x.lt(T::splat(0.0)), -s, s)
}

/// [`PixelProfile::coverage`] in every lane: `G(d + w/2) - G(d - w/2)`
/// clamped to `[0, 1]`, 0 where `width_px` is not positive or is NaN.
/// The scalar (`f32`) and lane (`F32Lanes`) forms round the same way.
#[inline(always)]
pub fn coverage_lanes<T: Lane>(profile: &PixelProfile, distance: T, width_px: T) -> T {
    coverage_in(&profile.lanes(), distance, width_px)
}

/// [`coverage_lanes`] with the profile's constants in lanes.
#[inline(always)]
fn coverage_in<T: Lane>(profile: &ProfileLanes<T>, distance: T, width_px: T) -> T {
    let half_width = T::splat(0.5) * width_px;
    let cov = centred_cumulative(profile, distance + half_width)
        - centred_cumulative(profile, distance - half_width);
    let cov = cov.max(T::splat(0.0)).min(T::splat(1.0));
    T::select(width_px.gt(T::splat(0.0)), cov, T::splat(0.0))
}

/// A segment set up for drawing: its two ends, the pixel profile across
/// it and the reciprocals every pixel needs. The reference
/// [`draw_segment`] and both tiled rasterisers ([`crate::raster`]) share
/// it, and the per-pixel step [`Segment::pixel`], so all three blend the
/// same bits.
#[derive(Clone, Copy, Debug)]
pub struct Segment {
    a: ScreenVertex,
    b: ScreenVertex,
    ex: f32,
    ey: f32,
    len2: f32,
    inv_len2: f32,
    inv_len: f32,
    profile: PixelProfile,
    /// Largest distance from the line at which a pixel centre can be
    /// covered: the profile's half-width plus half the wider end.
    radius_len: f32,
    /// `1 / ey` and `1 / ex` (0 where the component is 0).
    inv_ey: f32,
    inv_ex: f32,
    /// Pixel bounds `[x0, x1) x [y0, y1)` within the frame (as floats).
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
}

/// [`LANES`] segments set up at once ([`Segment::new_simd`]): every field
/// of [`Segment`] as a plane of lanes.
#[derive(Clone, Copy, Debug)]
pub struct SegmentsLanes {
    f: [F32Lanes; 32],
    drawn: u32,
}

impl SegmentsLanes {
    /// Lane `l` as the [`Segment`] of [`Segment::new`] (`None` where
    /// that is, or past the segments given).
    #[inline(always)]
    pub fn lane(&self, l: usize) -> Option<Segment> {
        if l >= LANES || self.drawn >> l & 1 == 0 {
            return None;
        }
        let fields: &[[f32; LANES]; 32] = bytemuck::cast_ref(&self.f);
        let f = |i: usize| fields[i][l];
        let end = |i: usize| ScreenVertex {
            x: f(i),
            y: f(i + 1),
            depth: f(i + 2),
            width_px: f(i + 3),
            color: Vec3::new(f(i + 4), f(i + 5), f(i + 6)),
        };
        Some(Segment {
            a: end(0),
            b: end(7),
            ex: f(14),
            ey: f(15),
            len2: f(16),
            inv_len2: f(17),
            inv_len: f(18),
            profile: PixelProfile {
                half: f(19),
                plateau: f(20),
                ramp: f(21),
                height: f(22),
                ramp_area: f(23),
                ramp_curve: f(24),
            },
            radius_len: f(25),
            inv_ey: f(26),
            inv_ex: f(27),
            x0: f(28),
            x1: f(29),
            y0: f(30),
            y1: f(31),
        })
    }

    /// The lanes that [`SegmentsLanes::lane`] gives a segment for.
    #[inline(always)]
    pub fn drawn(&self) -> u32 {
        self.drawn
    }

    /// Whether every drawn lane's [`Segment::walk`] is a band walk (both
    /// ends within [`BAND_REACH`] of the origin).
    #[inline(always)]
    pub fn near(&self) -> bool {
        let reach = F32Lanes::splat(BAND_REACH);
        let near = [0, 1, 7, 8]
            .map(|i| self.f[i].abs().simd_le(reach))
            .into_iter()
            .fold(F32Lanes::splat(f32::from_bits(u32::MAX)), |a, b| a & b);
        !near.to_bitmask() & self.drawn == 0
    }

    /// Lanes whose [`Segment::walk`] is [`Walk::BandColumns`] (`|e_x| >
    /// |e_y|`), as a mask.
    #[inline(always)]
    pub fn columns(&self) -> F32Lanes {
        self.f[14].abs().simd_gt(self.f[15].abs())
    }

    /// [`Segment::float_bounds`] lane by lane.
    #[inline(always)]
    pub fn float_bounds(&self) -> [F32Lanes; 4] {
        [self.f[28], self.f[29], self.f[30], self.f[31]]
    }

    /// The lines (rows, or columns where `columns` is set) whose pixel
    /// centres can be drawn, `[lo, hi)` as whole floats lane by lane: a
    /// drawn centre `a + t e + d n` has `0 <= t <= 1` and `|d| <=
    /// radius`, so its coordinate along the major axis lies within
    /// `radius |e_minor| / |e|` of the ends' range; widened by
    /// [`SPAN_MARGIN`] as the band is (the same rounding argument). Not
    /// clipped to the bounds. Tighter than the bounds' reach `w_max / 2 +
    /// 0.75` on the major axis: about one line less at each end of a
    /// steep thin hair.
    #[inline(always)]
    pub fn lines(&self, columns: F32Lanes) -> (F32Lanes, F32Lanes) {
        let f = &self.f;
        let pick = |col: usize, row: usize| columns.select(f[col], f[row]);
        lines_in([pick(0, 1), pick(7, 8), pick(15, 14), f[25], f[17]])
    }

    /// [`Segment::band`] lane by lane, each lane's own segment, rows or
    /// `columns` (a mask): the same operations, so the same bits.
    #[inline(always)]
    pub fn band(&self, c: F32Lanes, columns: F32Lanes) -> (F32Lanes, F32Lanes) {
        let f = &self.f;
        let pick = |col: usize, row: usize| columns.select(f[col], f[row]);
        band_in(
            c,
            [pick(1, 0), pick(0, 1), pick(15, 14), pick(27, 26), f[25]],
        )
    }

    /// [`Segment::fragment`] lane by lane, each lane's own segment at its
    /// pixel centre `(xc, yc)`: the same operations, so the same bits.
    #[inline(always)]
    pub fn fragment(&self, xc: F32Lanes, yc: F32Lanes, opacity: f32) -> Fragment<F32Lanes> {
        let f = &self.f;
        let lanes = SegmentLanes {
            ax: f[0],
            ay: f[1],
            ex: f[14],
            ey: f[15],
            inv_len2: f[17],
            inv_len: f[18],
            width: f[3],
            dwidth: f[10] - f[3],
            depth: f[2],
            ddepth: f[9] - f[2],
            color: [f[4], f[5], f[6]],
            dcolor: [f[11] - f[4], f[12] - f[5], f[13] - f[6]],
            profile: ProfileLanes {
                half: f[19],
                plateau: f[20],
                ramp: f[21],
                height: f[22],
                ramp_area: f[23],
                ramp_curve: f[24],
            },
        };
        lanes.fragment(xc, yc, F32Lanes::splat(opacity))
    }
}

/// What one pixel gets from a segment: its alpha (coverage times
/// opacity; 0 where the pixel is not drawn) and colour, per lane.
#[derive(Clone, Copy, Debug)]
pub struct Fragment<T: Lane> {
    /// Lanes the segment blends into.
    pub mask: T::Mask,
    /// `coverage * opacity` (meaningful where `mask` is set).
    pub alpha: T,
    /// The segment's view depth at the pixel.
    pub depth: T,
    /// Linear-RGB colour interpolated along the segment.
    pub color: V3<T>,
}

impl Segment {
    /// The pixels `[x0, x1) x [y0, y1)` segment `a -> b` can touch in a
    /// `width x height` frame: its ends' box grown by the reach
    /// `w_max / 2 + 0.75` (half the wider end plus more than the pixel
    /// profile's half-width, at most `sqrt(2) / 2`), clipped to the frame;
    /// `None` when that is empty or the segment is shorter than `1e-6` px
    /// or not finite.
    #[inline]
    pub fn pixel_bounds(
        a: &ScreenVertex,
        b: &ScreenVertex,
        width: usize,
        height: usize,
    ) -> Option<[usize; 4]> {
        let (ex, ey) = (b.x - a.x, b.y - a.y);
        let len2 = ex * ex + ey * ey;
        if len2.is_nan() || len2 <= 1e-12 || !len2.is_finite() {
            return None;
        }
        let [x0, x1, y0, y1] = float_bounds(a, b, width, height);
        (x0 < x1 && y0 < y1).then(|| {
            // Whole numbers in [0, 2^26] (the frame's size): exact as i32.
            [x0, x1, y0, y1].map(|v| v as i32 as usize)
        })
    }

    /// Sets up segment `a -> b` for a `width x height` frame; `None` when
    /// [`Segment::pixel_bounds`] is.
    #[inline]
    pub fn new(a: &ScreenVertex, b: &ScreenVertex, width: usize, height: usize) -> Option<Segment> {
        let (ex, ey) = (b.x - a.x, b.y - a.y);
        let len2 = ex * ex + ey * ey;
        if len2.is_nan() || len2 <= 1e-12 || !len2.is_finite() {
            return None;
        }
        let [x0, x1, y0, y1] = float_bounds(a, b, width, height);
        if !(x0 < x1 && y0 < y1) {
            return None;
        }
        let inv_len2 = 1.0 / len2;
        let inv_len = inv_len2.sqrt();
        let profile = PixelProfile::for_direction(ex, ey);
        let radius = profile.half + 0.5 * a.width_px.max(b.width_px);
        let recip = |v: f32| if v != 0.0 { 1.0 / v } else { 0.0 };
        Some(Segment {
            a: *a,
            b: *b,
            ex,
            ey,
            len2,
            inv_len2,
            inv_len,
            profile,
            radius_len: radius * len2.sqrt(),
            inv_ey: recip(ey),
            inv_ex: recip(ex),
            x0,
            x1,
            y0,
            y1,
        })
    }

    /// [`Segment::bounds`] as whole floats.
    #[inline(always)]
    pub fn float_bounds(&self) -> [f32; 4] {
        [self.x0, self.x1, self.y0, self.y1]
    }

    /// [`Segment::new`] of the segments `screen[k] -> screen[k + 1]` for
    /// the (up to [`LANES`]) `k` of `first`, all at once: the same
    /// operations in the same order, so every lane's [`SegmentsLanes::lane`]
    /// has the bits of [`Segment::new`] (for ends that [`crate::raster`]
    /// projected: finite, widths not negative; a test compares every
    /// field). Panics if a `k + 1` is outside `screen` (as indexing does).
    #[inline(always)]
    pub fn new_simd(
        screen: &[ScreenVertex],
        first: &[u32],
        width: usize,
        height: usize,
    ) -> SegmentsLanes {
        // Each lane's two ends are 14 consecutive floats: its floats 0..8
        // and 6..14 as rows, transposed to planes.
        const { assert!(std::mem::size_of::<ScreenVertex>() == 7 * 4) };
        let (mut head, mut tail) = ([F32Group::ZERO; LANES], [F32Group::ZERO; LANES]);
        let mut present = [0.0f32; LANES];
        for (l, &k) in first.iter().take(LANES).enumerate() {
            let pair = &screen[k as usize..k as usize + 2];
            let p = pair.as_ptr() as *const f32;
            // SAFETY: `ScreenVertex` is `repr(C)`, seven `f32` and no
            // padding (asserted above): `pair` is 14 floats, and both
            // reads (floats 0..8 and 6..14) lie within them.
            unsafe {
                head[l] = F32Group::new(std::ptr::read_unaligned(p as *const [f32; 8]));
                tail[l] = F32Group::new(std::ptr::read_unaligned(p.add(6) as *const [f32; 8]));
            }
            present[l] = 1.0;
        }
        let [ax, ay, ad, aw, ar, ag, _, _] = rows_to_planes(head);
        let [ab, bx, by, bd, bw, br, bg, bb] = rows_to_planes(tail);
        let s = F32Lanes::splat;
        // 1. Length: above 1e-12 and finite (NaN fails both).
        let (ex, ey) = (bx - ax, by - ay);
        let len2 = ex * ex + ey * ey;
        let long = len2.simd_gt(s(1e-12)) & len2.is_finite();
        // 2. The float bounds (`float_bounds`).
        let reach = s(0.5) * aw.fast_max(bw) + s(0.75);
        let (w, h) = (width as f32, height as f32);
        let x0 = (ax.fast_min(bx) - reach).floor().fast_max(F32Lanes::ZERO);
        let x1 = (ax.fast_max(bx) + reach).ceil().fast_min(s(w));
        let y0 = (ay.fast_min(by) - reach).floor().fast_max(F32Lanes::ZERO);
        let y1 = (ay.fast_max(by) + reach).ceil().fast_min(s(h));
        let drawn =
            long & x0.simd_lt(x1) & y0.simd_lt(y1) & F32Lanes::new(present).simd_gt(F32Lanes::ZERO);
        // 3. Reciprocals and the profile (`PixelProfile::for_direction`).
        let inv_len2 = s(1.0) / len2;
        let inv_len = inv_len2.sqrt();
        let len = len2.sqrt();
        let (pa, pb) = ((ey / len).abs(), (ex / len).abs());
        let (lo, hi) = (pa.fast_min(pb), pa.fast_max(pb));
        let height = s(1.0) / hi;
        let ramp_curve = lo
            .simd_gt(s(1e-20))
            .select(s(0.5) * height / lo, F32Lanes::ZERO);
        let half = s(0.5) * (pa + pb);
        let radius = half + s(0.5) * aw.fast_max(bw);
        let recip = |v: F32Lanes| v.simd_ne(F32Lanes::ZERO).select(s(1.0) / v, F32Lanes::ZERO);
        let fields = [
            ax,
            ay,
            ad,
            aw,
            ar,
            ag,
            ab,
            bx,
            by,
            bd,
            bw,
            br,
            bg,
            bb,
            ex,
            ey,
            len2,
            inv_len2,
            inv_len,
            half,
            s(0.5) * (hi - lo),
            lo,
            height,
            s(0.5) * height * lo,
            ramp_curve,
            radius * len,
            recip(ey),
            recip(ex),
            x0,
            x1,
            y0,
            y1,
        ];
        SegmentsLanes {
            f: fields,
            drawn: drawn.to_bitmask(),
        }
    }

    /// The pixel rectangle `[x0, x1) x [y0, y1)` that can be touched.
    #[inline]
    pub fn bounds(&self) -> [usize; 4] {
        // Whole numbers in [0, 2^26] (the frame's size): exact as i32.
        [
            self.x0 as i32 as usize,
            self.x1 as i32 as usize,
            self.y0 as i32 as usize,
            self.y1 as i32 as usize,
        ]
    }

    /// The pixels `[xa, xb)` of row `y` that can be touched: inside the
    /// bounds, within the strip's reach of the line (`|dist| <= radius`)
    /// and projecting into the segment (`0 <= t <= 1`). Both slabs are
    /// linear in x along a row; the range of pixel centres inside both is
    /// widened by [`SPAN_MARGIN`] (far more than the rounding of the slab
    /// ends for on-screen coordinates) and the exact per-pixel tests of
    /// [`Segment::pixel`] decide. `None` when empty. One lane of
    /// [`Segment::row_spans`].
    #[inline]
    pub fn row_span(&self, y: usize) -> Option<(usize, usize)> {
        let (xa, xb) = self.row_spans(y as f32);
        (xa < xb).then_some((xa as usize, xb as usize))
    }

    /// [`Segment::row_span`] of the rows `y` (one per lane, whole numbers)
    /// as floats `(xa, xb)`, both 0 where the span is empty; the scalar and
    /// lane forms give the same bits.
    #[inline(always)]
    pub fn row_spans<T: Rounding>(&self, y: T) -> (T, T) {
        let (a, ex, ey) = (&self.a, self.ex, self.ey);
        let py = (y + T::splat(0.5)) - T::splat(a.y);
        let mut lo = T::splat(self.x0 - a.x - 0.5);
        let mut hi = T::splat(self.x1 - a.x - 0.5);
        // dist = (ex py - ey px) / len within [-radius, radius].
        if ey != 0.0 {
            let exy = T::splat(ex) * py;
            let u = (exy - T::splat(self.radius_len)) * T::splat(self.inv_ey);
            let v = (exy + T::splat(self.radius_len)) * T::splat(self.inv_ey);
            lo = lo.max(u.min(v));
            hi = hi.min(u.max(v));
        }
        // t = (ex px + ey py) / len2 within [0, 1].
        if ex != 0.0 {
            let pey = py * T::splat(ey);
            let u = (-py * T::splat(ey)) * T::splat(self.inv_ex);
            let v = (T::splat(self.len2) - pey) * T::splat(self.inv_ex);
            lo = lo.max(u.min(v));
            hi = hi.min(u.max(v));
        }
        // px = x + 0.5 - a.x in [lo, hi], widened by SPAN_MARGIN.
        let xa = ((lo + T::splat(a.x)) - T::splat(0.5 + SPAN_MARGIN))
            .ceil()
            .max(T::splat(self.x0));
        let xb = (((hi + T::splat(a.x)) - T::splat(0.5 - SPAN_MARGIN)).floor() + T::splat(1.0))
            .min(T::splat(self.x1));
        let ok = lo.finite() & hi.finite() & !lo.gt(hi) & xa.lt(xb);
        let zero = T::splat(0.0);
        (T::select(ok, xa, zero), T::select(ok, xb, zero))
    }

    /// How the tiled rasterisers walk this segment ([`Walk`]).
    #[inline(always)]
    pub fn walk(&self) -> Walk {
        let near = |v: f32| v.abs() <= BAND_REACH;
        if !(near(self.a.x) && near(self.a.y) && near(self.b.x) && near(self.b.y)) {
            Walk::Rows
        } else if self.ex.abs() > self.ey.abs() {
            Walk::BandColumns
        } else {
            Walk::BandRows
        }
    }

    /// The lines of a band walk (rows, or columns for `columns`) whose
    /// pixel centres can be drawn, `[lo, hi)` as whole floats, not
    /// clipped to the bounds: one lane of [`SegmentsLanes::lines`] (see
    /// there).
    #[inline(always)]
    pub fn lines(&self, columns: bool) -> (f32, f32) {
        let (a, b, minor) = if columns {
            (self.a.x, self.b.x, self.ey)
        } else {
            (self.a.y, self.b.y, self.ex)
        };
        lines_in([a, b, minor, self.radius_len, self.inv_len2])
    }

    /// The candidate band of [`Walk::BandRows`] (`columns` false: the
    /// pixels `[xa, xb)` of the rows `c`) or [`Walk::BandColumns`] (the
    /// pixel rows `[ya, yb)` of the columns `c`), one line per lane, as
    /// whole floats: the pixel centres of the line within the strip's
    /// reach (`|dist| <= radius`, the first slab of
    /// [`Segment::row_spans`]), widened by [`SPAN_MARGIN`]. Neither the
    /// bounds nor `0 <= t <= 1` are applied (the caller clips to its
    /// tile, [`Segment::pixel`] tests `t`): for a thin hair running along
    /// the line's axis that costs no pass, since the band is at most
    /// about three pixels long in every line. The line's axis component
    /// of `e` must not be 0 (it is not, for the walk that uses it).
    #[inline(always)]
    pub fn band<T: Rounding>(&self, c: T, columns: bool) -> (T, T) {
        let (ax, ay, ex, inv_ey) = if columns {
            (self.a.y, self.a.x, self.ey, self.inv_ex)
        } else {
            (self.a.x, self.a.y, self.ex, self.inv_ey)
        };
        let s = T::splat;
        band_in(c, [ax, ay, ex, inv_ey, self.radius_len].map(s))
    }

    /// The fragment of the pixels with centres `(xc, yc)` (`x + 0.5`,
    /// `y + 0.5` per lane) over stored depths `depth`:
    ///
    /// ```text
    /// t = (px e_x + py e_y) / |e|^2,  dist = (e_x py - e_y px) / |e|,  (px, py) = centre - a
    /// alpha = coverage(dist, w_a + t (w_b - w_a)) * opacity
    /// ```
    ///
    /// drawn where `0 <= t < 1`, `alpha > 0` and the segment's depth
    /// `d_a + t (d_b - d_a)` is nearer than `depth` (the head's); colour
    /// `c_a + (c_b - c_a) t`. Plain multiplies and adds in a fixed order
    /// (no fused multiply-add), so every lane width gives the same bits.
    /// [`Segment::fragment`] and the depth test.
    #[inline(always)]
    pub fn pixel<T: Lane>(&self, xc: T, yc: T, depth: T, opacity: f32) -> Fragment<T> {
        let mut f = self.fragment(xc, yc, opacity);
        f.mask = f.mask & f.depth.lt(depth);
        f
    }

    /// [`Segment::pixel`] before the depth test: `mask` holds where
    /// `0 <= t < 1` and `alpha > 0`, and `depth` is the segment's depth
    /// at the pixel; a pixel is drawn where also `depth` is below the
    /// stored one (the tiled rasteriser tests that lane by lane while
    /// blending, with the same comparison).
    #[inline(always)]
    pub fn fragment<T: Lane>(&self, xc: T, yc: T, opacity: f32) -> Fragment<T> {
        let (a, b) = (&self.a, &self.b);
        let s = T::splat;
        let lanes = SegmentLanes {
            ax: s(a.x),
            ay: s(a.y),
            ex: s(self.ex),
            ey: s(self.ey),
            inv_len2: s(self.inv_len2),
            inv_len: s(self.inv_len),
            width: s(a.width_px),
            dwidth: s(b.width_px - a.width_px),
            depth: s(a.depth),
            ddepth: s(b.depth - a.depth),
            color: [a.color.x, a.color.y, a.color.z].map(s),
            dcolor: [
                b.color.x - a.color.x,
                b.color.y - a.color.y,
                b.color.z - a.color.z,
            ]
            .map(s),
            profile: self.profile.lanes(),
        };
        lanes.fragment(xc, yc, s(opacity))
    }
}

/// What [`Segment::fragment`] reads, in lanes: one segment splatted, or
/// one segment per lane ([`SegmentsLanes::fragment`]). The differences
/// `b - a` are formed before (in `f32` or per lane: the same bits).
#[derive(Clone, Copy, Debug)]
struct SegmentLanes<T> {
    ax: T,
    ay: T,
    ex: T,
    ey: T,
    inv_len2: T,
    inv_len: T,
    width: T,
    dwidth: T,
    depth: T,
    ddepth: T,
    color: [T; 3],
    dcolor: [T; 3],
    profile: ProfileLanes<T>,
}

impl<T: Lane> SegmentLanes<T> {
    /// The body of [`Segment::fragment`].
    #[inline(always)]
    fn fragment(&self, xc: T, yc: T, opacity: T) -> Fragment<T> {
        // 1. Position relative to a; t along the segment.
        let py = yc - self.ay;
        let px = xc - self.ax;
        let t = (px * self.ex + py * self.ey) * self.inv_len2;
        // 2. Signed distance from the line: cross(e, p) / |e|.
        let dist = (self.ex * py - self.ey * px) * self.inv_len;
        // 3. Coverage of the strip, width interpolated along it.
        let width = self.width + t * self.dwidth;
        let alpha = coverage_in(&self.profile, dist, width) * opacity;
        // 4. Depth along the segment (tested against the opaque surfaces
        // by the caller).
        let z = self.depth + t * self.ddepth;
        let mask = !t.lt(T::splat(0.0)) & t.lt(T::splat(1.0)) & alpha.gt(T::splat(0.0));
        // 5. Colour along the segment.
        let lerp = |i: usize| self.color[i] + self.dcolor[i] * t;
        Fragment {
            mask,
            alpha,
            depth: z,
            color: V3::new(lerp(0), lerp(1), lerp(2)),
        }
    }
}

/// The body of [`Segment::lines`] with `[a, b, e_minor, radius |e|,
/// 1 / |e|^2]` in lanes (`a`, `b` the ends' major coordinates).
#[inline(always)]
fn lines_in<T: Rounding>([a, b, minor, radius_len, inv_len2]: [T; 5]) -> (T, T) {
    let reach = radius_len * minor.abs() * inv_len2;
    let lo = ((a.min(b) - reach) - T::splat(0.5 + SPAN_MARGIN)).ceil();
    let hi = ((a.max(b) + reach) - T::splat(0.5 - SPAN_MARGIN)).floor() + T::splat(1.0);
    (lo, hi)
}

/// The body of [`Segment::band`] with the constants `[a_x, a_y, e_x,
/// 1 / e_y, radius |e|]` in lanes (x and y exchanged for columns).
#[inline(always)]
fn band_in<T: Rounding>(c: T, [ax, ay, ex, inv_ey, radius_len]: [T; 5]) -> (T, T) {
    // dist = (ex py - ey px) / len within [-radius, radius] (with x
    // and y exchanged for columns: the same slab).
    let py = (c + T::splat(0.5)) - ay;
    let exy = ex * py;
    let u = (exy - radius_len) * inv_ey;
    let v = (exy + radius_len) * inv_ey;
    let xa = ((u.min(v) + ax) - T::splat(0.5 + SPAN_MARGIN)).ceil();
    let xb = ((u.max(v) + ax) - T::splat(0.5 - SPAN_MARGIN)).floor() + T::splat(1.0);
    (xa, xb)
}

/// How the tiled rasterisers ([`crate::raster`]) walk a segment's pixels
/// ([`Segment::walk`]).
///
/// The reference ([`draw_segment`]) tests the pixels of each row's span
/// ([`Segment::row_spans`]); the spans are widened by [`SPAN_MARGIN`]
/// so that they contain every pixel [`Segment::pixel`] draws (its `t`
/// in `[0, 1)`, its distance within the strip's reach: the slabs of the
/// span, up to rounding). Any other candidate set that also contains
/// them draws the same pixels with the same bits. The band walks use
/// only the distance slab along the segment's major axis; the rounding
/// of both forms is far below the margin while both ends lie within
/// [`BAND_REACH`] pixels of the origin (a few units of `2^-11` px).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walk {
    /// The reference's row spans (an end farther than [`BAND_REACH`]).
    Rows,
    /// Rows, candidates [`Segment::band`] (`|e_y| >= |e_x|`).
    BandRows,
    /// Columns, candidates [`Segment::band`] (`|e_x| > |e_y|`: a column
    /// crosses at most about three pixels of a thin hair, where a row
    /// crosses `|e_x / e_y|` times more).
    BandColumns,
}

/// How far from the frame's origin (pixels) both ends of a segment lie
/// for the band walks ([`Walk`]).
pub const BAND_REACH: f32 = 4096.0;

/// How far (pixels) a row span reaches past the slabs' ends: pixel
/// centres within this of the exact bounds are tested, so float rounding
/// of the bounds never drops a covered pixel.
pub const SPAN_MARGIN: f32 = 1e-2;

/// Lanes that can round to whole numbers (for [`Segment::row_spans`]).
pub trait Rounding: Lane {
    /// The largest whole number `<= self`, per lane.
    fn floor(self) -> Self;
    /// The smallest whole number `>= self`, per lane.
    fn ceil(self) -> Self;
}

impl Rounding for f32 {
    #[inline(always)]
    fn floor(self) -> f32 {
        f32::floor(self)
    }
    #[inline(always)]
    fn ceil(self) -> f32 {
        f32::ceil(self)
    }
}

impl Rounding for F32Lanes {
    #[inline(always)]
    fn floor(self) -> F32Lanes {
        F32Lanes::floor(self)
    }
    #[inline(always)]
    fn ceil(self) -> F32Lanes {
        F32Lanes::ceil(self)
    }
}

/// [`Segment::pixel_bounds`] as floats (not checked for emptiness).
#[inline(always)]
fn float_bounds(a: &ScreenVertex, b: &ScreenVertex, width: usize, height: usize) -> [f32; 4] {
    let reach = 0.5 * a.width_px.max(b.width_px) + 0.75;
    let (w, h) = (width as f32, height as f32);
    // `Lane::min` / `Lane::max` (one instruction each, the SIMD tile
    // ranges' `fast_min` / `fast_max`): the ends are finite here, and a
    // NaN reach still gives the whole frame as `f32::min` / `f32::max` do.
    let (min, max) = (<f32 as Lane>::min, <f32 as Lane>::max);
    [
        max((min(a.x, b.x) - reach).floor(), 0.0),
        min((max(a.x, b.x) + reach).ceil(), w),
        max((min(a.y, b.y) - reach).floor(), 0.0),
        min((max(a.y, b.y) + reach).ceil(), h),
    ]
}

/// `dst + (c - dst) alpha` per lane: the blend every hair fragment gets.
#[inline(always)]
pub fn blend<T: Lane>(dst: T, color: T, alpha: T) -> T {
    dst + (color - dst) * alpha
}

/// Blends segment `a -> b` into `frame` with `alpha = coverage * opacity`:
/// `c <- c + alpha (colour - c)`, colour, width and depth interpolated
/// linearly along the segment ([`Segment::pixel`]). Pixels whose stored
/// depth (the head) is nearer than the segment are left alone. Calls
/// `visit` with every pixel index and alpha it blends (tests use it to sum
/// coverage; pass `|_, _| {}`). This is the direct reference: one segment
/// at a time over the whole frame, row by row ([`Segment::row_span`]).
#[inline]
pub fn draw_segment(
    frame: &mut Framebuffer,
    a: &ScreenVertex,
    b: &ScreenVertex,
    opacity: f32,
    mut visit: impl FnMut(usize, f32),
) {
    let width = frame.width();
    let Some(seg) = Segment::new(a, b, width, frame.height()) else {
        return;
    };
    let [_, _, y0, y1] = seg.bounds();
    for y in y0..y1 {
        let Some((xa, xb)) = seg.row_span(y) else {
            continue;
        };
        let row = y * width;
        for x in xa..xb {
            let i = row + x;
            let dst = &mut frame.pixels[i];
            let f = seg.pixel(x as f32 + 0.5, y as f32 + 0.5, dst.depth, opacity);
            if !f.mask {
                continue;
            }
            dst.color = Vec3::new(
                blend(dst.color.x, f.color.x, f.alpha),
                blend(dst.color.y, f.color.y, f.alpha),
                blend(dst.color.z, f.color.z, f.alpha),
            );
            visit(i, f.alpha);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_profile_has_unit_area_and_strips_integrate_to_their_width() {
        for (dx, dy) in [
            (1.0f32, 0.0f32),
            (0.0, 1.0),
            (1.0, 1.0),
            (3.0, -1.0),
            (-0.2, 1.0),
        ] {
            let p = PixelProfile::for_direction(dx, dy);
            assert_eq!(p.cumulative(-2.0), 0.0);
            assert_eq!(p.cumulative(2.0), 1.0);
            assert!((p.cumulative(0.0) - 0.5).abs() < 1e-6, "symmetric");
            for w in [0.1f32, 0.35, 0.8, 1.7, 3.2] {
                let n = 20_000;
                let step = 8.0 / n as f32;
                let sum: f32 = (0..n)
                    .map(|k| p.coverage(-4.0 + (k as f32 + 0.5) * step, w) * step)
                    .sum();
                assert!(
                    (sum - w).abs() < 1e-3 * w.max(1.0),
                    "({dx}, {dy}) w {w}: {sum}"
                );
                assert!(p.coverage(0.0, w) <= 1.0);
            }
        }
        // Axis-aligned: a box one pixel wide.
        let p = PixelProfile::for_direction(1.0, 0.0);
        assert!((p.coverage(0.0, 0.25) - 0.25).abs() < 1e-6);
        assert!((p.coverage(0.5, 0.5) - 0.25).abs() < 1e-6);
        assert_eq!(p.coverage(2.0, 0.5), 0.0);
        assert_eq!(p.coverage(0.0, f32::NAN), 0.0);
    }

    /// Lane `l` of `x8`'s lines, bands and fragments (rows and columns,
    /// pixel centres around the segment) against `one`'s, bit for bit.
    fn lanes_match_the_segment(x8: &SegmentsLanes, l: usize, one: &Segment) {
        let lane = |v: F32Lanes| v.to_array()[l].to_bits();
        for columns in [false, true] {
            let mask = F32Lanes::splat(if columns { 1.0 } else { 0.0 }).simd_gt(F32Lanes::ZERO);
            let (lo, hi) = x8.lines(mask);
            let (want_lo, want_hi) = one.lines(columns);
            assert_eq!([lane(lo), lane(hi)], [want_lo, want_hi].map(f32::to_bits));
            for c in [-3.0f32, 0.0, 17.0, 60.0] {
                let (a, b) = x8.band(F32Lanes::splat(c), mask);
                let (want_a, want_b) = one.band(c, columns);
                assert_eq!([lane(a), lane(b)], [want_a, want_b].map(f32::to_bits));
            }
        }
        let [x0, _, y0, _] = one.float_bounds();
        for (dx, dy) in [(0.5f32, 0.5f32), (1.5, 2.5), (3.5, 0.5), (2.5, 4.5)] {
            let (x, y) = (x0 + dx, y0 + dy);
            let f = x8.fragment(F32Lanes::splat(x), F32Lanes::splat(y), 0.8);
            let want = one.fragment(x, y, 0.8);
            assert_eq!(f.mask.to_bitmask() >> l & 1 != 0, want.mask);
            let got = [f.alpha, f.depth, f.color.x, f.color.y, f.color.z].map(lane);
            let want = [
                want.alpha,
                want.depth,
                want.color.x,
                want.color.y,
                want.color.z,
            ];
            assert_eq!(got, want.map(f32::to_bits));
        }
    }

    #[test]
    fn lane_segment_set_up_has_the_bits_of_the_scalar_one() {
        // Every field, and the lane-by-lane lines, bands and fragments.
        // Random ends (some off the frame), axis-aligned and diagonal
        // segments, lengths from below the 1e-6 px cut-off up, widths 0
        // to 4 px; in chunks of 1 to LANES so that absent lanes are covered.
        let mut rng = coif_base::SplitMix64::new(41);
        let mut screen = Vec::new();
        for i in 0..400 {
            let a = ScreenVertex {
                x: rng.range(-20.0, 120.0),
                y: rng.range(-20.0, 120.0),
                depth: rng.range(0.5, 3.0),
                width_px: rng.range(0.0, 4.0),
                color: Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), 0.3),
            };
            let (dx, dy) = match i % 5 {
                0 => (rng.range(-9.0, 9.0), 0.0),
                1 => (0.0, rng.range(-9.0, 9.0)),
                2 => {
                    let d = rng.range(-9.0, 9.0);
                    (d, -d)
                }
                3 => (rng.range(-1e-6, 1e-6), rng.range(-1e-6, 1e-6)),
                _ => (rng.range(-9.0, 9.0), rng.range(-9.0, 9.0)),
            };
            let b = ScreenVertex {
                x: a.x + dx,
                y: a.y + dy,
                width_px: rng.range(0.0, 4.0),
                ..a
            };
            screen.extend([a, b]);
        }
        let first: Vec<u32> = (0..400).map(|i| 2 * i).collect();
        let (mut some, mut none) = (0, 0);
        let mut at = 0;
        for len in (1..=LANES).cycle() {
            if at >= first.len() {
                break;
            }
            let chunk = &first[at..(at + len).min(first.len())];
            let x8 = Segment::new_simd(&screen, chunk, 100, 100);
            for (l, &k) in chunk.iter().enumerate() {
                let k = k as usize;
                let one = Segment::new(&screen[k], &screen[k + 1], 100, 100);
                let got = x8.lane(l);
                assert_eq!(format!("{one:?}"), format!("{got:?}"), "segment {k}");
                if let Some(one) = one {
                    lanes_match_the_segment(&x8, l, &one);
                }
                if one.is_some() {
                    some += 1;
                } else {
                    none += 1;
                }
            }
            assert!((chunk.len()..LANES).all(|l| x8.lane(l).is_none()));
            at += len;
        }
        assert!(some > 120 && none > 80, "{some} drawn, {none} not");
    }
}
