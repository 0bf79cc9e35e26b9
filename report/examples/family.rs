//! One family of the report alone, its rows as a table (kernel, setting,
//! path, ns median and range, error), and how long it took.
//!
//! `cargo run --release -p coif-report --example family -- NAME [--quick]`
//! (NAME as in `coif_report::FAMILIES`, e.g. `volume`, `"hair friction"`).

use coif_report::{Options, FAMILIES};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let names: Vec<&str> = FAMILIES.iter().map(|f| f.name).collect();
    let Some(family) = args
        .iter()
        .find(|a| *a != "--quick")
        .and_then(|n| FAMILIES.iter().find(|f| f.name == n))
    else {
        eprintln!("usage: family NAME [--quick]; NAME one of {names:?}");
        std::process::exit(2);
    };
    let t0 = std::time::Instant::now();
    let rows = (family.measure)(Options { quick });
    let seconds = t0.elapsed().as_secs_f64();
    for r in &rows {
        println!(
            "{:<24} {:<48} {:<6} {:>9.1} ns ({:.1} - {:.1}) error {:.4e}{}",
            r.kernel,
            r.setting,
            r.path.name(),
            r.time.median,
            r.time.min,
            r.time.max,
            r.error,
            if r.is_default { " default" } else { "" }
        );
    }
    println!("{}: {} rows in {seconds:.1} s", family.name, rows.len());
}
