//! Opaque triangles: edge functions, the top-left rule, a depth test.
//!
//! A triangle with projected corners `a, b, c` (pixels, y down) covers the
//! pixels whose **centre** `p = (i + 0.5, j + 0.5)` lies inside it: with the
//! edge function of edge `u -> v`
//!
//! ```text
//! E_uv(p) = (v_x - u_x)(p_y - u_y) - (v_y - u_y)(p_x - u_x)
//! ```
//!
//! (twice the signed area of `u, v, p`; Pineda 1988), `p` is inside when
//! the three edge functions have the sign of the triangle's area. A centre
//! exactly on an edge belongs to the triangle only if the edge's inward
//! normal `(-(v_y - u_y), v_x - u_x)` points to `+x`, or along `+y` for a
//! horizontal edge (a top-left rule): the two triangles sharing an edge see
//! opposite normals, so such a pixel is drawn exactly once. To make that
//! exact in floating point, an edge function is always evaluated with its
//! ends in one canonical order (the lexicographically smaller end first)
//! and negated for the other direction, so both triangles get the same
//! number up to its sign. A mesh of triangles that share edges therefore
//! covers every pixel centre inside it once: no gaps, no double blends.
//!
//! Pixel-centre sampling is a point sample of the coverage: the number of
//! pixels drawn equals the triangle's area up to the pixels along its
//! boundary, and averaged over sub-pixel offsets it equals the area exactly
//! (`render/tests/triangles.rs` measures both).
//!
//! Inside, the barycentric weights `l_k = E_k / (E_ab + E_bc + E_ca)` give
//! perspective-correct depth and colour: `1/z` is linear in screen space,
//! so `z = 1 / sum l_k / z_k` and `colour = z sum l_k colour_k / z_k`.
//! A pixel is written (colour and depth) when the triangle is nearer than
//! the depth already stored there (the head's, an earlier triangle's).
//! Triangles are two-sided: either winding is drawn.

use super::{Framebuffer, Pixel};
use glam::Vec3;

/// A projected corner: pixel position, view depth (> 0) and linear-RGB
/// colour.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriangleVertex {
    /// Pixel column (x right).
    pub x: f32,
    /// Pixel row (y down).
    pub y: f32,
    /// View depth (> 0).
    pub depth: f32,
    /// Linear-RGB colour.
    pub color: Vec3,
}

/// One edge's function `E(p) = e_x (p_y - o_y) - e_y (p_x - o_x)`, in f64,
/// evaluated from the canonical end `o` and negated if needed.
#[derive(Clone, Copy, Debug)]
struct Edge {
    ox: f64,
    oy: f64,
    ex: f64,
    ey: f64,
    sign: f64,
    /// Whether a centre exactly on the edge is inside (top-left rule).
    owns_boundary: bool,
}

impl Edge {
    fn new(u: &TriangleVertex, v: &TriangleVertex, orientation: f64) -> Edge {
        let (u2, v2) = ((u.x as f64, u.y as f64), (v.x as f64, v.y as f64));
        let (o, t, sign) = if u2 <= v2 {
            (u2, v2, 1.0)
        } else {
            (v2, u2, -1.0)
        };
        let sign = sign * orientation;
        // Inward normal of u -> v for a positive orientation: (-dy, dx).
        let (dx, dy) = ((v2.0 - u2.0) * orientation, (v2.1 - u2.1) * orientation);
        let (nx, ny) = (-dy, dx);
        Edge {
            ox: o.0,
            oy: o.1,
            ex: t.0 - o.0,
            ey: t.1 - o.1,
            sign,
            owns_boundary: nx > 0.0 || (nx == 0.0 && ny > 0.0),
        }
    }

    /// The edge function, positive inside.
    #[inline]
    fn eval(&self, px: f64, py: f64) -> f64 {
        self.sign * (self.ex * (py - self.oy) - self.ey * (px - self.ox))
    }

    #[inline]
    fn inside(&self, e: f64) -> bool {
        e > 0.0 || (e == 0.0 && self.owns_boundary)
    }
}

/// Draws the opaque triangle `a, b, c` (either winding) into `frame` with
/// a depth test; see the module doc for the coverage rule and the
/// interpolation. Calls `visit(pixel_index)` for every pixel written.
/// Returns the number of pixels written. Degenerate triangles, corners
/// with a non-finite position or a depth `<= 0` draw nothing.
pub fn fill_triangle(
    frame: &mut Framebuffer,
    a: &TriangleVertex,
    b: &TriangleVertex,
    c: &TriangleVertex,
    mut visit: impl FnMut(usize),
) -> usize {
    let (w, h) = (frame.width(), frame.height());
    let Some(setup) = TriangleSetup::new(a, b, c, w, h) else {
        return 0;
    };
    let [x0, x1, y0, y1] = setup.pixels;
    let mut written = 0;
    for y in y0..y1 {
        let row = &mut frame.pixels[y * w..(y + 1) * w];
        written += setup.fill_row(y, x0..x1, row, 0, |x| visit(y * w + x));
    }
    written
}

/// A triangle ready to fill: its edge functions, the pixels whose centre
/// can be inside, and what the interpolation needs. Every pixel's result
/// depends on the pixel alone (no incremental stepping), so filling the
/// triangle's pixels in any pieces (a tile at a time,
/// [`crate::triangle_bins`]) writes the same bits as [`fill_triangle`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct TriangleSetup {
    edges: [Edge; 3],
    /// `[x0, x1, y0, y1]`: the pixels whose centre can be inside, within
    /// the frame (never empty).
    pub(crate) pixels: [usize; 4],
    inv_area: f64,
    inv_z: [f32; 3],
    color_z: [Vec3; 3],
}

impl TriangleSetup {
    /// The triangle `a, b, c` in a `width x height` frame, or `None` when
    /// it draws nothing: a corner with a non-finite position or a depth
    /// `<= 0`, zero or non-finite area, or no pixel centre in the frame
    /// within its bounds.
    pub(crate) fn new(
        a: &TriangleVertex,
        b: &TriangleVertex,
        c: &TriangleVertex,
        width: usize,
        height: usize,
    ) -> Option<TriangleSetup> {
        let pixels = Self::pixel_bounds(a, b, c, width, height)?;
        let area2 = (b.x as f64 - a.x as f64) * (c.y as f64 - a.y as f64)
            - (b.y as f64 - a.y as f64) * (c.x as f64 - a.x as f64);
        if area2 == 0.0 || !area2.is_finite() {
            return None;
        }
        let orientation = area2.signum();
        // Edge k is opposite corner k: its function is corner k's weight.
        let edges = [
            Edge::new(b, c, orientation),
            Edge::new(c, a, orientation),
            Edge::new(a, b, orientation),
        ];
        let inv_z = [1.0 / a.depth, 1.0 / b.depth, 1.0 / c.depth];
        Some(TriangleSetup {
            edges,
            pixels,
            inv_area: 1.0 / area2.abs(),
            inv_z,
            color_z: [a.color * inv_z[0], b.color * inv_z[1], c.color * inv_z[2]],
        })
    }

    /// `[x0, x1, y0, y1]`, the pixels of a `width x height` frame whose
    /// centre can be inside the triangle `a, b, c` (`i + 0.5` within its
    /// bounds), or `None` when there are none or a corner has a non-finite
    /// position or a depth `<= 0`. A superset of the pixels
    /// [`TriangleSetup::new`] fills, cheap enough to bin by.
    #[inline]
    pub(crate) fn pixel_bounds(
        a: &TriangleVertex,
        b: &TriangleVertex,
        c: &TriangleVertex,
        width: usize,
        height: usize,
    ) -> Option<[usize; 4]> {
        let corners = [a, b, c];
        if corners
            .iter()
            .any(|v| !(v.x.is_finite() && v.y.is_finite() && v.depth.is_finite() && v.depth > 0.0))
        {
            return None;
        }
        let min_x = a.x.min(b.x).min(c.x);
        let max_x = a.x.max(b.x).max(c.x);
        let min_y = a.y.min(b.y).min(c.y);
        let max_y = a.y.max(b.y).max(c.y);
        // Pixels whose centre can be inside: i + 0.5 in [min, max].
        let x0 = (min_x - 0.5).ceil().max(0.0);
        let y0 = (min_y - 0.5).ceil().max(0.0);
        let x1 = ((max_x - 0.5).floor() + 1.0).min(width as f32);
        let y1 = ((max_y - 0.5).floor() + 1.0).min(height as f32);
        (x0 < x1 && y0 < y1).then_some([x0 as usize, x1 as usize, y0 as usize, y1 as usize])
    }

    /// Fills pixels `xs` of row `y`, whose pixels from column `first` on
    /// are `row` (pixel `x` is `row[x - first]`): each centre inside the
    /// triangle and nearer than the depth stored there gets the triangle's
    /// depth and colour, and `visit(x)`. Returns the pixels written.
    #[inline]
    pub(crate) fn fill_row(
        &self,
        y: usize,
        xs: std::ops::Range<usize>,
        row: &mut [Pixel],
        first: usize,
        mut visit: impl FnMut(usize),
    ) -> usize {
        let edges = &self.edges;
        let (inv_z, color_z) = (self.inv_z, self.color_z);
        let py = y as f64 + 0.5;
        let mut written = 0;
        for x in xs {
            let dst = &mut row[x - first];
            let px = x as f64 + 0.5;
            let e = edges.map(|edge| edge.eval(px, py));
            if !(edges[0].inside(e[0]) && edges[1].inside(e[1]) && edges[2].inside(e[2])) {
                continue;
            }
            let l = e.map(|e| (e * self.inv_area) as f32);
            let one_over_z = l[0] * inv_z[0] + l[1] * inv_z[1] + l[2] * inv_z[2];
            let depth = 1.0 / one_over_z;
            if depth.is_nan() || depth >= dst.depth {
                continue;
            }
            let color = (color_z[0] * l[0] + color_z[1] * l[1] + color_z[2] * l[2]) * depth;
            *dst = Pixel { color, depth };
            written += 1;
            visit(x);
        }
        written
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32) -> TriangleVertex {
        TriangleVertex {
            x,
            y,
            depth: 1.0,
            color: Vec3::ONE,
        }
    }

    #[test]
    fn an_axis_aligned_right_triangle_covers_the_centres_below_its_diagonal() {
        // Corners (0,0), (4,0), (0,4): centres (i+.5, j+.5) with i + j + 1 < 4,
        // plus the ones on the diagonal i + j + 1 = 4 if the diagonal owns them.
        let mut frame = Framebuffer::new(8, 8);
        let n = fill_triangle(&mut frame, &v(0.0, 0.0), &v(4.0, 0.0), &v(0.0, 4.0), |_| {});
        let strictly_inside = (0..4)
            .flat_map(|j| (0..4).map(move |i| (i, j)))
            .filter(|(i, j)| i + j + 1 < 4)
            .count();
        assert!(n == strictly_inside || n == strictly_inside + 4, "{n}");
        // The other half of the square gets exactly the rest: 16 in all.
        let m = fill_triangle(&mut frame, &v(4.0, 0.0), &v(4.0, 4.0), &v(0.0, 4.0), |_| {});
        assert_eq!(n + m, 16);
    }

    #[test]
    fn nearer_triangles_win_and_bad_corners_draw_nothing() {
        let mut frame = Framebuffer::new(4, 4);
        let far = |x, y| TriangleVertex {
            depth: 2.0,
            color: Vec3::X,
            ..v(x, y)
        };
        let near = |x, y| TriangleVertex {
            depth: 1.0,
            color: Vec3::Y,
            ..v(x, y)
        };
        assert_eq!(
            fill_triangle(
                &mut frame,
                &near(0., 0.),
                &near(4., 0.),
                &near(0., 4.),
                |_| {}
            ),
            6
        );
        // The far triangle (10 centres: it owns its diagonal) only shows
        // where the near one is not.
        assert_eq!(
            fill_triangle(&mut frame, &far(0., 0.), &far(4., 0.), &far(4., 4.), |_| {}),
            6
        );
        assert_eq!(frame.color(frame.index(0, 0)), Vec3::Y);
        assert_eq!(frame.color(frame.index(3, 0)), Vec3::X);
        let nan = v(f32::NAN, 1.0);
        assert_eq!(
            fill_triangle(&mut frame, &nan, &v(4., 0.), &v(0., 4.), |_| {}),
            0
        );
        let behind = TriangleVertex {
            depth: -1.0,
            ..v(0.0, 0.0)
        };
        assert_eq!(
            fill_triangle(&mut frame, &behind, &v(4., 0.), &v(0., 4.), |_| {}),
            0
        );
    }

    #[test]
    fn depth_and_colour_are_perspective_correct() {
        // Depth 1 at the left edge, 3 at the right: 1/z is linear in x, so
        // at the middle column z = 1 / ((1 + 1/3) / 2) = 1.5, not 2.
        let mut frame = Framebuffer::new(64, 4);
        let corner = |x: f32, y: f32, depth: f32| TriangleVertex {
            x,
            y,
            depth,
            color: Vec3::splat(depth),
        };
        fill_triangle(
            &mut frame,
            &corner(0.0, 0.0, 1.0),
            &corner(64.0, 0.0, 3.0),
            &corner(0.0, 4.0, 1.0),
            |_| {},
        );
        fill_triangle(
            &mut frame,
            &corner(64.0, 0.0, 3.0),
            &corner(64.0, 4.0, 3.0),
            &corner(0.0, 4.0, 1.0),
            |_| {},
        );
        let i = frame.index(31, 1);
        let x = 31.5 / 64.0;
        let expected = 1.0 / (1.0 - x + x / 3.0);
        assert!(
            (frame.depth(i) - expected).abs() < 1e-4,
            "{}",
            frame.depth(i)
        );
        // Colour = depth here (each corner's colour is its depth).
        assert!((frame.color(i).x - expected).abs() < 1e-4);
    }
}
