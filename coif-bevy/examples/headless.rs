//! Sintel's groom and bust in a headless Bevy app (no window, no
//! renderer): the plugin loads both through the asset server, the head
//! turns, a wind blows from the second second, and the example prints the
//! per-frame simulation and mesh times from `HairState::stats`.
//!
//! `cargo run --release -p coif-bevy --example headless [FRAMES]`
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use coif_bevy::{
    BodyMeshAsset, GroomAsset, Hair, HairPlugin, HairPrimitive, HairState, MeshCollider,
};
use std::time::Duration;

#[derive(Component)]
struct Head;

fn main() {
    let frames: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(240);
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin {
            file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/../assets").into(),
            ..default()
        },
        bevy::transform::TransformPlugin,
        HairPlugin::default(),
    ))
    // Simulated time: 1/60 s per frame, one fixed step each.
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        1.0 / 60.0,
    )))
    .add_systems(Startup, setup)
    .add_systems(Update, (turn_head, wind));
    let start = std::time::Instant::now();
    let (mut step_ms, mut mesh_ms, mut lod_ms, mut counted) = (0.0, 0.0, 0.0, 0);
    let mut last = None;
    for _ in 0..frames {
        app.update();
        let mut q = app.world_mut().query::<&HairState>();
        if let Some(state) = q.iter(app.world()).next() {
            let s = state.stats();
            step_ms += s.step_ms;
            mesh_ms += s.mesh_ms;
            lod_ms += s.lod_ms;
            counted += 1;
            last = Some(s);
        } else {
            // Assets still loading: real time passes for the loaders.
            std::thread::sleep(Duration::from_millis(2));
        }
    }
    let s = last.expect("the groom never loaded");
    println!(
        "{frames} frames in {:.2} s; per frame (mean of {counted}): step {:.2} ms, mesh {:.2} ms (coif's LOD {:.2} ms of it); \
         {} steps, {} awake strands, {} render hairs, {} mesh vertices",
        start.elapsed().as_secs_f64(),
        step_ms / counted as f32,
        mesh_ms / counted as f32,
        lod_ms / counted as f32,
        s.steps,
        s.awake_strands,
        s.render_hairs,
        s.mesh_vertices
    );
}

fn setup(mut commands: Commands, assets: Res<AssetServer>) {
    let head = commands.spawn((Head, Transform::default())).id();
    let groom: Handle<GroomAsset> = assets.load("sintel/sintel_lite.tfx");
    let bust: Handle<BodyMeshAsset> = assets.load("sintel/sintel_bust.obj");
    let mut hair = Hair::new(groom);
    hair.render.primitive = HairPrimitive::Ribbons;
    commands.spawn((hair, Transform::default(), ChildOf(head)));
    commands.spawn((
        MeshCollider {
            mesh: bust,
            cell: 0.004,
        },
        Transform::default(),
        ChildOf(head),
    ));
    // A camera 70 cm in front of the face (LOD and ribbons face it).
    commands.spawn((
        Camera3d::default(),
        Transform::from_xyz(-0.3, 0.4, 0.7).looking_at(Vec3::new(0.0, 0.35, 0.0), Vec3::Y),
    ));
}

/// The head turns 60 degrees and back every 4 s about the top of the neck.
fn turn_head(time: Res<Time>, mut heads: Query<&mut Transform, With<Head>>) {
    let t = time.elapsed_secs();
    let yaw = 60f32.to_radians() * (std::f32::consts::PI * t / 2.0).sin().max(0.0);
    let pivot = Vec3::new(0.0, 0.25, 0.0);
    for mut head in &mut heads {
        *head = Transform::from_translation(pivot)
            * Transform::from_rotation(Quat::from_rotation_y(yaw))
            * Transform::from_translation(-pivot);
    }
}

/// From the second second, 4 m/s of wind from the left with gusts.
fn wind(time: Res<Time>, mut hairs: Query<&mut Hair>) {
    let on = time.elapsed_secs() > 2.0;
    for mut hair in &mut hairs {
        hair.params.wind = if on {
            coif::glam::Vec3::new(4.0, 0.0, 0.0)
        } else {
            coif::glam::Vec3::ZERO
        };
        hair.params.drag = 2.0;
        hair.params.turbulence = if on { 1.0 } else { 0.0 };
    }
}
