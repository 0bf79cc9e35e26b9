//! `cargo run --release`: the built-in default scene. Hair grown straight out
//! of a sphere head falls under gravity and settles; per-step timings and the
//! largest stretch and penetration are printed.

use coif::kernels::{self, measure, scalar, SimParams, Strands};
use coif::scene::{grow_on_sphere, GrowOptions};
use std::time::Instant;

fn main() {
    let opts = GrowOptions {
        strand_count: 4096,
        curl: 0.3,
        ..Default::default()
    };
    let scene = grow_on_sphere(&opts);
    let rig = [scene.head.clone()];
    let params = SimParams::default();
    let mut strands = match Strands::from_polylines(&scene.points, scene.verts_per_strand) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("coif: cannot build the default scene: {e}");
            std::process::exit(1);
        }
    };
    let vertex_steps = (strands.strand_count() * strands.verts_per_strand()) as f64;
    println!(
        "coif default scene: {} strands x {} vertices on a {:.0} cm sphere head, dt {:.4} s, {} iterations, {} pearl(s)/segment",
        strands.strand_count(),
        strands.verts_per_strand(),
        opts.radius * 100.0,
        params.dt,
        params.iterations,
        params.pearls_per_segment
    );
    println!(
        "{:>6} {:>8} {:>12} {:>14} {:>12} {:>14}",
        "step", "time s", "step ms", "ns/vertex", "stretch %", "penetration mm"
    );
    let steps = 240;
    let mut total = 0.0f64;
    for i in 1..=steps {
        let t0 = Instant::now();
        kernels::step(&mut strands, &params, &rig);
        let dt = t0.elapsed().as_secs_f64();
        total += dt;
        if i % 20 == 0 || i == 1 {
            let m = measure(&strands, &rig);
            println!(
                "{:>6} {:>8.2} {:>12.3} {:>14.2} {:>12.3} {:>14.3}",
                i,
                i as f32 * params.dt,
                dt * 1e3,
                dt * 1e9 / vertex_steps,
                m.max_stretch * 100.0,
                m.max_penetration * 1e3
            );
        }
    }
    let mut reference = strands.clone();
    let t0 = Instant::now();
    scalar::step(&mut reference, &params, &rig);
    let scalar_time = t0.elapsed().as_secs_f64();
    println!(
        "SIMD: mean {:.3} ms/step ({:.2} ns per vertex-step); scalar reference: {:.3} ms/step; restored strands: {}",
        total / steps as f64 * 1e3,
        total / steps as f64 * 1e9 / vertex_steps,
        scalar_time * 1e3,
        strands.restored_strands()
    );
}
