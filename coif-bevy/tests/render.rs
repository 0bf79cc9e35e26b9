//! Sintel's hair drawn by Bevy's renderer, no window, by both draw paths
//! (the CPU mesh with `HairMaterial`, the GPU path with `GpuHairMaterial`):
//! the camera renders into an image, read back to the CPU. The two paths
//! draw the same hair in the same place, and the GPU path's hair casts
//! into Bevy's shadow maps. Skipped (with a
//! message) when wgpu finds no adapter; with Mesa's lavapipe
//! (`mesa-vulkan-drivers`) it runs on the CPU.
#![cfg(feature = "render")]

#[path = "../examples/common/scene.rs"]
mod scene;

use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::light::NotShadowCaster;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use coif_bevy::gpu::{GpuHairChunk, GpuHairMaterial};
use coif_bevy::headless::{self, Capture};
use coif_bevy::{HairDrawPath, HairMaterial, HairMeshOf, HairPlugin, HairState};
use std::io::Write;
use std::time::Duration;

const SIZE: u32 = 256;
const BACKGROUND: [u8; 3] = [0, 0, 0];

/// The picture and where the hair's bounding box projects (pixels).
struct Frame {
    rgba: Vec<u8>,
    hair_box: [f32; 4],
}

fn is_background(px: &[u8]) -> bool {
    px[..3]
        .iter()
        .zip(BACKGROUND)
        .all(|(a, b)| a.abs_diff(b) <= 2)
}

/// A capture after a few frames, with the hair's projected box.
fn capture(app: &mut App, image: &Handle<Image>) -> Frame {
    for _ in 0..3 {
        app.update();
    }
    let world = app.world_mut();
    Capture::request(&mut world.commands(), image.clone());
    world.flush();
    for _ in 0..50 {
        app.update();
        if let Some(img) = app.world().resource::<Capture>().image.as_ref() {
            let (w, h, rgba) = headless::rgba8(img).expect("an RGBA8 screenshot");
            assert_eq!((w, h), (SIZE, SIZE));
            return Frame {
                rgba,
                hair_box: hair_box(app),
            };
        }
    }
    panic!("the screenshot never arrived");
}

/// The hair's world positions projected by the camera: their pixel box.
fn hair_box(app: &mut App) -> [f32; 4] {
    let world = app.world_mut();
    let mut cams = world.query::<(&Camera, &GlobalTransform)>();
    let (camera, eye) = cams.single(world).expect("one camera");
    let (camera, eye) = (camera.clone(), *eye);
    let mut hairs = world.query::<&HairState>();
    let state = hairs.single(world).expect("one hair");
    let mut b = [f32::MAX, f32::MAX, f32::MIN, f32::MIN];
    for p in state.positions() {
        if let Ok(v) = camera.world_to_viewport(&eye, Vec3::from_array(p.to_array())) {
            b = [b[0].min(v.x), b[1].min(v.y), b[2].max(v.x), b[3].max(v.y)];
        }
    }
    b
}

/// Whether the hair of the current draw path has appeared.
fn hair_ready(app: &mut App, path: HairDrawPath) -> bool {
    match path {
        HairDrawPath::CpuMesh => {
            let mut q = app
                .world_mut()
                .query_filtered::<(), (With<HairMeshOf>, With<MeshMaterial3d<HairMaterial>>)>();
            q.iter(app.world()).next().is_some()
        }
        HairDrawPath::Gpu => {
            let mut q = app
                .world_mut()
                .query_filtered::<(), (With<GpuHairChunk>, With<MeshMaterial3d<GpuHairMaterial>>)>(
                );
            q.iter(app.world()).next().is_some()
        }
    }
}

/// Sintel rendered headless by `path` (with her bust drawn or not, the
/// hair casting shadows or not), once the hair shows; None without an
/// adapter.
fn render(path: HairDrawPath, bust: bool, hair_casts: bool) -> Option<Frame> {
    let Some(adapter) = headless::gpu_adapter() else {
        // Straight to stderr, past the test harness's capture, so that
        // the skip shows in CI's log.
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED: no GPU adapter (a Vulkan driver such as Mesa's \
             lavapipe, package mesa-vulkan-drivers, runs it on the CPU)"
        );
        return None;
    };
    println!("adapter: {adapter}");
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(AssetPlugin {
                file_path: scene::asset_dir(),
                ..default()
            })
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                close_when_requested: false,
                ..default()
            })
            .disable::<WinitPlugin>(),
    )
    .add_plugins(HairPlugin {
        draw_path: path,
        ..default()
    })
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        1.0 / 60.0,
    )))
    .insert_resource(ClearColor(Color::srgb_u8(
        BACKGROUND[0],
        BACKGROUND[1],
        BACKGROUND[2],
    )));
    if bust {
        app.add_systems(Update, scene::draw_bodies);
    }
    if !hair_casts {
        app.add_systems(Update, no_hair_shadows);
    }
    let image = app
        .world_mut()
        .resource_mut::<Assets<Image>>()
        .add(headless::target_image(SIZE, SIZE));
    let target = image.clone();
    app.add_systems(
        Startup,
        move |mut commands: Commands, assets: Res<AssetServer>| {
            scene::spawn_sintel(&mut commands, &assets, bust);
            commands.spawn((
                Camera3d::default(),
                Tonemapping::None,
                headless::image_target(target.clone()),
                Transform::from_xyz(-0.25, 0.38, 0.6).looking_at(scene::TARGET, Vec3::Y),
            ));
        },
    );
    headless::finish_plugins(&mut app);
    // Assets load on the IO pool; a bound, not a time limit.
    let mut loaded = false;
    for _ in 0..4000 {
        app.update();
        if hair_ready(&mut app, path) {
            loaded = true;
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(loaded, "the hair ({path:?}) never got its material");
    // The pipeline compiles in the background: capture until the hair
    // shows (at most 20 captures).
    let mut frame = capture(&mut app, &image);
    for _ in 0..20 {
        if frame.rgba.chunks_exact(4).any(|px| !is_background(px)) {
            break;
        }
        frame = capture(&mut app, &image);
    }
    // Two more captures: the shadow maps and LOD of a settled frame.
    frame = capture(&mut app, &image);
    Some(frame)
}

/// The hair's chunks cast no shadow (a comparison run).
fn no_hair_shadows(
    mut commands: Commands,
    chunks: Query<Entity, (With<GpuHairChunk>, Without<NotShadowCaster>)>,
) {
    for e in &chunks {
        commands.entity(e).insert(NotShadowCaster);
    }
}

/// Sintel's hair alone (every lit pixel is hair): it covers much of its
/// projected box, nothing is drawn away from it, and it is brown.
fn check_hair_alone(frame: &Frame, label: &str) -> Vec<bool> {
    let [x0, y0, x1, y1] = frame.hair_box;
    assert!(
        x0 >= 0.0 && y0 >= 0.0 && x1 <= SIZE as f32 && y1 <= SIZE as f32 && x1 - x0 > 20.0,
        "{label}: the hair should project inside the picture: {:?}",
        frame.hair_box
    );
    let (mut inside, mut drawn_inside, mut drawn_outside) = (0usize, 0usize, 0usize);
    let mut colour = [0u64; 3];
    let mut mask = Vec::new();
    for (i, px) in frame.rgba.chunks_exact(4).enumerate() {
        let (x, y) = (
            (i as u32 % SIZE) as f32 + 0.5,
            (i as u32 / SIZE) as f32 + 0.5,
        );
        // The box of the guides' points, grown by 3 px for ribbon width
        // and the render hairs between guides.
        let in_box = x >= x0 - 3.0 && x <= x1 + 3.0 && y >= y0 - 3.0 && y <= y1 + 3.0;
        let drawn = !is_background(px);
        mask.push(drawn);
        inside += in_box as usize;
        if drawn {
            if in_box {
                drawn_inside += 1;
                for c in 0..3 {
                    colour[c] += px[c] as u64;
                }
            } else {
                drawn_outside += 1;
            }
        }
    }
    let covered = drawn_inside as f64 / inside.max(1) as f64;
    println!(
        "{label}: hair box {:?}: {:.1} % of it drawn, {drawn_outside} pixels drawn outside, mean colour {:?}",
        frame.hair_box,
        100.0 * covered,
        colour.map(|c| c / drawn_inside.max(1) as u64)
    );
    assert!(
        covered > 0.25,
        "{label}: hair covers {:.1} % of its box",
        100.0 * covered
    );
    assert!(
        drawn_outside * 100 < drawn_inside,
        "{label}: {drawn_outside} pixels drawn outside the hair's box, {drawn_inside} inside"
    );
    // Brown hair (coif's default absorption): more red than blue.
    assert!(colour[0] > colour[2], "{label}: mean colour {colour:?}");
    mask
}

fn save(frame: &Frame, var: &str) {
    if let Ok(path) = std::env::var(var) {
        scene::write_png(&path, SIZE, SIZE, &frame.rgba).expect("the PNG is written");
    }
}

#[test]
fn sintel_hair_is_drawn_by_both_paths_alike() {
    let Some(cpu) = render(HairDrawPath::CpuMesh, false, true) else {
        return;
    };
    let cpu_mask = check_hair_alone(&cpu, "CPU mesh");
    save(&cpu, "COIF_BEVY_RENDER_PNG");
    let gpu = render(HairDrawPath::Gpu, false, true).expect("an adapter, as a moment ago");
    let gpu_mask = check_hair_alone(&gpu, "GPU");
    save(&gpu, "COIF_BEVY_RENDER_GPU_PNG");
    // The same hair in the same place: the drawn pixels overlap.
    let both = cpu_mask
        .iter()
        .zip(&gpu_mask)
        .filter(|(a, b)| **a && **b)
        .count();
    let either = cpu_mask
        .iter()
        .zip(&gpu_mask)
        .filter(|(a, b)| **a || **b)
        .count();
    let iou = both as f64 / either.max(1) as f64;
    println!(
        "drawn pixels: CPU mesh {}, GPU {}, intersection over union {iou:.3}",
        cpu_mask.iter().filter(|d| **d).count(),
        gpu_mask.iter().filter(|d| **d).count()
    );
    assert!(iou > 0.5, "the two paths' hair overlaps by {iou:.3}");
}

#[test]
fn gpu_hair_casts_into_bevys_shadow_maps() {
    let Some(casting) = render(HairDrawPath::Gpu, true, true) else {
        return;
    };
    save(&casting, "COIF_BEVY_RENDER_SHADOW_PNG");
    let not_casting = render(HairDrawPath::Gpu, true, false).expect("an adapter");
    // Where the hair's shadow falls (on the bust and on the hair itself)
    // pixels are darker than when it casts none; nowhere brighter.
    let luma = |px: &[u8]| px[0] as i32 + px[1] as i32 + px[2] as i32;
    let (mut darker, mut brighter) = (0usize, 0usize);
    for (a, b) in casting
        .rgba
        .chunks_exact(4)
        .zip(not_casting.rgba.chunks_exact(4))
    {
        let d = luma(a) - luma(b);
        if d < -12 {
            darker += 1;
        } else if d > 12 {
            brighter += 1;
        }
    }
    println!("with the hair's shadow: {darker} pixels darker, {brighter} brighter");
    assert!(darker > 500, "the hair's shadow darkens {darker} pixels");
    assert!(
        brighter * 10 < darker,
        "{brighter} pixels brighter, {darker} darker"
    );
}
