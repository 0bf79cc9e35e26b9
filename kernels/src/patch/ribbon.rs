//! A ready-made ribbon hanging from a sphere head, for demos and tests.

use super::grid::Patch;
use crate::{Error, Sphere};
use glam::Vec3;

/// A rest grid with its pinned flags and blend weights (row-major).
#[derive(Clone, Debug, PartialEq)]
pub struct Ribbon {
    /// Rest positions in world space, row-major (`rows * cols`).
    pub points: Vec<Vec3>,
    /// Rows of particles (row 0 attached to the head).
    pub rows: usize,
    /// Columns of particles (across the ribbon).
    pub cols: usize,
    /// Row 0 is pinned (attached to the head).
    pub pinned: Vec<bool>,
    /// Blend weights: 0 on row 0, rising linearly to 1 at a third of the
    /// length, 1 below.
    pub weights: Vec<f32>,
}

impl Ribbon {
    /// Builds the patch (rest grid, pins and weights).
    ///
    /// # Errors
    ///
    /// As [`Patch::new`] and [`Patch::set_weights`] for inconsistent fields.
    pub fn patch(&self) -> Result<Patch, Error> {
        let mut p = Patch::new(&self.points, self.rows, self.cols, &self.pinned)?;
        p.set_weights(&self.weights)?;
        Ok(p)
    }
}

/// A ribbon `width x length` metres of `rows x cols` particles attached to
/// the sphere `head` at the surface point in direction `attach` from the
/// centre (e.g. `-Vec3::Z` for the back of the head), lying in the tangent
/// plane there, 5 mm off the surface: row 0 runs across (horizontal) and
/// the rows run down along the surface. The engine moves the rest points
/// with the head (rigidly) to get the skinned positions of each frame.
/// `rows` and `cols` are raised to 2; a zero `attach` means `-Z`.
pub fn ribbon_on_sphere(
    head: &Sphere,
    attach: Vec3,
    width: f32,
    length: f32,
    rows: usize,
    cols: usize,
) -> Ribbon {
    let (rows, cols) = (rows.max(2), cols.max(2));
    let n = attach.try_normalize().unwrap_or(Vec3::NEG_Z);
    let across = Vec3::Y.cross(n).try_normalize().unwrap_or(Vec3::X);
    // Downward tangent: -y with its normal part removed (or any tangent at a pole).
    let down = (n * Vec3::Y.dot(n) - Vec3::Y)
        .try_normalize()
        .unwrap_or_else(|| n.cross(across).normalize());
    let top = head.center + n * (head.radius + 0.005);
    let mut points = Vec::with_capacity(rows * cols);
    let mut weights = Vec::with_capacity(rows * cols);
    let ramp = ((rows - 1) as f32 / 3.0).max(1.0);
    for r in 0..rows {
        for c in 0..cols {
            let u = c as f32 / (cols - 1) as f32 - 0.5;
            let v = r as f32 / (rows - 1) as f32;
            points.push(top + across * (u * width) + down * (v * length));
            weights.push((r as f32 / ramp).min(1.0));
        }
    }
    let pinned = (0..rows * cols).map(|k| k < cols).collect();
    Ribbon {
        points,
        rows,
        cols,
        pinned,
        weights,
    }
}
