//! Light space: an orthonormal frame with `z` along the light direction,
//! and the placement of the map's texels over the hair's footprint in it.

use glam::Vec3;

/// An orthonormal frame `(x_axis, y_axis, z_axis)` with `z_axis` the unit
/// light direction (from the light toward the scene), so that a point's
/// light-space `z` grows away from the light and the ray toward the light
/// runs along `-z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightFrame {
    /// Light-space x axis (world coordinates).
    pub x_axis: Vec3,
    /// Light-space y axis (world coordinates).
    pub y_axis: Vec3,
    /// Light-space z axis: the light direction, away from the light.
    pub z_axis: Vec3,
}

impl LightFrame {
    /// The frame of a light shining along `light_dir` (any length), or
    /// `None` when it is zero or not finite.
    pub fn new(light_dir: Vec3) -> Option<LightFrame> {
        let z_axis = light_dir.try_normalize()?;
        let (x_axis, y_axis) = z_axis.any_orthonormal_pair();
        Some(LightFrame {
            x_axis,
            y_axis,
            z_axis,
        })
    }

    /// `p` in light-space coordinates `(p.x_axis, p.y_axis, p.z_axis)`.
    #[inline(always)]
    pub fn to_light(&self, p: Vec3) -> Vec3 {
        Vec3::new(p.dot(self.x_axis), p.dot(self.y_axis), p.dot(self.z_axis))
    }
}

/// Where the map lies in light space: the square `[x0, x0 + n h] x
/// [y0, y0 + n h]` of `n x n` texels of side `h`, and the hair's depth range
/// `[near, far]`. Texel `(i, j)` has its centre at `(x0 + (i + 0.5) h,
/// y0 + (j + 0.5) h)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapPlacement {
    /// Light-space x of the map's lower-left corner.
    pub x0: f32,
    /// Light-space y of the map's lower-left corner.
    pub y0: f32,
    /// Texel side `h` and its inverse.
    pub texel: f32,
    /// `1 / h`.
    pub inv_texel: f32,
    /// Light-space depth of the nearest hair.
    pub near: f32,
    /// Light-space depth of the farthest hair.
    pub far: f32,
}

impl MapPlacement {
    /// Covers the light-space box `[min, max]` (x, y) of the hair with an
    /// `n x n` map: square texels, a margin of `pad` plus one texel on each
    /// side so that bilinear splats of the hair's edge stay inside.
    pub fn cover(min: Vec3, max: Vec3, pad: f32, n: usize) -> MapPlacement {
        let extent = (max.x - min.x).max(max.y - min.y) + 2.0 * pad;
        // At least a micrometre, so a single point still gets a valid map.
        let texel = (extent / (n as f32 - 2.0).max(1.0)).max(1.0e-6);
        let half = 0.5 * texel * n as f32;
        let (cx, cy) = (0.5 * (min.x + max.x), 0.5 * (min.y + max.y));
        MapPlacement {
            x0: cx - half,
            y0: cy - half,
            texel,
            inv_texel: 1.0 / texel,
            near: min.z,
            far: max.z,
        }
    }

    /// Continuous texel coordinates of light-space `(x, y)`, shifted by half
    /// a texel so that `floor` gives the lower-left of the four texels whose
    /// centres surround the point and the fraction gives bilinear weights.
    #[inline(always)]
    pub fn texel_coords(&self, x: f32, y: f32) -> (f32, f32) {
        (
            (x - self.x0) * self.inv_texel - 0.5,
            (y - self.y0) * self.inv_texel - 0.5,
        )
    }
}
