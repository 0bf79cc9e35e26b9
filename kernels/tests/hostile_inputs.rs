//! The public entry points of coif-kernels that take caller buffers or
//! counts, driven with hostile sizes and values (empty, zero and huge
//! counts, mismatched lengths, NaN, infinities, indices past the end): none
//! panics, and each refuses what it must with the right error, changing
//! nothing. Property tests (proptest): generated inputs find the cases
//! hand-written ones miss.

use coif_kernels::patch::{self, grid_normals, Patch};
use coif_kernels::{Capsule, Colliders, Error, Sdf, SimParams, Sphere, Strands, LANES};
use glam::{Affine3A, Vec3};
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
        1 => Just(1usize << 32),
    ]
}

/// `strands` straight strands of `verts` vertices hanging from a row.
fn hanging(strands: usize, verts: usize) -> Vec<Vec3> {
    (0..strands)
        .flat_map(|s| (0..verts).map(move |v| Vec3::new(0.01 * s as f32, -0.02 * v as f32, 0.0)))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// Strands from hostile polylines: the documented error or a set, never
    /// a panic.
    #[test]
    fn from_polylines_refuses_bad_input(points in prop::collection::vec(hostile_vec3(), 0..40),
                                        verts in hostile_count()) {
        let r = Strands::from_polylines(&points, verts);
        let expected = if verts < 2 {
            Some(Error::TooFewVertices { verts_per_strand: verts })
        } else if points.len() % verts != 0 {
            Some(Error::NotWholeStrands { points: points.len(), verts_per_strand: verts })
        } else if points.is_empty() {
            Some(Error::NoStrands)
        } else {
            points
                .iter()
                .position(|p| !p.is_finite())
                .map(|index| Error::NonFinite { index })
                .or_else(|| {
                    // Finite points farther than 1e6 m from their root are
                    // refused too (their segments can be infinitely long).
                    points.chunks_exact(verts).find_map(|strand| {
                        strand.iter().map(|p| (*p - strand[0]).length())
                            .find(|d| d.is_nan() || *d > 1e6)
                            .map(|value| Error::InvalidParameter {
                                name: "points",
                                value,
                                expected: "every point within 1e6 m of its strand's root",
                            })
                    })
                })
        };
        match (r, expected) {
            (Err(Error::InvalidParameter { name, value, .. }),
             Some(Error::InvalidParameter { name: want_name, value: want_value, .. })) => {
                prop_assert_eq!(name, want_name);
                prop_assert!(value == want_value || (value.is_nan() && want_value.is_nan()));
            }
            (Err(e), Some(want)) => prop_assert_eq!(e, want),
            (Ok(s), None) => prop_assert_eq!(s.strand_count(), points.len() / verts),
            (r, want) => prop_assert!(false, "{:?} but expected {:?}", r.err(), want),
        }
    }

    /// write_positions: every point when `out` can take them, otherwise
    /// BufferTooSmall and `out` untouched.
    #[test]
    fn write_positions_refuses_short_buffers(strands in 1usize..20, verts in 2usize..6,
                                             out_len in 0usize..130) {
        let s = Strands::from_polylines(&hanging(strands, verts), verts).unwrap();
        let needed = strands * verts;
        let sentinel = Vec3::splat(7.0);
        let mut out = vec![sentinel; out_len];
        match s.write_positions(&mut out) {
            Ok(n) => {
                prop_assert!(out_len >= needed);
                prop_assert_eq!(n, needed);
                prop_assert_eq!(&out[..needed], &s.positions()[..]);
                prop_assert!(out[needed..].iter().all(|&p| p == sentinel));
            }
            Err(e) => {
                prop_assert!(out_len < needed);
                prop_assert_eq!(e, Error::BufferTooSmall { needed, got: out_len });
                prop_assert!(out.iter().all(|&p| p == sentinel));
            }
        }
    }

    /// Roots and states of the wrong count or with non-finite points are
    /// refused and change nothing; accessors past the end say None / 0.
    #[test]
    fn setters_refuse_mismatched_counts(strands in 1usize..12, verts in 2usize..5,
                                        n in 0usize..60, p in hostile_vec3(), i in hostile_count()) {
        let mut s = Strands::from_polylines(&hanging(strands, verts), verts).unwrap();
        let before = s.positions();
        let roots = vec![p; n];
        match s.set_roots(&roots) {
            Ok(()) => prop_assert!(n == strands && p.is_finite()),
            Err(Error::CountMismatch { expected, got, .. }) => {
                prop_assert_eq!((expected, got), (strands, n));
            }
            Err(Error::NonFinite { .. }) => prop_assert!(n == strands && !p.is_finite()),
            Err(e) => prop_assert!(false, "unexpected {}", e),
        }
        if n != strands || !p.is_finite() {
            prop_assert_eq!(s.positions(), before.clone());
        }
        let state = vec![p; n];
        if s.set_state(&state, &state).is_err() {
            prop_assert!(n != strands * verts || !p.is_finite());
        }
        prop_assert!(s.vertex(i, 0).is_none() || i < strands);
        prop_assert!(s.vertex(0, i).is_none() || i < verts);
        prop_assert!(s.rest_length(i, i).is_none() || (i < strands && i < verts));
        prop_assert_eq!(s.lanes_in_block(i.max(s.block_count())), 0);
    }

    /// Patches: grids of hostile shape, points and buffers.
    #[test]
    fn patches_refuse_bad_shapes(rows in hostile_count(), cols in hostile_count(),
                                 len in 0usize..40, p in hostile_vec3(), out_len in 0usize..40) {
        let grid = vec![p; len];
        let pinned = vec![false; len];
        let r = Patch::new(&grid, rows, cols, &pinned);
        if rows < 2 || cols < 2 {
            let too_few = matches!(r, Err(Error::TooFewVertices { .. }));
            prop_assert!(too_few);
        } else if rows.checked_mul(cols) != Some(len) {
            let refused = matches!(r, Err(Error::CountMismatch { .. }) | Err(Error::InvalidParameter { .. }));
            prop_assert!(refused);
        }
        let mut normals = vec![Vec3::ONE; out_len];
        let g = grid_normals(&grid, rows, cols, &mut normals);
        if rows.checked_mul(cols) == Some(len) && out_len == len {
            prop_assert!(g.is_ok());
            prop_assert!(normals.iter().all(|n| n.is_finite()));
        } else {
            let is_mismatch = matches!(g, Err(Error::CountMismatch { .. }));
            prop_assert!(is_mismatch);
        }
    }

    /// A patch's outputs: write_positions takes any buffer that is long
    /// enough, write_blended exactly rows * cols; refusals write nothing.
    #[test]
    fn patch_buffers(rows in 2usize..6, cols in 2usize..6, out_len in 0usize..40,
                     w in hostile_f32()) {
        let (grid, pinned) = patch::quality::flag_scene(rows, cols);
        let mut patch = Patch::new(&grid, rows, cols, &pinned).unwrap();
        let n = rows * cols;
        let sentinel = Vec3::splat(7.0);
        let mut out = vec![sentinel; out_len];
        match patch.write_positions(&mut out) {
            Ok(k) => prop_assert!(k == n && out_len >= n),
            Err(e) => {
                prop_assert_eq!(e, Error::BufferTooSmall { needed: n, got: out_len });
                prop_assert!(out.iter().all(|&p| p == sentinel));
            }
        }
        let r = patch.write_blended(&mut out);
        prop_assert_eq!(r.is_ok(), out_len == n);
        if out_len != n {
            prop_assert!(out.iter().all(|&p| p == sentinel) || out_len >= n);
        }
        let weights = vec![w; n];
        prop_assert_eq!(patch.set_weights(&weights).is_ok(), (0.0..=1.0).contains(&w));
        prop_assert!(patch.set_weights(&weights[1..]).is_err());
        prop_assert!(patch.set_skinned(&vec![Vec3::new(w, 0.0, 0.0); n]).is_ok() == w.is_finite());
    }

    /// A step with hostile parameters and colliders: no panic, and hair
    /// that was finite stays finite or is restored.
    #[test]
    fn step_with_hostile_parameters(dt in hostile_f32(), damping in hostile_f32(),
                                    g in hostile_vec3(), wind in hostile_vec3(),
                                    drag in hostile_f32(), friction in hostile_f32(),
                                    center in hostile_vec3(), radius in hostile_f32(),
                                    iterations in 0u32..4) {
        let mut s = Strands::from_polylines(&hanging(9, 4), 4).unwrap();
        let params = SimParams {
            dt,
            damping,
            gravity: g,
            wind,
            drag,
            friction,
            iterations,
            ..Default::default()
        };
        let spheres = [Sphere { center, radius }];
        let capsules = [Capsule { a: center, b: g, radius }];
        let colliders = Colliders { spheres: &spheres, capsules: &capsules, ..Default::default() };
        coif_kernels::step(&mut s, &params, &spheres);
        coif_kernels::step_colliders(&mut s, &params, &colliders);
        coif_kernels::scalar::step_colliders(&mut s, &params, &colliders);
        prop_assert!(s.positions().iter().all(|p| p.is_finite()));
    }
}

/// Signed distance fields from hostile meshes: the documented errors.
#[test]
fn sdf_from_hostile_meshes() {
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    assert!(matches!(
        Sdf::from_mesh(&tri, &[], 0.1),
        Err(Error::NoTriangles)
    ));
    assert!(matches!(
        Sdf::from_mesh(&tri, &[[0, 1, 3]], 0.1),
        Err(Error::IndexOutOfRange { index: 3, .. })
    ));
    assert!(matches!(
        Sdf::from_mesh(&[Vec3::ZERO, Vec3::X, Vec3::NAN], &[[0, 1, 2]], 0.1),
        Err(Error::NonFinite { .. })
    ));
    for cell in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(
            Sdf::from_mesh(&tri, &[[0, 1, 2]], cell).is_err(),
            "cell {cell}"
        );
    }
    assert!(matches!(
        Sdf::from_mesh(&tri, &[[0, 1, 2]], 1e-9),
        Err(Error::GridTooLarge { .. })
    ));
    let mut sdf = Sdf::from_mesh(&tri, &[[0, 1, 2]], 0.1).unwrap();
    assert!(sdf
        .set_transform(Affine3A::from_scale(Vec3::splat(2.0)))
        .is_err());
    assert!(sdf
        .set_transform(Affine3A::from_translation(Vec3::NAN))
        .is_err());
    let _ = sdf.distance(Vec3::NAN);
    let _ = sdf.distance(Vec3::INFINITY);
}

/// 16 hanging strands with 16 m of spacing headroom: stepped `steps` times
/// with roots `roots(step)`; their positions.
fn step_hanging(params: &SimParams, steps: usize, roots: impl Fn(usize) -> Vec<Vec3>) -> Vec<Vec3> {
    let mut s = Strands::from_polylines(&hanging(16, 6), 6).unwrap();
    for i in 0..steps {
        s.set_roots(&roots(i)).unwrap();
        coif_kernels::step(&mut s, params, &[]);
    }
    s.positions()
}

#[test]
fn a_bad_hair_grid_cell_neither_panics_nor_hangs() {
    // NaN and infinity put every vertex on node 0 (an index below zero),
    // zero never grew coarser (a hang), negative likewise.
    for cell in [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        0.0,
        -0.01,
        1e-38,
    ] {
        let params = SimParams {
            volume_stiffness: 1.0,
            hair_friction: 1.0,
            hair_grid_cell: cell,
            ..Default::default()
        };
        let got = step_hanging(&params, 3, |_| {
            hanging(16, 6).into_iter().step_by(6).collect()
        });
        assert!(got.iter().all(|p| p.is_finite()), "cell {cell}");
    }
}

#[test]
fn one_root_sent_far_moves_no_other_strand() {
    // Strand 8 is lane 0 of block 1: the old rebase averaged lane 0 of each
    // block, so its root dragged the origin (and every strand) after it.
    let rest: Vec<Vec3> = hanging(16, 6).into_iter().step_by(6).collect();
    let params = SimParams::default();
    let clean = step_hanging(&params, 10, |_| rest.clone());
    for far in [1e5f32, 1e7, 1e30] {
        let moved = step_hanging(&params, 10, |_| {
            let mut r = rest.clone();
            r[8] = Vec3::new(far, 0.0, 0.0);
            r
        });
        for (i, (a, b)) in clean.iter().zip(&moved).enumerate() {
            if i / 6 != 8 {
                assert_eq!(a, b, "root of strand 8 at {far} m moved vertex {i}");
            }
        }
    }
}

#[test]
fn teleports_are_rigid_and_lose_no_precision() {
    let mut s = Strands::from_polylines(&hanging(16, 6), 6).unwrap();
    let start = s.positions();
    // A scale is not a teleport.
    assert!(matches!(
        s.teleport(Affine3A::from_scale(Vec3::splat(1e30))),
        Err(Error::InvalidTransform { .. })
    ));
    assert_eq!(s.positions(), start, "a refused teleport changed something");
    // There and back by a million metres (2.75 cm off before: the
    // translation rounded the local positions).
    s.teleport(Affine3A::from_translation(Vec3::X * 1e6))
        .unwrap();
    // (World positions there are f32: an ulp at 1e6 m is 6 cm.)
    let there = s.positions();
    assert!((there[1].x - start[1].x - 1e6).abs() <= 0.0625);
    s.teleport(Affine3A::from_translation(Vec3::X * -1e6))
        .unwrap();
    for (a, b) in start.iter().zip(s.positions()) {
        assert!((*a - b).length() < 1e-6, "{a} -> {b}");
    }
}

#[test]
fn points_beyond_the_steps_guard_and_blocks_past_the_end_are_refused() {
    // A segment near f32::MAX has an infinite length: the strand was
    // restored to its rest pose at every step, forever.
    let mut pts = hanging(2, 3);
    pts[4] = Vec3::new(3e38, 0.0, 0.0);
    assert!(matches!(
        Strands::from_polylines(&pts, 3),
        Err(Error::InvalidParameter { name: "points", .. })
    ));
    let s = Strands::from_polylines(&hanging(LANES + 1, 3), 3).unwrap();
    assert!(s.block_active_mask(99).to_array().iter().all(|&m| m == 0.0));
    assert_ne!(s.block_active_mask(1).to_array()[0], 0.0);
}
