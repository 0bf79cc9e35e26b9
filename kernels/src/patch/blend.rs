//! Output of a patch: the skin blend and the normals of the blended grid.

use super::grid::Patch;
use crate::Error;
use glam::Vec3;

impl Patch {
    /// Writes the blended world positions, row-major:
    /// `out = skinned (1 - weight) + simulated weight` per particle, so
    /// weight 0 gives the skinned position and weight 1 the simulated one
    /// exactly (for finite inputs). `skinned` is the last
    /// [`Patch::set_skinned`]. Needs `out.len() == rows * cols`.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] (and nothing written) unless `out.len() ==
    /// rows * cols`.
    pub fn write_blended(&self, out: &mut [Vec3]) -> Result<(), Error> {
        if out.len() != self.particle_count() {
            return Err(Error::CountMismatch {
                what: "output points (rows times columns)",
                expected: self.particle_count(),
                got: out.len(),
            });
        }
        let o = self.origin;
        for (k, slot) in out.iter_mut().enumerate() {
            let (i, l) = self.slot(k);
            let simulated = (o + self.pos[i].lane(l).as_dvec3()).as_vec3();
            let w = self.weight[k];
            *slot = self.skin_world[k] * (1.0 - w) + simulated * w;
        }
        Ok(())
    }
}

/// Area-weighted vertex normals of a row-major `rows x cols` grid, written
/// to `out` (same length).
///
/// Each quad `(r, c)` is split into triangles `(r,c) (r,c+1) (r+1,c)` and
/// `(r,c+1) (r+1,c+1) (r+1,c)`; a triangle's cross product
/// `(x_1 - x_0) x (x_2 - x_0)` (twice its area times its unit normal) is
/// added to its three corners and the sums are normalised (Gouraud 1971's
/// vertex normals, area-weighted). The normal points along
/// `d/dcolumn x d/drow`: for a grid whose columns run along +x and rows
/// along -y it is -z. Triangles with a non-finite cross product are skipped,
/// and a vertex without a usable triangle gets `(0, 0, 0)`, so a NaN
/// particle spoils only its own neighbourhood.
///
/// # Errors
///
/// [`Error::CountMismatch`] (and nothing written) unless `positions` and
/// `out` hold `rows * cols` points.
pub fn grid_normals(
    positions: &[Vec3],
    rows: usize,
    cols: usize,
    out: &mut [Vec3],
) -> Result<(), Error> {
    // An overflowing rows * cols matches no slice (instead of wrapping).
    let n = rows.checked_mul(cols);
    for len in [positions.len(), out.len()] {
        if Some(len) != n {
            return Err(Error::CountMismatch {
                what: "points (rows times columns)",
                expected: n.unwrap_or(usize::MAX),
                got: len,
            });
        }
    }
    out.fill(Vec3::ZERO);
    let mut add = |corners: [usize; 3]| {
        let [a, b, c] = corners.map(|k| positions[k]);
        let normal = (b - a).cross(c - a);
        if normal.is_finite() {
            for k in corners {
                out[k] += normal;
            }
        }
    };
    for r in 0..rows.saturating_sub(1) {
        for c in 0..cols.saturating_sub(1) {
            let k = r * cols + c;
            add([k, k + 1, k + cols]);
            add([k + 1, k + cols + 1, k + cols]);
        }
    }
    for v in out.iter_mut() {
        let len2 = v.length_squared();
        *v = if len2 > 1e-30 && len2.is_finite() {
            *v / len2.sqrt()
        } else {
            Vec3::ZERO
        };
    }
    Ok(())
}
