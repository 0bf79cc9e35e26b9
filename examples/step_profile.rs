//! A harness for profiling one simulation setting on the TressFX mohawk:
//! `cargo run --release --example step_profile -- ITERATIONS PEARLS SPHERES STEPS`
//! (defaults 4 1 16 50) prints the time per step and vertex-step. The
//! instruction counts per vertex-step quoted in kernels/README.md come from running
//! it under `valgrind --tool=callgrind` with 10 and 30 steps and dividing the
//! difference by 20 x 71,232 vertices. The rig is two 8 cm spheres tangent
//! under the scalp (`scene::scalp_spheres`) plus distractors a body length away.

use coif::geometry::scene::{rig_with_distractors, scalp_spheres};
use coif::groom::tfx;
use coif::kernels::{self, SimParams, Strands};
use std::time::Instant;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let iterations: u32 = args.get(1).map(|a| a.parse().unwrap()).unwrap_or(4);
    let pearls: u32 = args.get(2).map(|a| a.parse().unwrap()).unwrap_or(1);
    let nsph: usize = args.get(3).map(|a| a.parse().unwrap()).unwrap_or(16);
    let n: usize = args.get(4).map(|a| a.parse().unwrap()).unwrap_or(50);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/data/grooms/ratboy_mohawk.tfx"
    );
    let Ok(bytes) = std::fs::read(path) else {
        eprintln!(
            "step_profile: {path} is absent (the shared grooms are not beside the repository)"
        );
        std::process::exit(1);
    };
    let (pts, v) = tfx::parse(&bytes).unwrap().uniform_points(0.01).unwrap();
    let near = scalp_spheres(&pts, v, 2, 0.08);
    let params = SimParams {
        iterations,
        pearls_per_segment: pearls,
        ..Default::default()
    };
    let rig = rig_with_distractors(
        &near[..nsph.min(2)],
        near[0].center,
        0.1,
        nsph.saturating_sub(2),
    );
    let mut s = Strands::from_polylines(&pts, v).unwrap();
    for _ in 0..5 {
        kernels::step(&mut s, &params, &rig);
    }
    let t = Instant::now();
    for _ in 0..n {
        kernels::step(&mut s, &params, &rig);
    }
    let dt = t.elapsed().as_secs_f64() / n as f64;
    println!("it{iterations} p{pearls} s{nsph}: {:.3} ms/step {:.2} ns/vertex-step pen {:.4} touching {}", dt * 1e3, dt * 1e9 / pts.len() as f64, kernels::measure(&s, &rig).max_penetration, s.positions().iter().filter(|p| rig.iter().any(|q| (**p - q.center).length() < q.radius + 0.0025)).count());
}
