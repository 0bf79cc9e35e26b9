//! Simulation LOD, off-screen following and the crowd: level 0 is the
//! plain simulation; coarser levels stay near it (error per level, printed);
//! switching levels and coming back on screen do not pop; the standard
//! crowd of 16 advances at most 35 % of the strand-steps of simulating
//! everyone fully; any thread count gives the same bytes; stepping
//! allocates nothing.

use coif_frame::crowd::{add_distances, settled_head, Crowd};
use coif_frame::motion::turn_and_nod;
use coif_frame::sim_lod::{SimLod, STRIDES};
use coif_frame::HairScene;
use coif_kernels::{self as kernels, SimParams, Strands};
use glam::{Affine3A, Vec3};

#[global_allocator]
static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;

/// A small built-in head (guides combed back and draped for 7 s).
fn scene() -> (HairScene, Vec<Vec3>) {
    settled_head(384, 16).unwrap()
}

fn largest_move(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.distance(*y))
        .fold(0.0, f32::max)
}

fn rms(a: &[Vec3], b: &[Vec3]) -> f32 {
    let s: f32 = a.iter().zip(b).map(|(x, y)| x.distance_squared(*y)).sum();
    (s / a.len() as f32).sqrt()
}

#[test]
fn level_0_is_the_plain_simulation_and_coarser_levels_stay_near_it() {
    let (scene, settled) = scene();
    let verts = scene.verts_per_strand;
    let params = SimParams::default();
    let lod = SimLod::new(&scene.guides, &settled, verts, &STRIDES).unwrap();
    let guides = lod.guide_count();
    // Fewer guides per level, every level covering the scalp.
    for l in 1..lod.level_count() {
        let (n, stride) = (lod.simulated_guides(l).unwrap(), lod.stride(l).unwrap());
        assert!(n < lod.simulated_guides(l - 1).unwrap(), "level {l}: {n}");
        assert!(n >= guides / stride, "level {l}: {n} of {guides}");
        assert!(n <= 2 * guides / stride, "level {l}: {n} of {guides}");
    }
    let mut plain = Strands::from_polylines(&scene.guides, verts).unwrap();
    plain.set_state(&settled, &settled).unwrap();
    let mut runs: Vec<SimLod> = (0..lod.level_count())
        .map(|l| {
            let mut r = lod.clone();
            r.set_level(l, &scene.rig, 0.002);
            r
        })
        .collect();
    let mut errors = vec![0.0f32; runs.len()];
    let rig_at = |pose: &Affine3A| {
        scene
            .rig
            .iter()
            .map(|s| kernels::Sphere {
                center: pose.transform_point3(s.center),
                radius: s.radius,
            })
            .collect::<Vec<_>>()
    };
    for i in 0..150 {
        let pose = turn_and_nod(i as f32 / 60.0, scene.pivot);
        let rig = rig_at(&pose);
        let roots: Vec<Vec3> = settled
            .iter()
            .step_by(verts)
            .map(|p| pose.transform_point3(*p))
            .collect();
        plain.set_roots(&roots).unwrap();
        plain
            .set_rest_rotation(glam::Quat::from_mat3(&glam::Mat3::from(pose.matrix3)))
            .unwrap();
        kernels::step(&mut plain, &params, &rig);
        let reference = plain.positions();
        for (l, r) in runs.iter_mut().enumerate() {
            r.step(&params, pose, &rig);
            errors[l] = errors[l].max(rms(r.positions(), &reference));
        }
    }
    println!("largest RMS distance to every guide simulated, per level: {errors:?} m");
    assert_eq!(errors[0], 0.0, "level 0 is the plain simulation");
    for (l, e) in errors.iter().enumerate().skip(1) {
        assert!(*e > 0.0 && *e < 0.02, "level {l}: RMS {e} m");
    }
}

#[test]
fn switching_levels_and_coming_back_on_screen_do_not_pop() {
    let (scene, settled) = scene();
    let verts = scene.verts_per_strand;
    let params = SimParams::default();
    let mut lod = SimLod::new(&scene.guides, &settled, verts, &STRIDES).unwrap();
    let rig = scene.rig.clone();
    let mut last = lod.positions().to_vec();
    let mut worst_normal = 0.0f32;
    let mut worst_switch = 0.0f32;
    let mut worst_resume = 0.0f32;
    for i in 0..240 {
        let pose = turn_and_nod(i as f32 / 60.0, scene.pivot);
        let rig: Vec<kernels::Sphere> = rig
            .iter()
            .map(|s| kernels::Sphere {
                center: pose.transform_point3(s.center),
                radius: s.radius,
            })
            .collect();
        // Levels 0 -> 3 at step 40, 3 -> 1 at 80, 1 -> 0 at 120; off
        // screen 150..180 (following the head rigidly).
        let switch = [(40, 3), (80, 1), (120, 0)].iter().find(|s| s.0 == i);
        if let Some(&(_, l)) = switch {
            lod.set_level(l, &rig, 0.002);
        }
        if (150..180).contains(&i) {
            lod.follow_rigidly(pose);
        } else {
            lod.step(&params, pose, &rig);
        }
        // Off screen the output is where the head carried it.
        let m = lod.carried();
        let shown: Vec<Vec3> = lod
            .positions()
            .iter()
            .map(|p| m.transform_point3(*p))
            .collect();
        let moved = largest_move(&shown, &last);
        if switch.is_some() {
            worst_switch = worst_switch.max(moved);
        } else if i == 180 {
            worst_resume = moved;
        } else if (20..150).contains(&i) {
            worst_normal = worst_normal.max(moved);
        }
        last = shown;
    }
    println!(
        "largest vertex move per step: {worst_normal} m in motion, {worst_switch} m at a switch, {worst_resume} m when back on screen"
    );
    assert!(worst_normal > 0.005, "the head did move the hair");
    assert!(worst_switch <= worst_normal, "a level switch popped");
    assert!(worst_resume <= worst_normal, "coming back on screen jumped");
}

#[test]
fn the_crowd_of_16_advances_at_most_35_percent_and_any_thread_count_agrees() {
    let (scene, settled) = scene();
    let params = SimParams::default();
    let build = |skip| Crowd::standard(&scene, &settled, 16, &params, skip);
    let (mut lean, mut full) = (build(true).unwrap(), build(false).unwrap());
    let (mut advanced, mut everyone) = (0usize, 0usize);
    let mut errors = vec![(0.0f64, 0usize); STRIDES.len() + 1];
    let serial = coif_base::tasks::Serial;
    for i in 0..180 {
        let t = i as f32 / 60.0;
        lean.step(t, &serial);
        full.step(t, &serial);
        advanced += lean.simulated_strands();
        everyone += full.simulated_strands();
        add_distances(&lean, &full, &mut errors);
    }
    assert_eq!(everyone, 180 * full.guide_count());
    let share = advanced as f64 / everyone as f64;
    let per_level: Vec<String> = errors
        .iter()
        .map(|(s, n)| format!("{:.2} mm", 1e3 * (s / (*n).max(1) as f64).sqrt()))
        .collect();
    println!("crowd of 16: {:.1} % of the strand-steps; RMS distance to full per level 0..3, off screen: {per_level:?}", 100.0 * share);
    assert!(share <= 0.35, "advanced {:.1} %", 100.0 * share);
    let steps: Vec<_> = (0..16).map(|i| lean.character_step(i).unwrap()).collect();
    assert_eq!(steps.iter().filter(|s| !s.visible).count(), 4);
    assert!(steps[..4].iter().all(|s| s.visible && s.level == 0));
    assert!(steps[8..].iter().all(|s| s.visible && s.level >= 2));
    // The near characters are the full simulation's, up to sleeping.
    let near = (errors[0].0 / errors[0].1 as f64).sqrt();
    assert!(near < 2e-3, "near characters {near} m from the full run");
    // Two threads: the same bytes.
    #[cfg(feature = "rayon")]
    {
        let pool = coif_base::tasks::Rayon::new(2).unwrap();
        let mut threaded = build(true).unwrap();
        for i in 0..180 {
            threaded.step(i as f32 / 60.0, &pool);
        }
        for c in 0..16 {
            assert_eq!(threaded.positions(c), lean.positions(c), "character {c}");
        }
    }
}

#[test]
fn stepping_switching_and_following_allocate_nothing() {
    let (scene, settled) = scene();
    let params = SimParams::default();
    let mut crowd = Crowd::standard(&scene, &settled, 6, &params, true).unwrap();
    let mut lod = SimLod::new(&scene.guides, &settled, scene.verts_per_strand, &STRIDES).unwrap();
    lod.reserve_rig(scene.rig.len());
    let serial = coif_base::tasks::Serial;
    crowd.step(0.0, &serial);
    lod.step(&params, Affine3A::IDENTITY, &scene.rig);
    let before = coif_testkit::counting::allocations();
    for i in 1..90 {
        crowd.step(i as f32 / 60.0, &serial);
        lod.set_level(i % 4, &scene.rig, 0.002);
        if i % 3 == 0 {
            lod.follow_rigidly(Affine3A::from_translation(Vec3::X * i as f32 * 1e-3));
        } else {
            lod.step(&params, Affine3A::IDENTITY, &scene.rig);
        }
    }
    assert_eq!(coif_testkit::counting::allocations() - before, 0);
}
