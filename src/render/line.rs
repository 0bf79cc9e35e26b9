//! Anti-aliased lines of sub-pixel width.
//!
//! A hair segment is a strip of width `w` pixels around the line through its
//! two projected ends. The share of pixel `P` it covers is taken from the
//! perpendicular distance `d` of `P`'s centre to the line, with a box filter
//! one pixel wide across the line:
//!
//! ```text
//! W = max(w, 1)                                   (drawn at least a pixel wide ...)
//! coverage(d, w) = |[d - W/2, d + W/2] ∩ [-1/2, 1/2]| * w / W   (... with alpha scaled by w / W)
//! ```
//!
//! so that the coverage summed across the line is `w` for any `d` offset
//! (`∫ coverage dd = W * w / W = w`): a line of length `L` covers an area of
//! `w L` pixels, the analytic area, however thin it is (the test draws lines
//! at several angles and widths and compares). Along the line, a pixel
//! belongs to the segment when its centre projects to a parameter
//! `t` in `[0, 1)`: consecutive segments of a polyline abut without
//! double-blending their shared end.

use super::Framebuffer;
use glam::Vec3;

/// A projected hair vertex: pixel position, view depth, width in pixels and
/// linear-RGB colour.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ScreenVertex {
    pub x: f32,
    pub y: f32,
    pub depth: f32,
    pub width_px: f32,
    pub color: Vec3,
}

/// Share of a pixel covered by a line of width `width_px` whose centre is
/// `distance` pixels from the pixel's centre (see the module doc).
#[inline]
pub fn coverage(distance: f32, width_px: f32) -> f32 {
    if width_px.is_nan() || width_px <= 0.0 {
        return 0.0;
    }
    let drawn = width_px.max(1.0);
    let d = distance.abs();
    let lo = (d - 0.5 * drawn).max(-0.5);
    let hi = (d + 0.5 * drawn).min(0.5);
    (hi - lo).max(0.0) * (width_px / drawn)
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
    let reach = 0.5 * a.width_px.max(b.width_px).max(1.0) + 0.5;
    let (w, h) = (frame.width() as f32, frame.height() as f32);
    let x0 = (a.x.min(b.x) - reach).floor().max(0.0);
    let x1 = (a.x.max(b.x) + reach).ceil().min(w);
    let y0 = (a.y.min(b.y) - reach).floor().max(0.0);
    let y1 = (a.y.max(b.y) + reach).ceil().min(h);
    if !(x0 < x1 && y0 < y1) {
        return;
    }
    let (x0, x1, y0, y1) = (x0 as usize, x1 as usize, y0 as usize, y1 as usize);
    let width = frame.width();
    for y in y0..y1 {
        let py = y as f32 + 0.5 - a.y;
        let row = y * width;
        for x in x0..x1 {
            let px = x as f32 + 0.5 - a.x;
            let t = (px * ex + py * ey) * inv_len2;
            if !(0.0..1.0).contains(&t) {
                continue;
            }
            // Perpendicular distance: |cross(e, p)| / |e|.
            let dist = (ex * py - ey * px).abs() * inv_len;
            let cov = coverage(dist, a.width_px + t * (b.width_px - a.width_px));
            if cov <= 0.0 {
                continue;
            }
            let i = row + x;
            let depth = a.depth + t * (b.depth - a.depth);
            if depth >= frame.depth[i] {
                continue;
            }
            let alpha = cov * opacity;
            let c = a.color + (b.color - a.color) * t;
            let dst = &mut frame.color[i];
            *dst += (c - *dst) * alpha;
            visit(i, alpha);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coverage_integrates_to_the_width_across_the_line() {
        for w in [0.1f32, 0.35, 0.8, 1.0, 1.7, 3.2] {
            let n = 20_000;
            let step = 8.0 / n as f32;
            let sum: f32 = (0..n)
                .map(|k| coverage(-4.0 + (k as f32 + 0.5) * step, w) * step)
                .sum();
            assert!((sum - w).abs() < 1e-3 * w.max(1.0), "w {w}: {sum}");
            assert!(coverage(0.0, w) <= 1.0 + 1e-6);
        }
        assert_eq!(coverage(0.0, 0.0), 0.0);
        assert_eq!(coverage(0.0, f32::NAN), 0.0);
        assert_eq!(coverage(2.0, 0.5), 0.0);
    }
}
