//! Sintel's bust and hair in a window: the hair drawn with coif-bevy's
//! `HairMaterial` (Marschner from coif's tables), the bust with a
//! `StandardMaterial`, the head turning, an orbit camera (drag with the
//! left mouse button, scroll to zoom), the wind on W, and the last frame's
//! simulation and mesh-build times in the window title.
//!
//! ```sh
//! cargo run --release -p coif-bevy --example sintel
//! cargo run --release -p coif-bevy --example sintel -- --frames 120 --screenshot out.png
//! cargo run --release -p coif-bevy --example sintel -- --headless --frames 90 --screenshot docs/bevy_sintel.png
//! ```
//!
//! `--frames N --screenshot PATH` renders N frames once the hair exists,
//! saves the window (or with `--headless`, an image render target: no
//! window, no display) as a PNG and exits. `--size WxH` (default 960x720),
//! `--wind` starts with the wind on. `--draw-path gpu|cpu-mesh` (default
//! gpu) picks how the hair is drawn (`HairDrawPath`); `--timings PATH.csv`
//! writes one row per frame once the hair exists:
//! `frame,step_ms,plugin_ms,upload_bytes,hairs,path` (`plugin_ms`: the
//! plugin's CPU time that frame outside the step; `upload_bytes`: what it
//! handed to the GPU). The frame rate and per-frame times are printed to
//! standard output (every 60 frames, and a summary at the end).
#[path = "common/scene.rs"]
mod scene;

use bevy::camera::RenderTarget;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::time::TimeUpdateStrategy;
use bevy::window::{ExitCondition, PrimaryWindow, WindowResolution};
use bevy::winit::WinitPlugin;
use coif_bevy::headless::{self, Capture};
use coif_bevy::{ActiveDrawPath, HairDrawPath, HairPlugin, HairState};
use scene::{Wind, TARGET};
use std::io::Write;
use std::time::Duration;

struct Args {
    frames: Option<usize>,
    screenshot: Option<String>,
    headless: bool,
    size: (u32, u32),
    wind: bool,
    draw_path: HairDrawPath,
    timings: Option<String>,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        frames: None,
        screenshot: None,
        headless: false,
        size: (960, 720),
        wind: false,
        draw_path: HairDrawPath::Gpu,
        timings: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value"));
        match a.as_str() {
            "--frames" => {
                let v = value("--frames")?;
                args.frames = Some(v.parse().map_err(|_| format!("--frames {v}"))?);
            }
            "--screenshot" => args.screenshot = Some(value("--screenshot")?),
            "--headless" => args.headless = true,
            "--timings" => args.timings = Some(value("--timings")?),
            "--draw-path" => {
                args.draw_path = match value("--draw-path")?.as_str() {
                    "gpu" => HairDrawPath::Gpu,
                    "cpu-mesh" => HairDrawPath::CpuMesh,
                    other => return Err(format!("--draw-path {other}: gpu or cpu-mesh")),
                }
            }
            "--wind" => args.wind = true,
            "--size" => {
                let v = value("--size")?;
                let (w, h) = v.split_once('x').ok_or(format!("--size {v}: WxH"))?;
                let parse = |s: &str| s.parse::<u32>().ok().filter(|n| (16..=8192).contains(n));
                args.size = parse(w)
                    .zip(parse(h))
                    .ok_or(format!("--size {v}: 16 to 8192 pixels a side"))?;
            }
            "--help" | "-h" => {
                println!(
                    "sintel [--frames N] [--screenshot PATH.png] [--headless] [--size WxH] [--wind] [--draw-path gpu|cpu-mesh] [--timings PATH.csv]"
                );
                std::process::exit(0);
            }
            other => return Err(format!("unknown argument {other} (--help)")),
        }
    }
    if args.headless && (args.frames.is_none() || args.screenshot.is_none()) {
        return Err("--headless needs --frames N and --screenshot PATH".into());
    }
    Ok(args)
}

/// The orbit camera's state.
#[derive(Resource)]
struct Orbit {
    yaw: f32,
    pitch: f32,
    distance: f32,
}

/// Frames counted once the hair exists, and what to do at the last one.
#[derive(Resource)]
struct Unattended {
    frames: usize,
    counted: usize,
    screenshot: String,
    requested: bool,
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("sintel: {e}");
            std::process::exit(2);
        }
    };
    let mut app = App::new();
    let assets = AssetPlugin {
        file_path: scene::asset_dir(),
        ..default()
    };
    if args.headless {
        app.add_plugins(
            DefaultPlugins
                .set(assets)
                .set(WindowPlugin {
                    primary_window: None,
                    exit_condition: ExitCondition::DontExit,
                    close_when_requested: false,
                    ..default()
                })
                .disable::<WinitPlugin>(),
        )
        // Simulated time: 1/60 s a frame however slow the software GPU.
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
            1.0 / 60.0,
        )));
    } else {
        app.add_plugins(DefaultPlugins.set(assets).set(WindowPlugin {
            primary_window: Some(Window {
                title: "coif-bevy: Sintel".into(),
                resolution: WindowResolution::new(args.size.0, args.size.1),
                ..default()
            }),
            ..default()
        }));
    }
    let timings = match FrameLog::new(args.timings.as_deref()) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("sintel: {e}");
            std::process::exit(2);
        }
    };
    app.add_plugins(HairPlugin {
        draw_path: args.draw_path,
        ..default()
    })
    .insert_resource(timings)
    .add_systems(Last, log_frame)
    .insert_resource(ClearColor(Color::srgb(0.16, 0.17, 0.20)))
    .insert_resource(Wind { on: args.wind })
    .insert_resource(Orbit {
        yaw: -0.4,
        pitch: 0.12,
        distance: 0.75,
    })
    .add_systems(
        Update,
        (
            scene::draw_bodies,
            scene::turn_head,
            scene::blow,
            toggle_wind,
            orbit,
            title,
        ),
    );
    let (w, h) = args.size;
    let image = if args.headless {
        let handle = app
            .world_mut()
            .resource_mut::<Assets<Image>>()
            .add(headless::target_image(w, h));
        Some(handle)
    } else {
        None
    };
    let target = image.clone();
    app.add_systems(
        Startup,
        move |mut commands: Commands, assets: Res<AssetServer>| {
            scene::spawn_sintel(&mut commands, &assets, true);
            let mut camera = commands.spawn((
                Camera3d::default(),
                // Colours as the hair shader writes them (no tone curve).
                Tonemapping::None,
                Transform::default(),
            ));
            if let Some(image) = &target {
                camera.insert(headless::image_target(image.clone()));
            }
        },
    );
    match (args.frames, args.screenshot) {
        (Some(frames), Some(path)) if args.headless => {
            if let Err(e) = run_headless(&mut app, image, frames, &path) {
                eprintln!("sintel: {e}");
                std::process::exit(1);
            }
        }
        (frames, screenshot) => {
            if let Some(path) = screenshot {
                app.insert_resource(Unattended {
                    frames: frames.unwrap_or(120),
                    counted: 0,
                    screenshot: path,
                    requested: false,
                })
                .add_systems(Update, unattended);
            }
            app.run();
        }
    }
}

/// No window: update until `frames` frames with the hair, capture the
/// target image, write it.
fn run_headless(
    app: &mut App,
    image: Option<Handle<Image>>,
    frames: usize,
    path: &str,
) -> Result<(), String> {
    let image = image.ok_or("no target image")?;
    let Some(adapter) = headless::gpu_adapter() else {
        return Err("no GPU adapter (install a Vulkan driver, e.g. mesa-vulkan-drivers)".into());
    };
    println!("adapter: {adapter}");
    headless::finish_plugins(app);
    let mut counted = 0;
    let device = app
        .world()
        .get_resource::<bevy::render::renderer::RenderDevice>()
        .cloned();
    for _ in 0..frames + 10_000 {
        app.update();
        // Each frame's GPU work finished before the next: the frame time
        // logged is the whole frame's, not only the CPU's.
        if let Some(d) = device.as_ref() {
            let _ = d.wgpu_device().poll(wgpu::PollType::wait_indefinitely());
        }
        let mut hairs = app.world_mut().query::<&HairState>();
        if hairs.iter(app.world()).next().is_some() {
            counted += 1;
        } else {
            std::thread::sleep(Duration::from_millis(5)); // assets loading
        }
        if counted >= frames {
            break;
        }
    }
    if counted < frames {
        return Err("the groom never loaded".into());
    }
    if let Some(log) = app.world().get_resource::<FrameLog>() {
        log.summary();
    }
    let world = app.world_mut();
    Capture::request(&mut world.commands(), image);
    world.flush();
    for _ in 0..100 {
        app.update();
        let capture = app.world().get_resource::<Capture>();
        if let Some(img) = capture.and_then(|c| c.image.as_ref()) {
            let (w, h, rgba) = headless::rgba8(img).ok_or("unexpected screenshot format")?;
            scene::write_png(path, w, h, &rgba)?;
            println!("{path}: {w} x {h}, {frames} frames");
            return Ok(());
        }
    }
    Err("the screenshot never arrived".into())
}

fn toggle_wind(keys: Res<ButtonInput<KeyCode>>, mut wind: ResMut<Wind>) {
    if keys.just_pressed(KeyCode::KeyW) {
        wind.on = !wind.on;
    }
}

/// Drag with the left button to turn about the head, scroll to zoom.
fn orbit(
    buttons: Option<Res<ButtonInput<MouseButton>>>,
    motion: Option<Res<AccumulatedMouseMotion>>,
    scroll: Option<Res<AccumulatedMouseScroll>>,
    mut state: ResMut<Orbit>,
    mut cameras: Query<&mut Transform, With<Camera3d>>,
) {
    let dragging = buttons.is_some_and(|b| b.pressed(MouseButton::Left));
    if let Some(m) = motion.filter(|_| dragging) {
        state.yaw -= m.delta.x * 0.006;
        state.pitch = (state.pitch + m.delta.y * 0.006).clamp(-1.4, 1.4);
    }
    if let Some(s) = scroll {
        state.distance = (state.distance * (1.0 - 0.1 * s.delta.y)).clamp(0.2, 3.0);
    }
    let eye = TARGET
        + state.distance
            * Vec3::new(
                state.yaw.sin() * state.pitch.cos(),
                state.pitch.sin(),
                state.yaw.cos() * state.pitch.cos(),
            );
    for mut t in &mut cameras {
        *t = Transform::from_translation(eye).looking_at(TARGET, Vec3::Y);
    }
}

/// The last frame's times in the window title.
fn title(
    hairs: Query<&HairState>,
    wind: Res<Wind>,
    mut windows: Query<&mut Window, With<PrimaryWindow>>,
) {
    let (Some(state), Ok(mut window)) = (hairs.iter().next(), windows.single_mut()) else {
        return;
    };
    let s = state.stats();
    let text = format!(
        "coif-bevy: Sintel | step {:.2} ms | mesh {:.1} ms | {} hairs | wind {} (W) | drag to orbit",
        s.step_ms,
        s.mesh_ms,
        s.render_hairs,
        if wind.on { "on" } else { "off" }
    );
    if window.title != text {
        window.title = text;
    }
}

/// `--frames N --screenshot PATH` with a window: capture it at the Nth
/// frame with the hair, write the PNG, exit.
fn unattended(
    mut commands: Commands,
    mut job: ResMut<Unattended>,
    hairs: Query<(), With<HairState>>,
) {
    if hairs.is_empty() || job.requested {
        return;
    }
    job.counted += 1;
    if job.counted < job.frames {
        return;
    }
    job.requested = true;
    let path = job.screenshot.clone();
    commands
        .spawn(Screenshot(RenderTarget::Window(default())))
        .observe(
            move |captured: On<ScreenshotCaptured>,
                  log: Res<FrameLog>,
                  mut exit: MessageWriter<AppExit>| {
                log.summary();
                let written = headless::rgba8(&captured.image)
                    .ok_or_else(|| "unexpected screenshot format".to_string())
                    .and_then(|(w, h, rgba)| scene::write_png(&path, w, h, &rgba));
                match written {
                    Ok(()) => {
                        println!("{path} written");
                        exit.write(AppExit::Success);
                    }
                    Err(e) => {
                        eprintln!("sintel: {e}");
                        exit.write(AppExit::error());
                    }
                }
            },
        );
}

/// Per-frame times once the hair exists: the CSV of `--timings`, and the
/// frame rate on standard output.
#[derive(Resource)]
struct FrameLog {
    csv: Option<std::io::BufWriter<std::fs::File>>,
    frames: usize,
    /// When the last frame was logged (wall clock: `Time<Real>` follows
    /// the manual time strategy of the headless run).
    last: Option<std::time::Instant>,
    /// (frame ms, step ms, plugin ms, upload bytes) of every frame logged.
    rows: Vec<(f64, f32, f32, usize)>,
}

impl FrameLog {
    fn new(path: Option<&str>) -> Result<FrameLog, String> {
        let csv = match path {
            Some(p) => {
                let file = std::fs::File::create(p).map_err(|e| format!("{p}: {e}"))?;
                let mut w = std::io::BufWriter::new(file);
                writeln!(w, "frame,step_ms,plugin_ms,upload_bytes,hairs,path")
                    .map_err(|e| format!("{p}: {e}"))?;
                Some(w)
            }
            None => None,
        };
        Ok(FrameLog {
            csv,
            frames: 0,
            last: None,
            rows: Vec::new(),
        })
    }

    /// Frames, mean frame time (wall clock, between the ends of two
    /// frames; headless, each frame's GPU work is waited for) and rate,
    /// median step and plugin times, mean upload, over the frames logged
    /// so far (the first 10 dropped as warm-up when there are more than
    /// 20).
    fn summary(&self) {
        let skip = if self.rows.len() > 20 { 10 } else { 0 };
        let rows = &self.rows[skip..];
        if rows.is_empty() {
            return;
        }
        let median = |mut v: Vec<f32>| {
            v.sort_by(f32::total_cmp);
            v[v.len() / 2]
        };
        let frame_ms = rows.iter().map(|r| r.0).sum::<f64>() / rows.len() as f64;
        println!(
            "frames {}: {:.1} ms a frame ({:.1} fps), step {:.2} ms, plugin {:.3} ms (medians), {:.0} bytes uploaded a frame",
            rows.len(),
            frame_ms,
            1e3 / frame_ms.max(1e-9),
            median(rows.iter().map(|r| r.1).collect()),
            median(rows.iter().map(|r| r.2).collect()),
            rows.iter().map(|r| r.3 as f64).sum::<f64>() / rows.len() as f64,
        );
    }
}

/// Logs the frame that just ended (`Last`): a CSV row, and every 60
/// frames the rate so far on standard output.
fn log_frame(
    hairs: Query<&HairState>,
    path: Option<Res<ActiveDrawPath>>,
    mut log: ResMut<FrameLog>,
) {
    let Some(state) = hairs.iter().next() else {
        return;
    };
    let s = state.stats();
    let now = std::time::Instant::now();
    let frame_ms = log.last.map_or(0.0, |t| (now - t).as_secs_f64() * 1e3);
    log.last = Some(now);
    let path = match path.map(|p| p.0) {
        Some(HairDrawPath::Gpu) => "gpu",
        _ => "cpu-mesh",
    };
    let frame = log.frames;
    log.frames += 1;
    log.rows
        .push((frame_ms, s.step_ms, s.plugin_ms, s.upload_bytes));
    if let Some(csv) = log.csv.as_mut() {
        let _ = writeln!(
            csv,
            "{frame},{:.4},{:.4},{},{},{path}",
            s.step_ms, s.plugin_ms, s.upload_bytes, s.render_hairs
        );
        let _ = csv.flush();
    }
    if log.frames.is_multiple_of(60) {
        println!(
            "frame {}: {:.1} ms ({:.1} fps), step {:.2} ms, plugin {:.3} ms, {} bytes uploaded, {} hairs ({path})",
            log.frames,
            frame_ms,
            1e3 / frame_ms.max(1e-9),
            s.step_ms,
            s.plugin_ms,
            s.upload_bytes,
            s.render_hairs
        );
    }
}
