//! Coulomb friction against Coulomb's law: a strand lying on a slope (a
//! plane tilted by theta: a sphere of 50 m radius, locally flat to 0.9 mm
//! over the strand) stays put when the static coefficient exceeds
//! tan(theta) and slides down when the coefficients are below it, at
//! several angles; the same against a capsule and in the scalar twin. The
//! previous rule (a share of the tangential velocity removed per contact)
//! let hair creep off any slope.
//!
//! The strand lies across the slope, level, from its root: every vertex
//! is held by its own friction alone. Lying straight up the slope from its
//! root it is a column under its own weight: perfectly straight it cannot
//! move down at all (the length constraints hold it, whatever the
//! friction), and with any waviness a strand without bending stiffness
//! buckles off the surface and folds (measured: 0.57 m of travel at 10
//! degrees with static friction 10 % above tan(theta)), so that geometry
//! tests the chain's stiffness, not the friction.

use coif_kernels::{self as kernels, scalar, Capsule, Colliders, SimParams, Sphere, Strands};
use glam::Vec3;

const BIG: f32 = 50.0;

/// A strand of 25 x 1.2 cm lying level across the slope of angle `theta`
/// from its root at the origin (on the skin), the plane as a sphere, and
/// the slope's uphill direction.
fn slope(theta: f32, params: &SimParams) -> (Strands, Sphere, Vec3) {
    let up = Vec3::new(theta.cos(), theta.sin(), 0.0);
    let normal = Vec3::new(-theta.sin(), theta.cos(), 0.0);
    let skin = params.pearl_radius;
    let centre = -normal * (BIG + skin);
    // On the skin of the sphere: each vertex at distance BIG + skin.
    let pts: Vec<Vec3> = (0..25)
        .map(|v| {
            let p = Vec3::Z * (0.012 * v as f32);
            centre + (p - centre).normalize() * (BIG + skin)
        })
        .collect();
    let s = Strands::from_polylines(&pts, 25).unwrap();
    (
        s,
        Sphere {
            center: centre,
            radius: BIG,
        },
        up,
    )
}

/// How far the tip moved down the slope in `seconds`, metres.
fn tip_slide(theta: f32, mu_s: f32, mu_k: f32, seconds: f32, use_scalar: bool) -> f32 {
    let params = SimParams {
        friction: mu_k,
        static_friction: mu_s,
        sleep_speed: 0.0,
        ..Default::default()
    };
    let (mut s, plane, up) = slope(theta, &params);
    let start = s.vertex(0, 24).unwrap();
    for _ in 0..(seconds / params.dt).round() as usize {
        if use_scalar {
            scalar::step(&mut s, &params, std::slice::from_ref(&plane));
        } else {
            kernels::step(&mut s, &params, std::slice::from_ref(&plane));
        }
    }
    let tip = s.vertex(0, 24).unwrap();
    assert!(tip.is_finite());
    (start - tip).dot(up)
}

#[test]
fn hair_holds_on_a_slope_exactly_when_static_friction_exceeds_tan_theta() {
    for deg in [10.0f32, 20.0, 30.0, 40.0, 50.0] {
        let theta = deg.to_radians();
        let t = theta.tan();
        // Holds: static 10 % above tan(theta), kinetic half of that.
        let held = tip_slide(theta, 1.1 * t, 0.55 * t, 2.0, false);
        // Slides: both 10 % below tan(theta).
        let slid = tip_slide(theta, 0.9 * t, 0.9 * t, 2.0, false);
        eprintln!("{deg} degrees: held {held:.5} m, slid {slid:.4} m");
        assert!(held.abs() < 1e-3, "{deg} degrees: the tip moved {held} m");
        assert!(slid > 0.01, "{deg} degrees: the tip slid only {slid} m");
    }
}

#[test]
fn the_boundary_is_at_tan_theta_in_the_scalar_twin_too() {
    for deg in [15.0f32, 35.0] {
        let theta = deg.to_radians();
        let t = theta.tan();
        let held = tip_slide(theta, 1.1 * t, 0.55 * t, 2.0, true);
        let slid = tip_slide(theta, 0.9 * t, 0.9 * t, 2.0, true);
        assert!(held.abs() < 1e-3, "{deg} degrees: the tip moved {held} m");
        assert!(slid > 0.01, "{deg} degrees: the tip slid only {slid} m");
    }
}

#[test]
fn hair_holds_on_a_large_capsule_as_on_the_plane() {
    // A capsule of 20 m radius whose axis runs along z, 20 m below the
    // strand (which lies along z, on its skin): a slope of 25 degrees.
    let theta = 25f32.to_radians();
    let t = theta.tan();
    let up = Vec3::new(theta.cos(), theta.sin(), 0.0);
    let normal = Vec3::new(-theta.sin(), theta.cos(), 0.0);
    for (mu_s, mu_k, holds) in [(1.1 * t, 0.6 * t, true), (0.9 * t, 0.9 * t, false)] {
        let params = SimParams {
            friction: mu_k,
            static_friction: mu_s,
            sleep_speed: 0.0,
            ..Default::default()
        };
        let radius = 20.0;
        let c = -normal * (radius + params.pearl_radius);
        let cap = Capsule {
            a: c - Vec3::Z * 5.0,
            b: c + Vec3::Z * 5.0,
            radius,
        };
        let pts: Vec<Vec3> = (0..25).map(|v| Vec3::Z * (0.012 * v as f32)).collect();
        let mut s = Strands::from_polylines(&pts, 25).unwrap();
        let start = s.vertex(0, 24).unwrap();
        for _ in 0..120 {
            kernels::step_colliders(
                &mut s,
                &params,
                &Colliders {
                    capsules: &[cap],
                    ..Default::default()
                },
            );
        }
        let slid = (start - s.vertex(0, 24).unwrap()).dot(up);
        if holds {
            assert!(slid.abs() < 1e-3, "held: moved {slid} m");
        } else {
            assert!(slid > 0.01, "slid only {slid} m");
        }
    }
}
