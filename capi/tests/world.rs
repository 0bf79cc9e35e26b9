//! The world around the hair through C: `coif_step_colliders` (and its
//! executor form) with capsules, wind, drag, gusts and Coulomb friction
//! gives the bytes of `coif_kernels::step_colliders`; the new parameters
//! travel through `CoifSimParams`; fields built from C arrays give the
//! distances and steps of `Sdf::from_mesh`; every bad input is refused and
//! changes nothing.
//!
//! Tests that need a field build a closed octahedron, in Rust and through
//! C; the field must build, and every field check runs.

use coif_capi::*;
use coif_kernels::{Capsule, Colliders, Sdf, SimParams, Sphere, Strands};
use glam::{Affine3A, Quat, Vec3};
use std::ffi::c_void;
use std::ptr;

const STRANDS: usize = 19; // not a multiple of 8: a padded last block
const VERTS: usize = 12;

/// Strands hanging from a line along z at y = 1.6, 2 cm segments.
fn groom() -> Vec<Vec3> {
    let mut pts = Vec::with_capacity(STRANDS * VERTS);
    for i in 0..STRANDS {
        let root = Vec3::new(-0.01, 1.6, -0.09 + 0.01 * i as f32);
        for v in 0..VERTS {
            let t = v as f32;
            pts.push(root + Vec3::new(0.002 * (t * 0.7).sin(), -0.02 * t, 0.0));
        }
    }
    pts
}

fn roots(frame: usize) -> Vec<Vec3> {
    let shift = Vec3::new(0.01 * (frame as f32 * 0.05).sin(), 0.0, 0.0);
    groom().iter().step_by(VERTS).map(|r| *r + shift).collect()
}

fn flat(v: &[Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// Wind along +x with drag, gusts and frictions other than the defaults.
fn windy() -> CoifSimParams {
    CoifSimParams {
        wind: [2.0, 0.0, 0.5],
        drag: 5.0,
        turbulence: 0.4,
        turbulence_scale: 0.15,
        turbulence_period: 0.7,
        friction: 0.6,
        static_friction: 1.2,
        root_exit: 0.5,
        volume_stiffness: 0.7,
        hair_friction: 0.4,
        hair_grid_cell: 0.02,
        ..coif_sim_params_default()
    }
}

/// A capsule along z under the roots and one that swings (frame by frame).
fn capsules(frame: usize) -> [Capsule; 2] {
    let swing = 0.03 * (frame as f32 * 0.08).sin();
    [
        Capsule {
            a: Vec3::new(0.05, 1.5, -0.12),
            b: Vec3::new(0.05, 1.5, 0.12),
            radius: 0.03,
        },
        Capsule {
            a: Vec3::new(0.12 + swing, 1.45, -0.05),
            b: Vec3::new(0.12 + swing, 1.40, 0.05),
            radius: 0.02,
        },
    ]
}

fn c_capsules(caps: &[Capsule]) -> Vec<CoifCapsule> {
    caps.iter()
        .map(|c| CoifCapsule {
            a: c.a.to_array(),
            b: c.b.to_array(),
            radius: c.radius,
        })
        .collect()
}

fn sphere(frame: usize) -> [Sphere; 1] {
    [Sphere {
        center: Vec3::new(0.0, 1.38, 0.02 * (frame as f32 * 0.1).cos()),
        radius: 0.03,
    }]
}

fn c_spheres(s: &[Sphere]) -> Vec<CoifSphere> {
    s.iter()
        .map(|s| CoifSphere {
            center: s.center.to_array(),
            radius: s.radius,
        })
        .collect()
}

/// An octahedron of half-diagonal `r` about the origin: 6 vertices and 8
/// triangles, counter-clockwise seen from outside.
fn octahedron(r: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let v = vec![
        Vec3::X * r,
        -Vec3::X * r,
        Vec3::Y * r,
        -Vec3::Y * r,
        Vec3::Z * r,
        -Vec3::Z * r,
    ];
    let mut t = Vec::new();
    for (sx, sy, sz) in [
        (0, 2, 4),
        (1, 2, 4),
        (0, 3, 4),
        (1, 3, 4),
        (0, 2, 5),
        (1, 2, 5),
        (0, 3, 5),
        (1, 3, 5),
    ] {
        // The sign of an octant is the parity of its negative axes.
        let negatives = (sx == 1) as u32 + (sy == 3) as u32 + (sz == 5) as u32;
        if negatives.is_multiple_of(2) {
            t.push([sx, sy, sz]);
        } else {
            t.push([sx, sz, sy]);
        }
    }
    (v, t)
}

/// `xform` as the 3x4 row-major floats the C calls take.
fn rows(xform: Affine3A) -> [f32; 12] {
    let m = xform.matrix3;
    let t = xform.translation;
    [
        m.x_axis.x, m.y_axis.x, m.z_axis.x, t.x, //
        m.x_axis.y, m.y_axis.y, m.z_axis.y, t.y, //
        m.x_axis.z, m.y_axis.z, m.z_axis.z, t.z,
    ]
}

/// Where the field is at `frame`: turning about y and sliding along z.
fn field_pose(frame: usize) -> Affine3A {
    Affine3A::from_rotation_translation(
        Quat::from_rotation_y(0.02 * frame as f32),
        Vec3::new(0.1, 1.42, 0.01 * (frame as f32 * 0.05).sin()),
    )
}

/// A parallel-for that runs the indices backwards on the calling thread.
unsafe extern "C" fn backwards(_: *mut c_void, count: usize, task: CoifTaskFn, tctx: *mut c_void) {
    for i in (0..count).rev() {
        // SAFETY: each index once, before returning.
        unsafe { task(tctx, i) };
    }
}

fn new_strands(pts: &[Vec3]) -> *mut CoifStrands {
    let xyz = flat(pts);
    let mut c: *mut CoifStrands = ptr::null_mut();
    // SAFETY: `xyz` holds 3 floats per point; `c` is writable.
    let st = unsafe { coif_strands_new(xyz.as_ptr(), pts.len(), VERTS, &mut c) };
    assert_eq!(st, CoifStatus::COIF_OK);
    c
}

fn positions(c: *const CoifStrands) -> Vec<f32> {
    let mut out = vec![0.0f32; STRANDS * VERTS * 3];
    // SAFETY: `c` is live; `out` holds every point.
    let st = unsafe { coif_strands_positions(c, out.as_mut_ptr(), STRANDS * VERTS) };
    assert_eq!(st, CoifStatus::COIF_OK);
    out
}

fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[test]
fn the_octahedron_is_closed_and_faces_outward() {
    let (v, t) = octahedron(0.06);
    let mut volume = 0.0;
    let mut edges = std::collections::HashMap::new();
    for tri in &t {
        let [a, b, c] = tri.map(|i| v[i as usize]);
        // Each face's normal points away from the centre.
        assert!((b - a).cross(c - a).dot(a + b + c) > 0.0, "{tri:?}");
        volume += a.dot(b.cross(c)) / 6.0;
        for (i, j) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
            *edges.entry((i, j)).or_insert(0) += 1;
        }
    }
    // Every directed edge once and its reverse once: closed and consistent.
    for (&(i, j), &n) in &edges {
        assert_eq!((n, edges.get(&(j, i))), (1, Some(&1)));
    }
    let want = 4.0 / 3.0 * 0.06f32.powi(3);
    assert!((volume - want).abs() < 1e-9, "{volume} vs {want}");
}

#[test]
fn new_params_travel_both_ways() {
    let c = windy();
    let r = SimParams::from(&c);
    assert_eq!(r.wind, Vec3::new(2.0, 0.0, 0.5));
    assert_eq!(
        (
            r.drag,
            r.turbulence,
            r.turbulence_scale,
            r.turbulence_period
        ),
        (5.0, 0.4, 0.15, 0.7)
    );
    assert_eq!((r.friction, r.static_friction), (0.6, 1.2));
    assert_eq!(r.root_exit, 0.5);
    assert_eq!(
        (r.volume_stiffness, r.hair_friction, r.hair_grid_cell),
        (0.7, 0.4, 0.02)
    );
    assert_eq!(CoifSimParams::from(&r), c);
    // The defaults are Rust's, and a kinetic friction above 1 is accepted.
    let d = coif_sim_params_default();
    let rd = SimParams::default();
    assert_eq!(d.wind, rd.wind.to_array());
    assert_eq!(
        [
            d.drag,
            d.static_friction,
            d.turbulence,
            d.turbulence_scale,
            d.turbulence_period,
            d.root_exit,
            d.volume_stiffness,
            d.hair_friction,
            d.hair_grid_cell
        ],
        [
            rd.drag,
            rd.static_friction,
            rd.turbulence,
            rd.turbulence_scale,
            rd.turbulence_period,
            rd.root_exit,
            rd.volume_stiffness,
            rd.hair_friction,
            rd.hair_grid_cell
        ]
    );
    let rough = CoifSimParams { friction: 1.5, ..d };
    // SAFETY: pointers to locals.
    unsafe {
        assert_eq!(coif_sim_params_validate(&c), CoifStatus::COIF_OK);
        assert_eq!(coif_sim_params_validate(&rough), CoifStatus::COIF_OK);
    }
}

#[test]
fn c_step_colliders_matches_rust_bit_for_bit() {
    let pts = groom();
    let c_params = windy();
    let params = SimParams::from(&c_params);
    let mut rust = Strands::from_polylines(&pts, VERTS).unwrap();
    let c = new_strands(&pts);
    let c_exec = new_strands(&pts);
    let exec = CoifExecutor {
        ctx: ptr::null_mut(),
        threads: 3,
        run: Some(backwards),
    };
    for frame in 0..240 {
        let (r, caps, sph) = (roots(frame), capsules(frame), sphere(frame));
        rust.set_roots(&r).unwrap();
        let colliders = Colliders {
            spheres: &sph,
            capsules: &caps,
            sdfs: &[],
        };
        coif_kernels::step_colliders(&mut rust, &params, &colliders);
        let (r, caps, sph) = (flat(&r), c_capsules(&caps), c_spheres(&sph));
        // SAFETY: live handles; every array holds its count.
        unsafe {
            for h in [c, c_exec] {
                assert_eq!(
                    coif_strands_set_roots(h, r.as_ptr(), STRANDS),
                    CoifStatus::COIF_OK
                );
            }
            assert_eq!(
                coif_step_colliders(c, &c_params, sph.as_ptr(), 1, caps.as_ptr(), 2, ptr::null()),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_step_colliders_with(
                    c_exec,
                    &c_params,
                    sph.as_ptr(),
                    1,
                    caps.as_ptr(),
                    2,
                    ptr::null(),
                    &exec
                ),
                CoifStatus::COIF_OK
            );
        }
        if frame % 40 == 39 {
            let want = flat(&rust.positions());
            assert!(same_bits(&want, &positions(c)), "frame {frame}: C != Rust");
            assert!(
                same_bits(&want, &positions(c_exec)),
                "frame {frame}: C on an executor != Rust"
            );
        }
    }
    // The wind blew the tips downwind (+x), and no vertex is inside a capsule.
    let end = rust.positions();
    let tips_dx: f32 = (0..STRANDS)
        .map(|i| end[i * VERTS + VERTS - 1].x - end[i * VERTS].x)
        .sum::<f32>()
        / STRANDS as f32;
    assert!(tips_dx > 0.03, "tips moved {tips_dx} m downwind");
    for p in &end {
        for cap in capsules(239) {
            assert!(cap.distance(*p) > -1e-3, "{p} inside {cap:?}");
        }
    }
    // SAFETY: handles from coif_strands_new, freed once.
    unsafe {
        coif_strands_free(c);
        coif_strands_free(c_exec);
    }
}

#[test]
fn an_empty_field_set_is_no_field() {
    let pts = groom();
    let p = windy();
    let (a, b) = (new_strands(&pts), new_strands(&pts));
    let mut set: *mut CoifSdfSet = ptr::null_mut();
    // SAFETY: live handles; arrays hold their counts.
    unsafe {
        assert_eq!(coif_sdf_set_new(&mut set), CoifStatus::COIF_OK);
        assert_eq!(coif_sdf_set_count(set), 0);
        let caps = c_capsules(&capsules(0));
        for _ in 0..30 {
            assert_eq!(
                coif_step_colliders(a, &p, ptr::null(), 0, caps.as_ptr(), 2, set),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_step_colliders(b, &p, ptr::null(), 0, caps.as_ptr(), 2, ptr::null()),
                CoifStatus::COIF_OK
            );
        }
        assert!(same_bits(&positions(a), &positions(b)));
        coif_sdf_set_free(set);
        coif_strands_free(a);
        coif_strands_free(b);
    }
}

/// Builds the octahedron through C: the status and the handle.
fn c_octahedron(r: f32, cell: f32) -> (CoifStatus, *mut CoifSdf) {
    let (v, t) = octahedron(r);
    let xyz = flat(&v);
    let idx: Vec<u32> = t.iter().flatten().copied().collect();
    let mut out: *mut CoifSdf = ptr::NonNull::dangling().as_ptr();
    // SAFETY: the arrays hold their counts; `out` is writable.
    let st = unsafe { coif_sdf_new(xyz.as_ptr(), v.len(), idx.as_ptr(), t.len(), cell, &mut out) };
    (st, out)
}

/// The Rust field of the octahedron: a closed mesh, so it must build.
fn real_field(r: f32, cell: f32) -> Sdf {
    let (v, t) = octahedron(r);
    Sdf::from_mesh(&v, &t, cell)
        .unwrap_or_else(|e| panic!("Sdf::from_mesh refused a closed octahedron: {e}"))
}

#[test]
fn c_fields_match_rust_fields() {
    let mut rust_field = real_field(0.06, 0.01);
    let (st, mut c_field) = c_octahedron(0.06, 0.01);
    assert_eq!(st, CoifStatus::COIF_OK);
    let probes = [
        Vec3::ZERO,
        Vec3::new(0.1, 0.0, 0.0),
        Vec3::new(0.02, 0.03, -0.01),
        Vec3::new(0.1, 1.42, 0.0),
    ];
    let pose = field_pose(0);
    rust_field.set_transform(pose).unwrap();
    let m = rows(pose);
    // SAFETY: a live field; arrays of the sizes the calls read.
    unsafe {
        assert_eq!(
            coif_sdf_set_transform(c_field, m.as_ptr()),
            CoifStatus::COIF_OK
        );
        for p in probes {
            let mut d = f32::NAN;
            let st = coif_sdf_distance(c_field, p.to_array().as_ptr(), &mut d);
            assert_eq!(st, CoifStatus::COIF_OK);
            assert_eq!(d.to_bits(), rust_field.distance(p).to_bits(), "at {p}");
        }
    }
    // Into a set, then step against it with a capsule and wind.
    let mut set: *mut CoifSdfSet = ptr::null_mut();
    let mut index = usize::MAX;
    // SAFETY: live handles.
    unsafe {
        assert_eq!(coif_sdf_set_new(&mut set), CoifStatus::COIF_OK);
        assert_eq!(
            coif_sdf_set_add(set, &mut c_field, &mut index),
            CoifStatus::COIF_OK
        );
    }
    assert!(c_field.is_null(), "the set took the field");
    assert_eq!(index, 0);
    let pts = groom();
    let c_params = windy();
    let params = SimParams::from(&c_params);
    let mut rust = Strands::from_polylines(&pts, VERTS).unwrap();
    let c = new_strands(&pts);
    let mut fields = vec![rust_field];
    for frame in 0..180 {
        let pose = field_pose(frame);
        fields[0].set_transform(pose).unwrap();
        let r = roots(frame);
        rust.set_roots(&r).unwrap();
        let caps = capsules(frame);
        let colliders = Colliders {
            spheres: &[],
            capsules: &caps[..1],
            sdfs: &fields,
        };
        coif_kernels::step_colliders(&mut rust, &params, &colliders);
        let (r, caps, m) = (flat(&r), c_capsules(&caps[..1]), rows(pose));
        // SAFETY: live handles; arrays hold their counts.
        unsafe {
            assert_eq!(
                coif_sdf_set_transform_at(set, 0, m.as_ptr()),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_strands_set_roots(c, r.as_ptr(), STRANDS),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_step_colliders(c, &c_params, ptr::null(), 0, caps.as_ptr(), 1, set),
                CoifStatus::COIF_OK
            );
        }
        if frame % 30 == 29 {
            let want = flat(&rust.positions());
            assert!(same_bits(&want, &positions(c)), "frame {frame}: C != Rust");
        }
    }
    // No vertex inside the field (the same test through the set).
    for p in rust.positions() {
        let mut d = f32::NAN;
        // SAFETY: a live set; a point and an output.
        let st = unsafe { coif_sdf_set_distance_at(set, 0, p.to_array().as_ptr(), &mut d) };
        assert_eq!(st, CoifStatus::COIF_OK);
        assert!(d > -1e-3, "{p} is {d} m inside the field");
    }
    // SAFETY: handles freed once (the field with its set).
    unsafe {
        coif_sdf_set_free(set);
        coif_strands_free(c);
    }
}

#[test]
fn bad_world_inputs_are_refused_and_change_nothing() {
    use CoifStatus::*;
    let pts = groom();
    let c = new_strands(&pts);
    let p = windy();
    let caps = c_capsules(&capsules(0));
    // SAFETY: every pointer is valid for the count passed, or NULL / bad on purpose.
    unsafe {
        for _ in 0..20 {
            assert_eq!(
                coif_step_colliders(c, &p, ptr::null(), 0, caps.as_ptr(), 2, ptr::null()),
                COIF_OK
            );
        }
        let before = positions(c);

        // Parameters: each new field out of range or not finite.
        let bad_params = [
            (
                CoifSimParams {
                    wind: [0.0, f32::NAN, 0.0],
                    ..p
                },
                COIF_ERROR_NON_FINITE,
            ),
            (
                CoifSimParams {
                    wind: [f32::INFINITY, 0.0, 0.0],
                    ..p
                },
                COIF_ERROR_NON_FINITE,
            ),
            (
                CoifSimParams { drag: -1.0, ..p },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    drag: f32::NAN,
                    ..p
                },
                COIF_ERROR_NON_FINITE,
            ),
            (
                CoifSimParams {
                    friction: -0.1,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    static_friction: -0.1,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    turbulence: -1.0,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    turbulence_scale: 0.0,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    turbulence_period: 0.0,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    turbulence_period: f32::INFINITY,
                    ..p
                },
                COIF_ERROR_NON_FINITE,
            ),
            (
                CoifSimParams {
                    root_exit: -1.0,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    volume_stiffness: 1.5,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    hair_friction: -0.1,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                CoifSimParams {
                    hair_grid_cell: 0.0,
                    ..p
                },
                COIF_ERROR_INVALID_ARGUMENT,
            ),
        ];
        for (bad, want) in bad_params {
            assert_eq!(coif_sim_params_validate(&bad), want, "{bad:?}");
            assert_eq!(
                coif_step_colliders(c, &bad, ptr::null(), 0, caps.as_ptr(), 2, ptr::null()),
                want,
                "{bad:?}"
            );
        }

        // Capsules: not finite, negative radius, NULL with a count, misaligned.
        let mut nan_cap = caps.clone();
        nan_cap[1].b[2] = f32::NAN;
        let mut neg_cap = caps.clone();
        neg_cap[0].radius = -0.01;
        let bytes = vec![0u8; 2 * std::mem::size_of::<CoifCapsule>() + 4];
        let misaligned = bytes
            .as_ptr()
            .add(if bytes.as_ptr().align_offset(4) == 0 {
                1
            } else {
                0
            })
            .cast::<CoifCapsule>();
        let bad_sphere = [CoifSphere {
            center: [0.0, f32::NAN, 0.0],
            radius: 0.1,
        }];
        let no_run = CoifExecutor {
            ctx: ptr::null_mut(),
            threads: 2,
            run: None,
        };
        let statuses = [
            coif_step_colliders(c, &p, ptr::null(), 0, nan_cap.as_ptr(), 2, ptr::null()),
            coif_step_colliders(c, &p, ptr::null(), 0, neg_cap.as_ptr(), 2, ptr::null()),
            coif_step_colliders(c, &p, ptr::null(), 0, ptr::null(), 2, ptr::null()),
            coif_step_colliders(c, &p, ptr::null(), 0, misaligned, 2, ptr::null()),
            coif_step_colliders(c, &p, bad_sphere.as_ptr(), 1, caps.as_ptr(), 2, ptr::null()),
            coif_step_colliders(
                c,
                ptr::null(),
                ptr::null(),
                0,
                caps.as_ptr(),
                2,
                ptr::null(),
            ),
            coif_step_colliders(
                ptr::null_mut(),
                &p,
                ptr::null(),
                0,
                caps.as_ptr(),
                2,
                ptr::null(),
            ),
            coif_step_colliders_with(
                c,
                &p,
                ptr::null(),
                0,
                caps.as_ptr(),
                2,
                ptr::null(),
                &no_run,
            ),
            coif_step_colliders(
                c,
                &p,
                ptr::null(),
                0,
                caps.as_ptr(),
                usize::MAX / 8,
                ptr::null(),
            ),
        ];
        assert_eq!(
            statuses,
            [
                COIF_ERROR_NON_FINITE,
                COIF_ERROR_INVALID_ARGUMENT,
                COIF_ERROR_NULL,
                COIF_ERROR_INVALID_ARGUMENT,
                COIF_ERROR_NON_FINITE,
                COIF_ERROR_NULL,
                COIF_ERROR_NULL,
                COIF_ERROR_NULL,
                COIF_ERROR_INVALID_ARGUMENT,
            ]
        );
        assert!(
            same_bits(&before, &positions(c)),
            "a refused step moved the hair"
        );

        // Fields: every bad mesh leaves *out NULL.
        let (v, t) = octahedron(0.06);
        let xyz = flat(&v);
        let idx: Vec<u32> = t.iter().flatten().copied().collect();
        let mut bad_idx = idx.clone();
        bad_idx[5] = 6; // one past the last vertex
        let mut nan_xyz = xyz.clone();
        nan_xyz[7] = f32::NAN;
        let (nv, nt) = (v.len(), t.len());
        let cases: [(*const f32, usize, *const u32, usize, f32, CoifStatus); 11] = [
            (ptr::null(), nv, idx.as_ptr(), nt, 0.01, COIF_ERROR_NULL),
            (xyz.as_ptr(), nv, ptr::null(), nt, 0.01, COIF_ERROR_NULL),
            (
                xyz.as_ptr(),
                0,
                idx.as_ptr(),
                nt,
                0.01,
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                xyz.as_ptr(),
                nv,
                idx.as_ptr(),
                0,
                0.01,
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                xyz.as_ptr(),
                nv,
                bad_idx.as_ptr(),
                nt,
                0.01,
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                xyz.as_ptr(),
                nv - 1,
                idx.as_ptr(),
                nt,
                0.01,
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                nan_xyz.as_ptr(),
                nv,
                idx.as_ptr(),
                nt,
                0.01,
                COIF_ERROR_NON_FINITE,
            ),
            (
                xyz.as_ptr(),
                nv,
                idx.as_ptr(),
                nt,
                0.0,
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                xyz.as_ptr(),
                nv,
                idx.as_ptr(),
                nt,
                -0.01,
                COIF_ERROR_INVALID_ARGUMENT,
            ),
            (
                xyz.as_ptr(),
                nv,
                idx.as_ptr(),
                nt,
                f32::NAN,
                COIF_ERROR_NON_FINITE,
            ),
            (
                xyz.as_ptr(),
                nv,
                idx.as_ptr(),
                usize::MAX / 8,
                0.01,
                COIF_ERROR_INVALID_ARGUMENT,
            ),
        ];
        for (i, (x, n, ix, tn, cell, want)) in cases.into_iter().enumerate() {
            let mut out: *mut CoifSdf = ptr::NonNull::dangling().as_ptr();
            assert_eq!(coif_sdf_new(x, n, ix, tn, cell, &mut out), want, "case {i}");
            assert!(out.is_null(), "case {i}: *out not NULL");
        }
        assert_eq!(
            coif_sdf_new(xyz.as_ptr(), nv, idx.as_ptr(), nt, 0.01, ptr::null_mut()),
            COIF_ERROR_NULL
        );

        // Handles that are NULL, indices past the set, pointers to NULL.
        let m = rows(Affine3A::IDENTITY);
        let (mut d, q) = (7.0f32, [0.0f32; 3]);
        assert_eq!(
            coif_sdf_set_transform(ptr::null_mut(), m.as_ptr()),
            COIF_ERROR_NULL
        );
        assert_eq!(
            coif_sdf_distance(ptr::null(), q.as_ptr(), &mut d),
            COIF_ERROR_NULL
        );
        coif_sdf_free(ptr::null_mut());
        coif_sdf_set_free(ptr::null_mut());
        assert_eq!(coif_sdf_set_new(ptr::null_mut()), COIF_ERROR_NULL);
        let mut set: *mut CoifSdfSet = ptr::null_mut();
        assert_eq!(coif_sdf_set_new(&mut set), COIF_OK);
        let mut none: *mut CoifSdf = ptr::null_mut();
        let mut index = 99usize;
        assert_eq!(
            coif_sdf_set_add(set, ptr::null_mut(), &mut index),
            COIF_ERROR_NULL
        );
        assert_eq!(
            coif_sdf_set_add(set, &mut none, &mut index),
            COIF_ERROR_NULL
        );
        assert_eq!(
            coif_sdf_set_add(ptr::null_mut(), &mut none, &mut index),
            COIF_ERROR_NULL
        );
        assert_eq!(
            coif_sdf_set_transform_at(set, 0, m.as_ptr()),
            COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            coif_sdf_set_distance_at(set, 0, q.as_ptr(), &mut d),
            COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!((coif_sdf_set_count(set), index, d), (0, 99, 7.0));
        assert_eq!(coif_sdf_set_count(ptr::null()), 0);

        // With a field that builds: bad transforms and queries change nothing.
        let (st, mut f) = c_octahedron(0.06, 0.01);
        assert_eq!(st, COIF_OK);
        let at = [0.03f32, 0.01, 0.0];
        let mut d0 = f32::NAN;
        assert_eq!(coif_sdf_distance(f, at.as_ptr(), &mut d0), COIF_OK);
        let mut scaled = m;
        scaled[0] = 2.0;
        let mut mirrored = m;
        mirrored[10] = -1.0;
        let mut nan_m = m;
        nan_m[3] = f32::NAN;
        let nan_p = [0.0, f32::NAN, 0.0];
        assert_eq!(
            coif_sdf_set_transform(f, scaled.as_ptr()),
            COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            coif_sdf_set_transform(f, mirrored.as_ptr()),
            COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            coif_sdf_set_transform(f, nan_m.as_ptr()),
            COIF_ERROR_NON_FINITE
        );
        assert_eq!(coif_sdf_set_transform(f, ptr::null()), COIF_ERROR_NULL);
        assert_eq!(
            coif_sdf_distance(f, nan_p.as_ptr(), &mut d),
            COIF_ERROR_NON_FINITE
        );
        assert_eq!(
            coif_sdf_distance(f, at.as_ptr(), ptr::null_mut()),
            COIF_ERROR_NULL
        );
        let mut d1 = f32::NAN;
        assert_eq!(coif_sdf_distance(f, at.as_ptr(), &mut d1), COIF_OK);
        assert_eq!(
            d0.to_bits(),
            d1.to_bits(),
            "a refused transform moved the field"
        );
        assert_eq!(coif_sdf_set_add(set, &mut f, ptr::null_mut()), COIF_OK);
        assert!(f.is_null());
        assert_eq!(coif_sdf_set_count(set), 1);
        assert_eq!(
            coif_sdf_set_transform_at(set, 0, scaled.as_ptr()),
            COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            coif_sdf_set_transform_at(set, 1, m.as_ptr()),
            COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            coif_sdf_set_distance_at(set, 0, at.as_ptr(), &mut d1),
            COIF_OK
        );
        assert_eq!(d0.to_bits(), d1.to_bits());
        coif_sdf_set_free(set);
        coif_strands_free(c);
    }
}

/// `coif_strands_solve_sag_free` is `Strands::solve_sag_free`: the same
/// bytes after 60 steps with the springs on (the tips of the middle
/// strands hang into the sphere, and the groom holds under gravity: the
/// tips clear of the sphere end within 3 mm of it); a NaN sphere or a bad parameter is
/// refused and changes nothing.
#[test]
fn c_sag_free_solve_matches_rust_bit_for_bit() {
    let pts = groom();
    let c_params = CoifSimParams {
        local_shape_stiffness: 0.7,
        ..coif_sim_params_default()
    };
    let params = SimParams::from(&c_params);
    let caps = capsules(0);
    let sph = sphere(0);
    let colliders = Colliders {
        spheres: &sph,
        capsules: &caps,
        sdfs: &[],
    };
    let mut rust = Strands::from_polylines(&pts, VERTS).unwrap();
    rust.solve_sag_free(&params, &colliders).unwrap();
    let c = new_strands(&pts);
    let (c_caps, c_sph) = (c_capsules(&caps), c_spheres(&sph));
    let before = positions(c);
    let nan = [CoifSphere {
        center: [f32::NAN, 0.0, 0.0],
        radius: 0.1,
    }];
    let bad = CoifSimParams {
        local_shape_stiffness: 2.0,
        ..c_params
    };
    // SAFETY: live handle; every array holds its count.
    unsafe {
        assert_eq!(
            coif_strands_solve_sag_free(c, &c_params, nan.as_ptr(), 1, ptr::null(), 0, ptr::null()),
            CoifStatus::COIF_ERROR_NON_FINITE
        );
        assert_eq!(
            coif_strands_solve_sag_free(c, &bad, ptr::null(), 0, ptr::null(), 0, ptr::null()),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert!(
            same_bits(&before, &positions(c)),
            "a refused solve moved the hair"
        );
        assert_eq!(
            coif_strands_solve_sag_free(
                c,
                &c_params,
                c_sph.as_ptr(),
                1,
                c_caps.as_ptr(),
                2,
                ptr::null()
            ),
            CoifStatus::COIF_OK
        );
    }
    for _ in 0..60 {
        coif_kernels::step_colliders(&mut rust, &params, &colliders);
        // SAFETY: live handle; every array holds its count.
        let st = unsafe {
            coif_step_colliders(
                c,
                &c_params,
                c_sph.as_ptr(),
                1,
                c_caps.as_ptr(),
                2,
                ptr::null(),
            )
        };
        assert_eq!(st, CoifStatus::COIF_OK);
    }
    assert!(
        same_bits(&flat(&rust.positions()), &positions(c)),
        "after 60 steps: C != Rust"
    );
    let end = rust.positions();
    let mut held = 0;
    for i in 0..STRANDS {
        let tip = i * VERTS + VERTS - 1;
        // Tips clear of the sphere (the others rest on it).
        if pts[tip].distance(sph[0].center) > sph[0].radius + 0.01 {
            assert!(
                end[tip].distance(pts[tip]) < 0.003,
                "strand {i}'s tip sagged"
            );
            held += 1;
        }
    }
    assert!(
        held >= STRANDS / 2,
        "too few tips clear of the sphere: {held}"
    );
    // SAFETY: a handle from coif_strands_new, freed once.
    unsafe { coif_strands_free(c) };
}
