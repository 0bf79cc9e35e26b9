//! `cargo run --release -p coif-report --example sim_lod_table [-- --quick]`:
//! the simulation-LOD family (sleeping thresholds and guide levels against
//! their error) as one table, without running the whole report.

use coif_report::{sim_lod, Options};

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    println!("| kernel | setting | ns/vertex-step (min-max) | RMS distance (mm) |");
    println!("|---|---|---|---|");
    for r in sim_lod::rows(Options { quick }) {
        println!(
            "| {} | {}{} | {:.2} ({:.2}-{:.2}) | {:.3} |",
            r.kernel,
            r.setting,
            if r.is_default { " (default)" } else { "" },
            r.time.median,
            r.time.min,
            r.time.max,
            1e3 * r.error
        );
    }
}
