//! Capsules: a capsule with `a == b` moves hair exactly as the sphere does;
//! hair draped over one stays out of it (1 mm), an arm sweeping through
//! hanging hair at 3 m/s leaves it at most 2 mm deep; bad capsules are
//! ignored and never spread NaN; SIMD = scalar, any thread count gives the
//! same bytes, and no step allocates with every collider type.

mod common;

use coif_kernels::{self as kernels, scalar, Capsule, Colliders, SimParams, Sphere, Strands};
use common::executors;
use glam::Vec3;

/// Deepest penetration into any capsule of the hair, metres (>= 0): the
/// vertices and the points at every eighth of each segment (the hair
/// between the vertices, which the pearls keep out).
fn deepest(s: &Strands, capsules: &[Capsule]) -> f32 {
    let v = s.verts_per_strand();
    let p = s.positions();
    let mut worst: f32 = 0.0;
    for strand in p.chunks(v) {
        for w in strand.windows(2) {
            for k in 0..8 {
                let q = w[0].lerp(w[1], k as f32 / 8.0);
                for c in capsules {
                    worst = worst.max(-c.distance(q));
                }
            }
        }
    }
    worst
}

/// `count` strands of `verts` vertices hanging from a line along x at
/// height `y`, `spacing` apart, segment `seg`.
fn curtain(count: usize, verts: usize, y: f32, spacing: f32, seg: f32) -> Vec<Vec3> {
    (0..count)
        .flat_map(|i| {
            let root = Vec3::new(i as f32 * spacing - 0.5 * spacing * count as f32, y, 0.0);
            (0..verts).map(move |v| root - Vec3::Y * (seg * v as f32))
        })
        .collect()
}

#[test]
fn a_capsule_with_equal_ends_moves_hair_exactly_as_the_sphere_does() {
    let (pts, rig) = common::curly_strands(40, 12, 7);
    let params = SimParams::default();
    let caps: Vec<Capsule> = rig
        .iter()
        .map(|s| Capsule {
            a: s.center,
            b: s.center,
            radius: s.radius,
        })
        .collect();
    let mut a = Strands::from_polylines(&pts, 12).unwrap();
    let mut b = a.clone();
    for i in 0..90 {
        // The rig moves, so the sweep and the friction's motion count too.
        let off = Vec3::new(0.05 * (i as f32 * 0.1).sin(), 0.0, 0.0);
        let spheres: Vec<Sphere> = rig
            .iter()
            .map(|s| Sphere {
                center: s.center + off,
                radius: s.radius,
            })
            .collect();
        let moved: Vec<Capsule> = caps
            .iter()
            .map(|c| Capsule {
                a: c.a + off,
                b: c.b + off,
                radius: c.radius,
            })
            .collect();
        kernels::step(&mut a, &params, &spheres);
        kernels::step_colliders(
            &mut b,
            &params,
            &Colliders {
                capsules: &moved,
                ..Default::default()
            },
        );
    }
    assert_eq!(a.positions(), b.positions());
}

#[test]
fn hair_draped_over_a_capsule_stays_within_a_millimetre_of_its_surface() {
    // 64 strands of 25 x 1.2 cm dropped across a horizontal bar of 4 cm
    // radius, and a tilted one.
    for bar in [
        Capsule {
            a: Vec3::new(-1.0, -0.1, 0.0),
            b: Vec3::new(1.0, -0.1, 0.0),
            radius: 0.04,
        },
        Capsule {
            a: Vec3::new(-1.0, -0.2, -0.1),
            b: Vec3::new(1.0, -0.05, 0.12),
            radius: 0.03,
        },
    ] {
        let pts: Vec<Vec3> = curtain(64, 25, 0.0, 0.012, 0.012)
            .into_iter()
            .map(|p| p + Vec3::new(0.0, 0.0, 0.01 * (p.x * 40.0).sin()))
            .collect();
        let mut s = Strands::from_polylines(&pts, 25).unwrap();
        let params = SimParams::default();
        let colliders = Colliders {
            capsules: std::slice::from_ref(&bar),
            ..Default::default()
        };
        let mut worst: f32 = 0.0;
        for _ in 0..180 {
            kernels::step_colliders(&mut s, &params, &colliders);
            worst = worst.max(deepest(&s, &[bar]));
        }
        eprintln!("drape: deepest {worst} m");
        assert!(worst <= 1e-3, "{bar:?}: {worst} m deep");
        assert!(s.positions().iter().all(|p| p.is_finite()));
        // And it did drape: tips hang below the bar on both sides.
        let below = s.positions().iter().filter(|p| p.y < -0.15).count();
        assert!(below > 100, "{below} vertices below the bar");
    }
}

#[test]
fn an_arm_sweeping_through_hanging_hair_at_3_m_s_leaves_it_at_most_2_mm_deep() {
    let pts = curtain(64, 25, 0.0, 0.006, 0.012);
    let mut s = Strands::from_polylines(&pts, 25).unwrap();
    let params = SimParams::default();
    let mut worst: f32 = 0.0;
    let dt = params.dt;
    // A forearm (radius 4 cm, 30 cm long, along z) 15 cm below the roots,
    // from x = -0.6 to 0.6 at 3 m/s, and back.
    for i in 0..48 {
        let t = i as f32 * dt;
        let x = if t < 0.4 {
            -0.6 + 3.0 * t
        } else {
            0.6 - 3.0 * (t - 0.4)
        };
        let arm = Capsule {
            a: Vec3::new(x, -0.15, -0.15),
            b: Vec3::new(x, -0.15, 0.15),
            radius: 0.04,
        };
        kernels::step_colliders(
            &mut s,
            &params,
            &Colliders {
                capsules: &[arm],
                ..Default::default()
            },
        );
        worst = worst.max(deepest(&s, &[arm]));
    }
    eprintln!("sweep: deepest {worst} m");
    assert!(worst <= 2e-3, "{worst} m deep");
    // The arm went through the hair and pushed it.
    let max_x = s.positions().iter().map(|p| p.x.abs()).fold(0.0, f32::max);
    assert!(max_x > 0.25, "the hair was not pushed: {max_x}");
}

#[test]
fn bad_capsules_are_ignored_and_never_spread_nan() {
    let (pts, rig) = common::curly_strands(24, 10, 3);
    let params = SimParams::default();
    let bad = [
        Capsule {
            a: Vec3::NAN,
            b: Vec3::ZERO,
            radius: 0.1,
        },
        Capsule {
            a: Vec3::ZERO,
            b: Vec3::new(f32::INFINITY, 0.0, 0.0),
            radius: 0.1,
        },
        Capsule {
            a: Vec3::ZERO,
            b: Vec3::Y,
            radius: -0.1,
        },
        Capsule {
            a: Vec3::ZERO,
            b: Vec3::Y,
            radius: f32::NAN,
        },
        Capsule {
            a: Vec3::ZERO,
            b: Vec3::Y,
            radius: f32::INFINITY,
        },
    ];
    let mut clean = Strands::from_polylines(&pts, 10).unwrap();
    let mut dirty = clean.clone();
    let mut dirty_scalar = clean.clone();
    for _ in 0..60 {
        kernels::step(&mut clean, &params, &rig);
        let c = Colliders {
            spheres: &rig,
            capsules: &bad,
            ..Default::default()
        };
        kernels::step_colliders(&mut dirty, &params, &c);
        scalar::step_colliders(&mut dirty_scalar, &params, &c);
    }
    assert_eq!(clean.positions(), dirty.positions());
    assert_eq!(dirty.restored_strands(), 0);
    assert!(dirty_scalar.positions().iter().all(|p| p.is_finite()));
}

/// Capsules, spheres, wind and gusts: the scene of the twin and thread tests.
fn busy() -> (Vec<Vec3>, Vec<Sphere>, Vec<Capsule>, SimParams) {
    let (pts, rig) = common::curly_strands(100, 12, 11);
    let caps = vec![
        Capsule {
            a: Vec3::new(-0.2, -0.1, 0.05),
            b: Vec3::new(0.2, -0.12, 0.05),
            radius: 0.03,
        },
        Capsule {
            a: Vec3::new(0.0, 0.0, -0.3),
            b: Vec3::new(0.0, 0.05, 0.3),
            radius: 0.05,
        },
    ];
    let params = SimParams {
        wind: Vec3::new(1.0, 0.0, 0.5),
        drag: 3.0,
        turbulence: 0.5,
        local_shape_stiffness: 0.5,
        ..Default::default()
    };
    (pts, rig, caps, params)
}

#[test]
fn simd_matches_scalar_with_capsules_spheres_and_wind() {
    let (pts, rig, caps, params) = busy();
    let mut a = Strands::from_polylines(&pts, 12).unwrap();
    let mut b = a.clone();
    let mut worst: f32 = 0.0;
    for i in 0..120 {
        let off = Vec3::X * (0.1 * (i as f32 * 0.05).sin());
        let moved: Vec<Capsule> = caps
            .iter()
            .map(|c| Capsule {
                a: c.a + off,
                b: c.b + off,
                radius: c.radius,
            })
            .collect();
        let c = Colliders {
            spheres: &rig,
            capsules: &moved,
            ..Default::default()
        };
        kernels::step_colliders(&mut a, &params, &c);
        scalar::step_colliders(&mut b, &params, &c);
        worst = worst.max(kernels::measure::max_distance(&a, &b));
    }
    // The twins read the same estimate tables; the tolerance covers the
    // rare lane whose branch differs by one rounding.
    eprintln!("SIMD - scalar: {worst} m");
    assert!(worst <= 1e-4, "SIMD and scalar differ by {worst} m");
}

#[test]
fn capsules_give_the_same_bytes_on_any_thread_count() {
    let (pts, rig, caps, params) = busy();
    let runs: Vec<Vec<Vec3>> = executors::all()
        .iter()
        .map(|e| {
            let mut s = Strands::from_polylines(&pts, 12).unwrap();
            for i in 0..40 {
                let off = Vec3::X * (0.01 * i as f32);
                let moved: Vec<Capsule> = caps
                    .iter()
                    .map(|c| Capsule {
                        a: c.a + off,
                        b: c.b - off,
                        radius: c.radius,
                    })
                    .collect();
                let c = Colliders {
                    spheres: &rig,
                    capsules: &moved,
                    ..Default::default()
                };
                kernels::step_colliders_with(&mut s, &params, &c, e.as_ref());
            }
            s.positions()
        })
        .collect();
    for r in &runs[1..] {
        assert_eq!(r, &runs[0]);
    }
}
