//! The buffers' layouts: `#[repr(C)]` plain old data ([`bytemuck::Pod`]),
//! so a slice uploads as bytes (`bytemuck::cast_slice`) without a copy.
//! WGSL declares the same structs (shaders/render_vertex.wgsl); the sizes
//! and offsets are checked in this module's tests.

use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, DVec3, Mat4, Vec3};

/// One simulated guide vertex, 16 bytes (WGSL `vec4<f32>`): `position`
/// relative to the strands' origin (`Strands::origin`), metres; `w` is
/// unused (0). Guide `g`'s vertex `v` is entry `g V + v` (guide after
/// guide, root first), `V` vertices per guide.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GuideVertex {
    /// Position relative to the origin, metres.
    pub position: [f32; 3],
    /// Unused (0).
    pub w: f32,
}

/// One render hair, 32 bytes: the corner guides `(A, B, C)` of its scalp
/// triangle and its barycentric weights `(b_A, b_B, b_C)`, as coif-lod's
/// `Interpolation` places it (`P = b_A A + b_B B + b_C C` at every refined
/// vertex).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RenderHair {
    /// Guide indices (A, B, C).
    pub guides: [u32; 3],
    /// Unused (0).
    pub reserved: u32,
    /// Barycentric weights (b_A, b_B, b_C).
    pub weights: [f32; 3],
    /// Unused (0).
    pub reserved_weight: f32,
}

/// The view and level of detail of one hair's draw, 192 bytes (a uniform).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct HairView {
    /// The view's clip-from-world matrix, column major (unused by the
    /// compute entry point).
    pub clip_from_world: [[f32; 4]; 4],
    /// World from the guides' frame: the origin's translation and any
    /// rigid motion of the hair since it was stepped, column major.
    pub world_from_local: [[f32; 4]; 4],
    /// xyz the eye (w = 1, perspective) or the direction toward the viewer
    /// (w = 0, orthographic).
    pub eye: [f32; 4],
    /// `V`, control points per guide (at least 2).
    pub control_verts: u32,
    /// `N`, segments per B-spline span (at least 1).
    pub segments_per_span: u32,
    /// Render hairs drawn: the first `hairs` entries of the hairs buffer
    /// (a distance-LOD prefix: [`crate::render_hair_count`]).
    pub hairs: u32,
    /// `R = (V - 1) N + 1`, render vertices per hair.
    pub verts_per_hair: u32,
    /// Width at the root, metres.
    pub root_width: f32,
    /// Width at the tip, metres.
    pub tip_width: f32,
    /// The LOD width factor (coif-lod's `distance_lod`), 1 at full detail.
    pub width_factor: f32,
    /// The narrowest ribbon drawn, pixels; thinner hair fades.
    pub min_width_px: f32,
    /// `0.5 viewport height * clip_from_view[1][1]`: pixels per metre at a
    /// point is this over the point's clip `w`.
    pub pixels_per_clip: f32,
    /// Padding to a multiple of 16 bytes.
    pub padding: [f32; 3],
}

impl Default for HairView {
    /// Identity matrices, no hairs, `V = 2`, `N = 1`, coif's default widths
    /// (80 to 40 micrometres), one pixel at least.
    fn default() -> HairView {
        HairView {
            clip_from_world: Mat4::IDENTITY.to_cols_array_2d(),
            world_from_local: Mat4::IDENTITY.to_cols_array_2d(),
            eye: [0.0, 0.0, 1.0, 0.0],
            control_verts: 2,
            segments_per_span: 1,
            hairs: 0,
            verts_per_hair: 2,
            root_width: 80e-6,
            tip_width: 40e-6,
            width_factor: 1.0,
            min_width_px: 1.0,
            pixels_per_clip: 1.0,
            padding: [0.0; 3],
        }
    }
}

impl HairView {
    /// Sets the level: `control_verts` points per guide (clamped to at
    /// least 2), `segments_per_span` (at least 1), `hairs` drawn, and
    /// `verts_per_hair` from them.
    pub fn set_level(&mut self, control_verts: usize, segments_per_span: usize, hairs: usize) {
        let v = control_verts.clamp(2, u32::MAX as usize) as u32;
        let n = segments_per_span.clamp(1, 256) as u32;
        self.control_verts = v;
        self.segments_per_span = n;
        self.hairs = hairs.min(u32::MAX as usize) as u32;
        self.verts_per_hair = (v - 1).saturating_mul(n).saturating_add(1);
    }

    /// Sets `world_from_local` to `carry` after the translation to
    /// `origin` (the strands' origin, rounded to `f32` after the carry so
    /// that far from the world's origin the offset stays exact to the
    /// metre's fraction `f32` holds there).
    pub fn set_placement(&mut self, origin: DVec3, carry: Affine3A) {
        let m = Mat4::from(carry) * Mat4::from_translation(origin.as_vec3());
        self.world_from_local = m.to_cols_array_2d();
    }

    /// Sets the view: a perspective camera at `eye` (or, with
    /// `orthographic`, `eye` is the direction toward the viewer),
    /// `clip_from_world`, the projection's `clip_from_view[1][1]` and the
    /// viewport's height in pixels.
    pub fn set_camera(
        &mut self,
        clip_from_world: Mat4,
        eye: Vec3,
        orthographic: bool,
        projection_y_scale: f32,
        viewport_height_px: f32,
    ) {
        self.clip_from_world = clip_from_world.to_cols_array_2d();
        self.eye = [eye.x, eye.y, eye.z, if orthographic { 0.0 } else { 1.0 }];
        self.pixels_per_clip = 0.5 * viewport_height_px * projection_y_scale;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{align_of, offset_of, size_of};

    #[test]
    fn layouts_match_the_wgsl_structs() {
        assert_eq!(size_of::<GuideVertex>(), 16);
        assert_eq!(size_of::<RenderHair>(), 32);
        assert_eq!(offset_of!(RenderHair, weights), 16);
        assert_eq!(size_of::<HairView>(), 192);
        assert_eq!(offset_of!(HairView, world_from_local), 64);
        assert_eq!(offset_of!(HairView, eye), 128);
        assert_eq!(offset_of!(HairView, control_verts), 144);
        assert_eq!(offset_of!(HairView, root_width), 160);
        assert_eq!(offset_of!(HairView, pixels_per_clip), 176);
        assert_eq!(align_of::<HairView>(), 4);
        assert_eq!(size_of::<coif_lod::RenderVertex>(), 32);
    }

    #[test]
    fn level_gives_the_refined_vertex_count() {
        let mut v = HairView::default();
        v.set_level(24, 3, 100);
        assert_eq!(v.verts_per_hair, 70);
        assert_eq!(v.verts_per_hair as usize, coif_lod::refined_len(24, 3));
        v.set_level(0, 0, 5);
        assert_eq!(
            (v.control_verts, v.segments_per_span, v.verts_per_hair),
            (2, 1, 2)
        );
    }
}
