//! The plugin in a headless app (no window, no renderer): hair follows a
//! moving bone and keeps its groom, colliders take effect, wind moves it,
//! and the positions are those of calling coif directly.
mod common;

use bevy::prelude::*;
use coif::base::tasks::Serial;
use coif::glam as cg;
use coif::kernels::{step_colliders_with, Colliders, Sphere, Strands};
use coif_bevy::*;
use common::*;

fn rms(a: &[cg::Vec3], b: &[cg::Vec3]) -> f32 {
    let s: f32 = a.iter().zip(b).map(|(x, y)| x.distance_squared(*y)).sum();
    (s / a.len() as f32).sqrt()
}

/// The bone turns 60 degrees about Y and moves 20 cm, then holds: the
/// roots are where the pose puts them, and the hair, seen from the bone,
/// settles to the same groom as a hair whose bone never moved.
#[test]
fn hair_follows_a_moving_bone_and_keeps_its_groom() {
    let settle = |moved: bool| {
        let mut app = app(HairExecutor::TaskPool);
        let groom = add_groom(&mut app, sintel_groom());
        let (bone, hair) = spawn_hair(&mut app, Hair::new(groom));
        run(&mut app, 2);
        let rest = positions(&app, hair);
        let mut pose = Transform::IDENTITY;
        let mut lag: f32 = 0.0;
        for f in 0..60 {
            if moved {
                let t = (f + 1) as f32 / 60.0;
                pose = Transform::from_translation(Vec3::new(0.2 * t, 0.0, 0.0))
                    .with_rotation(Quat::from_rotation_y(60f32.to_radians() * t));
                *app.world_mut().get_mut::<Transform>(bone).unwrap() = pose;
            }
            app.update();
            // How far the hair trails the rigidly carried groom: it is simulated.
            let g = affine(app.world().get::<GlobalTransform>(hair).unwrap());
            let now = positions(&app, hair);
            let carried: Vec<cg::Vec3> = rest.iter().map(|p| g.transform_point3(*p)).collect();
            lag = lag.max(rms(&now, &carried));
        }
        println!("moved {moved}: largest RMS distance from the rigidly carried groom during the turn {lag:.5} m");
        if moved {
            assert!(lag > 1e-3, "the hair did not trail the turn: {lag}");
        }
        run(&mut app, 180);
        let state = app.world().get::<HairState>(hair).unwrap();
        assert!(state.stats().steps >= 230, "{:?}", state.stats());
        let world =
            cg::Affine3A::from_cols_array(&GlobalTransform::from(pose).affine().to_cols_array());
        let local: Vec<cg::Vec3> = state
            .positions()
            .iter()
            .map(|p| world.inverse().transform_point3(*p))
            .collect();
        // Roots exactly on the posed rest roots.
        let verts = state.verts_per_strand();
        for (r, l) in rest.iter().zip(&local).step_by(verts) {
            assert!(r.distance(*l) < 1e-4, "root {r} at {l}");
        }
        (rest, local)
    };
    let (rest, still) = settle(false);
    let (_, moved) = settle(true);
    let from_groom = rms(&still, &rest);
    let from_still = rms(&moved, &still);
    println!("RMS: still hair from its start {from_groom:.6} m, moved hair from still hair {from_still:.6} m");
    assert!(
        from_still < 0.01,
        "the moved hair settled {from_still} m from the still one"
    );
}

/// A sphere, a capsule and Sintel's bust (a mesh collider) each keep the
/// hair out; without them it passes through.
#[test]
fn colliders_take_effect() {
    // Sphere and capsule: a ball in the middle of hanging hair.
    let inside = |collider: Option<bool>| {
        let mut app = app(HairExecutor::TaskPool);
        let hair = hanging_hair(&mut app);
        let (_, hair) = spawn_hair(&mut app, hair);
        let center = Vec3::new(0.0, 0.1, 0.0);
        match collider {
            Some(true) => {
                app.world_mut().spawn((
                    SphereCollider { radius: 0.05 },
                    Transform::from_translation(center),
                ));
            }
            Some(false) => {
                // A capsule lying along X through the hair (Y turned to X).
                app.world_mut().spawn((
                    CapsuleCollider {
                        half_length: 0.1,
                        radius: 0.05,
                    },
                    Transform::from_translation(center)
                        .with_rotation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2)),
                ));
            }
            None => {}
        }
        run(&mut app, 90);
        let c = cg::Vec3::new(0.0, 0.1, 0.0);
        positions(&app, hair)
            .iter()
            .filter(|p| {
                let d = if collider == Some(false) {
                    cg::Vec2::new(p.y - c.y, p.z - c.z).length() // axis along X, |x| < 0.1
                } else {
                    p.distance(c)
                };
                d < 0.045
            })
            .count()
    };
    let (free, sphere, capsule) = (inside(None), inside(Some(true)), inside(Some(false)));
    println!("vertices inside: none {free}, sphere {sphere}, capsule {capsule}");
    assert!(free > 20, "{free}");
    assert_eq!(sphere, 0);
    assert_eq!(capsule, 0);

    // The bust: a field built once from the mesh asset, following its entity.
    let bust = sintel_bust();
    let field =
        coif::kernels::Sdf::from_mesh(bust.0.positions(), bust.0.triangles(), 0.004).unwrap();
    let deep = |with_bust: bool| {
        let mut app = app(HairExecutor::TaskPool);
        let groom = add_groom(&mut app, sintel_groom());
        let mut hair = Hair::new(groom);
        hair.params.local_shape_stiffness = 0.0; // the hair falls onto the body
        let (bone, hair) = spawn_hair(&mut app, hair);
        if with_bust {
            let mesh = app
                .world_mut()
                .resource_mut::<Assets<BodyMeshAsset>>()
                .add(sintel_bust());
            app.world_mut().spawn((
                MeshCollider { mesh, cell: 0.004 },
                Transform::IDENTITY,
                ChildOf(bone),
            ));
        }
        run(&mut app, 120);
        if with_bust {
            assert_eq!(app.world().resource::<HairFields>().fields().len(), 1);
        }
        positions(&app, hair)
            .iter()
            .filter(|p| field.distance(**p) < -0.01)
            .count()
    };
    let (without, with) = (deep(false), deep(true));
    println!("vertices over 1 cm inside the bust: without the collider {without}, with {with}");
    assert!(without > 50, "{without}");
    assert!(with * 20 < without, "{with} of {without}");
}

/// A steady wind along +X with drag blows the hanging hair's tips over.
#[test]
fn wind_moves_the_hair() {
    let tips_x = |wind: f32| {
        let mut app = app(HairExecutor::TaskPool);
        let mut hair = hanging_hair(&mut app);
        hair.params.wind = cg::Vec3::new(wind, 0.0, 0.0);
        hair.params.drag = 4.0;
        let (_, hair) = spawn_hair(&mut app, hair);
        run(&mut app, 120);
        let p = positions(&app, hair);
        let tips: Vec<f32> = p.iter().skip(15).step_by(16).map(|p| p.x).collect();
        tips.iter().sum::<f32>() / tips.len() as f32
    };
    let (still, blown) = (tips_x(0.0), tips_x(3.0));
    println!("mean tip x: still air {still:.4} m, 3 m/s wind {blown:.4} m");
    assert!(still.abs() < 1e-3);
    assert!(blown > 0.1, "{blown}");
}

/// The plugin on Bevy's compute pool gives the bytes of coif's serial step
/// called directly with the same poses and colliders.
#[test]
fn same_positions_as_coif_directly() {
    let mut app = app(HairExecutor::TaskPool);
    let groom_asset = sintel_groom();
    let guides_src = groom_asset.0.clone();
    let groom = add_groom(&mut app, groom_asset);
    let hair_c = Hair::new(groom);
    let params = hair_c.params.clone();
    let (bone, hair) = spawn_hair(&mut app, hair_c);
    let ball = Vec3::new(0.05, 0.33, -0.12); // behind the head, in the hair
    app.world_mut().spawn((
        SphereCollider { radius: 0.06 },
        Transform::from_translation(ball),
    ));
    app.update(); // the state is built at this frame's pose
    let mut direct: Option<Strands> = None;
    let guides = guides_src.guides(1, 24, 0.01).unwrap();
    let mut steps_seen = 0;
    let mut solved = false;
    for f in 0..90 {
        let pose = affine(app.world().get::<GlobalTransform>(hair).unwrap());
        if direct.is_none() {
            let mut s = Strands::from_polylines(&guides, 24).unwrap();
            s.teleport(pose).unwrap();
            direct = Some(s);
        }
        // The bone turns and rises; the step sees last frame's propagated pose.
        let t = f as f32 / 60.0;
        *app.world_mut().get_mut::<Transform>(bone).unwrap() =
            Transform::from_translation(Vec3::new(0.0, 0.05 * t, 0.0))
                .with_rotation(Quat::from_rotation_y(0.8 * (3.0 * t).sin()));
        app.update();
        let steps = app.world().get::<HairState>(hair).unwrap().stats().steps;
        let d = direct.as_mut().unwrap();
        let rig = [Sphere {
            center: cg::Vec3::from_array(ball.to_array()),
            radius: 0.06,
        }];
        for _ in steps_seen..steps {
            d.set_head_pose(pose).unwrap();
            if !solved {
                // The plugin's `Hair::sag_free`: before the first step.
                d.solve_sag_free(&params, &Colliders::spheres(&rig))
                    .unwrap();
                solved = true;
            }
            step_colliders_with(d, &params, &Colliders::spheres(&rig), &Serial);
        }
        steps_seen = steps;
    }
    assert!(steps_seen >= 85, "{steps_seen}");
    let threads = bevy::tasks::ComputeTaskPool::get().thread_num();
    println!("compute pool threads: {threads}, steps compared: {steps_seen}");
    assert!(threads >= 2, "{threads}");
    let plugin = positions(&app, hair);
    let coif_direct = direct.unwrap().positions();
    assert_eq!(plugin.len(), coif_direct.len());
    let same = plugin
        .iter()
        .zip(&coif_direct)
        .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits));
    assert!(same, "RMS {}", rms(&plugin, &coif_direct));
}

fn affine(g: &GlobalTransform) -> cg::Affine3A {
    cg::Affine3A::from_cols_array(&g.affine().to_cols_array())
}

/// The groom loader reads Sintel's `.tfx` through the asset server, and
/// the hair is built from it.
#[test]
fn groom_and_mesh_load_through_the_asset_server() {
    let mut app = app(HairExecutor::TaskPool);
    let server = app.world().resource::<AssetServer>().clone();
    let groom: Handle<GroomAsset> = server.load("sintel/sintel_lite.tfx");
    let bust: Handle<BodyMeshAsset> = server.load("sintel/sintel_bust.obj");
    let (bone, hair) = spawn_hair(&mut app, Hair::new(groom.clone()));
    app.world_mut().spawn((
        MeshCollider {
            mesh: bust,
            cell: 0.004,
        },
        Transform::IDENTITY,
        ChildOf(bone),
    ));
    for _ in 0..600 {
        app.update();
        if app.world().get::<HairState>(hair).is_some()
            && !app.world().resource::<HairFields>().fields().is_empty()
        {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let state = app
        .world()
        .get::<HairState>(hair)
        .expect("the groom loaded");
    assert_eq!(
        state.strands().strand_count(),
        sintel_groom().0.strand_count()
    );
    assert_eq!(app.world().resource::<HairFields>().fields().len(), 1);
}

/// The mesh each frame: ribbons with unit tangents, every render hair near
/// the camera and fewer far away; far enough, the hair is not simulated but
/// carried rigidly by the bone, and simulated again when the camera
/// returns.
#[test]
fn meshes_and_lod_follow_the_camera() {
    let mut app = app(HairExecutor::TaskPool);
    let groom = add_groom(&mut app, sintel_groom());
    let (bone, hair) = spawn_hair(&mut app, Hair::new(groom));
    let near = Transform::from_xyz(-0.3, 0.4, 0.7).looking_at(Vec3::new(0.0, 0.35, 0.0), Vec3::Y);
    let camera = app.world_mut().spawn((Camera3d::default(), near)).id();
    run(&mut app, 5);
    let stats = |app: &App| app.world().get::<HairState>(hair).unwrap().stats();
    let mesh_of = |app: &mut App| {
        let mut q = app.world_mut().query::<(&HairMeshOf, &Mesh3d)>();
        let (of, mesh) = q.single(app.world()).unwrap();
        assert_eq!(of.0, hair);
        app.world()
            .resource::<Assets<Mesh>>()
            .get(&mesh.0)
            .unwrap()
            .clone()
    };
    let s_near = stats(&app);
    let mesh = mesh_of(&mut app);
    let Some(bevy::mesh::VertexAttributeValues::Float32x4(tangents)) =
        mesh.attribute(Mesh::ATTRIBUTE_TANGENT)
    else {
        panic!("no tangents")
    };
    assert_eq!(tangents.len(), s_near.mesh_vertices);
    assert!(tangents
        .iter()
        .all(|t| (Vec3::new(t[0], t[1], t[2]).length() - 1.0).abs() < 1e-3));
    assert_eq!(
        mesh.indices().unwrap().len(),
        6 * (s_near.mesh_vertices / 2 - s_near.render_hairs)
    );
    assert!(!s_near.following);

    // 3 m away: fewer render hairs, still simulated.
    *app.world_mut().get_mut::<Transform>(camera).unwrap() =
        Transform::from_xyz(0.0, 0.35, 3.0).looking_at(Vec3::new(0.0, 0.35, 0.0), Vec3::Y);
    run(&mut app, 3);
    let s_mid = stats(&app);
    assert!(
        s_mid.render_hairs < s_near.render_hairs,
        "{s_mid:?} {s_near:?}"
    );
    assert!(!s_mid.following);

    // 100 m away: carried rigidly, no steps, positions move with the bone.
    *app.world_mut().get_mut::<Transform>(camera).unwrap() =
        Transform::from_xyz(0.0, 0.35, 100.0).looking_at(Vec3::new(0.0, 0.35, 0.0), Vec3::Y);
    run(&mut app, 3);
    let s_far = stats(&app);
    assert!(s_far.following, "{s_far:?}");
    let before = positions(&app, hair);
    let shift = Vec3::new(0.1, 0.0, 0.0);
    *app.world_mut().get_mut::<Transform>(bone).unwrap() = Transform::from_translation(shift);
    run(&mut app, 3);
    assert_eq!(stats(&app).steps, s_far.steps);
    let after = positions(&app, hair);
    for (a, b) in before.iter().zip(&after) {
        assert!((*b - *a - cg::Vec3::new(0.1, 0.0, 0.0)).length() < 1e-5);
    }
    // Back near: simulated again from where the bone carried it.
    *app.world_mut().get_mut::<Transform>(camera).unwrap() = near;
    run(&mut app, 3);
    let s_back = stats(&app);
    assert!(
        !s_back.following && s_back.steps > s_far.steps,
        "{s_back:?}"
    );
    let resumed = positions(&app, hair);
    assert!(rms(&resumed, &after) < 0.01, "{}", rms(&resumed, &after));
    // The hair despawned: its mesh entity goes too.
    app.world_mut().entity_mut(hair).despawn();
    run(&mut app, 2);
    let mut q = app.world_mut().query::<&HairMeshOf>();
    assert_eq!(q.iter(app.world()).count(), 0);
    println!(
        "render hairs near {}, at 3 m {}, at 100 m following: {}",
        s_near.render_hairs, s_mid.render_hairs, s_far.following
    );
}
