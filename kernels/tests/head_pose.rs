//! The one-call head pose (`Strands::set_head_pose`): Sintel's groom (the
//! shipped file) at local shape stiffness 1, turned 60 degrees about the
//! vertical and held for 3 s, stays within 1 mm of the same groom
//! simulated unturned and then turned rigidly; with the roots alone moved
//! (the rest frame left unturned) it does not.

use coif_geometry::groom;
use coif_kernels::{step, SimParams, Strands};
use glam::{Affine3A, Quat, Vec3};

const GROOM: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../assets/sintel/sintel_lite.tfx"
);

#[test]
fn a_turned_head_keeps_its_groom_in_one_call() {
    let g = groom::load(&std::fs::read(GROOM).unwrap()).unwrap();
    let (pts, verts) = g.uniform_points(0.01).unwrap();
    let params = SimParams {
        local_shape_stiffness: 1.0,
        sleep_speed: 0.0,
        ..Default::default()
    };
    let pivot = Vec3::new(0.0, 0.3, 0.0);
    let turn = |angle: f32| {
        Affine3A::from_translation(pivot)
            * Affine3A::from_quat(Quat::from_rotation_y(angle))
            * Affine3A::from_translation(-pivot)
    };
    let steps = (3.0 / params.dt) as usize;
    // Turned 60 degrees over the first second (smoothly), then held.
    let angle = |i: usize| {
        let t = (i as f32 * params.dt).min(1.0);
        60f32.to_radians() * (0.5 - 0.5 * (std::f32::consts::PI * t).cos())
    };
    let mut still = Strands::from_polylines(&pts, verts).unwrap();
    let mut posed = still.clone();
    let mut roots_only = still.clone();
    let rest_roots: Vec<Vec3> = pts.iter().step_by(verts).copied().collect();
    for i in 0..steps {
        let pose = turn(angle(i));
        posed.set_head_pose(pose).unwrap();
        let moved: Vec<Vec3> = rest_roots
            .iter()
            .map(|r| pose.transform_point3(*r))
            .collect();
        roots_only.set_roots(&moved).unwrap();
        step(&mut still, &params, &[]);
        step(&mut posed, &params, &[]);
        step(&mut roots_only, &params, &[]);
    }
    let pose = turn(angle(steps));
    let target: Vec<Vec3> = still
        .positions()
        .iter()
        .map(|p| pose.transform_point3(*p))
        .collect();
    let off = |s: &Strands| {
        s.positions()
            .iter()
            .zip(&target)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0f32, f32::max)
    };
    let (one_call, roots) = (off(&posed), off(&roots_only));
    eprintln!("after 3 s: one call {one_call} m, roots only {roots} m");
    assert!(one_call <= 1e-3, "{one_call}");
    assert!(roots > 1e-2, "{roots}");
    // A non-rigid or non-finite pose is refused and changes nothing.
    let before = posed.positions();
    assert!(posed
        .set_head_pose(Affine3A::from_scale(Vec3::splat(2.0)))
        .is_err());
    assert!(posed
        .set_head_pose(Affine3A::from_translation(Vec3::NAN))
        .is_err());
    assert_eq!(posed.positions(), before);
}
