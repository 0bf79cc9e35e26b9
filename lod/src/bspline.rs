//! Uniform cubic B-splines with phantom end points (as in
//! Alice: Madness Returns; any text on B-splines, e.g. Farin, "Curves and
//! Surfaces for CAGD", ch. 7).
//!
//! Control points `P_0 .. P_{n-1}` get phantom ends `P_{-1} = 2 P_0 - P_1` and
//! `P_n = 2 P_{n-1} - P_{n-2}`, so the curve starts exactly at `P_0` and ends
//! exactly at `P_{n-1}`. Span `j` (`0 <= j <= n - 2`) uses
//! `P_{j-1}, P_j, P_{j+1}, P_{j+2}` with, at `t` in `[0, 1]`,
//!
//! ```text
//! b0 = (1-t)^3 / 6              b1 = (3t^3 - 6t^2 + 4) / 6
//! b2 = (-3t^3 + 3t^2 + 3t + 1) / 6   b3 = t^3 / 6
//! d/dt: ( -(1-t)^2, 3t^2 - 4t, -3t^2 + 2t + 1, t^2 ) / 2
//! ```

use glam::Vec3;

/// Position weights `(b0, b1, b2, b3)` of a span at `t` in `[0, 1]`.
#[inline]
pub fn basis(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    [
        s * s * s / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    ]
}

/// Derivative weights `d b_i / dt` of a span at `t` in `[0, 1]`.
#[inline]
pub fn basis_derivative(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [
        -0.5 * s * s,
        0.5 * (3.0 * t * t - 4.0 * t),
        0.5 * (-3.0 * t * t + 2.0 * t + 1.0),
        0.5 * t * t,
    ]
}

/// Control point `i` of the extended polygon, `-1 <= i <= n`: the phantom
/// ends `2 P_0 - P_1` and `2 P_{n-1} - P_{n-2}` outside `0..n`. Meant for
/// `n >= 2`; without a polygon to extend (no panics): `n = 1` gives the
/// single point for every `i`, `n = 0` gives NaN.
#[inline]
pub fn control_point(control: &[Vec3], i: isize) -> Vec3 {
    let n = control.len() as isize;
    if n < 2 {
        return control.first().copied().unwrap_or(Vec3::NAN);
    }
    if i < 0 {
        2.0 * control[0] - control[1]
    } else if i >= n {
        2.0 * control[(n - 1) as usize] - control[(n - 2) as usize]
    } else {
        control[i as usize]
    }
}

/// Number of curve points [`refine`] writes for `n_control` control points:
/// `(n - 1) * N + 1` for `n >= 1` (with `N = 0` treated as `N = 1`), 0 for `n = 0`.
#[inline]
pub fn refined_len(n_control: usize, segments_per_span: usize) -> usize {
    if n_control == 0 {
        0
    } else {
        (n_control - 1) * segments_per_span.max(1) + 1
    }
}

/// The curve at global parameter `u` in `[0, n - 1]` (clamped): span
/// `j = min(floor(u), n - 2)`, `t = u - j`. Meant for `n >= 2`; no panics
/// below: `n = 1` gives the single point, `n = 0` gives NaN.
pub fn evaluate(control: &[Vec3], u: f32) -> Vec3 {
    if control.len() < 2 {
        return control.first().copied().unwrap_or(Vec3::NAN);
    }
    let (j, t) = span_of(control.len(), u);
    combine(control, j, basis(t))
}

/// The curve's derivative `dC/du` at global parameter `u` (see
/// [`evaluate`]); zero for `n = 1`, NaN for `n = 0`.
pub fn evaluate_derivative(control: &[Vec3], u: f32) -> Vec3 {
    match control.len() {
        0 => return Vec3::NAN,
        1 => return Vec3::ZERO,
        _ => {}
    }
    let (j, t) = span_of(control.len(), u);
    combine(control, j, basis_derivative(t))
}

fn span_of(n: usize, u: f32) -> (usize, f32) {
    let last = (n - 2) as f32;
    let u = u.clamp(0.0, last + 1.0);
    let j = u.floor().min(last);
    (j as usize, u - j)
}

#[inline]
fn combine(control: &[Vec3], j: usize, w: [f32; 4]) -> Vec3 {
    let j = j as isize;
    let p0 = control_point(control, j - 1);
    let p1 = control_point(control, j);
    let p2 = control_point(control, j + 1);
    let p3 = control_point(control, j + 2);
    p0 * w[0] + p1 * w[1] + p2 * w[2] + p3 * w[3]
}

/// Uniform cubic B-spline through the first and last control point, with
/// `segments_per_span` segments per span. Clears `out`, then writes
/// [`refined_len`]`(n, N)` points: the curve at `u = k / N`, `k = 0 ..= (n-1) N`.
///
/// Edge cases (no panics): `n = 0` writes nothing; `n = 1` writes the single
/// point; `N = 0` is treated as `N = 1`. The first and last points are the
/// first and last control points exactly (bit for bit). Non-finite control
/// points give non-finite curve points only in the spans that use them.
///
/// # Panics
///
/// Only as an allocation does: if the output (`refined_len(n, N)` points)
/// cannot be allocated, e.g. for an absurd `N` such as `usize::MAX`.
pub fn refine(control: &[Vec3], segments_per_span: usize, out: &mut Vec<Vec3>) {
    out.clear();
    let n = control.len();
    if n < 2 {
        out.extend_from_slice(control);
        return;
    }
    let weights = SpanWeights::new(segments_per_span);
    out.reserve(refined_len(n, segments_per_span));
    for j in 0..n - 1 {
        for k in 0..weights.segments_per_span() {
            out.push(combine(control, j, weights.position(k)));
        }
    }
    out.push(control[n - 1]);
    out[0] = control[0];
}

/// [`refine`] plus unit tangents (the normalised derivative, root to tip;
/// `Vec3::Y` where the derivative vanishes). Clears both outputs.
///
/// # Panics
///
/// As [`refine`]: only if the outputs cannot be allocated.
pub fn refine_with_tangents(
    control: &[Vec3],
    segments_per_span: usize,
    positions: &mut Vec<Vec3>,
    tangents: &mut Vec<Vec3>,
) {
    refine(control, segments_per_span, positions);
    tangents.clear();
    let n = control.len();
    if n < 2 {
        tangents.extend(control.iter().map(|_| Vec3::Y));
        return;
    }
    let weights = SpanWeights::new(segments_per_span);
    let segs = weights.segments_per_span();
    for j in 0..n - 1 {
        let last = if j == n - 2 { segs } else { segs - 1 };
        for k in 0..=last {
            let d = combine(control, j, weights.tangent(k));
            tangents.push(d.try_normalize().unwrap_or(Vec3::Y));
        }
    }
}

/// Position and derivative weights at `t = k / N`, `k = 0 ..= N`, computed
/// once per segments-per-span `N` (precompute the weights once, not per vertex).
#[derive(Clone, Debug, PartialEq)]
pub struct SpanWeights {
    segments_per_span: usize,
    position: Vec<[f32; 4]>,
    tangent: Vec<[f32; 4]>,
}

impl SpanWeights {
    /// Weights for `segments_per_span` (0 is treated as 1).
    ///
    /// # Panics
    ///
    /// Only if the `N + 1` weights cannot be allocated (an absurd `N`).
    pub fn new(segments_per_span: usize) -> SpanWeights {
        let n = segments_per_span.max(1);
        let t = |k: usize| k as f32 / n as f32;
        SpanWeights {
            segments_per_span: n,
            position: (0..=n).map(|k| basis(t(k))).collect(),
            tangent: (0..=n).map(|k| basis_derivative(t(k))).collect(),
        }
    }

    /// Segments per span `N` the weights were made for.
    pub fn segments_per_span(&self) -> usize {
        self.segments_per_span
    }

    /// Position weights at `t = k / N`.
    ///
    /// # Panics
    ///
    /// If `k > N` (as slice indexing does).
    #[inline]
    pub fn position(&self, k: usize) -> [f32; 4] {
        self.position[k]
    }

    /// Derivative weights at `t = k / N`.
    ///
    /// # Panics
    ///
    /// If `k > N` (as slice indexing does).
    #[inline]
    pub fn tangent(&self, k: usize) -> [f32; 4] {
        self.tangent[k]
    }

    /// [`SpanWeights::position`], or `None` for `k > N`.
    pub fn get_position(&self, k: usize) -> Option<[f32; 4]> {
        self.position.get(k).copied()
    }

    /// [`SpanWeights::tangent`], or `None` for `k > N`.
    pub fn get_tangent(&self, k: usize) -> Option<[f32; 4]> {
        self.tangent.get(k).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_partition_unity_and_derivatives_sum_to_zero() {
        for k in 0..=10 {
            let t = k as f32 / 10.0;
            let b = basis(t);
            let d = basis_derivative(t);
            assert!((b.iter().sum::<f32>() - 1.0).abs() < 1e-6);
            assert!(d.iter().sum::<f32>().abs() < 1e-6);
            assert!(b.iter().all(|&w| w >= 0.0));
        }
    }

    #[test]
    fn edge_cases_do_not_panic() {
        let mut out = vec![Vec3::ONE; 3];
        refine(&[], 4, &mut out);
        assert!(out.is_empty());
        refine(&[Vec3::X], 4, &mut out);
        assert_eq!(out, vec![Vec3::X]);
        refine(&[Vec3::X, Vec3::Y, Vec3::Z], 0, &mut out);
        assert_eq!(out.len(), refined_len(3, 0));
        assert_eq!(out.len(), 3);
    }

    #[test]
    fn two_points_give_a_straight_line() {
        let mut out = Vec::new();
        refine(&[Vec3::ZERO, Vec3::new(3.0, 0.0, 0.0)], 3, &mut out);
        for (k, p) in out.iter().enumerate() {
            assert!((p.x - k as f32).abs() < 1e-5, "{p}");
        }
    }
}
