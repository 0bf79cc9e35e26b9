//! The local shape springs (`kernels/src/shape.rs`) against their own
//! closed forms, and the sag-free rest state
//! (`Strands::solve_sag_free`): the static sag of a loaded strand and the
//! swing of a plucked one from the springs' energy, the groom as the
//! equilibrium after the solve, the solve's idempotence and its refusals,
//! and SIMD = scalar with the springs on.

use coif_kernels::shape::wave_speed;
use coif_kernels::{scalar, step, step_colliders, Colliders, SimParams, Sphere, Strands};
use glam::{Affine3A, Quat, Vec3};

/// The bits of every coordinate, point after point.
fn bits(points: &[Vec3]) -> Vec<u32> {
    points
        .iter()
        .flat_map(|p| p.to_array())
        .map(f32::to_bits)
        .collect()
}

/// A straight strand of `verts` points `seg` apart along +x from the origin.
fn straight(verts: usize, seg: f32) -> Vec<Vec3> {
    (0..verts).map(|v| Vec3::X * (seg * v as f32)).collect()
}

/// A horizontal strand under gravity, held by its springs alone (no
/// solve): segment `s` carries the weight of the `M_s` free vertices
/// below it, `kappa_s (e_s - t_s) = g M_s` with `kappa = (c / l)^2`, so
/// the tip drops `sum_s g M_s l^2 / c^2` (exact across the segments; the
/// tension that keeps their lengths adds `O(theta^2)`, under 1 % here).
/// Measured after 3 s at two stiffnesses: within 3 % of the closed form,
/// and four times less for twice the wave speed.
#[test]
fn a_loaded_strand_sags_as_its_springs_say() {
    let (verts, seg) = (21, 0.01);
    let pts = straight(verts, seg);
    let mut drops = Vec::new();
    for k in [1.0, 0.95] {
        let params = SimParams {
            local_shape_stiffness: k,
            sleep_speed: 0.0,
            ..SimParams::default()
        };
        let mut s = Strands::from_polylines(&pts, verts).unwrap();
        for _ in 0..180 {
            step(&mut s, &params, &[]);
        }
        let c = wave_speed(k);
        let weights: f32 = (0..verts - 1).map(|s| (verts - 1 - s) as f32).sum();
        let expected = 9.81 * seg * seg / (c * c) * weights;
        let drop = -s.positions()[verts - 1].y;
        println!("local shape {k}: tip drop {drop:.5} m, springs' closed form {expected:.5} m");
        assert!(
            (drop - expected).abs() <= 0.03 * expected,
            "local shape {k}: tip drop {drop} m against {expected} m"
        );
        drops.push((c, drop));
    }
    let [(c1, d1), (c2, d2)] = [drops[0], drops[1]];
    let ratio = (d2 / d1) / (c1 * c1 / (c2 * c2));
    assert!((ratio - 1.0).abs() < 0.03, "sag against 1 / c^2: {ratio}");
}

/// A straight strand without gravity, bent into the springs' lowest mode
/// (`x_j = A sin(j phi)`, `phi = pi / (2 N + 1)` for `N` free vertices of
/// a chain pinned at its root and free at its tip) and let go: it swings
/// at `omega_1 = 2 (c / l) sin(phi / 2)` (the chain's dispersion relation
/// for spring constant `(c / l)^2`). The period from the tip's zero
/// crossings over 3 s is within 2 % of `2 pi / omega_1`, and the swing
/// decays (damping 1: only the springs' own damping).
#[test]
fn a_plucked_strand_swings_at_its_springs_frequency() {
    let (verts, seg, k) = (21, 0.01, 0.7);
    let n = verts - 1;
    let phi = std::f32::consts::PI / (2 * n + 1) as f32;
    let amplitude = 0.002;
    let bent: Vec<Vec3> = (0..verts)
        .map(|j| Vec3::new(seg * j as f32, 0.0, amplitude * (j as f32 * phi).sin()))
        .collect();
    let params = SimParams {
        local_shape_stiffness: k,
        gravity: Vec3::ZERO,
        damping: 1.0,
        sleep_speed: 0.0,
        ..SimParams::default()
    };
    let mut s = Strands::from_polylines(&straight(verts, seg), verts).unwrap();
    s.set_state(&bent, &bent).unwrap();
    let mut crossings = Vec::new();
    let mut last = amplitude;
    let mut peak_late = 0.0f32;
    let steps = 180;
    for i in 1..=steps {
        step(&mut s, &params, &[]);
        let z = s.positions()[verts - 1].z;
        if (z < 0.0) != (last < 0.0) {
            // Linear interpolation of the crossing time.
            let t = (i as f32 - 1.0 + last / (last - z)) * params.dt;
            crossings.push(t);
        }
        if i > steps - 60 {
            peak_late = peak_late.max(z.abs());
        }
        last = z;
    }
    let c = wave_speed(k);
    let omega = 2.0 * (c / seg) * (phi / 2.0).sin();
    let expected = 2.0 * std::f32::consts::PI / omega;
    assert!(crossings.len() >= 4, "too few swings: {crossings:?}");
    let period =
        2.0 * (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f32;
    println!(
        "plucked: period {period:.4} s, closed form {expected:.4} s, late peak {peak_late:.5} m"
    );
    assert!(
        (period - expected).abs() <= 0.02 * expected,
        "period {period} s against {expected} s"
    );
    assert!(
        peak_late < amplitude,
        "the swing did not decay: {peak_late}"
    );
}

/// Curled strands under gravity and a teleport's worth of head turn:
/// without the solve they sag far from the groom; after it, the groom is
/// the step's equilibrium (every vertex within 0.1 mm of it after 3 s),
/// and a head turned by 0.5 rad in one step (the roots jump up to 7.5 cm)
/// and held carries the hair back to the groom turned with it (every
/// vertex within 1 mm after 10 s; measured 0.02 mm, and 0.9 mm after 6 s).
#[test]
fn after_the_solve_the_groom_is_the_equilibrium() {
    let verts = 24;
    let pts: Vec<Vec3> = (0..16)
        .flat_map(|i| {
            let root = Vec3::new(0.01 * i as f32, 0.0, 0.0);
            let turn = 0.3 * i as f32;
            (0..verts).map(move |v| {
                let a = 0.12 * v as f32;
                root + Quat::from_rotation_y(turn)
                    * Vec3::new(0.04 * a.sin(), 0.005 * v as f32, 0.04 * (1.0 - a.cos()))
            })
        })
        .collect();
    let params = SimParams {
        local_shape_stiffness: 0.6,
        sleep_speed: 0.0,
        ..SimParams::default()
    };
    let drift = |s: &Strands, groom: &[Vec3]| {
        s.positions()
            .iter()
            .zip(groom)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0f32, f32::max)
    };
    let mut sagging = Strands::from_polylines(&pts, verts).unwrap();
    let mut held = sagging.clone();
    held.solve_sag_free(&params, &Colliders::default()).unwrap();
    for _ in 0..180 {
        step(&mut sagging, &params, &[]);
        step(&mut held, &params, &[]);
    }
    let (sag, kept) = (drift(&sagging, &pts), drift(&held, &pts));
    println!(
        "largest distance from the groom after 3 s: {sag:.4} m as built, {kept:.6} m sag-free"
    );
    assert!(sag > 0.01, "the springs alone should sag: {sag}");
    assert!(kept < 1e-4, "the sag-free groom drifted {kept} m");
    // Turn the head about the roots' line and hold: the hair follows.
    let pose = Affine3A::from_rotation_y(0.5);
    held.set_head_pose(pose).unwrap();
    for _ in 0..600 {
        step(&mut held, &params, &[]);
    }
    let turned: Vec<Vec3> = pts.iter().map(|p| pose.transform_point3(*p)).collect();
    let back = drift(&held, &turned);
    println!("10 s after a held turn: {back:.5} m from the turned groom");
    assert!(
        back < 1e-3,
        "the hair did not return to the turned groom: {back}"
    );
}

/// Hair groomed into a sphere's skin: the solve leaves the pose as it is
/// and a second call changes nothing (the same bytes after 60 steps as
/// after one call); the step pushes the dipping strands out and their
/// springs hold them there, no vertex deeper than 0.2 mm into the skin
/// and none turned 30 degrees beyond its groom.
#[test]
fn hair_groomed_into_a_skin_is_pushed_out_and_held() {
    let verts = 16;
    let ball = Sphere {
        center: Vec3::new(0.0, -0.05, 0.0),
        radius: 0.05,
    };
    // Strands from the ball's top outward, the first eight dipping into it.
    let pts: Vec<Vec3> = (0..16)
        .flat_map(|i| {
            let dip = if i < 8 { 0.004 } else { -0.01 };
            let root = Vec3::new(0.0, 0.002, 0.004 * i as f32);
            (0..verts).map(move |v| {
                let x = 0.006 * v as f32;
                root + Vec3::new(x, -dip * (x * 40.0).sin(), 0.0)
            })
        })
        .collect();
    let params = SimParams {
        local_shape_stiffness: 0.7,
        ..SimParams::default()
    };
    let spheres = [ball.clone()];
    let colliders = Colliders::spheres(&spheres);
    let mut once = Strands::from_polylines(&pts, verts).unwrap();
    let built = bits(&once.positions());
    once.solve_sag_free(&params, &colliders).unwrap();
    assert!(bits(&once.positions()) == built, "the solve moved the hair");
    let mut twice = once.clone();
    twice.solve_sag_free(&params, &colliders).unwrap();
    for _ in 0..60 {
        step_colliders(&mut once, &params, &colliders);
        step_colliders(&mut twice, &params, &colliders);
    }
    let end = once.positions();
    assert!(
        bits(&end) == bits(&twice.positions()),
        "a second solve changed the steps"
    );
    let skin = ball.radius + params.pearl_radius;
    for (strand, (p, g)) in end.chunks(verts).zip(pts.chunks(verts)).enumerate() {
        for v in 1..verts {
            let depth = skin - p[v].distance(ball.center);
            assert!(
                depth < 2e-4,
                "strand {strand} vertex {v}: {depth} m into the skin"
            );
            if v + 1 < verts {
                let turn = (p[v] - p[v - 1]).angle_between(p[v + 1] - p[v]);
                let groomed = (g[v] - g[v - 1]).angle_between(g[v + 1] - g[v]);
                assert!(
                    turn - groomed < 30f32.to_radians(),
                    "strand {strand} vertex {v}: a kink"
                );
            }
        }
    }
}

/// Bad parameters and colliders are refused with an error, and nothing
/// changes.
#[test]
fn the_solve_refuses_bad_input() {
    let pts = straight(8, 0.01);
    let mut s = Strands::from_polylines(&pts, 8).unwrap();
    let before = bits(&s.positions());
    let nan_params = SimParams {
        local_shape_stiffness: f32::NAN,
        ..SimParams::default()
    };
    assert!(s
        .solve_sag_free(&nan_params, &Colliders::default())
        .is_err());
    let bad_dt = SimParams {
        dt: 0.0,
        ..SimParams::default()
    };
    assert!(s.solve_sag_free(&bad_dt, &Colliders::default()).is_err());
    let ok = SimParams::default();
    for sphere in [
        Sphere {
            center: Vec3::NAN,
            radius: 0.1,
        },
        Sphere {
            center: Vec3::ZERO,
            radius: -1.0,
        },
        Sphere {
            center: Vec3::ZERO,
            radius: f32::INFINITY,
        },
    ] {
        let spheres = [sphere.clone()];
        assert!(
            s.solve_sag_free(&ok, &Colliders::spheres(&spheres))
                .is_err(),
            "{sphere:?}"
        );
    }
    assert_eq!(bits(&s.positions()), before);
}

/// SIMD and scalar with the springs on, after the solve, through a head
/// turn over a sphere: the same bytes.
#[test]
fn springs_simd_matches_scalar_bit_for_bit() {
    let verts = 20;
    let pts: Vec<Vec3> = (0..12)
        .flat_map(|i| {
            let root = Vec3::new(0.008 * i as f32 - 0.05, 0.0, 0.0);
            (0..verts).map(move |v| {
                root + Vec3::new(0.003 * v as f32, -0.008 * v as f32, 0.002 * v as f32)
            })
        })
        .collect();
    let spheres = [Sphere {
        center: Vec3::new(0.0, -0.1, -0.03),
        radius: 0.04,
    }];
    let params = SimParams {
        local_shape_stiffness: 0.6,
        ..SimParams::default()
    };
    let mut a = Strands::from_polylines(&pts, verts).unwrap();
    a.solve_sag_free(&params, &Colliders::spheres(&spheres))
        .unwrap();
    let mut b = a.clone();
    for i in 0..60 {
        let pose = Affine3A::from_rotation_y(0.6 * (i as f32 * 0.1).sin());
        a.set_head_pose(pose).unwrap();
        b.set_head_pose(pose).unwrap();
        step(&mut a, &params, &spheres);
        scalar::step(&mut b, &params, &spheres);
    }
    assert_eq!(bits(&a.positions()), bits(&b.positions()));
    assert_ne!(bits(&a.positions()), bits(&pts), "nothing moved");
}

/// A reset starts from the current groom frame. The step spreads a turn
/// of the rest frame over its substeps (the springs' rest vectors turn
/// from the frame of the last step to the current one); strands put back
/// in their rest shape (`reset_to_rest`) or given a state (`set_state`)
/// after the frame turned are already in the current frame, so the next
/// step has no turn left to spread. Without gravity the hair, placed in
/// its rest shape in the turned frame, stays there: under 1e-5 m after a
/// step (a 1.2 rad turn spread over the substeps would swing the tip by
/// centimetres).
#[test]
fn a_reset_starts_the_shape_springs_from_the_current_frame() {
    let (verts, seg) = (16, 0.01);
    let pts = straight(verts, seg);
    let params = SimParams {
        local_shape_stiffness: 1.0,
        gravity: Vec3::ZERO,
        sleep_speed: 0.0,
        ..SimParams::default()
    };
    let turn = Quat::from_rotation_z(1.2);
    let placed: Vec<Vec3> = pts.iter().map(|p| turn * *p).collect();
    for reset in ["reset_to_rest", "set_state"] {
        let mut s = Strands::from_polylines(&pts, verts).unwrap();
        step(&mut s, &params, &[]);
        s.set_rest_rotation(turn).unwrap();
        match reset {
            "reset_to_rest" => s.reset_to_rest(),
            _ => s.set_state(&placed, &placed).unwrap(),
        }
        let before = s.positions();
        for (p, q) in before.iter().zip(&placed) {
            assert!(p.distance(*q) < 1e-6, "{reset}: placed at {p}, rest {q}");
        }
        step(&mut s, &params, &[]);
        let moved = s
            .positions()
            .iter()
            .zip(&before)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0f32, f32::max);
        assert!(
            moved < 1e-5,
            "{reset}: the hair moved {moved} m in one step"
        );
    }
}
