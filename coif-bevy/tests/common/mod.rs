//! A headless app (no window, no renderer) with the plugin, and Sintel's
//! shipped files.
#![allow(dead_code)]

use bevy::app::{TaskPoolOptions, TaskPoolPlugin};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use coif_bevy::*;
use std::time::Duration;

pub const ASSETS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/sintel/");

/// MinimalPlugins, assets, transforms and the plugin; time advances
/// 1/60 s per update (one fixed step each).
pub fn app(executor: HairExecutor) -> App {
    let mut app = App::new();
    // Three compute threads whatever the machine, so that the step really
    // runs on several (the pool is per process: every test asks the same).
    let compute = bevy::app::TaskPoolThreadAssignmentPolicy {
        min_threads: 3,
        max_threads: 3,
        percent: 1.0,
        on_thread_spawn: None,
        on_thread_destroy: None,
    };
    let tasks = TaskPoolPlugin {
        task_pool_options: TaskPoolOptions {
            compute,
            ..default()
        },
    };
    app.add_plugins((
        MinimalPlugins.set(tasks),
        AssetPlugin {
            file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/../assets").into(),
            ..default()
        },
        bevy::transform::TransformPlugin,
        HairPlugin {
            executor,
            ..default()
        },
    ));
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        1.0 / 60.0,
    )));
    app
}

pub fn sintel_groom() -> GroomAsset {
    let bytes = std::fs::read(format!("{ASSETS}sintel_lite.tfx")).unwrap();
    GroomAsset(coif::groom::load(&bytes).unwrap())
}

pub fn sintel_bust() -> BodyMeshAsset {
    let text = std::fs::read(format!("{ASSETS}sintel_bust.obj")).unwrap();
    BodyMeshAsset(coif::geometry::mesh::TriangleMesh::from_obj(&text, 0.01).unwrap())
}

/// A head bone at the origin with `hair` under it; returns (bone, hair).
pub fn spawn_hair(app: &mut App, hair: Hair) -> (Entity, Entity) {
    let world = app.world_mut();
    let bone = world.spawn(Transform::IDENTITY).id();
    let hair = world.spawn((hair, Transform::IDENTITY, ChildOf(bone))).id();
    (bone, hair)
}

pub fn add_groom(app: &mut App, groom: GroomAsset) -> Handle<GroomAsset> {
    app.world_mut()
        .resource_mut::<Assets<GroomAsset>>()
        .add(groom)
}

pub fn positions(app: &App, hair: Entity) -> Vec<coif::glam::Vec3> {
    app.world()
        .get::<HairState>(hair)
        .expect("hair state")
        .positions()
        .to_vec()
}

/// A square of straight strands hanging from y = `top`, `n x n` roots
/// `spacing` apart, `len` long, in metres (scale 1 in the Hair).
pub fn hanging_groom(n: usize, spacing: f32, top: f32, len: f32, verts: usize) -> GroomAsset {
    let mut points = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let x = (i as f32 - (n - 1) as f32 / 2.0) * spacing;
            let z = (j as f32 - (n - 1) as f32 / 2.0) * spacing;
            for v in 0..verts {
                let y = top - len * v as f32 / (verts - 1) as f32;
                points.push(coif::glam::Vec3::new(x, y, z));
            }
        }
    }
    let counts = vec![verts; n * n];
    GroomAsset(coif::groom::Groom::from_strands(points, &counts).unwrap())
}

pub fn hanging_hair(app: &mut App) -> Hair {
    let groom = add_groom(app, hanging_groom(6, 0.02, 0.3, 0.3, 16));
    let mut hair = Hair::new(groom);
    hair.scale = 1.0;
    hair.verts_per_strand = 16;
    hair.params.local_shape_stiffness = 0.0;
    hair.params.volume_stiffness = 0.0;
    hair.params.hair_friction = 0.0;
    hair.params.sleep_speed = 0.0;
    hair
}

pub fn run(app: &mut App, updates: usize) {
    for _ in 0..updates {
        app.update();
    }
}
