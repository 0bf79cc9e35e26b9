//! Refinement: `coif_lod::refine` against an independent closed-form
//! B-spline evaluation, exact end points, tangents against finite
//! differences, the SIMD batch against its scalar twin and against `refine`,
//! culled blocks skipped, and the chosen level's measured error in budget.

use coif_base::{SplitMix64, LANES};
use coif_kernels::Strands;
use coif_lod::{self as lod, level, quality, RefinedGuides, Visibility};
use glam::{DVec3, Vec3};

/// Uniform cubic B-spline in matrix form, in f64 (written independently of
/// the library's weight formulas): `C(t) = [t^3 t^2 t 1] M [P0 P1 P2 P3]^T`
/// with `M = 1/6 [[-1 3 -3 1] [3 -6 3 0] [-3 0 3 0] [1 4 1 0]]`.
fn closed_form(control: &[Vec3], u: f64) -> DVec3 {
    let n = control.len();
    let p = |i: isize| -> DVec3 {
        let c = |k: usize| control[k].as_dvec3();
        if i < 0 {
            2.0 * c(0) - c(1)
        } else if i as usize >= n {
            2.0 * c(n - 1) - c(n - 2)
        } else {
            c(i as usize)
        }
    };
    let j = (u.floor() as usize).min(n - 2);
    let t = u - j as f64;
    let m = [
        [-1.0, 3.0, -3.0, 1.0],
        [3.0, -6.0, 3.0, 0.0],
        [-3.0, 0.0, 3.0, 0.0],
        [1.0, 4.0, 1.0, 0.0],
    ];
    let tv = [t * t * t, t * t, t, 1.0];
    let mut out = DVec3::ZERO;
    for (k, offset) in (-1isize..=2).enumerate() {
        let w: f64 = tv.iter().zip(&m).map(|(tr, row)| tr * row[k]).sum::<f64>() / 6.0;
        out += w * p(j as isize + offset);
    }
    out
}

fn random_strand(rng: &mut SplitMix64, n: usize, scale: f32) -> Vec<Vec3> {
    let mut p = Vec3::new(rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0)) * scale;
    (0..n)
        .map(|_| {
            let q = p;
            p += Vec3::new(rng.range(-0.5, 0.5), -1.0, rng.range(-0.5, 0.5)) * (0.1 * scale);
            q
        })
        .collect()
}

#[test]
fn refine_matches_closed_form_and_hits_end_points_exactly() {
    let mut rng = SplitMix64::new(1);
    let mut out = Vec::new();
    for &n in &[2usize, 3, 4, 7, 16] {
        for &segs in &[1usize, 2, 4, 5, 16] {
            let ctrl = random_strand(&mut rng, n, 0.3);
            lod::refine(&ctrl, segs, &mut out);
            assert_eq!(out.len(), (n - 1) * segs + 1);
            assert_eq!(out[0], ctrl[0], "root must be exact");
            assert_eq!(*out.last().unwrap(), ctrl[n - 1], "tip must be exact");
            for (k, p) in out.iter().enumerate() {
                let exact = closed_form(&ctrl, k as f64 / segs as f64);
                let err = (p.as_dvec3() - exact).length();
                assert!(err < 1e-6, "n {n} N {segs} k {k}: {p} vs {exact} ({err})");
            }
        }
    }
}

#[test]
fn refine_edge_cases_are_documented_behaviour() {
    let mut out = vec![Vec3::ONE];
    lod::refine(&[], 4, &mut out);
    assert!(out.is_empty());
    lod::refine(&[Vec3::X], 4, &mut out);
    assert_eq!(out, vec![Vec3::X]);
    let ctrl = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)];
    let mut one = Vec::new();
    lod::refine(&ctrl, 0, &mut out);
    lod::refine(&ctrl, 1, &mut one);
    assert_eq!(out, one, "N = 0 is treated as N = 1");
}

#[test]
fn tangents_match_finite_differences() {
    let mut rng = SplitMix64::new(2);
    let (mut pos, mut tan) = (Vec::new(), Vec::new());
    for _ in 0..20 {
        let ctrl = random_strand(&mut rng, 9, 0.2);
        let segs = 5;
        lod::refine_with_tangents(&ctrl, segs, &mut pos, &mut tan);
        assert_eq!(tan.len(), pos.len());
        let last = (ctrl.len() - 1) as f64;
        for (k, t) in tan.iter().enumerate() {
            let u = k as f64 / segs as f64;
            let h = 1e-4;
            let (a, b) = ((u - h).max(0.0), (u + h).min(last));
            // One-sided at the ends; central inside (the derivative is continuous).
            let fd = (closed_form(&ctrl, b) - closed_form(&ctrl, a)) / (b - a);
            let fd = fd.normalize().as_vec3();
            assert!((t.length() - 1.0).abs() < 1e-5, "not unit: {t}");
            assert!((*t - fd).length() < 2e-3, "k {k}: {t} vs {fd}");
        }
    }
}

fn strand_set(seed: u64, strands: usize, verts: usize) -> (Vec<Vec3>, Strands) {
    let mut rng = SplitMix64::new(seed);
    let mut pts = Vec::new();
    for _ in 0..strands {
        pts.extend(random_strand(&mut rng, verts, 0.25));
    }
    let s = Strands::from_polylines(&pts, verts).unwrap();
    (pts, s)
}

#[test]
fn simd_batch_matches_scalar_twin_and_single_strand_refine() {
    // 21 strands: three blocks at 8 lanes (the last with five padding
    // lanes), two at 16.
    let (_, strands) = strand_set(3, 21, 9);
    let blocks = 21usize.div_ceil(LANES);
    let local = strands.positions_local();
    let mut simd = RefinedGuides::new(strands.blocks(), 16).unwrap();
    let mut scal = RefinedGuides::new(strands.blocks(), 16).unwrap();
    let (mut single, mut single_t) = (Vec::new(), Vec::new());
    for &segs in &[1usize, 3, 4, 7, 16] {
        simd.set_segments_per_span(segs).unwrap();
        assert_eq!(simd.segments_per_span(), segs);
        scal.set_segments_per_span(segs).unwrap();
        assert_eq!(
            lod::refine_strands(strands.blocks(), None, &mut simd).unwrap(),
            blocks
        );
        assert_eq!(
            lod::scalar::refine_strands(strands.blocks(), None, &mut scal).unwrap(),
            blocks
        );
        let r = simd.verts_per_strand();
        assert_eq!(r, lod::refined_len(9, segs));
        for i in 0..21 {
            let ctrl = &local[i * 9..(i + 1) * 9];
            lod::refine_with_tangents(ctrl, segs, &mut single, &mut single_t);
            for v in 0..r {
                let (ps, pc) = (simd.position(i, v), scal.position(i, v));
                let (ts, tc) = (simd.tangent(i, v), scal.tangent(i, v));
                assert!((ps - pc).length() < 1e-6, "pos {i} {v}: {ps} vs {pc}");
                assert!((ts - tc).length() < 1e-6, "tan {i} {v}: {ts} vs {tc}");
                assert!((ps - single[v]).length() < 1e-6, "vs refine {i} {v}");
                assert!(
                    (ts - single_t[v]).length() < 1e-5,
                    "vs refine tangent {i} {v}"
                );
            }
            assert_eq!(simd.position(i, 0), ctrl[0]);
            assert_eq!(simd.position(i, r - 1), ctrl[8]);
        }
    }
}

#[test]
fn culled_blocks_are_not_refined() {
    // Three blocks; block 1 (strands LANES..2 LANES) sits 10 m away along +x.
    let n = 3 * LANES;
    let (mut pts, _) = strand_set(4, n, 6);
    for p in &mut pts[LANES * 6..2 * LANES * 6] {
        p.x += 10.0;
    }
    let strands = Strands::from_polylines(&pts, 6).unwrap();
    let mut out = RefinedGuides::new(strands.blocks(), 8).unwrap();
    out.set_segments_per_span(4).unwrap();
    assert_eq!(
        lod::refine_strands(strands.blocks(), None, &mut out).unwrap(),
        3
    );
    let before: Vec<Vec3> = (0..out.verts_per_strand())
        .map(|v| out.position(LANES + 1, v))
        .collect();

    // Move strand LANES + 1 (and all others) by 1 cm, then refine with a frustum
    // holding everything but x > 5 m (a slab): block 1 is culled.
    for p in &mut pts {
        p.z += 0.01 * (p.x > 5.0) as i32 as f32 + 0.003;
    }
    let moved = Strands::from_polylines(&pts, 6).unwrap();
    let big = glam::Vec4::new(0.0, 1.0, 0.0, 1e6);
    let slab = lod::Frustum::from_planes([
        glam::Vec4::new(-1.0, 0.0, 0.0, 5.0),
        big,
        big,
        big,
        big,
        big,
    ]);
    let mut vis = Visibility::new(n, 0);
    lod::cull(moved.blocks(), None, 0, &slab, 0.0, &mut vis).unwrap();
    assert_eq!(vis.guide_blocks_needed(), 2);
    assert!(!vis.guide_block_needed(1));
    assert_eq!(
        lod::refine_strands(moved.blocks(), Some(&vis), &mut out).unwrap(),
        2
    );
    assert!(!out.is_block_refined(1) && out.is_block_refined(0) && out.is_block_refined(2));
    let after: Vec<Vec3> = (0..out.verts_per_strand())
        .map(|v| out.position(LANES + 1, v))
        .collect();
    assert_eq!(before, after, "a culled block must not be written");
    assert_eq!(
        lod::scalar::refine_strands(moved.blocks(), Some(&vis), &mut out).unwrap(),
        2
    );
    let after: Vec<Vec3> = (0..out.verts_per_strand())
        .map(|v| out.position(LANES + 1, v))
        .collect();
    assert_eq!(before, after, "the scalar twin must skip it too");

    // Everything visible: block 1 is refined with the new data.
    assert_eq!(
        lod::refine_strands(moved.blocks(), None, &mut out).unwrap(),
        3
    );
    assert!(out.is_block_refined(1));
    assert_ne!(out.position(LANES + 1, 1), before[1]);
}

#[test]
fn mismatched_buffer_writes_nothing() {
    let (_, a) = strand_set(5, 8, 6);
    let (_, b) = strand_set(6, 8, 7);
    let mut out = RefinedGuides::new(a.blocks(), 4).unwrap();
    let refused = Err(lod::Error::CountMismatch {
        what: "control points per strand (RefinedGuides made for another set)",
        expected: 6,
        got: 7,
    });
    assert_eq!(lod::refine_strands(b.blocks(), None, &mut out), refused);
    assert_eq!(
        lod::scalar::refine_strands(b.blocks(), None, &mut out),
        refused
    );
    assert!((0..out.block_count()).all(|b| !out.is_block_refined(b)));
    assert!(RefinedGuides::new(a.blocks(), 0).is_err());
}

#[test]
fn chosen_level_stays_within_pixel_budget() {
    let mut rng = SplitMix64::new(7);
    for trial in 0..40 {
        // Curly strands of 16 controls, 10-30 cm long, 0.5-3 cm curls.
        let radius = rng.range(0.005, 0.03);
        let length = rng.range(0.1, 0.3);
        let turns = rng.range(0.5, 4.0);
        let ctrl = quality::helix(16, radius, length, turns);
        let ppm = level::pixels_per_metre(rng.range(0.3, 5.0), 0.8, 1080.0);
        let eps_px = [0.25f32, 0.5, 1.0][trial % 3];
        let d2 = level::max_second_difference(&ctrl);
        let n = level::segments_per_span(d2, ppm, eps_px, 64);
        assert!(n < 64, "budget reachable without clamping");
        let measured_px = quality::chord_error(&ctrl, n) * ppm;
        assert!(
            measured_px <= eps_px,
            "trial {trial}: N {n} measured {measured_px} px > budget {eps_px} px"
        );
        // The bound is not vacuous: at N = 1 the bound is above the measured error too.
        assert!(
            quality::chord_error(&ctrl, 1) * ppm <= level::chord_error_bound(d2 * ppm, 1) * 1.0001
        );
    }
}

#[test]
fn batch_second_difference_matches_per_strand() {
    let (pts, strands) = strand_set(8, 19, 10);
    let expected = pts
        .chunks(10)
        .map(|c| {
            let o = strands.origin().as_vec3();
            let local: Vec<Vec3> = c.iter().map(|p| *p - o).collect();
            level::max_second_difference(&local)
        })
        .fold(0.0, f32::max);
    let got = level::max_second_difference_strands(strands.blocks());
    assert!(
        (got - expected).abs() <= 1e-5 * expected,
        "{got} vs {expected}"
    );
}

#[test]
fn positions_only_refinement_matches_the_full_pass() {
    let (_, strands) = strand_set(9, 13, 7);
    let mut full = RefinedGuides::new(strands.blocks(), 8).unwrap();
    let mut simd = RefinedGuides::new(strands.blocks(), 8).unwrap();
    let mut scal = RefinedGuides::new(strands.blocks(), 8).unwrap();
    for segs in [1, 4, 8] {
        for out in [&mut full, &mut simd, &mut scal] {
            out.set_segments_per_span(segs).unwrap();
        }
        lod::refine_strands(strands.blocks(), None, &mut full).unwrap();
        assert_eq!(
            lod::refine_strands_positions(strands.blocks(), None, &mut simd).unwrap(),
            13usize.div_ceil(LANES)
        );
        assert_eq!(
            lod::scalar::refine_strands_positions(strands.blocks(), None, &mut scal).unwrap(),
            13usize.div_ceil(LANES)
        );
        for b in 0..13usize.div_ceil(LANES) {
            assert_eq!(simd.block_positions(b), full.block_positions(b));
        }
        for i in 0..13 {
            for v in 0..full.verts_per_strand() {
                assert!((scal.position(i, v) - full.position(i, v)).length() < 1e-6);
            }
        }
    }
}
