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
use glam::Vec3;

/// A projected hair vertex: pixel position, view depth, width in pixels and
/// linear-RGB colour.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
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
}

impl PixelProfile {
    /// The profile across a line of direction `(dx, dy)` (any length > 0).
    pub fn for_direction(dx: f32, dy: f32) -> PixelProfile {
        let len = (dx * dx + dy * dy).sqrt();
        let (a, b) = ((dy / len).abs(), (dx / len).abs());
        let (lo, hi) = (a.min(b), a.max(b));
        PixelProfile {
            half: 0.5 * (a + b),
            plateau: 0.5 * (hi - lo),
            ramp: lo,
            height: 1.0 / hi,
        }
    }

    /// `G(x)`: the share of the pixel on the side `<= x` of a line at
    /// signed distance `x` from its centre.
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
    /// centre line is `distance` pixels from the pixel's centre.
    #[inline]
    pub fn coverage(&self, distance: f32, width_px: f32) -> f32 {
        if width_px.is_nan() || width_px <= 0.0 {
            return 0.0;
        }
        (self.cumulative(distance + 0.5 * width_px) - self.cumulative(distance - 0.5 * width_px))
            .clamp(0.0, 1.0)
    }
}

/// Blends segment `a -> b` into `frame` with `alpha = coverage * opacity`:
/// `c <- c + alpha (colour - c)`, colour, width and depth interpolated
/// linearly along the segment. Pixels whose stored depth (the head) is
/// nearer than the segment are left alone. Calls `visit` with every pixel
/// index and alpha it blends (tests use it to sum coverage; pass `|_, _| {}`).
#[inline]
pub fn draw_segment(
    frame: &mut Framebuffer,
    a: &ScreenVertex,
    b: &ScreenVertex,
    opacity: f32,
    mut visit: impl FnMut(usize, f32),
) {
    let (ex, ey) = (b.x - a.x, b.y - a.y);
    let len2 = ex * ex + ey * ey;
    if len2.is_nan() || len2 <= 1e-12 || !len2.is_finite() {
        return;
    }
    let inv_len2 = 1.0 / len2;
    let inv_len = inv_len2.sqrt();
    let profile = PixelProfile::for_direction(ex, ey);
    let reach = 0.5 * a.width_px.max(b.width_px) + 0.75;
    let (w, h) = (frame.width() as f32, frame.height() as f32);
    let x0 = (a.x.min(b.x) - reach).floor().max(0.0);
    let x1 = (a.x.max(b.x) + reach).ceil().min(w);
    let y0 = (a.y.min(b.y) - reach).floor().max(0.0);
    let y1 = (a.y.max(b.y) + reach).ceil().min(h);
    if !(x0 < x1 && y0 < y1) {
        return;
    }
    let (y0, y1) = (y0 as usize, y1 as usize);
    let width = frame.width();
    // Pixels that can be touched lie in two slabs: |dist| <= radius (the
    // strip plus the pixel profile's half-width) and 0 <= t < 1. Both are
    // linear in x on a row, so each row visits only the x range inside both
    // (widened by a pixel; the exact tests below decide).
    let radius = profile.half + 0.5 * a.width_px.max(b.width_px);
    let len = len2.sqrt();
    for y in y0..y1 {
        let py = y as f32 + 0.5 - a.y;
        let (mut lo, mut hi) = (x0 - a.x - 0.5, x1 - a.x - 0.5);
        // dist = (ex py - ey px) / len within [-radius, radius].
        if ey != 0.0 {
            let (u, v) = ((ex * py - radius * len) / ey, (ex * py + radius * len) / ey);
            lo = lo.max(u.min(v));
            hi = hi.min(u.max(v));
        }
        // t = (ex px + ey py) / len2 within [0, 1].
        if ex != 0.0 {
            let (u, v) = (-py * ey / ex, (len2 - py * ey) / ex);
            lo = lo.max(u.min(v));
            hi = hi.min(u.max(v));
        }
        if lo.is_nan() || hi.is_nan() || lo > hi {
            continue;
        }
        // px = x + 0.5 - a.x.
        let xa = (lo + a.x - 0.5).floor().max(x0) as usize;
        let xb = ((hi + a.x - 0.5).ceil() + 1.0).min(x1) as usize;
        let row = y * width;
        for x in xa..xb {
            let px = x as f32 + 0.5 - a.x;
            let t = (px * ex + py * ey) * inv_len2;
            if !(0.0..1.0).contains(&t) {
                continue;
            }
            // Signed perpendicular distance: cross(e, p) / |e|.
            let dist = (ex * py - ey * px) * inv_len;
            let cov = profile.coverage(dist, a.width_px + t * (b.width_px - a.width_px));
            if cov <= 0.0 {
                continue;
            }
            let i = row + x;
            let depth = a.depth + t * (b.depth - a.depth);
            let dst = &mut frame.pixels[i];
            if depth >= dst.depth {
                continue;
            }
            let alpha = cov * opacity;
            let c = a.color + (b.color - a.color) * t;
            dst.color += (c - dst.color) * alpha;
            visit(i, alpha);
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
}
