//! A row-major grid of vertices drawn as opaque triangles (the ribbon).

use super::hair::NEAR;
use super::triangle::{fill_triangle, TriangleVertex};
use super::{Camera, Framebuffer};
use glam::Vec3;

/// Draws the `rows x cols` grid `positions` (row-major, point `(r, c)` at
/// `r * cols + c`, in the camera's space) with per-vertex linear-RGB
/// `colors`: each quad `(r, c)` as the triangles `(r,c) (r,c+1) (r+1,c)`
/// and `(r,c+1) (r+1,c+1) (r+1,c)` (the split of
/// `coif_kernels::patch::grid_normals`), opaque, two-sided, depth-tested
/// with [`fill_triangle`]. The triangles share edges, so the top-left rule
/// draws each covered pixel once per layer of the surface. A triangle with
/// a corner behind the near plane or non-finite is skipped (its
/// neighbours are kept). Returns the number of pixels written; nothing is
/// drawn when the slices do not hold `rows * cols` entries.
pub fn draw_grid(
    frame: &mut Framebuffer,
    camera: &Camera,
    positions: &[Vec3],
    colors: &[Vec3],
    rows: usize,
    cols: usize,
) -> usize {
    let n = rows.saturating_mul(cols);
    if positions.len() != n || colors.len() != n {
        return 0;
    }
    let project = |k: usize| -> Option<TriangleVertex> {
        let p = camera.project(positions[k], NEAR)?;
        colors[k].is_finite().then_some(TriangleVertex {
            x: p.x,
            y: p.y,
            depth: p.z,
            color: colors[k],
        })
    };
    let mut written = 0;
    for r in 0..rows.saturating_sub(1) {
        // Project the two rows of a band once per quad corner pair.
        let mut left = (project(r * cols), project((r + 1) * cols));
        for c in 0..cols - 1 {
            let k = r * cols + c;
            let right = (project(k + 1), project(k + cols + 1));
            if let (Some(a), Some(b), Some(d)) = (&left.0, &right.0, &left.1) {
                written += fill_triangle(frame, a, b, d, |_| {});
            }
            if let (Some(b), Some(e), Some(d)) = (&right.0, &right.1, &left.1) {
                written += fill_triangle(frame, b, e, d, |_| {});
            }
            left = right;
        }
    }
    written
}
