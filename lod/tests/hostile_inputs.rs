//! Every public entry point of coif-lod that takes caller buffers, counts
//! that must agree, or raw numbers, driven with hostile sizes and values
//! (empty, zero and huge counts, mismatched containers, NaN, infinities,
//! indices past the end): none panics, each refuses what it must with the
//! right error and then writes nothing. Property tests (proptest):
//! generated inputs find the cases hand-written ones miss.

use coif_kernels::Strands;
use coif_lod::{
    self as lod, level, Error, Fitter, Frustum, HairWidth, Interpolation, RefinedGuides,
    RenderHairs, RenderVertex, Resampler, Visibility,
};
use glam::{Mat4, Vec3, Vec4};
use proptest::prelude::*;

fn hostile_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => -2.0f32..2.0,
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => Just(0.0f32),
        1 => Just(f32::MAX),
        1 => any::<f32>(),
    ]
}

fn hostile_vec3() -> impl Strategy<Value = Vec3> {
    (hostile_f32(), hostile_f32(), hostile_f32()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Counts: small ones, zero, and ones no machine can hold.
fn hostile_count() -> impl Strategy<Value = usize> {
    prop_oneof![
        6 => 0usize..12,
        1 => Just(usize::MAX),
        1 => Just(usize::MAX / 2 + 1),
        1 => Just(1usize << 40),
    ]
}

/// A set of `n` guides of `verts` vertices on a row, the scalp triangles
/// between consecutive triples, and its interpolation.
struct Set {
    strands: Strands,
    interp: Interpolation,
}

fn set(n: usize, verts: usize, density: f32) -> Set {
    let roots: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(0.01 * i as f32, 0.0, 0.01 * (i % 2) as f32))
        .collect();
    let pts: Vec<Vec3> = roots
        .iter()
        .flat_map(|r| {
            (0..verts).map(move |v| *r + Vec3::new(0.001 * v as f32, -0.02 * v as f32, 0.0))
        })
        .collect();
    let tris: Vec<[u32; 3]> = (0..n.saturating_sub(2) as u32)
        .map(|i| [i, i + 1, i + 2])
        .collect();
    Set {
        strands: Strands::from_polylines(&pts, verts).unwrap(),
        interp: Interpolation::new(&roots, &tris, density, 5).unwrap(),
    }
}

/// A set's refined guides at `segs`, its hairs interpolated.
fn pipeline(s: &Set, max_segs: usize, segs: usize) -> (RefinedGuides, RenderHairs) {
    let mut guides = RefinedGuides::new(s.strands.blocks(), max_segs).unwrap();
    guides.set_segments_per_span(segs).unwrap();
    lod::refine_strands(s.strands.blocks(), None, &mut guides).unwrap();
    let mut hairs = RenderHairs::new(&s.interp, &guides);
    lod::interpolate(&s.interp, &guides, None, s.interp.group_count(), &mut hairs).unwrap();
    (guides, hairs)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// Refining into guides made for another shape: CountMismatch, nothing
    /// refined; into the right shape: every block.
    #[test]
    fn refine_needs_the_shape_it_was_made_for(na in 3usize..20, va in 2usize..6,
                                              nb in 3usize..20, vb in 2usize..6) {
        let (a, b) = (set(na, va, 100.0), set(nb, vb, 100.0));
        for scalar in [false, true] {
            let mut guides = RefinedGuides::new(a.strands.blocks(), 4).unwrap();
            let r = if scalar {
                lod::scalar::refine_strands(b.strands.blocks(), None, &mut guides)
            } else {
                lod::refine_strands(b.strands.blocks(), None, &mut guides)
            };
            if (na, va) == (nb, vb) {
                prop_assert_eq!(r, Ok(guides.block_count()));
            } else {
                let is_mismatch = matches!(r, Err(Error::CountMismatch { .. }));
                prop_assert!(is_mismatch);
                prop_assert!((0..guides.block_count()).all(|k| !guides.is_block_refined(k)));
            }
            let p = lod::refine_strands_positions(b.strands.blocks(), None, &mut guides);
            prop_assert_eq!(p.is_ok(), (na, va) == (nb, vb));
        }
    }

    /// Levels outside 1..=max are refused (the level kept); the clamped
    /// setter clamps.
    #[test]
    fn levels_outside_the_buffer_are_refused(max in 1usize..20, n in hostile_count()) {
        let s = set(4, 3, 100.0);
        let mut guides = RefinedGuides::new(s.strands.blocks(), max).unwrap();
        let before = guides.segments_per_span();
        match guides.set_segments_per_span(n) {
            Ok(()) => prop_assert_eq!(guides.segments_per_span(), n),
            Err(e) => {
                prop_assert!(n == 0 || n > max);
                let is_param = matches!(e, Error::InvalidParameter { name: "segments_per_span", .. });
                prop_assert!(is_param);
                prop_assert_eq!(guides.segments_per_span(), before);
            }
        }
        prop_assert_eq!(guides.set_segments_per_span_clamped(n), n.clamp(1, max));
    }

    /// Buffers of any shape: RefinedGuides::with_shape refuses counts that
    /// cannot exist instead of overflowing.
    #[test]
    fn with_shape_never_panics(strands in hostile_count(), verts in hostile_count(),
                               max in hostile_count()) {
        // Entries per output array, if they can exist at all.
        let blocks = strands.div_ceil(8);
        let len = verts
            .checked_sub(1)
            .and_then(|v| blocks.checked_mul(v))
            .and_then(|x| x.checked_mul(max))
            .and_then(|x| x.checked_add(blocks))
            .filter(|&len| len <= isize::MAX as usize / 192);
        let valid = (1..=256).contains(&max) && verts >= 2;
        match (valid, len) {
            (true, Some(len)) if len > 1 << 20 => {} // would really allocate: skip
            (true, Some(_)) => prop_assert!(RefinedGuides::with_shape(strands, verts, max).is_ok()),
            _ => {
                let r = RefinedGuides::with_shape(strands, verts, max);
                let is_param = matches!(r, Err(Error::InvalidParameter { .. }));
                prop_assert!(is_param);
            }
        }
    }

    /// Interpolating with containers of other sets, or hairs too small for
    /// the guides' level: the error, and the hairs keep their last pass.
    #[test]
    fn interpolate_refuses_mismatched_containers(na in 3usize..16, nb in 3usize..16,
                                                 segs in 1usize..5, drawn in hostile_count()) {
        let (a, b) = (set(na, 4, 400.0), set(nb, 4, 250.0));
        let (guides_a, mut hairs_a) = pipeline(&a, 4, segs);
        let (guides_b, _) = pipeline(&b, 4, segs);
        let written_before: Vec<bool> =
            (0..hairs_a.group_count()).map(|g| hairs_a.is_group_written(g)).collect();
        for scalar in [false, true] {
            for positions_only in [false, true] {
                let r = match (scalar, positions_only) {
                    (false, false) => lod::interpolate(&a.interp, &guides_b, None, drawn, &mut hairs_a),
                    (false, true) => lod::interpolate_positions(&a.interp, &guides_b, None, drawn, &mut hairs_a),
                    (true, false) => lod::scalar::interpolate(&a.interp, &guides_b, None, drawn, &mut hairs_a),
                    (true, true) => lod::scalar::interpolate_positions(&a.interp, &guides_b, None, drawn, &mut hairs_a),
                };
                if na == nb {
                    prop_assert!(r.is_ok());
                } else {
                    let is_mismatch = matches!(r, Err(Error::CountMismatch { expected, got, .. }) if (expected, got) == (na, nb));
                    prop_assert!(is_mismatch);
                    let after: Vec<bool> =
                        (0..hairs_a.group_count()).map(|g| hairs_a.is_group_written(g)).collect();
                    prop_assert_eq!(&after, &written_before);
                }
                // Hairs made for b's interpolation.
                let mut hairs_b = RenderHairs::new(&b.interp, &guides_b);
                let r = lod::interpolate(&a.interp, &guides_a, None, drawn, &mut hairs_b);
                prop_assert_eq!(r.is_ok(), a.interp.group_count() == b.interp.group_count());
            }
        }
        // Hairs sized for a lower level than the guides are at.
        let mut guides = RefinedGuides::new(a.strands.blocks(), 8).unwrap();
        guides.set_segments_per_span(1).unwrap();
        let mut small = RenderHairs::with_capacity(a.interp.group_count(), lod::refined_len(4, 1));
        guides.set_segments_per_span(8).unwrap();
        lod::refine_strands(a.strands.blocks(), None, &mut guides).unwrap();
        let r = lod::interpolate(&a.interp, &guides, None, drawn, &mut small);
        if a.interp.group_count() > 0 {
            let too_small = matches!(r, Err(Error::BufferTooSmall { .. }));
            prop_assert!(too_small);
        }
    }

    /// Render vertices: written when `out` holds render_vertex_len of them,
    /// BufferTooSmall otherwise, CountMismatch for hairs of another
    /// interpolation; hostile widths and factors never panic.
    #[test]
    fn render_vertices_refuse_short_buffers(n in 3usize..12, segs in 1usize..4,
                                            drawn in hostile_count(), out_len in 0usize..4000,
                                            root in hostile_f32(), tip in hostile_f32(),
                                            factor in hostile_f32()) {
        let s = set(n, 4, 60.0);
        let (_, hairs) = pipeline(&s, 4, segs);
        let needed = lod::render_vertex_len(&s.interp, &hairs, drawn);
        let width = HairWidth { root, tip };
        let sentinel = RenderVertex { width: 7.0, ..RenderVertex::default() };
        let mut out = vec![sentinel; out_len];
        match lod::write_render_vertices(&s.interp, &hairs, drawn, width, factor, &mut out) {
            Ok(written) => {
                prop_assert!(out_len >= needed);
                prop_assert_eq!(written, needed);
            }
            Err(e) => {
                prop_assert_eq!(e, Error::BufferTooSmall { needed, got: out_len });
                prop_assert!(out.iter().all(|v| *v == sentinel));
            }
        }
        let other = set(n + 3, 4, 60.0);
        let (_, other_hairs) = pipeline(&other, 4, segs);
        if other.interp.group_count() != s.interp.group_count() {
            let r = lod::write_render_vertices(&s.interp, &other_hairs, drawn, width, factor, &mut out);
            let is_mismatch = matches!(r, Err(Error::CountMismatch { .. }));
            prop_assert!(is_mismatch);
        }
    }

    /// Culling with a Visibility of other counts is refused; hostile
    /// frustums, margins and prefixes never panic.
    #[test]
    fn cull_refuses_mismatched_visibility(n in 3usize..20, guides in 0usize..30, groups in 0usize..30,
                                          plane in (hostile_f32(), hostile_f32(), hostile_f32(), hostile_f32()),
                                          margin in hostile_f32(), drawn in hostile_count()) {
        let s = set(n, 3, 300.0);
        let frustum = Frustum::from_planes([Vec4::new(plane.0, plane.1, plane.2, plane.3); 6]);
        let mut vis = Visibility::new(guides, groups);
        let r = lod::cull(s.strands.blocks(), Some(&s.interp), drawn, &frustum, margin, &mut vis);
        let fits = guides.div_ceil(8) == n.div_ceil(8) && groups == s.interp.group_count();
        prop_assert_eq!(r.is_ok(), fits);
        let mut vis = Visibility::new(n, s.interp.group_count());
        prop_assert!(lod::cull(s.strands.blocks(), Some(&s.interp), drawn, &frustum, margin, &mut vis).is_ok());
        let mut vis = Visibility::new(n, 0);
        prop_assert!(lod::cull(s.strands.blocks(), None, drawn, &frustum, margin, &mut vis).is_ok());
        let vp = Mat4::from_cols_array(&[plane.0; 16]);
        let _ = Frustum::from_view_projection(vp).relative_to(glam::DVec3::NAN);
    }

    /// Interpolation from hostile scalps: the documented error, never a
    /// panic.
    #[test]
    fn interpolation_refuses_bad_scalps(roots in prop::collection::vec(hostile_vec3(), 0..8),
                                        tris in prop::collection::vec(prop::array::uniform3(0u32..10), 0..6),
                                        density in hostile_f32()) {
        match Interpolation::new(&roots, &tris, density, 3) {
            Ok(i) => {
                prop_assert!(density.is_finite() && density >= 0.0);
                prop_assert!(roots.iter().all(|p| p.is_finite()));
                prop_assert_eq!(i.guide_count(), roots.len());
                let d = lod::distance_lod(&i, density, density);
                prop_assert!(d.groups_drawn <= i.group_count());
            }
            Err(Error::InvalidParameter { .. }) => {}
            Err(Error::NonFinite { index }) => prop_assert!(!roots[index].is_finite()),
            Err(Error::GuideOutOfRange { triangle, guide }) => {
                prop_assert!(tris[triangle].contains(&guide) && guide as usize >= roots.len());
            }
            Err(e) => prop_assert!(false, "unexpected {}", e),
        }
    }

    /// Fits and resampling with hostile counts and values.
    #[test]
    fn fits_refuse_bad_input(points in prop::collection::vec(hostile_vec3(), 0..24),
                             n_control in hostile_count(), smoothing in hostile_f32(),
                             out_len in 0usize..40) {
        let r = lod::fit(&points, n_control, smoothing);
        if n_control < 2 || n_control > points.len() || !(smoothing >= 0.0 && smoothing.is_finite())
            || points.iter().any(|p| !p.is_finite())
        {
            prop_assert!(r.is_err());
        }
        if let Ok(mut f) = Fitter::new(points.len(), n_control, smoothing) {
            let mut out = vec![Vec3::ONE; out_len];
            let r = f.fit_into(&points, &mut out);
            if out_len != n_control {
                let is_mismatch = matches!(r, Err(Error::CountMismatch { .. }));
                prop_assert!(is_mismatch);
                prop_assert!(out.iter().all(|&p| p == Vec3::ONE));
            }
        }
        if let Ok(mut res) = Resampler::new(16, n_control.min(16), smoothing) {
            let mut out = vec![Vec3::ONE; out_len];
            let r = res.resample_into(&points, &mut out);
            if points.is_empty() || out_len != res.n_vertices() {
                prop_assert!(r.is_err());
            }
        }
    }

    /// The curve helpers and the level arithmetic on short polygons and
    /// non-finite numbers.
    #[test]
    fn curve_helpers_never_panic(control in prop::collection::vec(hostile_vec3(), 0..6),
                                 u in hostile_f32(), i in any::<isize>(), segs in 0usize..20,
                                 a in hostile_f32(), b in hostile_f32(), c in hostile_f32()) {
        let _ = lod::bspline::evaluate(&control, u);
        let _ = lod::bspline::evaluate_derivative(&control, u);
        let _ = lod::bspline::control_point(&control, i);
        let mut out = Vec::new();
        lod::refine(&control, segs, &mut out);
        prop_assert_eq!(out.len(), lod::refined_len(control.len(), segs));
        let mut tangents = Vec::new();
        lod::refine_with_tangents(&control, segs, &mut out, &mut tangents);
        prop_assert_eq!(tangents.len(), out.len());
        let _ = level::max_second_difference(&control);
        let _ = level::segments_for_error(a, b, segs);
        let _ = level::segments_per_span(a, b, c, segs);
        let _ = level::pixels_per_metre(a, b, c);
        let _ = level::chord_error_bound(a, segs);
        let mut samples = vec![Vec3::ZERO; segs];
        lod::arc_length_samples(&control, &mut samples);
    }
}

/// Accessors past the end panic as documented (# Panics), instead of
/// reading a neighbour's data.
#[test]
fn accessors_past_the_end_panic_as_documented() {
    let s = set(5, 4, 400.0);
    let (guides, hairs) = pipeline(&s, 4, 2);
    let r = guides.verts_per_strand();
    let reads_next = std::panic::catch_unwind(|| guides.position(0, r));
    assert!(
        reads_next.is_err(),
        "vertex r of strand 0 is not the next strand's vertex 0"
    );
    assert!(std::panic::catch_unwind(|| guides.position(5, 0)).is_err());
    let v = hairs.verts_per_hair();
    assert!(std::panic::catch_unwind(|| hairs.position(0, 0, v)).is_err());
    assert!(std::panic::catch_unwind(|| hairs.position(0, coif_base::LANES, 0)).is_err());
    // The non-panicking accessors answer for any index.
    assert!(!guides.is_block_refined(usize::MAX));
    assert!(!hairs.is_group_written(usize::MAX));
    assert!(s.interp.group_blend(&guides, usize::MAX).is_none());
    // Every panicking accessor has a form that does not panic (as
    // `Groom::get_strand` for `Groom::strand`), and the block and group
    // slices are empty past the end.
    assert_eq!(guides.get_position(0, 0), Some(guides.position(0, 0)));
    assert_eq!(guides.get_position(0, r), None);
    assert_eq!(guides.get_tangent(usize::MAX, 0), None);
    assert!(guides.block_positions(usize::MAX).is_empty());
    assert!(guides.block_tangents(usize::MAX / 2).is_empty());
    assert_eq!(hairs.get_position(0, 0, 0), Some(hairs.position(0, 0, 0)));
    assert_eq!(hairs.get_position(0, coif_base::LANES, 0), None);
    assert_eq!(hairs.get_tangent(0, 0, v), None);
    assert!(hairs.group_positions(usize::MAX).is_empty());
    assert!(hairs.group_tangents(usize::MAX).is_empty());
    assert_eq!(s.interp.get_weights(0, 0), Some(s.interp.weights(0, 0)));
    assert_eq!(s.interp.get_weights(usize::MAX, 0), None);
    let blend = s.interp.group_blend(&guides, 0).unwrap();
    assert_eq!(blend.get_position(0, 0), Some(blend.position(0, 0)));
    assert_eq!(blend.get_tangent(0, usize::MAX), None);
    assert!(s.strands.block_positions_local(usize::MAX).is_empty());
    let w = lod::SpanWeights::new(2);
    assert_eq!(w.get_position(2), Some(w.position(2)));
    assert_eq!(w.get_tangent(3), None);
}
