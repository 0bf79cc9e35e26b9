//! Level of detail into caller buffers: B-spline refinement of the strands
//! (`coif_lod::refine_strands`) and render hairs interpolated from them
//! (`coif_lod::Interpolation`, `interpolate`, `write_render_vertices`).

use crate::{
    guard, guard_or, handle, handle_mut, input, new_handle, output, CoifStatus, CoifStrands,
};
use coif_lod::{HairWidth, Interpolation, RefinedGuides, RenderHairs, RenderVertex};
use glam::Vec3;

/// One render-hair vertex, 32 bytes, the layout of `coif_lod::RenderVertex`
/// (a GPU vertex buffer can take an array of them as is): position (metres,
/// relative to `coif_strands_origin` of the guides), width (metres, the
/// distance-LOD width factor included), unit tangent root to tip, and the
/// parameter along the hair (0 at the root, 1 at the tip).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoifRenderVertex {
    /// Position relative to the guides' origin, metres.
    pub position: [f32; 3],
    /// Hair width at this vertex, metres.
    pub width: f32,
    /// Unit tangent, root to tip.
    pub tangent: [f32; 3],
    /// Parameter along the hair, 0 at the root, 1 at the tip.
    pub strand_parameter: f32,
}

// `CoifRenderVertex` and `RenderVertex` are the same bytes: the casts of the
// caller's vertex buffer below rely on it (the header checks the C side).
const _: () = {
    use std::mem::{align_of, offset_of, size_of};
    assert!(size_of::<CoifRenderVertex>() == 32 && size_of::<RenderVertex>() == 32);
    assert!(align_of::<CoifRenderVertex>() == align_of::<RenderVertex>());
    assert!(offset_of!(CoifRenderVertex, position) == offset_of!(RenderVertex, position));
    assert!(offset_of!(CoifRenderVertex, width) == offset_of!(RenderVertex, width));
    assert!(offset_of!(CoifRenderVertex, tangent) == offset_of!(RenderVertex, tangent));
    assert!(
        offset_of!(CoifRenderVertex, strand_parameter)
            == offset_of!(RenderVertex, strand_parameter)
    );
};

impl From<coif_lod::Error> for CoifStatus {
    fn from(e: coif_lod::Error) -> CoifStatus {
        crate::set_last_error(&e);
        use coif_lod::Error as E;
        match e {
            E::NonFinite { .. } => CoifStatus::COIF_ERROR_NON_FINITE,
            E::InvalidParameter { value, .. } if !value.is_finite() => {
                CoifStatus::COIF_ERROR_NON_FINITE
            }
            E::CountMismatch { .. } => CoifStatus::COIF_ERROR_COUNT_MISMATCH,
            E::BufferTooSmall { .. } => CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
            _ => CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
        }
    }
}

/// Largest segments per span of a refinement (`coif_lod::RefinedGuides`).
const MAX_SEGMENTS_PER_SPAN: usize = 256;

fn check_segments(segments_per_span: usize) -> Result<(), CoifStatus> {
    if (1..=MAX_SEGMENTS_PER_SPAN).contains(&segments_per_span) {
        Ok(())
    } else {
        Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT)
    }
}

/// Writes the local origin of the set (f64 x, y, z, world metres) into
/// `out_xyz`: render vertices are relative to it (add it in the model
/// matrix, in double precision where the world is large).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT` (misaligned).
///
/// # Safety
/// `s` is NULL or a live handle; `out_xyz` is NULL or points to 3 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn coif_strands_origin(
    s: *const CoifStrands,
    out_xyz: *mut f64,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle; `out_xyz` NULL or 3 writable doubles.
        let h = unsafe { handle(s) }?;
        let out = unsafe { output(out_xyz, 3, 3) }?;
        out.copy_from_slice(&h.strands.origin().to_array());
        Ok(())
    })
}

/// Number of points `coif_refine(s, segments_per_span, ...)` writes:
/// strands times `(V - 1) N + 1` for `V` vertices per strand and `N =
/// segments_per_span` (0 for NULL or `N` outside 1..=256).
///
/// # Safety
/// `s` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_refine_bound(
    s: *const CoifStrands,
    segments_per_span: usize,
) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle.
        match (unsafe { s.as_ref() }, check_segments(segments_per_span)) {
            (Some(h), Ok(())) => refined_points(h, segments_per_span),
            _ => 0,
        }
    })
}

fn refined_points(h: &CoifStrands, segments_per_span: usize) -> usize {
    h.strands.strand_count()
        * coif_lod::refined_len(h.strands.verts_per_strand(), segments_per_span)
}

/// Refines every strand into a uniform cubic B-spline through its vertices
/// as control points (`coif_lod::refine_strands`, SIMD; phantom end points,
/// ends pinned to the first and last vertex), `segments_per_span` (1..=256)
/// segments per span, and writes the points (world metres, 3 floats each,
/// strand after strand, root first) into `out_xyz` and, unless
/// `out_tangents` is NULL, the unit tangents (3 floats each) into
/// `out_tangents`. Both hold `capacity_points` points, at least
/// `coif_refine_bound(s, segments_per_span)`.
///
/// The refinement scratch lives in the handle: the first call, and a call
/// at a finer level than any before, allocate it; others allocate nothing.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT` (level out of
/// range, a misaligned buffer), `COIF_ERROR_BUFFER_TOO_SMALL` (nothing written).
///
/// # Safety
/// `s` is NULL or a live handle; `out_xyz` (and `out_tangents` unless NULL)
/// is NULL or points to `3 * capacity_points` writable floats; the two do not overlap.
#[no_mangle]
pub unsafe extern "C" fn coif_refine(
    s: *mut CoifStrands,
    segments_per_span: usize,
    out_xyz: *mut f32,
    out_tangents: *mut f32,
    capacity_points: usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle not aliased during the call.
        let h = unsafe { handle_mut(s) }?;
        check_segments(segments_per_span)?;
        let n = refined_points(h, segments_per_span);
        // SAFETY: the caller's contract on the buffers; `Vec3` is three packed f32.
        let xyz = unsafe { output(out_xyz.cast::<Vec3>(), n, capacity_points) }?;
        let mut tangents = if out_tangents.is_null() {
            None
        } else {
            // SAFETY: as above.
            Some(unsafe { output(out_tangents.cast::<Vec3>(), n, capacity_points) }?)
        };
        let (origin, strand_count) = (h.strands.origin(), h.strands.strand_count());
        let guides = refined_guides(h, segments_per_span)?;
        let r_len = guides.verts_per_strand();
        for i in 0..strand_count {
            for r in 0..r_len {
                xyz[i * r_len + r] = (origin + guides.position(i, r).as_dvec3()).as_vec3();
                if let Some(t) = tangents.as_deref_mut() {
                    t[i * r_len + r] = guides.tangent(i, r);
                }
            }
        }
        Ok(())
    })
}

/// The handle's scratch, refined at `segments_per_span` (made or remade
/// only when it cannot hold that level).
fn refined_guides(
    h: &mut CoifStrands,
    segments_per_span: usize,
) -> Result<&RefinedGuides, CoifStatus> {
    let fits = h
        .refined
        .as_ref()
        .is_some_and(|g| g.max_segments_per_span() >= segments_per_span);
    if !fits {
        h.refined = Some(RefinedGuides::new(h.strands.blocks(), segments_per_span)?);
    }
    let guides = h.refined.as_mut().expect("made above");
    guides.set_segments_per_span(segments_per_span)?;
    coif_lod::refine_strands(h.strands.blocks(), None, guides)?;
    Ok(guides)
}

/// Settings of the render hairs (`coif_hairs_new`); start from
/// `coif_hair_settings_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifHairSettings {
    /// Seed of the hairs' placement (same seed, same hairs).
    pub seed: u64,
    /// Render hairs per square centimetre of scalp (finite, >= 0; default 150).
    pub hairs_per_cm2: f32,
    /// Finest level `coif_hairs_write_vertices` will be asked for (1..=256,
    /// default 16); the buffers inside the handle are sized for it.
    pub max_segments_per_span: u32,
    /// 1: every scalp triangle gets a whole number of groups of 8 hairs
    /// (`Interpolation::with_whole_groups`, no SIMD lane wasted); 0
    /// (default): hair counts per triangle in steps of 1.
    pub whole_groups: u32,
    /// Hair width at the root, metres (finite, >= 0; default 80e-6).
    pub width_root: f32,
    /// Hair width at the tip, metres (finite, >= 0; default 40e-6).
    pub width_tip: f32,
}

/// Default render-hair settings: 150 hairs per cm^2, seed 7, up to 16
/// segments per span, 80 to 40 micrometre wide hairs.
#[no_mangle]
pub extern "C" fn coif_hair_settings_default() -> CoifHairSettings {
    let width = HairWidth::default();
    CoifHairSettings {
        seed: 7,
        hairs_per_cm2: 150.0,
        max_segments_per_span: coif_lod::DEFAULT_MAX_SEGMENTS_PER_SPAN as u32,
        whole_groups: 0,
        width_root: width.root,
        width_tip: width.tip,
    }
}

/// An opaque set of render hairs interpolated from guide strands (created
/// by `coif_hairs_new`, freed by `coif_hairs_free`): where each hair sits,
/// and the buffers of a frame, sized once.
pub struct CoifHairs {
    pub(crate) interpolation: Interpolation,
    guides: RefinedGuides,
    hairs: RenderHairs,
    width: HairWidth,
}

/// Places render hairs on scalp triangles between guide strands
/// (`coif_lod::Interpolation`): `triangle_count` triangles, 3 indices each
/// into the strands of `guides` (at `triangles`), each render hair a fixed
/// barycentric blend of its triangle's three guides. The guides' current
/// roots give the triangles' areas (hair counts). The handle only reads
/// `guides` now; later calls take the guides again (the same shape).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_INVALID_ARGUMENT` (no triangles,
/// an index out of range, a setting out of range, more than 2^24 hairs),
/// `COIF_ERROR_NON_FINITE` (a NaN or infinite setting).
///
/// # Safety
/// `guides` is NULL or a live handle; `triangles` is NULL or points to
/// `3 * triangle_count` readable indices; `settings` is NULL or readable;
/// `out` is NULL or points to a writable `CoifHairs *`.
#[no_mangle]
pub unsafe extern "C" fn coif_hairs_new(
    guides: *const CoifStrands,
    triangles: *const u32,
    triangle_count: usize,
    settings: *const CoifHairSettings,
    out: *mut *mut CoifHairs,
) -> CoifStatus {
    guard(|| {
        // SAFETY: every pointer is NULL or valid (the caller's contract).
        unsafe {
            new_handle(out, || {
                let g = handle(guides)?;
                let set = handle(settings)?;
                if triangles.is_null() {
                    return Err(CoifStatus::COIF_ERROR_NULL);
                }
                if triangle_count == 0 {
                    return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
                }
                let tris = input(triangles.cast::<[u32; 3]>(), triangle_count)?;
                make_hairs(g, tris, set)
            })
        }
    })
}

fn make_hairs(
    g: &CoifStrands,
    triangles: &[[u32; 3]],
    set: &CoifHairSettings,
) -> Result<CoifHairs, CoifStatus> {
    let width = HairWidth {
        root: set.width_root,
        tip: set.width_tip,
    };
    if !(width.root.is_finite() && width.tip.is_finite()) {
        return Err(CoifStatus::COIF_ERROR_NON_FINITE);
    }
    if width.root < 0.0 || width.tip < 0.0 || set.whole_groups > 1 {
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    let verts = g.strands.verts_per_strand();
    let mut points = vec![Vec3::ZERO; g.strands.strand_count() * verts];
    g.strands.write_positions(&mut points)?;
    let roots: Vec<Vec3> = points.iter().step_by(verts).copied().collect();
    let interpolation = if set.whole_groups == 1 {
        Interpolation::with_whole_groups(&roots, triangles, set.hairs_per_cm2, set.seed)?
    } else {
        Interpolation::new(&roots, triangles, set.hairs_per_cm2, set.seed)?
    };
    let guides = RefinedGuides::new(g.strands.blocks(), set.max_segments_per_span as usize)?;
    let hairs = RenderHairs::new(&interpolation, &guides);
    Ok(CoifHairs {
        interpolation,
        guides,
        hairs,
        width,
    })
}

/// Frees render hairs made by `coif_hairs_new`. NULL is fine.
///
/// # Safety
/// `h` is NULL or a handle from `coif_hairs_new` not freed before.
#[no_mangle]
pub unsafe extern "C" fn coif_hairs_free(h: *mut CoifHairs) {
    // SAFETY: the caller's contract.
    unsafe { crate::free_handle(h) }
}

/// Number of render hairs (0 for NULL).
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_hairs_hair_count(h: *const CoifHairs) -> usize {
    // SAFETY: NULL or a live handle.
    guard_or(0, || {
        unsafe { h.as_ref() }.map_or(0, |h| h.interpolation.hair_count())
    })
}

/// Number of hair groups (up to 8 hairs of one triangle each; drawing the
/// first k groups of their shuffled order thins the hair evenly). 0 for NULL.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_hairs_group_count(h: *const CoifHairs) -> usize {
    // SAFETY: NULL or a live handle.
    guard_or(0, || {
        unsafe { h.as_ref() }.map_or(0, |h| h.interpolation.group_count())
    })
}

/// Number of vertices `coif_hairs_write_vertices(h, ..., segments_per_span,
/// groups_drawn, ...)` writes: the hairs of the first `groups_drawn` groups
/// (all of them for `groups_drawn >= coif_hairs_group_count`) times `(V - 1)
/// N + 1` vertices each (0 for NULL or `N` outside 1..=max_segments_per_span).
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn coif_hairs_vertex_bound(
    h: *const CoifHairs,
    segments_per_span: usize,
    groups_drawn: usize,
) -> usize {
    guard_or(0, || {
        // SAFETY: NULL or a live handle.
        unsafe { h.as_ref() }.map_or(0, |h| {
            vertex_bound(h, segments_per_span, groups_drawn).unwrap_or(0)
        })
    })
}

fn vertex_bound(
    h: &CoifHairs,
    segments_per_span: usize,
    groups_drawn: usize,
) -> Result<usize, CoifStatus> {
    if !(1..=h.guides.max_segments_per_span()).contains(&segments_per_span) {
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    let r_len = coif_lod::refined_len(h.guides.control_verts_per_strand(), segments_per_span);
    Ok(h.interpolation.hairs_in_prefix(groups_drawn) * r_len)
}

/// Distance LOD (`coif_lod::distance_lod`): from the projected width of one
/// hair in pixels, how many groups to draw (`*groups_drawn`: all while a
/// hair is at least a pixel wide, fewer below, never below the fraction
/// `min_fraction` in (0, 1]) and the width factor that keeps the coverage
/// (`*width_factor`, for `coif_hairs_write_vertices`).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE`,
/// `COIF_ERROR_INVALID_ARGUMENT` (a negative width, `min_fraction` outside
/// (0, 1]).
///
/// # Safety
/// `h` is NULL or a live handle; the outputs are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn coif_hairs_distance_lod(
    h: *const CoifHairs,
    hair_width_px: f32,
    min_fraction: f32,
    groups_drawn: *mut usize,
    width_factor: *mut f32,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle; outputs NULL or writable.
        let h = unsafe { handle(h) }?;
        let groups_out = unsafe { output(groups_drawn, 1, 1) }?;
        let factor_out = unsafe { output(width_factor, 1, 1) }?;
        if !(hair_width_px.is_finite() && min_fraction.is_finite()) {
            return Err(CoifStatus::COIF_ERROR_NON_FINITE);
        }
        if hair_width_px < 0.0 || !(min_fraction > 0.0 && min_fraction <= 1.0) {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        let d = coif_lod::distance_lod(&h.interpolation, hair_width_px, min_fraction);
        groups_out[0] = d.groups_drawn;
        factor_out[0] = d.width_factor;
        Ok(())
    })
}

/// One frame of render hairs: refines `guides` at `segments_per_span`
/// (1..=`max_segments_per_span` of the settings), interpolates the hairs of
/// the first `groups_drawn` groups (SIMD) and writes their vertices, hair
/// after hair, root first, widths times `width_factor` (> 0; 1, or the
/// factor of `coif_hairs_distance_lod`) into `out`, which holds `capacity`
/// vertices, at least `coif_hairs_vertex_bound`. `*written` (unless NULL)
/// is the number written, the bound. Positions are relative to
/// `coif_strands_origin(guides)`. Allocates nothing.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_COUNT_MISMATCH` (`guides` not of
/// the shape the hairs were made for), `COIF_ERROR_INVALID_ARGUMENT` (level
/// out of range, `width_factor <= 0`), `COIF_ERROR_NON_FINITE`,
/// `COIF_ERROR_BUFFER_TOO_SMALL` (nothing written).
///
/// # Safety
/// `h` and `guides` are NULL or live handles; `out` is NULL or points to
/// `capacity` writable vertices; `written` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn coif_hairs_write_vertices(
    h: *mut CoifHairs,
    guides: *const CoifStrands,
    segments_per_span: usize,
    groups_drawn: usize,
    width_factor: f32,
    out: *mut CoifRenderVertex,
    capacity: usize,
    written: *mut usize,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or live handles not aliased during the call.
        let h = unsafe { handle_mut(h) }?;
        let g = unsafe { handle(guides) }?;
        if g.strands.strand_count() != h.guides.strand_count()
            || g.strands.verts_per_strand() != h.guides.control_verts_per_strand()
        {
            return Err(CoifStatus::COIF_ERROR_COUNT_MISMATCH);
        }
        if !width_factor.is_finite() {
            return Err(CoifStatus::COIF_ERROR_NON_FINITE);
        }
        if width_factor <= 0.0 {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        let n = vertex_bound(h, segments_per_span, groups_drawn)?;
        let written = if written.is_null() {
            None
        } else {
            // SAFETY: non-NULL, so writable per the caller's contract.
            Some(unsafe { output(written, 1, 1) }?)
        };
        // SAFETY: the caller's contract; `CoifRenderVertex` is `RenderVertex`'s layout (asserted).
        let out = unsafe { output(out.cast::<RenderVertex>(), n, capacity) }?;
        let groups = groups_drawn.min(h.interpolation.group_count());
        h.guides.set_segments_per_span(segments_per_span)?;
        coif_lod::refine_strands(g.strands.blocks(), None, &mut h.guides)?;
        coif_lod::interpolate(&h.interpolation, &h.guides, None, groups, &mut h.hairs)?;
        let count = coif_lod::write_render_vertices(
            &h.interpolation,
            &h.hairs,
            groups,
            h.width,
            width_factor,
            out,
        )?;
        if let Some(w) = written {
            w[0] = count;
        }
        Ok(())
    })
}
