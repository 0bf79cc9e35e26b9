//! Choosing the refinement level from screen size .
//!
//! On span `j` the curve's second derivative is the linear blend
//! `C''(t) = (1 - t) d2P_j + t d2P_{j+1}` of the control polygon's second
//! differences `d2P_i = P_{i-1} - 2 P_i + P_{i+1}`, so `|C''| <= max |d2P|`.
//! Linear interpolation over a parameter step `h = 1 / N` is off by at most
//! `h^2 / 8 max |C''|` (the standard interpolation error bound), hence the
//! chord error of `N` segments per span is at most `max |d2P| / (8 N^2)`, and
//!
//! ```text
//! N = ceil( sqrt( max|d2P|_px / (8 eps_px) ) )
//! ```
//!
//! keeps it under `eps_px` pixels. The phantom ends add no second difference
//! (`P_{-1} - 2 P_0 + P_1 = 0`).

use coif_base::lanes::F32Lanes;
use coif_base::StrandBlocks;
use glam::Vec3;

/// `max |P_{i-1} - 2 P_i + P_{i+1}|` over the interior control points
/// (0 for fewer than three points; NaN points are ignored).
pub fn max_second_difference(control: &[Vec3]) -> f32 {
    control
        .windows(3)
        .map(|w| (w[0] - 2.0 * w[1] + w[2]).length())
        .fold(0.0, f32::max)
}

/// The largest control-polygon second difference over every strand of a set
/// (SIMD over the eight strands of a block; padding lanes repeat a real
/// strand, so they change nothing). In metres. NaN lanes are ignored.
pub fn max_second_difference_strands(strands: StrandBlocks<'_>) -> f32 {
    let mut m = F32Lanes::ZERO;
    for b in 0..strands.block_count() {
        let p = strands.block_positions_local(b);
        for w in p.windows(3) {
            let d = w[0] - w[1] - w[1] + w[2];
            // wide's max ignores NaN (like f32::max), so NaN lanes keep m.
            m = d.dot(d).sqrt().max(m);
        }
    }
    m.as_array().iter().copied().fold(0.0, f32::max)
}

/// The chord-error bound `max_d2 / (8 N^2)` of `N` segments per span (in the
/// units of `max_d2`). `N = 0` is treated as 1.
pub fn chord_error_bound(max_d2: f32, segments_per_span: usize) -> f32 {
    let n = segments_per_span.max(1) as f32;
    max_d2 / (8.0 * n * n)
}

/// Smallest `N` in `1 ..= max_segments` with `max_d2_px / (8 N^2) <= eps_px`:
/// `ceil(sqrt(max_d2_px / (8 eps_px)))`, clamped. Non-positive or NaN
/// budgets give `max_segments`; a NaN or zero curvature gives 1.
pub fn segments_for_error(max_d2_px: f32, eps_px: f32, max_segments: usize) -> usize {
    let max_segments = max_segments.max(1);
    if max_d2_px.is_nan() || max_d2_px <= 0.0 {
        return 1;
    }
    if eps_px.is_nan() || eps_px <= 0.0 {
        return max_segments;
    }
    let n = (max_d2_px / (8.0 * eps_px)).sqrt().ceil();
    if n >= max_segments as f32 {
        max_segments
    } else {
        (n as usize).max(1)
    }
}

/// Pixels per metre at `distance` in front of a perspective camera of
/// vertical field of view `fov_y` (radians) on a viewport `viewport_height_px`
/// high: `H / (2 d tan(fov_y / 2))`.
pub fn pixels_per_metre(distance: f32, fov_y: f32, viewport_height_px: f32) -> f32 {
    viewport_height_px / (2.0 * distance * (0.5 * fov_y).tan())
}

/// The level for a set whose largest control-polygon second difference is
/// `max_d2_m` metres, seen at `pixels_per_metre`, with an error budget of
/// `eps_px` pixels: [`segments_for_error`] of the projected size.
pub fn segments_per_span(
    max_d2_m: f32,
    pixels_per_metre: f32,
    eps_px: f32,
    max_segments: usize,
) -> usize {
    segments_for_error(max_d2_m * pixels_per_metre, eps_px, max_segments)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_is_the_smallest_that_meets_the_budget() {
        for &(d2, eps) in &[(10.0f32, 0.5f32), (1.0, 1.0), (300.0, 0.25), (0.01, 0.5)] {
            let n = segments_for_error(d2, eps, 64);
            assert!(chord_error_bound(d2, n) <= eps * 1.0001, "{d2} {eps} {n}");
            if n > 1 {
                assert!(chord_error_bound(d2, n - 1) > eps, "{d2} {eps} {n}");
            }
        }
        assert_eq!(segments_for_error(1e9, 0.1, 16), 16);
        assert_eq!(segments_for_error(f32::NAN, 0.1, 16), 1);
        assert_eq!(segments_for_error(5.0, 0.0, 16), 16);
    }
}
