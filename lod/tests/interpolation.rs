//! Interpolation: valid barycentric weights, output inside the guides'
//! hull, SIMD = scalar, density in hairs per cm^2, even prefix thinning with
//! coverage-keeping width, frustum culling that never drops visible hair,
//! and the engine vertex buffer.

use coif_base::SplitMix64;
use coif_kernels::Strands;
use coif_lod::{
    self as lod, HairWidth, Interpolation, RefinedGuides, RenderHairs, RenderVertex, Visibility,
};
use glam::{DVec3, Vec3, Vec4};

const GRID: usize = 11; // guides per side, 1 cm apart: a 10 x 10 cm scalp patch
const CM: f32 = 0.01;
const VERTS: usize = 8;

/// Guide `j * GRID + i` is rooted at (j cm, 0, i cm) and hangs down 12 cm
/// with random sway, so guide blocks run along +x.
fn scalp(seed: u64) -> (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>) {
    let mut rng = SplitMix64::new(seed);
    let mut roots = Vec::new();
    let mut pts = Vec::new();
    for j in 0..GRID {
        for i in 0..GRID {
            let root = Vec3::new(j as f32 * CM, 0.0, i as f32 * CM);
            roots.push(root);
            let mut p = root;
            for _ in 0..VERTS {
                pts.push(p);
                p += Vec3::new(rng.range(-0.004, 0.004), -0.015, rng.range(-0.004, 0.004));
            }
        }
    }
    let mut tris = Vec::new();
    for j in 0..GRID - 1 {
        for i in 0..GRID - 1 {
            let g = |j: usize, i: usize| (j * GRID + i) as u32;
            tris.push([g(j, i), g(j + 1, i), g(j, i + 1)]);
            tris.push([g(j + 1, i), g(j + 1, i + 1), g(j, i + 1)]);
        }
    }
    (roots, pts, tris)
}

struct Scene {
    strands: Strands,
    interp: Interpolation,
    guides: RefinedGuides,
    hairs: RenderHairs,
}

fn scene(density: f32, segs: usize) -> Scene {
    let (roots, pts, tris) = scalp(21);
    let strands = Strands::from_polylines(&pts, VERTS).unwrap();
    let interp = Interpolation::new(&roots, &tris, density, 99).unwrap();
    let mut guides = RefinedGuides::new(strands.blocks(), 8).unwrap();
    guides.set_segments_per_span(segs).unwrap();
    let hairs = RenderHairs::new(&interp, &guides);
    Scene {
        strands,
        interp,
        guides,
        hairs,
    }
}

#[test]
fn weights_are_valid_barycentric_coordinates() {
    let s = scene(150.0, 2);
    for (g, group) in s.interp.groups().iter().enumerate() {
        assert!((1..=8).contains(&group.hairs));
        for l in 0..8 {
            let w = s.interp.weights(g, l);
            assert!(w.iter().all(|&b| b >= 0.0), "{w:?}");
            assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6, "{w:?}");
        }
    }
    for _ in 0..1000 {
        let b = lod::barycentric(0.999_999_9, 0.999_999_9);
        assert!(b.iter().all(|&x| x >= 0.0) && (b.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    }
    // Reproducible from the seed; another seed places hair elsewhere.
    let (roots, _, tris) = scalp(21);
    let a = Interpolation::new(&roots, &tris, 150.0, 5).unwrap();
    let b = Interpolation::new(&roots, &tris, 150.0, 5).unwrap();
    let c = Interpolation::new(&roots, &tris, 150.0, 6).unwrap();
    assert_eq!(a.groups(), b.groups());
    assert_eq!(a.weights(3, 2), b.weights(3, 2));
    assert_ne!(a.weights(3, 2), c.weights(3, 2));
}

#[test]
fn interpolated_hair_lies_inside_the_guides_hull_and_simd_equals_scalar() {
    let mut s = scene(150.0, 3);
    lod::refine_strands(s.strands.blocks(), None, &mut s.guides).unwrap();
    let groups = s.interp.group_count();
    assert_eq!(
        lod::interpolate(&s.interp, &s.guides, None, groups, &mut s.hairs).unwrap(),
        groups
    );
    let mut scalar = RenderHairs::new(&s.interp, &s.guides);
    assert_eq!(
        lod::scalar::interpolate(&s.interp, &s.guides, None, groups, &mut scalar).unwrap(),
        groups
    );
    let r_len = s.hairs.verts_per_hair();
    assert_eq!(r_len, lod::refined_len(VERTS, 3));
    for (g, group) in s.interp.groups().iter().enumerate() {
        let [a, b, c] = group.guides.map(|x| x as usize);
        for l in 0..group.hairs as usize {
            for r in 0..r_len {
                let p = s.hairs.position(g, l, r);
                let t = s.hairs.tangent(g, l, r);
                assert!((p - scalar.position(g, l, r)).length() < 1e-7);
                assert!((t - scalar.tangent(g, l, r)).length() < 1e-6);
                assert!((t.length() - 1.0).abs() < 1e-5);
                let corners = [a, b, c].map(|k| s.guides.position(k, r).as_dvec3());
                let bary = barycentric_of(p.as_dvec3(), corners);
                assert!(
                    bary.iter().all(|&x| x > -1e-4),
                    "g {g} l {l} r {r}: {bary:?}"
                );
                let back: DVec3 = (0..3).map(|k| bary[k] * corners[k]).sum();
                assert!(
                    (back - p.as_dvec3()).length() < 1e-6,
                    "off the guides' plane"
                );
            }
        }
    }
}

/// Barycentric coordinates of the point of triangle `t` nearest `p`
/// (least squares on the triangle's plane).
fn barycentric_of(p: DVec3, t: [DVec3; 3]) -> [f64; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let det = a * c - b * b;
    let v = (c * d1 - b * d2) / det;
    let w = (a * d2 - b * d1) / det;
    [1.0 - v - w, v, w]
}

#[test]
fn density_matches_hairs_per_cm2() {
    for &density in &[120.0f32, 150.0, 200.0] {
        let mut s = scene(density, 1);
        lod::refine_strands(s.strands.blocks(), None, &mut s.guides).unwrap();
        let groups = s.interp.group_count();
        lod::interpolate(&s.interp, &s.guides, None, groups, &mut s.hairs).unwrap();
        let area_cm2 = s.interp.scalp_area_m2() / 1e-4;
        assert!((area_cm2 - 100.0).abs() < 1e-3);
        let total = s.interp.hair_count() as f64 / area_cm2;
        assert!(
            (total / density as f64 - 1.0).abs() < 0.05,
            "total density {total}"
        );
        // Local density in a 6 x 6 cm window that cuts across triangles.
        let (x0, z0, side) = (2.3 * CM, 1.7 * CM, 6.0 * CM);
        let mut inside = 0;
        for (g, group) in s.interp.groups().iter().enumerate() {
            for l in 0..group.hairs as usize {
                let root = s.hairs.position(g, l, 0) + s.strands.origin().as_vec3();
                assert!(root.y.abs() < 1e-6, "roots stay on the scalp");
                if (x0..x0 + side).contains(&root.x) && (z0..z0 + side).contains(&root.z) {
                    inside += 1;
                }
            }
        }
        let local = inside as f64 / 36.0;
        assert!(
            (local / density as f64 - 1.0).abs() < 0.05,
            "density {density}: window has {local} per cm^2"
        );
    }
}

#[test]
fn a_prefix_is_an_even_thinning_and_width_keeps_coverage() {
    let mut s = scene(150.0, 1);
    lod::refine_strands(s.strands.blocks(), None, &mut s.guides).unwrap();
    let lod_half = lod::distance_lod(&s.interp, 0.5, 0.1);
    let groups = s.interp.group_count();
    assert_eq!(lod_half.groups_drawn, groups.div_ceil(2));
    let written = lod::interpolate(
        &s.interp,
        &s.guides,
        None,
        lod_half.groups_drawn,
        &mut s.hairs,
    )
    .unwrap();
    assert_eq!(written, lod_half.groups_drawn);
    let (mut all, mut drawn) = ([0usize; 4], [0usize; 4]);
    for (g, group) in s.interp.groups().iter().enumerate() {
        // Quadrant of the group's triangle centre.
        let [a, b, c] = group.guides.map(|k| (k as usize / GRID, k as usize % GRID));
        let q = usize::from(a.0 + b.0 + c.0 >= 15) * 2 + usize::from(a.1 + b.1 + c.1 >= 15);
        all[q] += group.hairs as usize;
        if g < lod_half.groups_drawn {
            drawn[q] += group.hairs as usize;
            assert!(s.hairs.is_group_written(g));
        } else {
            assert!(!s.hairs.is_group_written(g));
        }
    }
    for q in 0..4 {
        let f = drawn[q] as f64 / all[q] as f64;
        assert!((f - 0.5).abs() < 0.07, "quadrant {q}: drew {f} of its hair");
    }
    // Coverage: drawn hairs x width factor = all hairs.
    for &px in &[0.05f32, 0.3, 0.5, 0.99] {
        let d = lod::distance_lod(&s.interp, px, 0.1);
        assert_eq!(d.hairs_drawn, s.interp.hairs_in_prefix(d.groups_drawn));
        let kept = d.hairs_drawn as f32 * d.width_factor;
        assert!((kept / s.interp.hair_count() as f32 - 1.0).abs() < 1e-5);
        assert!(d.groups_drawn as f32 >= px.max(0.1) * groups as f32);
    }
    let full = lod::distance_lod(&s.interp, 2.0, 0.1);
    assert_eq!((full.groups_drawn, full.width_factor), (groups, 1.0));
    assert_eq!(
        lod::distance_lod(&s.interp, f32::NAN, 0.1).groups_drawn,
        groups
    );
}

#[test]
fn frustum_culling_skips_work_but_never_visible_hair() {
    let mut s = scene(150.0, 2);
    let groups = s.interp.group_count();
    // Reference: everything refined and interpolated.
    lod::refine_strands(s.strands.blocks(), None, &mut s.guides).unwrap();
    lod::interpolate(&s.interp, &s.guides, None, groups, &mut s.hairs).unwrap();
    let full = s.hairs.clone();

    // A view of the half-space x <= 3.5 cm (world), with a real camera
    // frustum's other planes far away.
    let big = Vec4::new(0.0, 1.0, 0.0, 100.0);
    let frustum =
        lod::Frustum::from_planes([Vec4::new(-1.0, 0.0, 0.0, 3.5 * CM), big, big, big, big, big]);
    let mut vis = Visibility::new(s.strands.strand_count(), groups);
    lod::cull(
        s.strands.blocks(),
        Some(&s.interp),
        groups,
        &frustum,
        0.0,
        &mut vis,
    )
    .unwrap();
    assert!(
        vis.groups_visible() < groups / 2,
        "culling must drop hair out of view"
    );
    assert!(vis.guide_blocks_needed() < s.strands.block_count());

    let mut guides = RefinedGuides::new(s.strands.blocks(), 8).unwrap();
    guides.set_segments_per_span(2).unwrap();
    let refined = lod::refine_strands(s.strands.blocks(), Some(&vis), &mut guides).unwrap();
    assert_eq!(refined, vis.guide_blocks_needed());
    let mut hairs = RenderHairs::new(&s.interp, &guides);
    let written = lod::interpolate(&s.interp, &guides, Some(&vis), groups, &mut hairs).unwrap();
    assert_eq!(written, vis.groups_visible());
    let origin_x = s.strands.origin().x as f32;
    for (g, group) in s.interp.groups().iter().enumerate() {
        for l in 0..group.hairs as usize {
            let any_inside =
                (0..full.verts_per_hair()).any(|r| full.position(g, l, r).x + origin_x <= 3.5 * CM);
            if any_inside {
                assert!(
                    vis.group_visible(g),
                    "group {g} has visible hair but was culled"
                );
            }
        }
        if vis.group_visible(g) {
            assert!(hairs.is_group_written(g));
            assert_eq!(hairs.group_positions(g), full.group_positions(g));
        } else {
            assert!(!hairs.is_group_written(g));
        }
    }
    // Gribb-Hartmann planes of a real camera: a point in front is inside,
    // one behind is not.
    // Right-handed perspective, depth 0..1: fov_y 0.8 rad, aspect 1.5,
    // near 0.1, far 10; the camera at z = 1 looks down -z.
    let (f, aspect, near, far) = (1.0 / 0.4f32.tan(), 1.5, 0.1, 10.0);
    let proj = glam::Mat4::from_cols(
        Vec4::new(f / aspect, 0.0, 0.0, 0.0),
        Vec4::new(0.0, f, 0.0, 0.0),
        Vec4::new(0.0, 0.0, far / (near - far), -1.0),
        Vec4::new(0.0, 0.0, near * far / (near - far), 0.0),
    );
    let view = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, -1.0));
    let cam = lod::Frustum::from_view_projection(proj * view);
    assert!(cam.intersects_box(Vec3::splat(-0.01), Vec3::splat(0.01), 0.0));
    assert!(!cam.intersects_box(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.1, 0.1, 2.1), 0.0));
    assert!(!cam.intersects_box(Vec3::new(5.0, 0.0, -0.1), Vec3::new(5.1, 0.1, 0.0), 0.0));
}

#[test]
fn render_vertices_fill_an_engine_buffer() {
    let mut s = scene(120.0, 2);
    lod::refine_strands(s.strands.blocks(), None, &mut s.guides).unwrap();
    let d = lod::distance_lod(&s.interp, 0.4, 0.1);
    lod::interpolate(&s.interp, &s.guides, None, d.groups_drawn, &mut s.hairs).unwrap();
    let len = lod::render_vertex_len(&s.interp, &s.hairs, d.groups_drawn);
    assert_eq!(len, d.hairs_drawn * s.hairs.verts_per_hair());
    let mut buf = vec![RenderVertex::default(); len];
    let width = HairWidth {
        root: 1e-4,
        tip: 5e-5,
    };
    let n = lod::write_render_vertices(
        &s.interp,
        &s.hairs,
        d.groups_drawn,
        width,
        d.width_factor,
        &mut buf,
    )
    .unwrap();
    assert_eq!(n, len);
    assert_eq!(lod::vertex_bytes(&buf).len(), 32 * len);
    let r_len = s.hairs.verts_per_hair();
    for hair in buf.chunks(r_len) {
        assert_eq!(hair[0].strand_parameter, 0.0);
        assert_eq!(hair[r_len - 1].strand_parameter, 1.0);
        assert!((hair[0].width - 1e-4 * d.width_factor).abs() < 1e-9);
        assert!((hair[r_len - 1].width - 5e-5 * d.width_factor).abs() < 1e-9);
        assert!(hair
            .iter()
            .all(|v| (Vec3::from(v.tangent).length() - 1.0).abs() < 1e-5));
    }
    // The first hair is lane 0 of group 0.
    assert_eq!(Vec3::from(buf[1].position), s.hairs.position(0, 0, 1));
    // A short buffer is refused, not filled with what fits.
    let mut short = vec![RenderVertex::default(); r_len + 1];
    assert_eq!(
        lod::write_render_vertices(&s.interp, &s.hairs, d.groups_drawn, width, 1.0, &mut short),
        Err(lod::Error::BufferTooSmall {
            needed: lod::render_vertex_len(&s.interp, &s.hairs, d.groups_drawn),
            got: r_len + 1
        })
    );
    assert_eq!(short, vec![RenderVertex::default(); r_len + 1]);
}

#[test]
fn bad_scalps_return_errors() {
    let (roots, _, tris) = scalp(1);
    assert!(Interpolation::new(&roots, &[[0, 1, 999]], 150.0, 1).is_err());
    assert!(Interpolation::new(&roots, &tris, -1.0, 1).is_err());
    assert!(Interpolation::new(&roots, &tris, f32::NAN, 1).is_err());
    assert!(Interpolation::new(&roots, &tris, 1e12, 1).is_err());
    let mut bad = roots.clone();
    bad[3].x = f32::INFINITY;
    assert!(Interpolation::new(&bad, &tris, 150.0, 1).is_err());
    let empty = Interpolation::new(&roots, &[], 150.0, 1).unwrap();
    assert_eq!((empty.hair_count(), empty.group_count()), (0, 0));
}

#[test]
fn placement_is_uniform_inside_a_triangle() {
    // One 20 x 20 cm right triangle (200 cm^2) at 150 per cm^2: the four
    // half-size sub-triangles (corners A, B, C and the middle) must each
    // get the requested density within 5%.
    let roots = [
        Vec3::ZERO,
        Vec3::new(0.2, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.2),
    ];
    let mut pts = Vec::new();
    for r in roots {
        pts.extend([r, r - Vec3::Y * 0.1]);
    }
    let strands = Strands::from_polylines(&pts, 2).unwrap();
    let interp = Interpolation::new(&roots, &[[0, 1, 2]], 150.0, 3).unwrap();
    let mut guides = RefinedGuides::new(strands.blocks(), 1).unwrap();
    lod::refine_strands(strands.blocks(), None, &mut guides).unwrap();
    let mut hairs = RenderHairs::new(&interp, &guides);
    lod::interpolate(&interp, &guides, None, interp.group_count(), &mut hairs).unwrap();
    let origin = strands.origin();
    let corners = roots.map(|r| r.as_dvec3());
    let mut counts = [0usize; 4];
    for (g, group) in interp.groups().iter().enumerate() {
        for l in 0..group.hairs as usize {
            let p = hairs.position(g, l, 0).as_dvec3() + origin;
            let b = barycentric_of(p, corners);
            let region = (0..3).find(|&k| b[k] > 0.5).unwrap_or(3);
            counts[region] += 1;
        }
    }
    for (k, &c) in counts.iter().enumerate() {
        let density = c as f64 / 50.0;
        assert!(
            (density / 150.0 - 1.0).abs() < 0.05,
            "sub-triangle {k}: {density} per cm^2 ({counts:?})"
        );
    }
}

#[test]
fn positions_only_pass_matches_full_pass_and_scalar() {
    let mut s = scene(150.0, 2);
    lod::refine_strands(s.strands.blocks(), None, &mut s.guides).unwrap();
    let groups = s.interp.group_count();
    lod::interpolate(&s.interp, &s.guides, None, groups, &mut s.hairs).unwrap();
    let full = s.hairs.clone();
    assert!(full.has_tangents());
    let mut simd = RenderHairs::new(&s.interp, &s.guides);
    let mut scalar = RenderHairs::new(&s.interp, &s.guides);
    assert_eq!(
        lod::interpolate_positions(&s.interp, &s.guides, None, groups, &mut simd).unwrap(),
        groups
    );
    assert_eq!(
        lod::scalar::interpolate_positions(&s.interp, &s.guides, None, groups, &mut scalar)
            .unwrap(),
        groups
    );
    assert!(!simd.has_tangents());
    for g in 0..groups {
        assert_eq!(simd.group_positions(g), full.group_positions(g));
        for (a, b) in simd
            .group_positions(g)
            .iter()
            .zip(scalar.group_positions(g))
        {
            for l in 0..8 {
                assert!((a.lane(l) - b.lane(l)).length() < 1e-7);
            }
        }
    }
    // Vertex tangents from differences agree with the interpolated ones.
    let len = lod::render_vertex_len(&s.interp, &simd, groups);
    let mut a = vec![RenderVertex::default(); len];
    let mut b = vec![RenderVertex::default(); len];
    lod::write_render_vertices(&s.interp, &full, groups, HairWidth::default(), 1.0, &mut a)
        .unwrap();
    lod::write_render_vertices(&s.interp, &simd, groups, HairWidth::default(), 1.0, &mut b)
        .unwrap();
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.position, y.position);
        let d = Vec3::from(x.tangent).dot(Vec3::from(y.tangent));
        assert!(d > 0.95, "difference tangent off by {} rad", d.acos());
    }
}

#[test]
fn whole_groups_keep_the_density_and_fill_every_lane() {
    let (roots, _, tris) = scalp(21);
    let interp = Interpolation::with_whole_groups(&roots, &tris, 150.0, 4).unwrap();
    assert!(interp.groups().iter().all(|g| g.hairs == 8));
    let density = interp.hair_count() as f64 / (interp.scalp_area_m2() / 1e-4);
    assert!((density / 150.0 - 1.0).abs() < 0.05, "{density}");
}

/// `Interpolation::group_blend`, the row-by-row interpolation of one group
/// that fused passes use: its `_x8` rows are the numbers `interpolate`
/// writes, bit for bit (the same blend), and its scalar twins agree with
/// them (positions bit for bit: the same fused multiply-adds; tangents
/// within 1e-6, rsqrt + Newton against `1 / sqrt`).
#[test]
fn group_blend_rows_equal_interpolate_and_the_scalar_twin() {
    let mut s = scene(150.0, 3);
    lod::refine_strands(s.strands.blocks(), None, &mut s.guides).unwrap();
    let groups = s.interp.group_count();
    lod::interpolate(&s.interp, &s.guides, None, groups, &mut s.hairs).unwrap();
    assert!(groups > 10);
    for g in 0..groups {
        assert!(s.interp.is_group_drawn(g, groups, None, &s.guides));
        assert!(
            !s.interp.is_group_drawn(g, g, None, &s.guides),
            "past the prefix"
        );
        let blend = s.interp.group_blend(&s.guides, g).unwrap();
        assert_eq!(blend.verts(), s.hairs.verts_per_hair());
        assert_eq!(blend.hairs(), s.interp.groups()[g].hairs as usize);
        for r in 0..blend.verts() {
            let (p, t) = (blend.position_simd(r), blend.tangent_simd(r));
            let i = r;
            assert_eq!(p, s.hairs.group_positions(g)[i], "group {g} row {r}");
            assert_eq!(t, s.hairs.group_tangents(g)[i], "group {g} row {r}");
            for l in 0..8 {
                assert_eq!(blend.position(l, r), p.lane(l));
                assert!((blend.tangent(l, r) - t.lane(l)).length() < 1e-6);
            }
        }
    }
    assert!(s.interp.group_blend(&s.guides, groups).is_none());
}

/// `Interpolation::groups_blend`, the blend of `GROUPS_PER_BLOCK` groups in
/// one block's lanes that the fused prepare pass uses (two at 16 lanes, one
/// at 8): lane `8 k + i` is lane `i` of `group_blend` of group `k`, bit for
/// bit (the same blend, each group's guides broadcast to its eight lanes),
/// and the real hairs are each group's first lanes. Too many groups, none,
/// or one out of range is refused.
#[test]
fn groups_blend_lanes_equal_each_groups_own_blend() {
    use coif_base::lanes::{GROUPS_PER_BLOCK, GROUP_LANES};
    let mut s = scene(150.0, 5);
    lod::refine_strands(s.strands.blocks(), None, &mut s.guides).unwrap();
    let groups = s.interp.group_count();
    assert!(groups > 2 * GROUPS_PER_BLOCK);
    let mut partial = 0;
    for first in (0..groups - GROUPS_PER_BLOCK).step_by(3) {
        // Groups that are not neighbours, as a thinned shadow map takes.
        let list: Vec<usize> = (0..GROUPS_PER_BLOCK).map(|k| first + 2 * k).collect();
        let blend = s.interp.groups_blend(&s.guides, &list).unwrap();
        let mut bits = 0u32;
        for (k, &g) in list.iter().enumerate() {
            let own = s.interp.group_blend(&s.guides, g).unwrap();
            let hairs = s.interp.groups()[g].hairs as usize;
            partial += usize::from(hairs < GROUP_LANES);
            assert_eq!(blend.group_hairs(k), hairs);
            bits |= ((1 << hairs) - 1) << (k * GROUP_LANES);
            for r in 0..blend.verts() {
                let (p, t) = (blend.position_simd(r), blend.tangent_simd(r));
                let (p_own, t_own) = (own.position_simd(r), own.tangent_simd(r));
                for i in 0..GROUP_LANES {
                    let l = k * GROUP_LANES + i;
                    assert_eq!(p.lane(l), p_own.lane(i), "group {g} lane {i} row {r}");
                    assert_eq!(t.lane(l), t_own.lane(i), "group {g} lane {i} row {r}");
                    assert_eq!(blend.position(l, r), p.lane(l));
                    assert!((blend.tangent(l, r) - t.lane(l)).length() < 1e-6);
                }
            }
        }
        assert_eq!(blend.hair_bits(), bits);
        assert_eq!(
            blend.hairs(),
            list.iter()
                .map(|&g| s.interp.groups()[g].hairs as usize)
                .sum::<usize>()
        );
    }
    assert!(
        partial > 0,
        "some groups should hold fewer than eight hairs"
    );
    // One group in a block: the other slots hold no hair.
    let one = s.interp.groups_blend(&s.guides, &[1]).unwrap();
    assert_eq!(one.hair_bits(), (1 << s.interp.groups()[1].hairs) - 1);
    assert!(s.interp.groups_blend(&s.guides, &[]).is_none());
    assert!(s
        .interp
        .groups_blend(&s.guides, &[0; GROUPS_PER_BLOCK + 1])
        .is_none());
    assert!(s.interp.groups_blend(&s.guides, &[groups]).is_none());
}
