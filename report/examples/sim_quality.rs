//! Time against error for the simulation: `cargo run --release --example sim_quality`
//! prints a table and writes `sim_quality.csv` (iterations 1..32 x pearls 0..3,
//! settling and whipping scenes, against a 256-iteration converged run).

use coif_report::quality::simulation::{study, to_csv, ITERATIONS, PEARLS};

fn main() {
    let rows = study(&ITERATIONS, &PEARLS);
    println!(
        "{:>9} {:>4} {:>6} {:>10} {:>10} {:>9} {:>8} {:>9} {:>9}",
        "scene",
        "iter",
        "pearls",
        "SIMD ns/v",
        "scalar ns",
        "stretch%",
        "pen mm",
        "max d mm",
        "rms d mm"
    );
    for r in &rows {
        println!(
            "{:>9} {:>4} {:>6} {:>10.2} {:>10.2} {:>9.3} {:>8.3} {:>9.2} {:>9.2}",
            r.scene.name(),
            r.iterations,
            r.pearls,
            r.simd_ns_per_vertex_step,
            r.scalar_ns_per_vertex_step,
            r.max_stretch * 100.0,
            r.max_penetration * 1e3,
            r.max_distance_to_converged * 1e3,
            r.rms_distance_to_converged * 1e3
        );
    }
    match std::fs::write("sim_quality.csv", to_csv(&rows)) {
        Ok(()) => println!("wrote sim_quality.csv"),
        Err(e) => eprintln!("could not write sim_quality.csv: {e}"),
    }
}
