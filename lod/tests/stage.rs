//! The LOD stage of a frame, end to end, with a counting allocator: after
//! the buffers are sized once, a frame (cull, level, refine, interpolate,
//! vertex write) allocates nothing, and its output matches the unculled,
//! full-detail path on the hair it draws.

use coif_kernels::Strands;
use coif_lod::{
    self as lod, level, HairWidth, Interpolation, RefinedGuides, RenderHairs, RenderVertex,
    Visibility,
};
use coif_testkit::counting::allocations;
use glam::{Mat4, Vec3, Vec4};

#[global_allocator]
static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;

#[test]
fn a_frame_allocates_nothing_and_draws_what_full_detail_draws() {
    // A 12 x 12 grid of guides 1 cm apart, far from the world origin.
    let far = Vec3::new(5000.0, 20.0, -3000.0);
    let (mut roots, mut pts) = (Vec::new(), Vec::new());
    for j in 0..12 {
        for i in 0..12 {
            let root = far + Vec3::new(j as f32 * 0.01, 0.0, i as f32 * 0.01);
            roots.push(root);
            for v in 0..10 {
                let a = (i * 7 + j * 3) as f32 + v as f32 * 0.8;
                pts.push(root + Vec3::new(0.008 * a.cos(), -0.02 * v as f32, 0.008 * a.sin()));
            }
        }
    }
    let mut tris = Vec::new();
    for j in 0..11u32 {
        for i in 0..11u32 {
            let g = |j: u32, i: u32| j * 12 + i;
            tris.push([g(j, i), g(j + 1, i), g(j, i + 1)]);
            tris.push([g(j + 1, i), g(j + 1, i + 1), g(j, i + 1)]);
        }
    }
    let strands = Strands::from_polylines(&pts, 10).unwrap();
    let interp = Interpolation::new(&roots, &tris, 150.0, 1).unwrap();

    // Buffers, sized once.
    let mut vis = Visibility::new(strands.strand_count(), interp.group_count());
    let mut guides = RefinedGuides::new(strands.blocks(), 16).unwrap();
    let mut hairs = RenderHairs::new(&interp, &guides);
    let max_vertices = interp.hair_count() * lod::refined_len(10, 16);
    let mut vertices = vec![RenderVertex::default(); max_vertices];

    // A camera 40 cm away looking at the left half of the patch.
    let eye = far + Vec3::new(-0.02, -0.05, 0.4);
    let f = 1.0 / 0.3f32.tan();
    let proj = Mat4::from_cols(
        Vec4::new(f, 0.0, 0.0, 0.0),
        Vec4::new(0.0, f, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 100.0 / (0.1 - 100.0), -1.0),
        Vec4::new(0.0, 0.0, 0.1 * 100.0 / (0.1 - 100.0), 0.0),
    );
    let frustum = lod::Frustum::from_view_projection(proj * Mat4::from_translation(-eye));

    let frame = |vis: &mut Visibility,
                 guides: &mut RefinedGuides,
                 hairs: &mut RenderHairs,
                 out: &mut [RenderVertex]| {
        let ppm = level::pixels_per_metre(0.4, 0.6, 1080.0);
        let d = lod::distance_lod(&interp, 80e-6 * ppm, 0.1);
        lod::cull(
            strands.blocks(),
            Some(&interp),
            d.groups_drawn,
            &frustum,
            1e-3,
            vis,
        )
        .unwrap();
        let n = level::segments_per_span(
            level::max_second_difference_strands(strands.blocks()),
            ppm,
            0.5,
            16,
        );
        guides.set_segments_per_span(n).unwrap();
        lod::refine_strands(strands.blocks(), Some(vis), guides).unwrap();
        lod::interpolate(&interp, guides, Some(vis), d.groups_drawn, hairs).unwrap();
        let written = lod::write_render_vertices(
            &interp,
            hairs,
            d.groups_drawn,
            HairWidth::default(),
            d.width_factor,
            out,
        )
        .unwrap();
        (n, d, written)
    };

    frame(&mut vis, &mut guides, &mut hairs, &mut vertices);
    let before = allocations();
    let (n, d, written) = frame(&mut vis, &mut guides, &mut hairs, &mut vertices);
    assert_eq!(allocations(), before, "a frame must not allocate");

    assert!(n > 1 && n <= 16);
    assert!(written > 0);
    assert!(
        vis.groups_visible() < d.groups_drawn,
        "part of the patch is out of view"
    );

    // Full detail, no culling: the drawn groups are identical.
    let mut all_guides = RefinedGuides::new(strands.blocks(), 16).unwrap();
    all_guides.set_segments_per_span(n).unwrap();
    lod::refine_strands(strands.blocks(), None, &mut all_guides).unwrap();
    let mut all_hairs = RenderHairs::new(&interp, &all_guides);
    lod::interpolate(
        &interp,
        &all_guides,
        None,
        interp.group_count(),
        &mut all_hairs,
    )
    .unwrap();
    for g in 0..interp.group_count() {
        if hairs.is_group_written(g) {
            assert_eq!(hairs.group_positions(g), all_hairs.group_positions(g));
        }
    }
    // World positions come back to within f32 resolution at 5 km.
    let world = Vec3::from(vertices[0].position) + strands.origin().as_vec3();
    assert!((world - far).length() < 0.3, "{world}");
}
