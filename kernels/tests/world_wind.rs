//! Wind and drag against their exact consequences (independent of the
//! solver): a strand in a steady wind hangs straight along
//! `gravity + drag wind`, small swings decay as `exp(-drag t / 2)`; gusts
//! move neighbouring strands differently, give the same bytes on SIMD and
//! scalar and on any thread count, and hair asleep in still air wakes when
//! the wind changes.

mod common;

use coif_kernels::{self as kernels, scalar, SimParams, Strands};
use common::executors;
use glam::Vec3;

/// One straight strand of `verts` vertices, `seg` apart, hanging down.
fn hanging(verts: usize, seg: f32) -> Vec<Vec3> {
    (0..verts).map(|v| -Vec3::Y * (seg * v as f32)).collect()
}

#[test]
fn a_strand_in_a_steady_wind_hangs_straight_along_gravity_plus_drag_wind() {
    let (verts, seg) = (32, 0.01);
    let length = seg * (verts - 1) as f32;
    for (wind, drag) in [
        (Vec3::new(5.0, 0.0, 0.0), 2.0),
        (Vec3::new(0.0, 0.0, -3.0), 10.0),
        (Vec3::new(2.0, 1.0, -1.0), 50.0),
        (Vec3::new(20.0, 0.0, 0.0), 1.0),
        // Upward air stronger than gravity: the strand stands up.
        (Vec3::new(1.0, 30.0, 0.0), 0.5),
        (Vec3::new(-1.0, 0.0, 1.0), 300.0),
        (Vec3::new(-0.05, 0.0, 0.05), 300.0),
        (Vec3::new(-3.0, 0.0, 3.0), 100.0),
        (Vec3::new(-10.0, 0.0, 10.0), 10.0),
    ] {
        let params = SimParams {
            wind,
            drag,
            sleep_speed: 0.0,
            ..Default::default()
        };
        // Long enough to settle: 10 s, or five of the overdamped strand's
        // relaxation times `drag L / |a|` where drag dominates.
        let accel = (params.gravity + wind * drag).length();
        let seconds = (5.0 * drag * length / accel).max(10.0);
        let mut s = Strands::from_polylines(&hanging(verts, seg), verts).unwrap();
        for _ in 0..(seconds / params.dt) as usize {
            kernels::step(&mut s, &params, &[]);
        }
        let p = s.positions();
        let along = p[verts - 1] - p[0];
        let expected = (params.gravity + wind * drag).normalize();
        let angle = along.angle_between(expected).to_degrees();
        let straight = along.length() / length;
        assert!(
            angle < 1.0 && straight >= 0.98,
            "wind {wind} drag {drag}: {angle:.3} degrees off, tip-root {:.2} % of the length",
            straight * 100.0
        );
    }
}

/// Peaks of `|x|` of a signal sampled every `dt`, as (time, value).
fn peaks(x: &[f32], dt: f32) -> Vec<(f64, f64)> {
    (1..x.len() - 1)
        .filter(|&i| x[i].abs() > x[i - 1].abs() && x[i].abs() >= x[i + 1].abs())
        .map(|i| (i as f64 * dt as f64, x[i].abs() as f64))
        .collect()
}

/// Least-squares slope of `ln(value)` against time.
fn log_slope(p: &[(f64, f64)]) -> f64 {
    let n = p.len() as f64;
    let (mt, ml) = (
        p.iter().map(|q| q.0).sum::<f64>() / n,
        p.iter().map(|q| q.1.ln()).sum::<f64>() / n,
    );
    let cov: f64 = p.iter().map(|q| (q.0 - mt) * (q.1.ln() - ml)).sum();
    let var: f64 = p.iter().map(|q| (q.0 - mt) * (q.0 - mt)).sum();
    cov / var
}

#[test]
fn small_swings_decay_as_exp_minus_drag_t_over_2() {
    // A pendulum of one 20 cm segment and a chain of 16 x 2 cm, started
    // 3 degrees off vertical at rest, undamped but for the drag.
    for (verts, seg) in [(2, 0.2), (17, 0.02)] {
        for drag in [0.5f32, 2.0, 6.0] {
            let params = SimParams {
                damping: 1.0,
                drag,
                sleep_speed: 0.0,
                ..Default::default()
            };
            let tilt = glam::Quat::from_rotation_z(3f32.to_radians());
            let pts: Vec<Vec3> = hanging(verts, seg).iter().map(|p| tilt * *p).collect();
            let mut s = Strands::from_polylines(&pts, verts).unwrap();
            let steps = (6.0 / params.dt) as usize;
            let mut x = Vec::with_capacity(steps);
            for _ in 0..steps {
                kernels::step(&mut s, &params, &[]);
                x.push(s.vertex(0, verts - 1).unwrap().x);
            }
            let p = peaks(&x, params.dt);
            let p: Vec<_> = p.into_iter().filter(|q| q.1 > 1e-5).collect();
            assert!(
                p.len() >= 4,
                "{verts} vertices, drag {drag}: {} peaks",
                p.len()
            );
            let rate = -log_slope(&p);
            let expected = drag as f64 / 2.0;
            assert!(
                (rate - expected).abs() <= 0.1 * expected,
                "{verts} vertices, drag {drag}: decay rate {rate:.4} /s, exact {expected}"
            );
        }
    }
}

/// 64 strands hanging from a 2 m line, in gusts.
fn gusty() -> (Vec<Vec3>, usize, SimParams) {
    let verts = 16;
    let pts: Vec<Vec3> = (0..64)
        .flat_map(|i| {
            let root = Vec3::new(i as f32 * 0.03, 0.0, 0.0);
            hanging(verts, 0.015).into_iter().map(move |p| p + root)
        })
        .collect();
    let params = SimParams {
        wind: Vec3::new(0.0, 0.0, 2.0),
        drag: 5.0,
        turbulence: 1.5,
        turbulence_scale: 0.3,
        ..Default::default()
    };
    (pts, verts, params)
}

#[test]
fn gusts_move_neighbouring_strands_differently_and_change_over_time() {
    let (pts, verts, params) = gusty();
    let mut s = Strands::from_polylines(&pts, verts).unwrap();
    let tip = |s: &Strands, i: usize| s.vertex(i, verts - 1).unwrap();
    let mut spread_seen: f32 = 0.0;
    let mut moved: f32 = 0.0;
    let mut last = tip(&s, 0);
    for step in 0..240 {
        kernels::step(&mut s, &params, &[]);
        if step > 60 {
            // Strands 0 and 20 are 60 cm apart: two gust scales.
            spread_seen = spread_seen.max((tip(&s, 0) - tip(&s, 20)).length());
            moved = moved.max((tip(&s, 0) - last).length());
        }
        last = tip(&s, 0);
    }
    assert!(
        spread_seen > 0.01,
        "strands 60 cm apart moved as one: {spread_seen} m"
    );
    assert!(moved > 1e-4, "the gusts do not change in time");
    assert!(s.awake_strands() == 64, "hair in gusts fell asleep");
    // The same wind without gusts: every strand the same.
    let calm = SimParams {
        turbulence: 0.0,
        ..params
    };
    let mut c = Strands::from_polylines(&pts, verts).unwrap();
    for _ in 0..240 {
        kernels::step(&mut c, &calm, &[]);
    }
    let d = (tip(&c, 0) - Vec3::new(0.0, 0.0, 0.0)) - (tip(&c, 20) - Vec3::X * 0.6);
    assert!(d.length() < 1e-5, "{d}");
}

#[test]
fn gusts_give_the_same_bytes_on_simd_scalar_and_any_thread_count() {
    let (pts, verts, params) = gusty();
    let mut a = Strands::from_polylines(&pts, verts).unwrap();
    let mut b = a.clone();
    for _ in 0..60 {
        kernels::step(&mut a, &params, &[]);
        scalar::step(&mut b, &params, &[]);
    }
    let worst = a
        .positions()
        .iter()
        .zip(b.positions())
        .map(|(p, q)| (*p - q).length())
        .fold(0.0f32, f32::max);
    assert!(worst <= 1e-5, "SIMD and scalar differ by {worst} m");
    let runs: Vec<Vec<Vec3>> = executors::all()
        .iter()
        .map(|e| {
            let mut s = Strands::from_polylines(&pts, verts).unwrap();
            for _ in 0..60 {
                kernels::step_with(&mut s, &params, &[], e.as_ref());
            }
            s.positions()
        })
        .collect();
    for r in &runs[1..] {
        assert_eq!(r, &runs[0]);
    }
}

#[test]
fn hair_asleep_in_still_air_wakes_when_the_wind_changes() {
    let pts: Vec<Vec3> = (0..16)
        .flat_map(|i| {
            let root = Vec3::new(i as f32 * 0.02, 0.0, 0.0);
            hanging(12, 0.02).into_iter().map(move |p| p + root)
        })
        .collect();
    let still = SimParams {
        drag: 3.0,
        ..Default::default()
    };
    let mut s = Strands::from_polylines(&pts, 12).unwrap();
    for _ in 0..120 {
        kernels::step(&mut s, &still, &[]);
    }
    assert_eq!(s.awake_strands(), 0, "still hair should sleep");
    let before = s.positions();
    let windy = SimParams {
        wind: Vec3::new(3.0, 0.0, 0.0),
        ..still
    };
    kernels::step(&mut s, &windy, &[]);
    assert_eq!(s.awake_strands(), 16, "the wind's change woke nothing");
    for _ in 0..30 {
        kernels::step(&mut s, &windy, &[]);
    }
    let moved = s
        .positions()
        .iter()
        .zip(&before)
        .map(|(p, q)| p.x - q.x)
        .fold(0.0f32, f32::max);
    assert!(moved > 0.01, "the wind moved the tips {moved} m");
}
