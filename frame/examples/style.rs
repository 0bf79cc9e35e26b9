//! The style run (`coif_frame::style`) on Sintel's groom and bust at
//! several local shape stiffnesses: rest drift, kinks, swing, return, the
//! sag-free solve's time and the step's.
//!
//! `cargo run --release -p coif-frame --example style [-- [--no-sag-free] [--no-field] [--no-gravity] [--body] [--turbulence M/S] K ...]`
//!
//! `--no-sag-free` steps the groom as built (the springs' rest is the
//! groom); `--no-field` and `--no-gravity` take the bust's field or
//! gravity away (the diagnosis in `kernels/README.md`, "Styled hair that
//! moves"). `--body` takes the default scene's simulation
//! (`FrameSettings::with_body_simulation`: the air's drag, hair-hair
//! volume and friction; calm air), and `--turbulence` adds gusts of that
//! RMS speed throughout (the scene's gust at its peak is
//! `motion::GUST_TURBULENCE`, 1.5 m/s: held at rest, it keeps blowing
//! the hair away from its groom, `motion::gust_turbulence`).

use coif_base::tasks::Serial;
use coif_frame::style::StyleScene;
use coif_kernels::SimParams;
use glam::Vec3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str| args.iter().any(|a| a == name);
    let mut scene = StyleScene::sintel()?;
    if flag("--no-field") {
        scene.field = None;
    }
    let turbulence = args
        .iter()
        .position(|a| a == "--turbulence")
        .and_then(|i| args.get(i + 1))
        .map(|a| a.parse::<f32>())
        .transpose()?;
    let ks: Vec<f32> = args
        .iter()
        .enumerate()
        .filter(|(i, _)| *i == 0 || args[i - 1] != "--turbulence")
        .filter_map(|(_, a)| a.parse().ok())
        .collect();
    let ks = if ks.is_empty() {
        vec![1.0, 0.9, 0.7, 0.6, 0.5, 0.3, 0.0]
    } else {
        ks
    };
    let sag_free = !flag("--no-sag-free");
    if let Some(field) = &scene.field {
        let skin = SimParams::default().pearl_radius;
        let near = scene
            .guides
            .chunks(scene.verts)
            .filter(|g| g[1..].iter().any(|p| field.distance(*p) < skin))
            .count();
        println!(
            "{near} of {} guides have a free vertex within the {} mm skin of the body",
            scene.guides.len() / scene.verts,
            skin * 1e3
        );
    }
    println!("| local shape | rest drift p95 | kinked at rest / in the turn | swing | 2.5 s after | sag-free solve | step |");
    println!("|---|---|---|---|---|---|---|");
    let base = if flag("--body") {
        coif_frame::FrameSettings::default()
            .with_body_simulation()
            .simulation
    } else {
        SimParams::default()
    };
    for k in ks {
        let params = SimParams {
            local_shape_stiffness: k,
            gravity: if flag("--no-gravity") {
                Vec3::ZERO
            } else {
                base.gravity
            },
            turbulence: turbulence.unwrap_or(base.turbulence),
            ..base.clone()
        };
        let r = scene.run(&params, &Serial, |s, p, c| {
            if sag_free {
                s.solve_sag_free(p, c)?;
            }
            Ok(())
        })?;
        println!(
            "| {k} | {:.1} mm | {:.2} / {:.2} % | {:.1} mm | {:.1} mm | {:.0} ms | {:.0} us |",
            r.rest_drift_p95 * 1e3,
            r.kinked_at_rest * 100.0,
            r.kinked_in_turn * 100.0,
            r.swing * 1e3,
            r.returned * 1e3,
            r.solve_seconds * 1e3,
            r.step_seconds * 1e6,
        );
    }
    Ok(())
}
