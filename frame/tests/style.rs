//! Styled hair that moves, on Sintel's groom and bust (4 mm field, the
//! default `SimParams` but the stiffness, one step of 1/60 s per frame;
//! `coif_frame::style`): the goals of the local shape springs with the
//! sag-free rest state, and the diagnosis behind them.

use coif_base::tasks::Serial;
use coif_frame::style::{StyleRun, StyleScene};
use coif_kernels::SimParams;
use glam::Vec3;

fn run(scene: &StyleScene, k: f32, gravity: Vec3) -> StyleRun {
    let params = SimParams {
        local_shape_stiffness: k,
        gravity,
        ..SimParams::default()
    };
    scene
        .run(&params, &Serial, |s, p, c| Ok(s.solve_sag_free(p, c)?))
        .unwrap()
}

/// No frizz from 0.5 to 1 (at most 1 % of the interior vertices turn 30
/// degrees beyond their groomed angle, at rest after 3 s or in a 40-degree
/// head turn); no sag from 0.7 to 1 (the 95th percentile vertex within 3
/// mm of the groom after 3 s); at 0.7 the turn swings the tips 10 mm RMS
/// or more from the hair carried rigidly and they are back within 3 mm
/// 2.5 s after; softer swings no less. The landed rule it replaces:
/// 14-54 % kinked at rest between 0.5 and 0.95, 31-68 mm of drift.
#[test]
fn sintel_keeps_her_style_swings_and_returns() {
    let scene = StyleScene::sintel().unwrap();
    let g = SimParams::default().gravity;
    let mut swings = Vec::new();
    for k in [1.0, 0.9, 0.7, 0.6, 0.5] {
        let r = run(&scene, k, g);
        println!(
            "local shape {k}: drift p95 {:.2} mm, kinked {:.2} / {:.2} %, swing {:.1} mm, after {:.2} mm, solve {:.0} ms",
            r.rest_drift_p95 * 1e3,
            r.kinked_at_rest * 100.0,
            r.kinked_in_turn * 100.0,
            r.swing * 1e3,
            r.returned * 1e3,
            r.solve_seconds * 1e3
        );
        assert!(
            r.kinked_at_rest <= 0.01,
            "k {k}: kinked at rest {}",
            r.kinked_at_rest
        );
        assert!(
            r.kinked_in_turn <= 0.01,
            "k {k}: kinked in the turn {}",
            r.kinked_in_turn
        );
        if k >= 0.7 {
            assert!(
                r.rest_drift_p95 <= 0.003,
                "k {k}: drift {}",
                r.rest_drift_p95
            );
        }
        if k == 0.7 {
            assert!(r.swing >= 0.010, "k 0.7: swing {}", r.swing);
            assert!(r.returned <= 0.003, "k 0.7: 2.5 s after {}", r.returned);
        }
        swings.push((k, r.swing));
    }
    for w in swings.windows(2) {
        assert!(
            w[1].1 >= w[0].1,
            "softer {} swung less than {}: {swings:?}",
            w[1].0,
            w[0].0
        );
    }
}

/// The diagnosis: with no gravity and no collider the groom is the
/// equilibrium of any shape rule, so a strand that leaves it does so on
/// the rule's own energy. The landed rule (TressFX's local shape
/// constraints, the child taking the whole correction) left it at every
/// stiffness below 1: 16 mm (p95) at 0.9 and 92 mm at 0.5 after 3 s,
/// more than half the vertices kinked in the turn. The springs keep it
/// within 0.1 mm (rounding: 0.02 mm measured at 0.5) and turn with the
/// head without a kink.
#[test]
fn without_load_the_groom_stays_put_at_any_stiffness() {
    let mut scene = StyleScene::sintel().unwrap();
    scene.field = None;
    for k in [0.9, 0.7, 0.5] {
        let r = run(&scene, k, Vec3::ZERO);
        assert!(r.rest_drift_p95 < 1e-4, "k {k}: drift {}", r.rest_drift_p95);
        assert_eq!(r.kinked_at_rest, 0.0, "k {k}");
        assert!(r.kinked_in_turn <= 0.01, "k {k}: {}", r.kinked_in_turn);
        assert!(r.returned < 0.003, "k {k}: {}", r.returned);
    }
}
