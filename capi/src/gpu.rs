//! GPU buffers (`coif-gpu`): the guides packed every frame
//! (`coif_gpu::pack_guides`), the render hairs packed once
//! (`coif_gpu::pack_hairs`) and the view uniform's layout
//! (`coif_gpu::HairView`), for an engine that makes the render hairs in
//! coif's shaders instead of writing their vertices on the CPU
//! (`coif_hairs_write_vertices`).
//!
//! | buffer | C type | size | written |
//! |---|---|---|---|
//! | guides (storage) | `CoifGpuGuideVertex` | 16 B per guide vertex | every frame, `coif_gpu_pack_guides` |
//! | hairs (storage) | `CoifGpuRenderHair` | 32 B per render hair | once, `coif_gpu_pack_hairs` |
//! | view (uniform) | `CoifGpuHairView` | 192 B | every frame, by the engine |

use crate::{guard, guard_or, handle, output, CoifHairs, CoifStatus, CoifStrands};
use coif_gpu::{GuideVertex, HairView, RenderHair};

/// One guide vertex of the guides buffer, 16 bytes, the layout of
/// `coif_gpu::GuideVertex` (WGSL `vec4<f32>`): the position relative to
/// `coif_strands_origin` of the guides, metres; `w` is 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoifGpuGuideVertex {
    /// Position relative to the guides' origin, metres.
    pub position: [f32; 3],
    /// Unused (0).
    pub w: f32,
}

/// One render hair of the hairs buffer, 32 bytes, the layout of
/// `coif_gpu::RenderHair`: the corner guides `(A, B, C)` of its scalp
/// triangle (strand indices of the guides) and its barycentric weights
/// `(b_A, b_B, b_C)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoifGpuRenderHair {
    /// Guide indices (A, B, C).
    pub guides: [u32; 3],
    /// Unused (0).
    pub reserved: u32,
    /// Barycentric weights (b_A, b_B, b_C).
    pub weights: [f32; 3],
    /// Unused (0).
    pub reserved_weight: f32,
}

/// The view and level of detail of one hair's draw, 192 bytes: the
/// uniform of coif's shaders, the layout of `coif_gpu::HairView` (matrices
/// column major, `m[column][row]`). The engine fills it every frame; start
/// from `coif_gpu_hair_view_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifGpuHairView {
    /// The view's clip-from-world matrix, column major (unused by the
    /// compute entry point).
    pub clip_from_world: [[f32; 4]; 4],
    /// World from the guides' frame, column major: the translation to
    /// `coif_strands_origin` and any rigid motion of the hair since it was
    /// stepped.
    pub world_from_local: [[f32; 4]; 4],
    /// xyz the eye (w = 1, perspective) or the direction toward the viewer
    /// (w = 0, orthographic).
    pub eye: [f32; 4],
    /// `V`, control points per guide (`coif_strands_verts_per_strand`, at
    /// least 2).
    pub control_verts: u32,
    /// `N`, segments per B-spline span (at least 1).
    pub segments_per_span: u32,
    /// Render hairs drawn: the first `hairs` entries of the hairs buffer
    /// (`coif_gpu_render_hair_count` of the groups drawn).
    pub hairs: u32,
    /// `R = (V - 1) N + 1`, render vertices per hair.
    pub verts_per_hair: u32,
    /// Width at the root, metres.
    pub root_width: f32,
    /// Width at the tip, metres.
    pub tip_width: f32,
    /// The LOD width factor (`coif_hairs_distance_lod`), 1 at full detail.
    pub width_factor: f32,
    /// The narrowest ribbon drawn, pixels; thinner hair fades.
    pub min_width_px: f32,
    /// `0.5 * viewport height * clip_from_view[1][1]`: pixels per metre at
    /// a point is this over the point's clip `w`.
    pub pixels_per_clip: f32,
    /// Padding to a multiple of 16 bytes (0).
    pub padding: [f32; 3],
}

// The C structs are the coif-gpu structs' bytes: the casts of the caller's
// buffers below rely on it (the header checks the C side).
const _: () = {
    use std::mem::{align_of, offset_of, size_of};
    assert!(size_of::<CoifGpuGuideVertex>() == 16 && size_of::<GuideVertex>() == 16);
    assert!(align_of::<CoifGpuGuideVertex>() == align_of::<GuideVertex>());
    assert!(offset_of!(CoifGpuGuideVertex, w) == offset_of!(GuideVertex, w));
    assert!(size_of::<CoifGpuRenderHair>() == 32 && size_of::<RenderHair>() == 32);
    assert!(align_of::<CoifGpuRenderHair>() == align_of::<RenderHair>());
    assert!(offset_of!(CoifGpuRenderHair, reserved) == offset_of!(RenderHair, reserved));
    assert!(offset_of!(CoifGpuRenderHair, weights) == offset_of!(RenderHair, weights));
    assert!(
        offset_of!(CoifGpuRenderHair, reserved_weight) == offset_of!(RenderHair, reserved_weight)
    );
    assert!(size_of::<CoifGpuHairView>() == 192 && size_of::<HairView>() == 192);
    assert!(align_of::<CoifGpuHairView>() == align_of::<HairView>());
    assert!(
        offset_of!(CoifGpuHairView, world_from_local) == offset_of!(HairView, world_from_local)
    );
    assert!(offset_of!(CoifGpuHairView, eye) == offset_of!(HairView, eye));
    assert!(offset_of!(CoifGpuHairView, control_verts) == offset_of!(HairView, control_verts));
    assert!(
        offset_of!(CoifGpuHairView, segments_per_span) == offset_of!(HairView, segments_per_span)
    );
    assert!(offset_of!(CoifGpuHairView, hairs) == offset_of!(HairView, hairs));
    assert!(offset_of!(CoifGpuHairView, verts_per_hair) == offset_of!(HairView, verts_per_hair));
    assert!(offset_of!(CoifGpuHairView, root_width) == offset_of!(HairView, root_width));
    assert!(offset_of!(CoifGpuHairView, tip_width) == offset_of!(HairView, tip_width));
    assert!(offset_of!(CoifGpuHairView, width_factor) == offset_of!(HairView, width_factor));
    assert!(offset_of!(CoifGpuHairView, min_width_px) == offset_of!(HairView, min_width_px));
    assert!(offset_of!(CoifGpuHairView, pixels_per_clip) == offset_of!(HairView, pixels_per_clip));
    assert!(offset_of!(CoifGpuHairView, padding) == offset_of!(HairView, padding));
};

impl From<HairView> for CoifGpuHairView {
    fn from(v: HairView) -> CoifGpuHairView {
        CoifGpuHairView {
            clip_from_world: v.clip_from_world,
            world_from_local: v.world_from_local,
            eye: v.eye,
            control_verts: v.control_verts,
            segments_per_span: v.segments_per_span,
            hairs: v.hairs,
            verts_per_hair: v.verts_per_hair,
            root_width: v.root_width,
            tip_width: v.tip_width,
            width_factor: v.width_factor,
            min_width_px: v.min_width_px,
            pixels_per_clip: v.pixels_per_clip,
            padding: v.padding,
        }
    }
}

/// The view of `coif_gpu::HairView::default()`: identity matrices, no
/// hairs, `V = 2`, `N = 1` (`verts_per_hair` 2), 80 to 40 micrometre wide
/// hair, width factor 1, one pixel at least, `pixels_per_clip` 1, the eye
/// direction +z (orthographic).
#[no_mangle]
pub extern "C" fn coif_gpu_hair_view_default() -> CoifGpuHairView {
    CoifGpuHairView::from(HairView::default())
}

/// Packs every guide vertex of `s` into the guides buffer `out`, which
/// holds `capacity` entries, at least `coif_strands_point_count(s)`: guide
/// after guide, root first (vertex `v` of guide `g` at `g V + v`),
/// positions relative to `coif_strands_origin(s)`, `w` 0
/// (`coif_gpu::pack_guides`). `*written` (unless NULL) is the number
/// written, `coif_strands_point_count(s)`. Non-finite positions are copied
/// as they are. Call it every frame after the step; allocates nothing.
///
/// Errors: `COIF_ERROR_NULL` (`s` or `out`), `COIF_ERROR_INVALID_ARGUMENT`
/// (a misaligned buffer or count), `COIF_ERROR_BUFFER_TOO_SMALL` (nothing
/// written).
///
/// # Safety
/// `s` is NULL or a live handle; `out` is NULL or points to `capacity`
/// writable guide vertices; `written` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn coif_gpu_pack_guides(
    s: *const CoifStrands,
    out: *mut CoifGpuGuideVertex,
    capacity: usize,
    written: *mut usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL, misaligned (both refused) or a live handle.
        let h = unsafe { handle(s) }?;
        let n = h.strands.strand_count() * h.strands.verts_per_strand();
        let written = if written.is_null() {
            None
        } else {
            // SAFETY: non-NULL, so writable per the caller's contract.
            Some(unsafe { output(written, 1, 1) }?)
        };
        // SAFETY: the caller's contract; `CoifGpuGuideVertex` is
        // `GuideVertex`'s layout (asserted).
        let out = unsafe { output(out.cast::<GuideVertex>(), n, capacity) }?;
        let count = coif_gpu::pack_guides(h.strands.blocks(), out)?;
        if let Some(w) = written {
            w[0] = count;
        }
        Ok(())
    })
}

/// Packs every render hair of `h` into the hairs buffer `out`, which holds
/// `capacity` entries, at least `coif_hairs_hair_count(h)`, in the order
/// `coif_hairs_write_vertices` writes their vertices: group after group (a
/// prefix is an even thinning of the scalp, `coif_gpu_render_hair_count`),
/// each hair its scalp triangle's guides and its barycentric weights
/// (`coif_gpu::pack_hairs`). `*written` (unless NULL) is the number
/// written, `coif_hairs_hair_count(h)`. Once per set of render hairs.
///
/// Errors: `COIF_ERROR_NULL` (`h` or `out`, even with no hairs),
/// `COIF_ERROR_INVALID_ARGUMENT` (a misaligned buffer or count),
/// `COIF_ERROR_BUFFER_TOO_SMALL` (nothing written).
///
/// # Safety
/// `h` is NULL or a live handle; `out` is NULL or points to `capacity`
/// writable render hairs; `written` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn coif_gpu_pack_hairs(
    h: *const CoifHairs,
    out: *mut CoifGpuRenderHair,
    capacity: usize,
    written: *mut usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL, misaligned (both refused) or a live handle.
        let h = unsafe { handle(h) }?;
        let n = h.interpolation.hair_count();
        let written = if written.is_null() {
            None
        } else {
            // SAFETY: non-NULL, so writable per the caller's contract.
            Some(unsafe { output(written, 1, 1) }?)
        };
        // SAFETY: the caller's contract; `CoifGpuRenderHair` is
        // `RenderHair`'s layout (asserted).
        let out = unsafe { output(out.cast::<RenderHair>(), n, capacity) }?;
        let count = coif_gpu::pack_hairs(&h.interpolation, out)?;
        if let Some(w) = written {
            w[0] = count;
        }
        Ok(())
    })
}

/// Render hairs drawn when the first `groups_drawn` groups are (all of
/// them for `groups_drawn >= coif_hairs_group_count(h)`): the `hairs` field
/// of `CoifGpuHairView` for the groups `coif_hairs_distance_lod` gives
/// (`coif_gpu::render_hair_count`). 0 for NULL.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_gpu_render_hair_count(
    h: *const CoifHairs,
    groups_drawn: usize,
) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle (the caller's contract).
        unsafe { h.as_ref() }.map_or(0, |h| {
            coif_gpu::render_hair_count(&h.interpolation, groups_drawn)
        })
    })
}
