//! Sintel's bust and hair for the `sintel` example and `tests/render.rs`
//! (included by path by both).
#![allow(dead_code)]

use bevy::prelude::*;
use coif_bevy::{BodyMeshAsset, GroomAsset, Hair, HairLook, HairPrimitive, MeshCollider};

/// The repository's `assets/` folder (Sintel's groom and bust).
pub fn asset_dir() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/../assets").into()
}

/// The head bone: turned by [`turn_head`].
#[derive(Component)]
pub struct Head;

/// An entity that draws a body mesh asset once it has loaded.
#[derive(Component)]
pub struct DrawBody(pub Handle<BodyMeshAsset>);

/// The wind, toggled by the example's W key.
#[derive(Resource, Clone, Copy)]
pub struct Wind {
    pub on: bool,
}

/// Where the camera looks: the middle of the head.
pub const TARGET: Vec3 = Vec3::new(0.0, 0.33, 0.0);

/// The head bone with the hair, the bust's collider and (with `bust`) the
/// drawn bust under it; the directional light along the hair's light.
pub fn spawn_sintel(commands: &mut Commands, assets: &AssetServer, bust: bool) -> Entity {
    let head = commands
        .spawn((Head, Transform::default(), Visibility::default()))
        .id();
    let groom: Handle<GroomAsset> = assets.load("sintel/sintel_lite.tfx");
    let body: Handle<BodyMeshAsset> = assets.load("sintel/sintel_bust.obj");
    let mut hair = Hair::new(groom);
    hair.render.primitive = HairPrimitive::Ribbons;
    // Ribbons a few pixels wide at this distance rather than a fraction
    // of one: 80 um hairs would mostly fall between the samples.
    hair.render.width_scale = 4.0;
    commands.spawn((
        hair,
        Transform::default(),
        Visibility::default(),
        ChildOf(head),
    ));
    let mut collider = commands.spawn((
        MeshCollider {
            mesh: body.clone(),
            cell: 0.004,
        },
        Transform::default(),
        Visibility::default(),
        ChildOf(head),
    ));
    if bust {
        collider.insert(DrawBody(body));
    }
    let look = HairLook::default();
    commands.spawn((
        DirectionalLight {
            illuminance: 4000.0,
            // The GPU path's hair casts into the map and receives it.
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::default().looking_to(-look.to_light, Vec3::Y),
        // One cascade over the bust's few metres: every shadow pass runs
        // the hair's vertex shader again (on lavapipe, on one core).
        bevy::light::CascadeShadowConfigBuilder {
            num_cascades: 1,
            minimum_distance: 0.1,
            maximum_distance: 3.0,
            ..default()
        }
        .build(),
    ));
    head
}

/// Gives each [`DrawBody`] entity its mesh and a skin-coloured
/// `StandardMaterial` once the body asset has loaded.
pub fn draw_bodies(
    mut commands: Commands,
    bodies: Query<(Entity, &DrawBody), Without<Mesh3d>>,
    assets: Res<Assets<BodyMeshAsset>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    for (entity, body) in &bodies {
        let Some(asset) = assets.get(&body.0) else {
            continue;
        };
        commands.entity(entity).insert((
            Mesh3d(meshes.add(asset.to_mesh())),
            MeshMaterial3d(materials.add(StandardMaterial {
                base_color: Color::srgb(0.80, 0.62, 0.52),
                perceptual_roughness: 0.7,
                ..default()
            })),
        ));
    }
}

/// The head turns 60 degrees and back every 4 s about the top of the neck.
pub fn turn_head(time: Res<Time>, mut heads: Query<&mut Transform, With<Head>>) {
    let t = time.elapsed_secs();
    let yaw = 60f32.to_radians() * (std::f32::consts::PI * t / 2.0).sin().max(0.0);
    let pivot = Vec3::new(0.0, 0.25, 0.0);
    for mut head in &mut heads {
        *head = Transform::from_translation(pivot)
            * Transform::from_rotation(Quat::from_rotation_y(yaw))
            * Transform::from_translation(-pivot);
    }
}

/// 4 m/s of gusty wind from the left while [`Wind`] is on.
pub fn blow(wind: Res<Wind>, mut hairs: Query<&mut Hair>) {
    for mut hair in &mut hairs {
        let (w, turbulence) = if wind.on {
            (coif::glam::Vec3::new(4.0, 0.0, 0.0), 1.0)
        } else {
            (coif::glam::Vec3::ZERO, 0.0)
        };
        if hair.params.wind != w {
            hair.params.wind = w;
            hair.params.turbulence = turbulence;
            hair.params.drag = 2.0;
        }
    }
}

/// Writes tightly packed sRGB RGBA8 pixels as a PNG.
pub fn write_png(path: &str, width: u32, height: u32, rgba: &[u8]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(rgba).map_err(|e| e.to_string())
}
