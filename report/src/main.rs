//! `cargo run --release --bin report -- [--quick] [--out DIR]`: measures
//! every kernel's run time against its error and writes `results.csv`,
//! `summary.md` and one SVG plot per kernel into DIR (default `report/`).
//! See [`coif::report`].

use coif_report::{self as report, Options};
use std::path::PathBuf;

const MACHINE: &str = "a 2-core Intel Xeon, build x86-64-v3 (AVX2 + FMA)";

fn main() {
    let mut quick = false;
    let mut out = PathBuf::from("report");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--quick" => quick = true,
            "--out" => match args.next() {
                Some(d) => out = PathBuf::from(d),
                None => {
                    eprintln!("--out needs a directory");
                    std::process::exit(2);
                }
            },
            "-h" | "--help" => {
                println!("usage: report [--quick] [--out DIR]");
                return;
            }
            other => {
                eprintln!("unknown argument {other:?}; usage: report [--quick] [--out DIR]");
                std::process::exit(2);
            }
        }
    }
    let t0 = std::time::Instant::now();
    let rows = report::run(Options { quick });
    match report::write(&rows, &out, MACHINE) {
        Ok(files) => {
            for f in files {
                println!("wrote {}", f.display());
            }
            println!("{} rows in {:.1} s", rows.len(), t0.elapsed().as_secs_f64());
        }
        Err(e) => {
            eprintln!("cannot write the report into {}: {e}", out.display());
            std::process::exit(1);
        }
    }
}
