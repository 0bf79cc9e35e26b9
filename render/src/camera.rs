//! Perspective look-at camera.

use glam::{Mat4, Vec3, Vec4};

/// A pinhole camera at `eye` looking at a target, `fov_y` radians of
/// vertical field of view, over a `width` x `height` pixel viewport.
///
/// Pixel coordinates: x to the right, y down, pixel `(i, j)` covers
/// `[i, i + 1) x [j, j + 1)`, so its centre is `(i + 0.5, j + 0.5)`.
/// Depth is the view-space distance along the viewing direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    forward: Vec3,
    right: Vec3,
    down: Vec3,
    fov_y: f32,
    /// Pixels per unit of `lateral offset / depth`: `H / (2 tan(fov_y / 2))`.
    focal_px: f32,
    width: usize,
    height: usize,
}

impl Camera {
    /// A camera at `eye` looking at `target` with `up` roughly up. A
    /// degenerate frame (eye at target, up along the view) falls back to
    /// looking down -z with +y up.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y: f32,
        width: usize,
        height: usize,
    ) -> Camera {
        let forward = (target - eye).try_normalize().unwrap_or(Vec3::NEG_Z);
        let right = forward
            .cross(up)
            .try_normalize()
            .unwrap_or_else(|| forward.any_orthonormal_vector());
        let true_up = right.cross(forward);
        let fov_y = if fov_y.is_finite() {
            fov_y.clamp(1e-3, 3.0)
        } else {
            0.8
        };
        let (width, height) = (width.max(1), height.max(1));
        Camera {
            eye,
            target,
            up,
            forward,
            right,
            down: -true_up,
            fov_y,
            focal_px: height as f32 / (2.0 * (0.5 * fov_y).tan()),
            width,
            height,
        }
    }

    /// The same camera moved by `-offset`: for geometry stored relative to
    /// a local origin (`Strands::origin`), pass that origin.
    pub fn shifted(&self, offset: Vec3) -> Camera {
        Camera::look_at(
            self.eye - offset,
            self.target - offset,
            self.up,
            self.fov_y,
            self.width,
            self.height,
        )
    }

    /// Eye position.
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// The point looked at.
    pub fn target(&self) -> Vec3 {
        self.target
    }

    /// The up direction the camera was built with (not necessarily unit).
    pub fn up(&self) -> Vec3 {
        self.up
    }

    /// Unit view direction, eye toward target.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// Vertical field of view in radians.
    pub fn fov_y(&self) -> f32 {
        self.fov_y
    }

    /// Image width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// `(eye, forward, right, down, focal_px)`: what [`Camera::project`]
    /// reads (for the eight-lane projection of the rasteriser).
    pub(crate) fn basis(&self) -> (Vec3, Vec3, Vec3, Vec3, f32) {
        (self.eye, self.forward, self.right, self.down, self.focal_px)
    }

    /// Pixels per metre at view depth `depth`: `focal_px / depth`.
    pub fn pixels_per_metre(&self, depth: f32) -> f32 {
        self.focal_px / depth
    }

    /// `(x_px, y_px, depth)` of world point `p`; `None` behind the eye
    /// (depth below `near`) or for non-finite input.
    #[inline]
    pub fn project(&self, p: Vec3, near: f32) -> Option<Vec3> {
        let d = p - self.eye;
        let z = d.dot(self.forward);
        if z.is_nan() || z <= near {
            return None;
        }
        let k = self.focal_px / z;
        let x = 0.5 * self.width as f32 + k * d.dot(self.right);
        let y = 0.5 * self.height as f32 + k * d.dot(self.down);
        (x.is_finite() && y.is_finite()).then_some(Vec3::new(x, y, z))
    }

    /// Unit direction of the ray through pixel position `(x, y)`.
    #[inline]
    pub fn ray_direction(&self, x: f32, y: f32) -> Vec3 {
        let u = (x - 0.5 * self.width as f32) / self.focal_px;
        let v = (y - 0.5 * self.height as f32) / self.focal_px;
        (self.forward + self.right * u + self.down * v).normalize()
    }

    /// Right-handed view-projection matrix with clip depth in `[0, 1]`
    /// (for [`coif_lod::Frustum::from_view_projection`]).
    pub fn view_projection(&self, near: f32, far: f32) -> Mat4 {
        let aspect = self.width as f32 / self.height as f32;
        let f = 1.0 / (0.5 * self.fov_y).tan();
        let r = far / (near - far);
        // Rows: (f / aspect, 0, 0, 0), (0, f, 0, 0), (0, 0, r, r near), (0, 0, -1, 0).
        let projection = Mat4::from_cols(
            Vec4::new(f / aspect, 0.0, 0.0, 0.0),
            Vec4::new(0.0, f, 0.0, 0.0),
            Vec4::new(0.0, 0.0, r, -1.0),
            Vec4::new(0.0, 0.0, r * near, 0.0),
        );
        // Rows: right, up, -forward, with the eye moved to the origin.
        let (x, y, z) = (self.right, -self.down, -self.forward);
        let view = Mat4::from_cols(
            Vec4::new(x.x, y.x, z.x, 0.0),
            Vec4::new(x.y, y.y, z.y, 0.0),
            Vec4::new(x.z, y.z, z.z, 0.0),
            Vec4::new(-x.dot(self.eye), -y.dot(self.eye), -z.dot(self.eye), 1.0),
        );
        projection * view
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_target_projects_to_the_centre_and_rays_go_back_through_pixels() {
        let c = Camera::look_at(Vec3::new(0.3, 0.2, 1.0), Vec3::ZERO, Vec3::Y, 0.7, 200, 100);
        let p = c.project(Vec3::ZERO, 0.01).unwrap();
        assert!(
            (p.x - 100.0).abs() < 1e-3 && (p.y - 50.0).abs() < 1e-3,
            "{p}"
        );
        let q = Vec3::new(0.05, 0.1, -0.02);
        let s = c.project(q, 0.01).unwrap();
        let dir = c.ray_direction(s.x, s.y);
        let back = c.eye() + dir * ((q - c.eye()).length());
        assert!((back - q).length() < 1e-4, "{back} vs {q}");
        // Up in the world is up (smaller y) in the picture.
        assert!(c.project(Vec3::Y * 0.1, 0.01).unwrap().y < 50.0);
        assert!(c.project(c.eye() - c.forward(), 0.01).is_none());
        // The view-projection agrees with `project` (clip depth in [0, 1]).
        let clip = c.view_projection(0.01, 100.0) * q.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        assert!((ndc.x - (s.x / 100.0 - 1.0)).abs() < 1e-4, "{ndc}");
        assert!((ndc.y - (1.0 - s.y / 50.0)).abs() < 1e-4, "{ndc}");
        assert!(ndc.z > 0.0 && ndc.z < 1.0);
    }
}
